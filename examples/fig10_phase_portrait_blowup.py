"""Paper Fig. 10: phase portrait of the reduced system beyond tau_c (B~ < 0).

Equations: Eq. (reduced) as in Fig. 9, with the paper's (A~, B~) = (5.3932, -0.0015) (the mean fit at
tau ~ 10.0833 % > tau_c) and C from q_1(0) = Q_1(0)/2, q_2(0) = 0 (N = 64): the well-defined region is
Delta > r_1^2 = 8.125, unbounded.
Shows: Delta_1 = 9.1274 (centre) and Delta_2 = 15.4383 (saddle) at theta = pi/2, the separatrix
through the saddle (orange), and the orbit of the initial state (blue) starting at the bottom and
escaping to Delta -> infinity: the finite-time blow-up of the envelope equations.
Run: python examples/fig10_phase_portrait_blowup.py --out DIR   (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(10, __doc__))
