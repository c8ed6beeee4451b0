"""Figs. 12-14 — chaos in the disordered chain (model 3, tau = 10 %) grows with N.

Equations: paper Eq. varnonlin and its variational equations. For each N = 4, 8, 16, 32, 64 and
30 disorder realisations (seeds 1..30, v_j = 1 + (tau/300) z_j): lambda(t) and SALI(t)
(Figs. 12, 13) and the percentage of orbits with SALI < 1e-8 (Fig. 14).
Parameters: quick default t = 2e4 with the tangent map (Yoshida 4, dt = 0.01); the paper used
DOP853 on the variational equations to t = 1e8: --method dop853 --full.
Run: python examples/fig12_14_chaos_disorder.py [--out DIR] [--t-end T] [--realisations R]
"""
import argparse

from fputlab.figures import fig12_13

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--full", action="store_true")
    p.add_argument("--t-end", type=float, default=2e4)
    p.add_argument("--realisations", type=int, default=30)
    p.add_argument("--method", default="yoshida4")
    a = p.parse_args()
    for path in fig12_13(a.out, a.full, realisations=a.realisations, t_end=a.t_end, method=a.method):
        print(path)
