"""Paper Fig. 4: Galerkin truncation of the disordered lattice to its first M normal modes.

Equations: model 3 (Eq. varnonlin), x_j'' = (x_{j+1} - x_j) - (x_j - x_{j-1})
+ alpha (r_j^2 - r_{j-1}^2), r_j = v_{j+1} x_{j+1} - v_j x_j, fixed ends. In modes x = A Q
(A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1))) the truncation keeps Q_1..Q_M (Eq. eqnmfsvarnonlin with
Q_k = 0 for k > M):  Q_k'' = -omega_k^2 Q_k + [A F^(A Q)]_k,  k <= M,  integrated in C with
Yoshida 4 (drift Q += h P, kick P += h Q'').
Parameters: N = 64, alpha = 0.25, M = 2, 4, 8 (columns), tau = 0, 5, 10 % (rows), v = 1 + (tau/300) z
with the z of seed 578 (the realisation whose (A~, B~) at tau = 10 % is closest to the paper's
(4.97, 0.05)), initial state Q_1(0) = sqrt((N+1)/2) (x_j = sin(pi j/(N+1))), t <= 1.5e5,
dt = 0.1 (quick; --full: the paper's dt = 0.01).
Shows: E_k = (P_k^2 + omega_k^2 Q_k^2)/2 for k = 1..4. Two modes already recur (with a shorter
period than the full chain); as tau grows the energy stays in mode 1 (localisation).
Run: python examples/fig04_galerkin.py --out DIR   (about 10 s on 2 cores)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    raise SystemExit(example_main(4, __doc__))
