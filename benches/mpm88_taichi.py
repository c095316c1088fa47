"""Taichi side of the mpm88 benchmark (reference for the Rust implementation).

Runs the `substep` kernel of Taichi's examples/simulation/mpm88.py unchanged,
only parameterised by particle count (the two 2-D configs listed in the
example mpm3d.py: n_particles = n_grid**2 // 2):
    8192 particles  -> n_grid 128 (dx 1/128), dt 2e-4
    32768 particles -> n_grid 256 (dx 1/256), dt 1e-4
Initial state: x from a float32 (N, 2) .npy, v = (0, -1), J = 1, C = 0.

Usage:
  python benches/mpm88_taichi.py --init FILE.npy --steps N
         [--threads T] [--f64] [--warmup K] [--no-fast-math]

Warmup steps (default 1, they compile the kernel) run first; the state is
then reset to the initial state, so the reported result is exactly `steps`
substeps from the init file. Prints one JSON line.
"""
import argparse
import contextlib
import json
import os
import sys
import time

import numpy as np

os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")  # keep stdout JSON-only
import taichi as ti  # noqa: E402

CONFIGS = {8192: (128, 2e-4), 32768: (256, 1e-4)}  # n_particles -> (n_grid, dt)


def build(n_particles):
    n_grid, dt = CONFIGS[n_particles]
    dx = 1 / n_grid
    p_rho = 1
    p_vol = (dx * 0.5) ** 2
    p_mass = p_vol * p_rho
    gravity = 9.8
    bound = 3
    E = 400

    x = ti.Vector.field(2, float, n_particles)
    v = ti.Vector.field(2, float, n_particles)
    C = ti.Matrix.field(2, 2, float, n_particles)
    J = ti.field(float, n_particles)
    grid_v = ti.Vector.field(2, float, (n_grid, n_grid))
    grid_m = ti.field(float, (n_grid, n_grid))

    # ---- verbatim from mpm88.py (Taichi 1.7.4) ----
    @ti.kernel
    def substep():
        for i, j in grid_m:
            grid_v[i, j] = [0, 0]
            grid_m[i, j] = 0
        for p in x:
            Xp = x[p] / dx
            base = int(Xp - 0.5)
            fx = Xp - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
            stress = -dt * 4 * E * p_vol * (J[p] - 1) / dx**2
            affine = ti.Matrix([[stress, 0], [0, stress]]) + p_mass * C[p]
            for i, j in ti.static(ti.ndrange(3, 3)):
                offset = ti.Vector([i, j])
                dpos = (offset - fx) * dx
                weight = w[i].x * w[j].y
                grid_v[base + offset] += weight * (p_mass * v[p] + affine @ dpos)
                grid_m[base + offset] += weight * p_mass
        for i, j in grid_m:
            if grid_m[i, j] > 0:
                grid_v[i, j] /= grid_m[i, j]
            grid_v[i, j].y -= dt * gravity
            if i < bound and grid_v[i, j].x < 0:
                grid_v[i, j].x = 0
            if i > n_grid - bound and grid_v[i, j].x > 0:
                grid_v[i, j].x = 0
            if j < bound and grid_v[i, j].y < 0:
                grid_v[i, j].y = 0
            if j > n_grid - bound and grid_v[i, j].y > 0:
                grid_v[i, j].y = 0
        for p in x:
            Xp = x[p] / dx
            base = int(Xp - 0.5)
            fx = Xp - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1) ** 2, 0.5 * (fx - 0.5) ** 2]
            new_v = ti.Vector.zero(float, 2)
            new_C = ti.Matrix.zero(float, 2, 2)
            for i, j in ti.static(ti.ndrange(3, 3)):
                offset = ti.Vector([i, j])
                dpos = (offset - fx) * dx
                weight = w[i].x * w[j].y
                g_v = grid_v[base + offset]
                new_v += weight * g_v
                new_C += 4 * weight * g_v.outer_product(dpos) / dx**2
            v[p] = new_v
            x[p] += dt * v[p]
            J[p] *= 1 + dt * new_C.trace()
            C[p] = new_C
    # ---- end verbatim ----

    return dict(x=x, v=v, C=C, J=J, substep=substep, p_mass=p_mass)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--init", required=True, help="float32 (N, 2) positions .npy")
    ap.add_argument("--steps", type=int, required=True)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--f64", action="store_true", help="default_fp=ti.f64")
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--no-fast-math", action="store_true",
                    help="ti.init(fast_math=False); Taichi's default is True")
    args = ap.parse_args()

    x0 = np.load(args.init)
    if x0.ndim != 2 or x0.shape[1] != 2:
        sys.exit(f"error: {args.init}: expected shape (N, 2), got {x0.shape}")
    n = x0.shape[0]
    if n not in CONFIGS:
        sys.exit(f"error: {n} particles not supported; mpm88 configs are "
                 f"{sorted(CONFIGS)} (n_grid 128/dt 2e-4, n_grid 256/dt 1e-4)")

    fp = ti.f64 if args.f64 else ti.f32
    with contextlib.redirect_stdout(sys.stderr):  # ti.init prints a banner
        ti.init(arch=ti.cpu, cpu_max_num_threads=args.threads, default_fp=fp,
                random_seed=0, fast_math=not args.no_fast_math)
    s = build(n)
    npfp = np.float64 if args.f64 else np.float32

    def reset():
        s["x"].from_numpy(x0.astype(npfp))
        s["v"].from_numpy(np.tile(np.array([0, -1], npfp), (n, 1)))
        s["C"].from_numpy(np.zeros((n, 2, 2), npfp))
        s["J"].from_numpy(np.ones(n, npfp))
        ti.sync()

    reset()
    for _ in range(args.warmup):
        s["substep"]()
    reset()  # warmup only compiles; the timed run starts from the init state

    t0 = time.perf_counter()
    for _ in range(args.steps):
        s["substep"]()
    ti.sync()
    seconds = time.perf_counter() - t0

    x = s["x"].to_numpy().astype(np.float64)
    v = s["v"].to_numpy().astype(np.float64)
    J = s["J"].to_numpy().astype(np.float64)
    print(json.dumps({
        "implementation": "taichi",
        "taichi_version": ".".join(map(str, ti.__version__)),
        "precision": "f64" if args.f64 else "f32",
        "fast_math": not args.no_fast_math,
        "particles": n,
        "steps": args.steps,
        "threads": args.threads,
        "mean_x": float(x[:, 0].mean()),
        "mean_y": float(x[:, 1].mean()),
        "kinetic_energy": float(0.5 * s["p_mass"] * np.sum(v * v)),
        "mean_J": float(J.mean()),
        "seconds": seconds,
        "particle_steps_per_s": n * args.steps / seconds if seconds > 0 else None,
    }))


if __name__ == "__main__":
    main()
