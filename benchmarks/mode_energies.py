#!/usr/bin/env python3
"""Mode energies per state against N, for N whose transform length has a large prime factor
(N + 1 prime for fixed ends, N prime for rings: Bluestein's algorithm, csrc/fft.c) next to smooth
neighbours (GSL's mixed radix). Before fft.c, Lattice(65536).mode_energies took 58 s (N + 1 =
65537 prime: GSL's generic radix is O(N^2) for a prime length).

    .venv/bin/python benchmarks/mode_energies.py [--repeats 5]
"""
import argparse
import time

import numpy as np

import fputlab

CASES = [("fixed", 65535), ("fixed", 65536), ("fixed", 1_048_575), ("fixed", 1_048_578),
         ("periodic", 65536), ("periodic", 65537), ("periodic", 1_048_576), ("periodic", 1_048_573)]


def per_state(lat, y, repeats):
    """Seconds per state inside a run (the integrator's workspace and FFT plan reused)."""
    it = fputlab.Integrator(lat, y)
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        it.sample([it.t + 1e-9], mode_energies=True, energies=False)
        with_modes = time.perf_counter() - t
        t = time.perf_counter()
        it.sample([it.t + 1e-9], mode_energies=False, energies=False)
        best = min(best, with_modes - (time.perf_counter() - t))
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    print(f"{'boundary':>9} {'N':>9} {'one-shot [s]':>13} {'per sample [s]':>15}")
    for boundary, N in CASES:
        lat = fputlab.Lattice(N, boundary=boundary)
        y = np.random.default_rng(0).standard_normal(2 * N)
        t = time.perf_counter()
        lat.mode_energies(y)
        one_shot = time.perf_counter() - t
        print(f"{boundary:>9} {N:>9} {one_shot:13.4f} {per_state(lat, y, args.repeats):15.4f}")


if __name__ == "__main__":
    main()
