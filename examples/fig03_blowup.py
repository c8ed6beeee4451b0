r"""
Fig. 3: finite-time blow-up above the variability threshold
===========================================================

**Equations:** paper Eq. varnonlin (model 3, see Fig. 2).

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25`, :math:`\tau = 20\,\% > \tau_c`, disorder
seed 1, the paper's initial state; Yoshida 4 at :math:`dt = 0.01`. The run stops when a bond
passes the cubic barrier, :math:`|x_{j+1} - x_j| > 1/\alpha`, located by root-finding inside the
step.

**Shows:** :math:`E_1 \dots E_4` grow abruptly and the solution blows up (here at
:math:`t = 2545`; the paper's own realisation near :math:`t = 2000`).

**Run:** ``python examples/fig03_blowup.py [--out DIR] [--format pdf] [--seed S]``
"""
import argparse

from fputlab.figures import FORMATS, fig3, figure_output

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--format", choices=FORMATS, default="png", help="png, or pdf/svg for a paper")
    p.add_argument("--dpi", type=float, default=110, help="resolution of PNG output")
    a = p.parse_args()
    with figure_output(a.format, a.dpi):
        print(fig3(a.out, seed=a.seed))
