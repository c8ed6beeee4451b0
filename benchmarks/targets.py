#!/usr/bin/env python3
"""The speed target of issue 15 ("On the old target of the integrator issue"): the best fputlab
method against scipy's best solve_ivp method at equal accuracy, for N = 8, 16, 32, 64 and 4096.
Target: >= 100x at N <= 64, >= 10x at N = 4096.

The problem is run.py's (homogeneous FPUT-alpha chain, alpha = 0.25, fixed ends, mode-1 orbit,
2 random unit deviation vectors, T = 100) and so are the reference (srkn14a6 at dt = 0.01,
checked at dt = 0.02) and scipy's vectorised right-hand side (run.FputRHS). Accuracy = max abs
error of the final state (orbit and both deviation vectors).

Every method is swept over its accuracy knob (scipy and fputlab's adaptive methods: rtol = atol
= 1e-3 ... 1e-12; fixed-step methods: a list of step sizes), each point timed in *process CPU
time*, each run looped to >= --min-time s: the minimum over --repeats rounds, each round timing
every point of the size once in turn (the machine is shared and has slow phases seconds long:
interleaving spreads them over all methods alike instead of all repeats of one point). The cost of a method at a target error e* is interpolated in log-log
between the two neighbouring points of its Pareto front that bracket e* (never extrapolated: a
method whose sweep does not reach e* has no cost there; one whose loosest point is already more
accurate than e* costs what that point costs). The best of each side is compared.

    .venv/bin/python benchmarks/targets.py                      # ~5-10 min here
    .venv/bin/python benchmarks/targets.py --sizes 8 64 --json out.json
    .venv/bin/python benchmarks/targets.py --sizes 4096 --fputlab-methods srkn14a6 aba864 gsl-rk8pd
"""
from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
             "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run as B  # noqa: E402  (the shared problem, reference and scipy right-hand side)

import fputlab  # noqa: E402

cpu = time.process_time
T_END = 100.0
TOLS = [10.0 ** -k for k in range(3, 13)]
# fixed-step methods: steps per unit time swept (dt = 1/n divides T = 100 exactly)
FIXED_STEPS = {
    "dprkn12": [0.5, 0.8, 1, 1.25, 2, 2.5, 4],
    "dprkn8": [1, 1.25, 2, 2.5, 4, 5, 8, 10],
    "srkn14a6": [1.25, 1.6, 2, 2.5, 4, 5, 8, 10, 20, 40],
    "aba864": [4, 5, 8, 10, 16, 20, 32, 40, 80, 160],
    "yoshida4": [50, 100, 200, 400, 800, 1600],
    "leapfrog": [100, 200, 400, 800, 1600, 3200],
}
FPL_ADAPTIVE = ["gsl-rk8pd", "dop853"]
SCIPY_METHODS = ["DOP853", "RK45", "LSODA"]
TARGET_ERRORS = [1e-6, 1e-9]


def loop_time(fn, once, min_time):
    """Process CPU time of one fn() call, looped to >= min_time (once: a first estimate)."""
    inner = max(1, math.ceil(min_time / max(once, 1e-6)))
    t0 = cpu()
    for _ in range(inner):
        fn()
    return (cpu() - t0) / inner


def time_in_rounds(timers, cfg):
    """Every point's cost = the minimum over --repeats rounds, each round timing every point of
    this N (both sides) once in turn: a slow phase of a shared machine (seconds long here) then
    hits some rounds of every method alike instead of all repeats of one point."""
    for _ in range(cfg.repeats):
        for pt, fn in timers:
            pt["cpu"] = min(pt["cpu"], loop_time(fn, pt["cpu"], cfg.min_time))


def scipy_run(method, N, st, T, tol):
    from scipy.integrate import solve_ivp
    rhs = B.FputRHS(N)
    sol = solve_ivp(rhs, (0.0, T), st.reshape(-1), method=method, rtol=tol, atol=tol,
                    t_eval=[T])
    if not sol.success:
        raise RuntimeError(f"solve_ivp {method} failed: {sol.message}")
    return sol.y[:, -1].reshape(st.shape)


def fpl_run(lat, st, T, method, **kw):
    integ = fputlab.Integrator(lat, st, method=method, **kw)
    return integ.advance(T)


def sweep(label, knobs, make, ref, floor_err, cfg, log, timers):
    """Points (knob, error, cpu seconds of a first run) for each knob, loose to tight; stops once
    the error is far below every target or a run would exceed the CPU cap. Each point's run is
    appended to timers for time_in_rounds."""
    pts = []
    for knob in knobs:
        fn = make(knob)
        t0 = cpu()
        try:
            y = fn()
        except (fputlab.FputlabError, RuntimeError) as exc:   # e.g. a step beyond stability
            log(f"    {label} {knob:g}: failed ({exc}), skipped")
            continue
        once = cpu() - t0
        err = float(np.abs(y - ref).max())
        if not math.isfinite(err):
            log(f"    {label} {knob:g}: non-finite result, skipped")
            continue
        if once > cfg.cap:
            log(f"    {label} {knob:g}: one run {once:.1f} s > cap {cfg.cap:g} s, stop")
            pts.append({"knob": knob, "error": err, "cpu": once, "single": True})
            break
        pts.append({"knob": knob, "error": err, "cpu": once})
        timers.append((pts[-1], fn))
        if err < floor_err:
            break
    return pts


