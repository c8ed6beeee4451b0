"""Figs. 12-14 — chaos in the disordered chain (model 3, tau = 10 %) grows with N.

Equations: paper Eq. varnonlin, x_j'' = (x_{j+1} - 2x_j + x_{j-1})
+ alpha[(v_{j+1}x_{j+1} - v_j x_j)^2 - (v_j x_j - v_{j-1}x_{j-1})^2], alpha = 0.25, fixed ends,
and its variational equations (tangent map) for two deviation vectors.
Parameters: N = 4, 8, 16, 32, 64; 30 disorder realisations (seeds 1..30,
v_j = 1 + (tau/300) z_j); initial state x_j = sin(pi j/(N+1)), p = 0; srkn14a6 at dt = 0.5
(validated against Yoshida 4 at dt = 0.01 and DOP853, the paper's method); renormalisation
every unit of time; an orbit stops when SALI < 1e-8 (chaotic) or a bond passes the barrier
1/alpha (blow-up, never counted as chaos).
Shows: lambda(t) with the 1/t law and SALI(t) per realisation (Figs. 12, 13) and the chaotic
and blow-up percentages vs N (Fig. 14), at the time every orbit has reached.
The study is resumable: the quick default goes to t = 1e5 (about a minute on two cores);
--t-end 1e8 (or --full) continues the same work directory to the paper's length (hours; kill
and rerun at will).
Run: python examples/fig12_14_chaos_disorder.py [--out DIR] [--work-dir D] [--t-end T]
"""
import argparse

from fputlab.figures import fig12_13

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--work-dir", help="study directory (default OUT/chaos_study)")
    p.add_argument("--full", action="store_true", help="continue to t = 1e8")
    p.add_argument("--t-end", type=float, help="how far to go in this call (default 1e5)")
    a = p.parse_args()
    for path in fig12_13(a.out, a.full, work_dir=a.work_dir, t_until=a.t_end):
        print(path)
