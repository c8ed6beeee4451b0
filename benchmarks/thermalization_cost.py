"""Projected cost of the thermalization studies (docs/thermalization.md) from the measured CPU
time per step.

Measured here: the process (CPU) time per unit of simulated time of one orbit of each built-in
study, through the study kind's own task (`run_study("thermalization", ...)`: random-phase
state, the study's method and dt, the windowed samples), so the projection charges what a study
really pays. Projected: the cost
of a point eps with T_eq(eps) = C eps^-a, run by the driver to the first segment end past
2 T_eq (about where 95 % of the bootstrap ensembles have crossed), for `orbits` orbits on one
core. C and a come from a finished study directory (--study DIR: its fit) or the command line.

Usage:
  python benchmarks/thermalization_cost.py                       # CPU cost per unit time
  python benchmarks/thermalization_cost.py --study DIR --eps 0.05 0.04 0.03
  python benchmarks/thermalization_cost.py --law 5.2e4 8 --at 0.1 --eps 0.05 0.04
"""
import argparse
import math
import time
from dataclasses import replace

from fputlab.thermalization_study import (STUDIES, THERMALIZATION_KIND, ThermalizationStudy,
                                          projected_cost)


def cpu_per_unit(spec, t_run: float) -> float:
    """CPU seconds per unit of simulated time of one orbit of `spec` (0 to t_run), the kind's
    task run in this process (the engine would run it in a worker)."""
    grid, settings = THERMALIZATION_KIND.normalise({"eps": [spec.eps[0]], "orbit": [0, 1]},
                                                   spec.settings(0))

    def one(orbit):
        THERMALIZATION_KIND.run(settings, [{"eps": grid["eps"][0], "orbit": orbit}], [None],
                                t_run)
    one(0)                                              # warm-up (imports, first-call costs)
    c0 = time.process_time()
    one(1)
    return (time.process_time() - c0) / t_run


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--studies", nargs="+", default=["alpha", "beta", "toda",
                                                    "disorder-nonlinear-10",
                                                    "disorder-hamiltonian-10"])
    p.add_argument("--t-run", type=float, default=2e4)
    p.add_argument("--study", help="a finished study directory: project with its fit")
    p.add_argument("--law", type=float, nargs=2, metavar=("T_AT", "A"),
                   help="T_eq = T_AT (eps/AT)^-A")
    p.add_argument("--at", type=float, default=0.1)
    p.add_argument("--eps", type=float, nargs="+", default=[])
    a = p.parse_args()
    per = {}
    for name in a.studies:
        per[name] = cpu_per_unit(STUDIES[name], a.t_run)
        print(f"{name:>24}: {1e6 * per[name]:6.2f} us CPU per unit time per orbit "
              f"({STUDIES[name].method}, dt = {STUDIES[name].dt:g}, N = {STUDIES[name].N})")
    law = None
    if a.study:
        st = ThermalizationStudy(a.study)
        fit = st.results()["fit"]
        spec = st.spec
        law = (fit["prefactor"], fit["exponent"])
    elif a.law:
        spec = STUDIES["alpha"]
        law = (a.law[0] * a.at ** a.law[1], a.law[1])
    if law and a.eps:
        C, A = law
        sec_per_step = per.get(spec.label, per[a.studies[0]]) * spec.dt
        spec = replace(spec, eps=tuple(a.eps), t_max=max(spec.t_max, 4 * C * min(a.eps) ** -A))
        teq = {e: C * e ** -A for e in a.eps}
        cost = projected_cost(spec, sec_per_step, teq)
        print(f"projection with T_eq = {C:.3g} eps^-{A:.2f}, {spec.orbits} orbits, one core:")
        for e in a.eps:
            print(f"  eps = {e:<6g} T_eq ~ {teq[e]:.2e}  cost ~ {cost[e] / 3600:8.2f} core-hours")


if __name__ == "__main__":
    main()