def cost_at(target, pts, ref_floor):
    """CPU cost at error `target`, interpolated log-log on the Pareto front; None if the
    sweep does not bracket the target (or the target is below the reference's own error)."""
    if target < ref_floor:
        return None
    P = sorted((max(p["error"], ref_floor), p["cpu"]) for p in pts)
    front = []
    for e, c in P:                       # ascending error: cheapest at least this accurate
        c = min(c, front[-1][1]) if front else c
        front.append((e, c))
    if not front or target < front[0][0]:
        return None
    if target >= front[-1][0]:           # even the loosest point is accurate enough
        return front[-1][1]
    for (e1, c1), (e2, c2) in zip(front, front[1:]):
        if e1 <= target <= e2:
            if e1 == e2:
                return min(c1, c2)
            f = (math.log(target) - math.log(e1)) / (math.log(e2) - math.log(e1))
            return math.exp(math.log(c1) + f * (math.log(c2) - math.log(c1)))
    return front[0][1] if target == front[0][0] else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 32, 64, 4096])
    ap.add_argument("--repeats", type=int, default=9,
                    help="rounds timing every point once each; a point's minimum counts")
    ap.add_argument("--min-time", type=float, default=0.03)
    ap.add_argument("--cap", type=float, default=15.0, help="CPU seconds a single run may take")
    ap.add_argument("--json", help="write every point here")
    ap.add_argument("--fputlab-methods", nargs="+", help="default: " + " ".join(
        list(FIXED_STEPS) + FPL_ADAPTIVE))
    ap.add_argument("--scipy-methods", nargs="+", default=SCIPY_METHODS)
    cfg = ap.parse_args(argv)
    log = lambda s: print(s, file=sys.stderr, flush=True)   # noqa: E731
    methods = set(fputlab.methods())
    if cfg.fputlab_methods:
        methods &= set(cfg.fputlab_methods) | {"srkn14a6"}    # srkn14a6: the reference
    log(f"load average at start: {B.loadavg()}")
    scipy_run("DOP853", 8, B.problem(8)[1], 1.0, 1e-3)        # warm-up: imports
    out = {"sizes": {}, "load_start": B.loadavg(), "targets": TARGET_ERRORS}
    floor = min(TARGET_ERRORS) / 30
    for N in cfg.sizes:
        lat, st = B.problem(N)
        ref, rinfo = B.reference(lat, st, T_END, methods)
        rfloor = rinfo["check_diff_state"]
        log(f"N = {N}: reference {rinfo['method']} {rinfo['setting']}, check {rfloor:.1e}")
        res = {"reference": rinfo, "fputlab": {}, "scipy": {}}
        wanted = set(cfg.fputlab_methods or methods)
        timers = []
        for m, ns in FIXED_STEPS.items():
            if m in methods and m in wanted:
                res["fputlab"][m] = sweep(m, ns, lambda n, m=m: (
                    lambda: fpl_run(lat, st, T_END, m, dt=1.0 / n)), ref, floor, cfg, log,
                    timers)
        for m in FPL_ADAPTIVE:
            if m in methods and m in wanted:
                res["fputlab"][m] = sweep(m, TOLS, lambda tol, m=m: (
                    lambda: fpl_run(lat, st, T_END, m, rtol=tol, atol=tol)), ref, floor, cfg,
                    log, timers)
        for m in cfg.scipy_methods:
            res["scipy"][m] = sweep("scipy " + m, TOLS, lambda tol, m=m: (
                lambda: scipy_run(m, N, st, T_END, tol)), ref, floor, cfg, log, timers)
        time_in_rounds(timers, cfg)
        res["at"] = {}
        for e in TARGET_ERRORS:
            row = {}
            for side in ("fputlab", "scipy"):
                costs = {m: cost_at(e, pts, rfloor) for m, pts in res[side].items()}
                costs = {m: c for m, c in costs.items() if c is not None}
                best = min(costs, key=costs.get) if costs else None
                row[side] = {"costs": costs, "best": best,
                             "cpu": costs[best] if best else None}
            f, s = row["fputlab"]["cpu"], row["scipy"]["cpu"]
            row["speedup"] = s / f if f and s else None
            res["at"][f"{e:.0e}"] = row
            sp = row["speedup"]
            log(f"  error {e:.0e}: fputlab best {row['fputlab']['best']} {f and f * 1e3:.3g} ms; "
                f"scipy best {row['scipy']['best']} {s and s * 1e3:.3g} ms; "
                f"speed-up {'-' if sp is None else f'{sp:.3g}x'}")
        out["sizes"][N] = res
    out["load_end"] = B.loadavg()
    log(f"load average at end: {out['load_end']}")
    print("\n| N | error | fputlab best | CPU [ms] | scipy best | CPU [ms] | speed-up | target |")
    print("|---:|---:|---|---:|---|---:|---:|---|")
    for N, res in out["sizes"].items():
        goal = 100.0 if N <= 64 else 10.0
        for e, row in res["at"].items():
            f, s, sp = row["fputlab"]["cpu"], row["scipy"]["cpu"], row["speedup"]
            print(f"| {N} | {e} | {row['fputlab']['best']} | {f * 1e3:.3g} | "
                  f"{row['scipy']['best']} | {s * 1e3:.3g} | {sp:.3g}x | "
                  f"{'met' if sp >= goal else 'NOT met'} (>= {goal:g}x) |"
                  if f and s else f"| {N} | {e} | - | - | - | - | - | no bracket |")
    if cfg.json:
        Path(cfg.json).write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
