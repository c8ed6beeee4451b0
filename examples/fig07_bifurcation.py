"""Paper Fig. 7: bifurcation diagram of the reduced system in the (A~, B~) plane.

Equations: with q_1 = r_1 e^{i phi_1}, q_2 = r_2 e^{2 i phi_2}, P = r_1^2 + r_2^2,
Delta = r_1^2 - r_2^2, theta = phi_2 - phi_1 (Eq. reduced):
P' = ((A~-B~)/(A~+B~)) Delta',  Delta' = sqrt(2(P-Delta)) sin(2 theta)(P+Delta)(A~+B~)/2,
theta' = -[2A~cos(2theta)(Delta-P) + B~cos(2theta)(Delta+P) - sqrt(2(P-Delta))]/(2 sqrt(2(P-Delta))),
constant C = P - ((A~-B~)/(A~+B~)) Delta, well defined where P - Delta > 0 and P + Delta >= 0.
Equilibria: Eqs. (theta_1_2, deltaequi), eigenvalues (eigequi), existence 1 + 6A~(A~+B~)C >= 0.
Parameters: the paper's initial state q_1(0) = Q_1(0)/2, q_2(0) = 0, r_1^2 = (N+1)/8 = 8.125.
Shows: regions by the equilibria inside the well-defined region and their type; curves
1 + 12 A~B~r_1^2 = 0 (blue; solid above A~ + B~ = 0, dashed below), 1 - 4 A~B~r_1^2 = 0 (red; Delta_2
turns from centre to saddle, and leaves the well-defined region for B~ > 0) and A~ + B~ = 0 (black
dashed). Right: wider view with the exact E[A~], E[B~] for tau = 0..20 % and the paper's points.
Run: python examples/fig07_bifurcation.py --out DIR   (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(7, __doc__))
