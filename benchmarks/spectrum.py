"""Cost of the full Lyapunov spectrum (issue: all 128 exponents of N = 64 to t = 1e5 within a few
minutes on one core).

Measures, on one core, fputlab.chaos.lyapunov_spectrum for the homogeneous FPUT-alpha chain
(alpha = 0.25, N = 64, the mode-1 state at amplitude 8, all k = 2N = 128 deviation vectors,
random initial vectors, seed 1): the time to T (default 2000, best of `--repeats`), split into
the integration of orbit + 128 vectors and the QR re-orthonormalisations, and the projection
to t = 1e5 (linear in T: the work per unit time is constant). Each setting is one row. Times are
the process's CPU time (one thread: the cost on one core, also on a shared, oversubscribed
machine), with the wall time of the same run next to it.
Usage: python benchmarks/spectrum.py [--t-end 2000] [--repeats 2] [--full] [--json out.json]
  --full also runs the first setting to t = 1e5 (a few minutes) instead of projecting.
"""
import argparse
import json
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import fputlab  # noqa: E402
from fputlab.chaos import lyapunov_spectrum  # noqa: E402

N, T_GOAL = 64, 1e5
#: (method, dt, renormalize_every)
SETTINGS = [("srkn14a6", 0.5, 1.0), ("srkn14a6", 0.5, 10.0), ("yoshida4", 0.1, 10.0),
            ("dprkn12", 1.0, 10.0)]


def best_of(fn, repeats):
    """(CPU seconds, wall seconds, result) of the repeat with the least CPU time."""
    best, out = (float("inf"), float("inf")), None
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        out = fn()
        best = min(best, (time.process_time() - c, time.perf_counter() - w))
    return best[0], best[1], out


def integration_only(lat, y0, method, dt, T):
    """The same integration (orbit + 128 vectors, no QR) through the integrator."""
    w = np.linalg.qr(np.random.default_rng(1).standard_normal((2 * N, 2 * N)))[0].T
    ig = fputlab.Integrator(lat, np.vstack([y0, w]), method=method, dt=dt)
    ig.advance(T)


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--t-end", type=float, default=2000.0)
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--full", action="store_true")
    p.add_argument("--json")
    a = p.parse_args()
    lat = fputlab.Lattice(N, 0.25)
    y0 = lat.mode_state(1, 8.0)
    rows = []
    print("| method | dt | renormalize_every | T | CPU [s] | (wall [s]) | integration [s] | "
          "QR [s] | projected to t = 1e5 [min] | lambda_1 | sum |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for method, dt, tau in SETTINGS:
        cpu, wall, res = best_of(lambda: lyapunov_spectrum(lat, a.t_end, y0=y0, method=method,
                                                           dt=dt, renormalize_every=tau),
                                 a.repeats)
        integ, _, _ = best_of(lambda: integration_only(lat, y0, method, dt, a.t_end), a.repeats)
        row = {"method": method, "dt": dt, "renormalize_every": tau, "T": a.t_end, "cpu": cpu,
               "wall": wall, "integration": integ, "qr": max(cpu - integ, 0.0),
               "projected_min": cpu * T_GOAL / a.t_end / 60, "lambda_1": res.exponents[0],
               "sum": float(res.exponents.sum())}
        rows.append(row)
        print(f"| {method} | {dt} | {tau} | {a.t_end:g} | {cpu:.2f} | ({wall:.2f}) | "
              f"{integ:.2f} | {row['qr']:.2f} | {row['projected_min']:.1f} | "
              f"{row['lambda_1']:.3e} | {row['sum']:.1e} |", flush=True)
    if a.full:
        method, dt, tau = SETTINGS[0]
        cpu, wall, res = best_of(lambda: lyapunov_spectrum(lat, T_GOAL, y0=y0, method=method,
                                                           dt=dt, renormalize_every=tau), 1)
        rows.append({"method": method, "dt": dt, "renormalize_every": tau, "T": T_GOAL,
                     "cpu": cpu, "wall": wall, "lambda_1": res.exponents[0],
                     "sum": float(res.exponents.sum())})
        print(f"full run to t = 1e5 ({method}, dt = {dt}, every {tau}): CPU {cpu / 60:.2f} min "
              f"(wall {wall / 60:.2f} min), lambda_1 = {res.exponents[0]:.4e}, "
              f"sum = {res.exponents.sum():.1e}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
