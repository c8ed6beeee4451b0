"""Cost of the chaos indicators (issue: chaos must cost no more than the integration it rides on).

Measures, on one core, for N = 64 (homogeneous chain, paper initial state, 2 deviation vectors):
  * the plain integration of orbit + 2 deviation vectors to t = T with Yoshida 4 (dt = 0.01),
  * the same with mLE + SALI + GALI bookkeeping (renormalisation every 1 time unit),
and reports the overhead, the time to t = 1e6, and the projected time to reproduce Fig. 14 at
the paper's length (t = 1e8, 30 realisations for each N = 4, 8, 16, 32, 64) on this 2-core
machine, both with the tangent map (Yoshida 4) and with DOP853 on the variational equations (the
paper's choice for model 3; its cost per unit time is measured on a shorter run).
Usage: python benchmarks/chaos_cost.py [--t-end 1e5] [--json out.json]
"""
import argparse
import json
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np

import fputlab
from fputlab import chaos


def best_of(fn, repeats=3):
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--t-end", type=float, default=1e5)
    p.add_argument("--json")
    a = p.parse_args()
    T = a.t_end
    out = {"t_end": T}
    per_unit = {}
    for N in (4, 8, 16, 32, 64):
        lat = fputlab.Lattice(N, 0.25)
        W = np.random.default_rng(1).standard_normal((2, 2 * N))
        y = np.vstack([lat.mode_state(), W])
        plain = best_of(lambda: fputlab.Integrator(lat, y, dt=0.01).advance(T))
        with_chaos = best_of(lambda: chaos.lyapunov(lat, T, w0=W, n_samples=200))
        lat3 = fputlab.Lattice(N, 0.25, "nonlinear", tau=10.0, seed=1)
        Td = T / 50
        dop = best_of(lambda: chaos.lyapunov(lat3, Td, method="dop853", rtol=1e-10, atol=1e-12,
                                             renorm_interval=10.0), repeats=1)
        per_unit[N] = {"yoshida4": with_chaos / T, "dop853": dop / Td}
        out[f"N{N}"] = {"plain_s": plain, "chaos_s": with_chaos, "overhead": with_chaos / plain - 1,
                        "yoshida4_s_per_unit_time": with_chaos / T, "dop853_s_per_unit_time": dop / Td}
        print(f"N = {N:3d}: integration {plain:6.3f} s, with mLE/SALI/GALI {with_chaos:6.3f} s "
              f"(overhead {100 * (with_chaos / plain - 1):+.1f} %) to t = {T:g}; "
              f"DOP853 variational {dop / Td * 1e3:.3f} ms per unit time")
    t64 = per_unit[64]["yoshida4"] * 1e6
    out["N64_time_to_1e6_s"] = t64
    print(f"\nN = 64 to t = 1e6 with mLE + SALI (Yoshida 4): {t64:.1f} s")
    for method in ("yoshida4", "dop853"):
        cpu = sum(30 * per_unit[N][method] * 1e8 for N in per_unit)
        out[f"fig14_full_{method}_hours_on_2_cores"] = cpu / 2 / 3600
        print(f"Fig. 14 at full length (t = 1e8, 30 realisations x N = 4..64), {method}: "
              f"{cpu / 3600:.1f} CPU-hours = {cpu / 2 / 3600:.1f} h on 2 cores")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
