"""Paper Fig. 6: the two-mode system and its envelope equations.

Equations: Eq. (msvar)  Q_1'' = -omega_1^2 Q_1 + eps (A_1 Q_1^2 + A_2 Q_2^2 + A_3 Q_1 Q_2),
Q_2'' = -omega_2^2 Q_2 + eps (B_1 Q_1^2 + B_2 Q_2^2 + B_3 Q_1 Q_2)  (integrated in C, Yoshida 4), and
Eq. (msfinal2) in the slow time T = eps t (eps = omega_2 - 2 omega_1 < 0):
i dq_1/dT = q_1 + A~ conj(q_1) q_2,  i dq_2/dT = q_2 + B~ q_1^2,  q_1(0) = Q_1(0)/2, q_2(0) = 0
(RK4). At leading order Q_j(t) = 2 Re(q_j(T) exp(i(omega_j t + T))), so the envelope of Q_j is 2|q_j|.
Parameters: N = 64, alpha = 0.25, Q_1(0) = sqrt((N+1)/2), tau = 0 % and 10 % (seed 578),
t <= 1e5, dt = 0.05 (quick; --full: 0.01).
Shows: Q_1 (blue), Q_2 (red) and +-2|q_1|, +-2|q_2| (black): the envelope equations follow the
two-mode dynamics; at tau = 10 % almost no energy reaches mode 2 (B~ = 0.051 is small).
Run: python examples/fig06_envelopes.py --out DIR   (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(6, __doc__))
