"""Paper Fig. 8: the equilibria Delta_1 and Delta_2 of the reduced system over the (A~, B~) plane.

Equations: Eq. (deltaequi) for the paper's initial state (C (A~+B~) = 2 B~ r_1^2, r_1^2 = (N+1)/8):
Delta_j = (6A~^2C - 3A~B~C - (-1)^j sqrt(1 + 6A~(A~+B~)C) - 1)(A~+B~)/(18 A~^2 B~),
Delta_1 evaluated without the cancellation at small B~ (it tends to r_1^2 as B~ -> 0).
Parameters: N = 64, A~, B~ in [-1, 1].
Shows: (a) Delta_1, (b) tanh(Delta_2/100) (Delta_2 diverges as B~ -> 0); white where no equilibria
exist (1 + 12 A~B~r_1^2 < 0); the curves of Fig. 7.
Run: python examples/fig08_equilibria.py --out DIR   (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(8, __doc__))
