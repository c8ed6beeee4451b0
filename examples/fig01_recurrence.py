r"""
Fig. 1: FPUT recurrence in the homogeneous chain
================================================

**Equations** (paper Eqs. Hamilt, eqnmotions), fixed ends :math:`x_0 = x_{N+1} = 0`:

.. math::

   \ddot x_j = (x_{j+1} - x_j) + \alpha (x_{j+1} - x_j)^2 - (x_j - x_{j-1}) - \alpha (x_j - x_{j-1})^2 .

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25`, :math:`x_j(0) = \sin(\pi j/(N+1))`,
:math:`p = 0` (:math:`E = 0.03795`); Yoshida 4 at :math:`dt = 0.01`.

**Shows:** (a) the envelope of :math:`x_j(t)`; (b) the mode energies :math:`E_1 \dots E_4`:
almost all the energy returns to mode 1 near :math:`t = 5.6\times 10^4`.

**Run:** ``python examples/fig01_recurrence.py [--out DIR] [--format pdf] [--full]``
"""
import argparse

from fputlab.figures import FORMATS, fig1, figure_output

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--full", action="store_true")
    p.add_argument("--format", choices=FORMATS, default="png", help="png, or pdf/svg for a paper")
    p.add_argument("--dpi", type=float, default=110, help="resolution of PNG output")
    a = p.parse_args()
    with figure_output(a.format, a.dpi):
        print(fig1(a.out, full=a.full))
