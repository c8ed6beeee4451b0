"""Paper Fig. 9: phase portraits of the reduced system (Eqs. delta3, theta3) in the (theta, Delta) plane.

Equations: Eq. (reduced) in the slow time T with P = C + ((A~-B~)/(A~+B~)) Delta; its orbits are the
level sets of the second invariant I = r_1^2 (1 + 2 A~ r_2 cos 2theta), r_1^2 = (P+Delta)/2,
r_2^2 = (P-Delta)/2 (with C this makes the system integrable).
Parameters: (a) tau = 0 %: (A~, B~) = (3.63, 0.91); (b) tau = 10 %: (4.97, 0.05), as the paper
quotes them; C from q_1(0) = Q_1(0)/2, q_2(0) = 0 (N = 64).
Shows: level sets of I (grey), the flow direction in T (arrows), the well-defined region (white),
the equilibria — (a) (0, 5.0948) and (pi/2, 4.3386), both centres (paper: 5.09, 4.34); (b)
(0, 6.2978), (pi/2, 4.0294) (paper, from the rounded A~, B~: 6.27, 4.08) — and the orbit of the
initial state (blue; computed from Eq. msfinal2, since theta is undefined at q_2 = 0).
Run: python examples/fig09_phase_portraits.py --out DIR   (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(9, __doc__))
