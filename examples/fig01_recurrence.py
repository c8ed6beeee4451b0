"""Fig. 1 — FPUT recurrence of the homogeneous FPUT-alpha chain.

Equations (paper Eqs. Hamilt, eqnmotions), fixed ends x_0 = x_{N+1} = 0:
    x_j'' = (x_{j+1} - x_j) + alpha (x_{j+1} - x_j)^2 - (x_j - x_{j-1}) - alpha (x_j - x_{j-1})^2
Parameters: N = 64, alpha = 0.25, x_j(0) = sin(pi j/(N+1)), p = 0 (E = 0.03795); Yoshida 4, dt = 0.01.
Shows: (a) the envelope of x_j(t); (b) E_1..E_4 — almost all energy returns to mode 1 near
t = 5.6e4.   Run: python examples/fig01_recurrence.py [--out DIR] [--full]
"""
import argparse

from fputlab.figures import fig1

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--full", action="store_true")
    a = p.parse_args()
    print(fig1(a.out, full=a.full))
