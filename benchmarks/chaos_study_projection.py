"""Projected wall time of the paper's full chaos study (Figs. 12-14: model 3, tau = 10 %,
30 realisations x N = 4, 8, 16, 32, 64, t = 1e8) on this 2-core machine.

Measured here: the CPU cost per unit of simulated time of one orbit with mLE + SALI bookkeeping
(process time of a short run, so other load does not count), for each N and each way of running:
Yoshida 4 at dt = 0.01 (the paper's tangent map), srkn14a6 at dt = 0.5 (the study's default) and,
if available, the batched kernel (fputlab.chaos.batch, 30 orbits of one N in vector lanes).
Early stop: an orbit stops when it is classified chaotic or blows up. Where decided orbits are
known (--study DIR, a fputlab.chaos.study work directory) each orbit is charged up to the time it
stopped; orbits not yet decided are charged to t = 1e8 (so the projection is an upper bound).

Usage: python benchmarks/chaos_study_projection.py [--study DIR] [--t-run 2e4] [--json out.json]
"""
import argparse
import json
import time

import fputlab
from fputlab import chaos

NS = (4, 8, 16, 32, 64)
T_FULL, R, CORES = 1e8, 30, 2


def cpu_per_unit(fn, t_run):
    fn(min(t_run, 50.0))                  # warm-up: first-call costs are not per unit time
    c0 = time.process_time()
    fn(t_run)
    return (time.process_time() - c0) / t_run


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--study", help="a fputlab.chaos.study work directory: use its early stops")
    p.add_argument("--t-run", type=float, default=2e4, help="simulated time per measurement")
    p.add_argument("--json")
    a = p.parse_args()
    try:
        from fputlab.chaos.batch import lyapunov_batch
    except ImportError:
        lyapunov_batch = None
    cost = {}
    for N in NS:
        lats = [fputlab.Lattice(N, 0.25, "nonlinear", tau=10.0, seed=s) for s in range(1, R + 1)]
        row = {
            "yoshida4": cpu_per_unit(lambda T: chaos.lyapunov(lats[1], T), a.t_run / 10),
            "srkn14a6": cpu_per_unit(lambda T: chaos.lyapunov(lats[1], T, method="srkn14a6",
                                                             dt=0.5), a.t_run),
        }
        if lyapunov_batch is not None:
            row["srkn14a6 batched"] = cpu_per_unit(
                lambda T: lyapunov_batch(lats, T, method="srkn14a6", dt=0.5), a.t_run) / R
        cost[N] = row
        print(f"N = {N:2d}: " + ", ".join(f"{k} {1e6 * v:.2f} us" for k, v in row.items()) +
              " of CPU per unit time and orbit", flush=True)
    # how long each orbit runs: to 1e8, or to its early stop where the study knows it
    stops = {N: [T_FULL] * R for N in NS}
    if a.study:
        from fputlab.chaos.study import ChaosStudy
        study = ChaosStudy(a.study)
        for N, res in study.results().items():
            stops[N] = [(r.t_blowup if r.blew_up else r.t_final) if r is not None and
                        (r.blew_up or r.chaotic) else T_FULL for r in res]
        decided = sum(t < T_FULL for v in stops.values() for t in v)
        print(f"\nearly stops from {a.study}: {decided} of {R * len(NS)} orbits decided "
              f"(the others charged to t = 1e8)")
    out = {"cost_s_per_unit_time": {str(N): v for N, v in cost.items()}, "projection_h": {}}
    print()
    for way in cost[NS[0]]:
        full = sum(cost[N][way] * T_FULL * R for N in NS) / CORES / 3600
        early = sum(cost[N][way] * sum(stops[N]) for N in NS) / CORES / 3600
        out["projection_h"][way] = {"no_early_stop": full, "early_stop": early}
        print(f"{way:>17}: {full:6.1f} h without early stop, {early:6.1f} h with it "
              f"(wall, {CORES} cores)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
