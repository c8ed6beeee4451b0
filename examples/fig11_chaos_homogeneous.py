"""Fig. 11 — the homogeneous chain is regular: mLE ~ 1/t and SALI bounded away from zero.

Equations: paper Eq. eqnmotions with its variational equations dw/dt = Df(x(t)) w, integrated by
the tangent-map method with Yoshida 4 (dt = 0.01). mLE: lambda(t) = (1/t) ln(|w(t)|/|w(0)|)
(Benettin renormalisation every 1 time unit); SALI = min |w1^ -+ w2^|.
Parameters: N = 4, 8, 16, 32, 64, alpha = 0.25, paper initial state; t = 1e5 by default, the
paper's t = 1e8 with --full (about 10 CPU-hours for N = 64).
Run: python examples/fig11_chaos_homogeneous.py [--out DIR] [--full]
"""
import argparse

from fputlab.figures import fig11

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--full", action="store_true")
    a = p.parse_args()
    print(fig11(a.out, full=a.full))
