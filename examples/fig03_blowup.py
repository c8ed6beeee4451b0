"""Fig. 3 — finite-time blow-up above the variability threshold (model 3, tau = 20 % > tau_c).

Equations: paper Eq. varnonlin (see fig02). Parameters: N = 64, alpha = 0.25, tau = 20 %, seed 1,
paper initial state; Yoshida 4 at dt = 0.01; the run stops when a bond passes the cubic barrier
(|x_{j+1} - x_j| > 1/alpha), located by root-finding inside the step.
Shows: E_1..E_4 grow abruptly and the solution blows up (here at t = 2545; the paper's own
realisation near t = 2000).   Run: python examples/fig03_blowup.py [--out DIR] [--seed S]
"""
import argparse

from fputlab.figures import fig3

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    print(fig3(a.out, seed=a.seed))
