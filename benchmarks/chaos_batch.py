"""Batched chaos kernel against the single-orbit path (issue "Batched orbits").

For each N in 4, 8, 16, 32, 64 and R in 1, 4, 8, 30: R disorder realisations of model 3
(tau = 10 %, seeds 1..R, mode-1 initial state, 2 deviation vectors, renormalisation every 1,
mLE + SALI + GALI bookkeeping) run to t = T; with --model toda, R orbits of the Toda lattice
(alpha = 0.25, fixed ends; homogeneous, so R copies of one lattice from R random initial states,
seed 1, amplitude 0.1)
  * together by fputlab.chaos.batch.lyapunov_batch (one call), and
  * one after the other by fputlab.chaos.lyapunov (the single-orbit fpl_chaos path),
in the same process, minimum of `--repeats` runs each. Reported: ns per particle-step per orbit,
time / (steps x N x R), and the speed-up single / batch. Times are the process's CPU time (not
wall time: on a shared machine the wall clock also counts other jobs' turns); one core.
Usage: python benchmarks/chaos_batch.py [--model nonlinear|toda] [--t-end 200]
       [--methods yoshida4 srkn14a6] [--json out.json]
"""
import argparse
import json
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import fputlab  # noqa: E402
from fputlab import chaos  # noqa: E402
from fputlab.chaos import batch as chaos_batch  # noqa: E402

DT = {"yoshida4": 0.01, "srkn14a6": 0.4, "aba864": 0.0625, "leapfrog": 0.005}


def best_of(fn, repeats):
    best = float("inf")
    for _ in range(repeats):
        t = time.process_time()
        fn()
        best = min(best, time.process_time() - t)
    return best


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--model", choices=["nonlinear", "toda"], default="nonlinear")
    p.add_argument("--t-end", type=float, default=200.0)
    p.add_argument("--methods", nargs="+", default=["yoshida4", "srkn14a6"])
    p.add_argument("--sizes", nargs="+", type=int, default=[4, 8, 16, 32, 64])
    p.add_argument("--orbits", nargs="+", type=int, default=[1, 4, 8, 30])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--json")
    a = p.parse_args()
    T = a.t_end
    rows = []
    start = time.perf_counter()
    for method in a.methods:
        dt = DT[method]
        steps = round(T / dt)
        what = "model 3 tau = 10 %" if a.model == "nonlinear" else "Toda alpha = 0.25"
        print(f"\n{method}, dt = {dt}, T = {T:g} ({steps} steps), {what}")
        print(f"{'N':>4} {'R':>4} {'single ns/(p*step)':>19} {'batch ns/(p*step)':>18} {'speed-up':>9}")
        for N in a.sizes:
            R_max = max(a.orbits)
            if a.model == "toda":
                lats = [fputlab.Lattice(N, 0.25, "toda")] * R_max
                y0 = 0.1 * np.random.default_rng(1).standard_normal((R_max, 2 * N))
            else:
                lats = [fputlab.Lattice(N, 0.25, "nonlinear", tau=10.0, seed=s)
                        for s in range(1, R_max + 1)]
                y0 = None
            single_per_orbit = None
            for R in a.orbits:
                sub = lats[:R]
                kw = dict(method=method, dt=dt, n_samples=50)
                # the single-orbit path: R calls (its cost per orbit does not depend on R; measured
                # once on up to 8 orbits and reused)
                if single_per_orbit is None:
                    probe = range(min(8, R_max))
                    single_per_orbit = best_of(
                        lambda: [chaos.lyapunov(lats[r], T, **kw,
                                                **({} if y0 is None else {"y0": y0[r]}))
                                 for r in probe], a.repeats) / len(probe)
                batch = best_of(lambda: chaos_batch.lyapunov_batch(
                    sub, T, **kw, **({} if y0 is None else {"y0": y0[:R]})), a.repeats)
                ns_single = single_per_orbit / (steps * N) * 1e9
                ns_batch = batch / (steps * N * R) * 1e9
                rows.append({"model": a.model, "method": method, "dt": dt, "N": N, "R": R, "T": T,
                             "single_ns_per_particle_step": ns_single,
                             "batch_ns_per_particle_step_per_orbit": ns_batch,
                             "speedup": ns_single / ns_batch})
                print(f"{N:4d} {R:4d} {ns_single:19.2f} {ns_batch:18.2f} {ns_single / ns_batch:8.2f}x")
    print(f"\ntotal {time.perf_counter() - start:.1f} s")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    main()
