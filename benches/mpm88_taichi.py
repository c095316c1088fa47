"""Taichi side of the mpm88 benchmark (reference for the Rust implementation).

Runs the `substep` kernel of Taichi's examples/simulation/mpm88.py unchanged,
only parameterised by particle count (the two 2-D configs listed in the
example mpm3d.py: n_particles = n_grid**2 // 2):
    8192 particles  -> n_grid 128 (dx 1/128), dt 2e-4
    32768 particles -> n_grid 256 (dx 1/256), dt 1e-4
Initial state: x from a float32 (N, 2) .npy, v = (0, -1), J = 1, C = 0.

--material elastic|plastic swaps the liquid for the elastoplastic solid of
`contphy-eval bench mpm88 --material` (src/physics/mpm/mpm88.rs): the same
grid, dt, gravity, walls and initial state, with a deformation gradient F per
particle, the fixed-corotated Kirchhoff stress of Taichi's mpm99.py example
(2 mu (F - R) F^T + lam J (J - 1) I) and, after each update
F <- (I + dt C) F, the return map of src/physics/mpm/elastic.rs written out
the same way (the 2-D polar rotation and one Jacobi rotation for the SVD,
singular values clamped to [0.05, 20], von Mises on the Hencky strain for
plastic). Same constants: E 360, nu 0.2, yield stress 2 (plastic).

Usage:
  python benches/mpm88_taichi.py --init FILE.npy --steps N
         [--threads T] [--f64] [--warmup K] [--no-fast-math]
         [--material liquid|elastic|plastic]

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

# The solids of src/physics/mpm/mpm88.rs (SOLID_YOUNGS_MODULUS, SOLID_POISSON_RATIO,
# PLASTIC_YIELD_STRESS): P-wave modulus lam + 2 mu = 400, the liquid's E.
SOLID_E = 360.0
SOLID_NU = 0.2
PLASTIC_YIELD_STRESS = 2.0
# elastic.rs SINGULAR_VALUE_RANGE
SIGMA_MIN, SIGMA_MAX = 0.05, 20.0


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


def build_solid(n_particles, plastic):
    """The mpm88 substep with an elastoplastic solid in place of the liquid."""
    n_grid, dt = CONFIGS[n_particles]
    dx = 1 / n_grid
    p_rho = 1
    p_vol = (dx * 0.5) ** 2
    p_mass = p_vol * p_rho
    gravity = 9.8
    bound = 3
    mu = SOLID_E / (2 * (1 + SOLID_NU))
    lam = SOLID_E * SOLID_NU / ((1 + SOLID_NU) * (1 - 2 * SOLID_NU))
    yield_strain = PLASTIC_YIELD_STRESS / (2 * mu)

    x = ti.Vector.field(2, float, n_particles)
    v = ti.Vector.field(2, float, n_particles)
    C = ti.Matrix.field(2, 2, float, n_particles)
    F = ti.Matrix.field(2, 2, float, n_particles)
    J = ti.field(float, n_particles)
    yielded = ti.field(ti.i32, n_particles)
    stretch_clamped = ti.field(ti.i32, n_particles)
    grid_v = ti.Vector.field(2, float, (n_grid, n_grid))
    grid_m = ti.field(float, (n_grid, n_grid))

    @ti.func
    def polar_rotation(f):
        """(cos, sin) of the rotation R of F = R S (elastic.rs polar_rotation; the same
        closed form as ti.polar_decompose in 2-D)."""
        px = f[0, 0] + f[1, 1]
        py = f[1, 0] - f[0, 1]
        length = ti.sqrt(px * px + py * py)
        cs = ti.Vector([1.0, 0.0])
        if length > 0:
            cs = ti.Vector([px / length, py / length])
        return cs

    @ti.func
    def return_map(f, p):
        """elastic.rs decompose + return_map: F = U diag(sigma) V^T via the polar rotation
        and one Jacobi rotation; clamp sigma, then (plastic) project the deviatoric Hencky
        strain onto 2 mu |e_dev| <= yield; recompose only when something changed."""
        cs = polar_rotation(f)
        c, s = cs[0], cs[1]
        s00 = c * f[0, 0] + s * f[1, 0]
        s01 = c * f[0, 1] + s * f[1, 1]
        s11 = -s * f[0, 1] + c * f[1, 1]
        phi = 0.5 * ti.atan2(2.0 * s01, s00 - s11)
        sp = ti.sin(phi)
        cp = ti.cos(phi)
        sig = ti.Vector([
            cp * cp * s00 + 2.0 * cp * sp * s01 + sp * sp * s11,
            sp * sp * s00 - 2.0 * cp * sp * s01 + cp * cp * s11,
        ])
        changed = 0
        for k in ti.static(range(2)):
            if not (sig[k] >= SIGMA_MIN and sig[k] <= SIGMA_MAX):
                sig[k] = ti.min(ti.max(sig[k], SIGMA_MIN), SIGMA_MAX)
                changed = 1
        if changed:
            stretch_clamped[p] += 1
        if ti.static(plastic):
            e0 = ti.log(sig[0])
            e1 = ti.log(sig[1])
            mean = 0.5 * (e0 + e1)
            d0 = e0 - mean
            d1 = e1 - mean
            norm = ti.sqrt(d0 * d0 + d1 * d1)
            excess = norm - yield_strain
            if excess > 0:
                keep = 1.0 - excess / norm
                sig = ti.Vector([ti.exp(mean + keep * d0), ti.exp(mean + keep * d1)])
                if not changed:
                    yielded[p] += 1
                changed = 1
        result = f
        if changed:
            rotation = ti.Matrix([[c, -s], [s, c]])
            vmat = ti.Matrix([[cp, -sp], [sp, cp]])
            u = rotation @ vmat
            scaled = ti.Matrix([[u[0, 0] * sig[0], u[0, 1] * sig[1]],
                                [u[1, 0] * sig[0], u[1, 1] * sig[1]]])
            result = scaled @ vmat.transpose()
        return result

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
            # Fixed-corotated Kirchhoff stress (mpm99.py; elastic.rs corotated_stress).
            f = F[p]
            cs = polar_rotation(f)
            rotation = ti.Matrix([[cs[0], -cs[1]], [cs[1], cs[0]]])
            jp = f.determinant()
            tau = 2 * mu * (f - rotation) @ f.transpose() \
                + ti.Matrix.identity(float, 2) * lam * (jp - 1) * jp
            stress = (-dt * 4 * p_vol / dx**2) * tau
            affine = stress + p_mass * C[p]
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
            C[p] = new_C
            f = return_map((ti.Matrix.identity(float, 2) + dt * new_C) @ F[p], p)
            F[p] = f
            J[p] = f.determinant()

    return dict(x=x, v=v, C=C, J=J, F=F, yielded=yielded,
                stretch_clamped=stretch_clamped, substep=substep, p_mass=p_mass,
                mu=mu, lam=lam)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--init", required=True, help="float32 (N, 2) positions .npy")
    ap.add_argument("--steps", type=int, required=True)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--f64", action="store_true", help="default_fp=ti.f64")
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--no-fast-math", action="store_true",
                    help="ti.init(fast_math=False); Taichi's default is True")
    ap.add_argument("--material", choices=["liquid", "elastic", "plastic"],
                    default="liquid",
                    help="mpm88's liquid (default) or the elastoplastic solid")
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
    solid = args.material != "liquid"
    s = build_solid(n, args.material == "plastic") if solid else build(n)
    npfp = np.float64 if args.f64 else np.float32

    def reset():
        s["x"].from_numpy(x0.astype(npfp))
        s["v"].from_numpy(np.tile(np.array([0, -1], npfp), (n, 1)))
        s["C"].from_numpy(np.zeros((n, 2, 2), npfp))
        s["J"].from_numpy(np.ones(n, npfp))
        if solid:
            s["F"].from_numpy(np.tile(np.eye(2, dtype=npfp), (n, 1, 1)))
            s["yielded"].fill(0)
            s["stretch_clamped"].fill(0)
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
    report = {
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
    }
    if solid:
        report.update({
            "material": args.material,
            "youngs_modulus": SOLID_E,
            "poisson_ratio": SOLID_NU,
            "yield_stress": PLASTIC_YIELD_STRESS if args.material == "plastic" else None,
            "yielded": int(s["yielded"].to_numpy().astype(np.int64).sum()),
            "stretch_clamped": int(s["stretch_clamped"].to_numpy().astype(np.int64).sum()),
            "finite": bool(np.isfinite(x).all() and np.isfinite(v).all()
                           and np.isfinite(J).all()),
        })
    print(json.dumps(report))


if __name__ == "__main__":
    main()
