"""Which integrator for the chaos study? Classes and cost of the same orbits with several methods.

The paper computes lambda(t) and SALI(t) with Yoshida 4 at dt = 0.01 (tangent map) and with DOP853
on the variational equations (model 3). This runs orbits of the paper's study (model 3,
tau = 10 %, the mode-1 initial state, seeds as in the study) that turn chaotic late, and regular
ones, with each method, and reports per orbit and method: the class at t_end, when SALI fell below
1e-8, and the CPU time (process time, so other load on the machine does not count). A method is
validated when it classifies every orbit as the reference methods do; the chaos study then uses
the cheapest validated one (fputlab.chaos.ENSEMBLE_METHOD).

Usage: python benchmarks/chaos_methods.py [--quick] [--dop853] [--json out.json]
  --quick   shorter runs (the regular orbits to 2e5; about a minute)
  --dop853  also DOP853 on the variational equations (slow: ~30x Yoshida 4's cost per unit time)
"""
import argparse
import json
import time

import fputlab
from fputlab import chaos

# (N, seed, t_end, what the study found with srkn14a6 at dt = 0.5)
ORBITS = [(16, 6, 2e6, "chaotic near 9e5"), (32, 26, 1e6, "chaotic near 2.4e5"),
          (32, 16, 1e6, "chaotic near 2.6e5"), (16, 1, 1e6, "regular"),
          (32, 2, 1e6, "regular to 1e6")]
METHODS = [("yoshida4", 0.01), ("srkn14a6", 0.5), ("aba864", 0.05)]


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--dop853", action="store_true")
    p.add_argument("--json")
    a = p.parse_args()
    methods = METHODS + ([("dop853", None)] if a.dop853 else [])
    rows = []
    print(f"{'N':>3} {'seed':>4} {'t_end':>7} {'method':>9} {'class':>10} {'t_chaotic':>10} "
          f"{'CPU s':>8} {'us/unit':>8}")
    for N, seed, t_end, note in ORBITS:
        if a.quick:
            t_end = min(t_end, 4e5 if "chaotic near 2" in note else 2e5)
        lat = fputlab.Lattice(N, 0.25, "nonlinear", tau=10.0, seed=seed)
        for method, dt in methods:
            c0 = time.process_time()
            r = chaos.lyapunov(lat, t_end, method=method, dt=dt, stop_when_chaotic=True,
                               n_samples=100)
            cpu = time.process_time() - c0
            t_run = r.t_blowup if r.blew_up else r.t_final
            row = {"N": N, "seed": seed, "t_end": t_end, "method": method, "dt": dt,
                   "class": r.classify(), "t_chaotic": r.t_chaotic, "cpu_s": cpu,
                   "us_per_unit_time": 1e6 * cpu / t_run, "study_note": note}
            rows.append(row)
            print(f"{N:3d} {seed:4d} {t_end:7.0e} {method:>9} {row['class']:>10} "
                  f"{r.t_chaotic:10.4g} {cpu:8.1f} {row['us_per_unit_time']:8.2f}", flush=True)
    agree = {}
    for N, seed, *_ in ORBITS:
        cls = {r["method"]: r["class"] for r in rows if (r["N"], r["seed"]) == (N, seed)}
        agree[f"N{N}_seed{seed}"] = cls
        print(f"N = {N:2d} seed {seed:2d}: " + ", ".join(f"{m} {c}" for m, c in cls.items()) +
              ("" if len(set(cls.values())) == 1 else "   <- methods disagree"))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rows": rows, "classes": agree}, f, indent=2)


if __name__ == "__main__":
    main()
