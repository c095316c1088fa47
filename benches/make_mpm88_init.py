"""Write deterministic initial particle positions for the mpm88 benchmark.

Same distribution as Taichi's examples/simulation/mpm88.py `init()`:
    x[i] = [ti.random() * 0.4 + 0.2, ti.random() * 0.4 + 0.2]
i.e. uniform in [0.2, 0.6)^2, here drawn with numpy's default_rng(seed)
(float64 draws, stored as float32, shape (N, 2)).

Usage: python benches/make_mpm88_init.py [--out DIR] [--seed S] [--n N ...]
Writes DIR/mpm88_init_<N>.npy for N in 8192 and 32768 by default.
"""
import argparse
import os

import numpy as np


def make_positions(n, seed):
    rng = np.random.default_rng(seed)
    return (rng.random((n, 2)) * 0.4 + 0.2).astype(np.float32)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="target/mpm88")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--n", type=int, nargs="+", default=[8192, 32768])
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for n in args.n:
        path = os.path.join(args.out, f"mpm88_init_{n}.npy")
        np.save(path, make_positions(n, args.seed))
        print(path)


if __name__ == "__main__":
    main()
