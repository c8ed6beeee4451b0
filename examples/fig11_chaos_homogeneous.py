r"""
Fig. 11: the homogeneous chain is regular
=========================================

**Equations:** paper Eq. eqnmotions with its variational equations
:math:`\dot w = Df(x(t))\, w`, integrated by the tangent-map method with Yoshida 4
(:math:`dt = 0.01`). The maximum Lyapunov exponent and the smaller alignment index are

.. math::

   \lambda(t) = \frac{1}{t} \ln\frac{\|w(t)\|}{\|w(0)\|}, \qquad
   \mathrm{SALI}(t) = \min\left(\|\hat w_1 + \hat w_2\|, \|\hat w_1 - \hat w_2\|\right),

with Benettin's renormalisation every unit of time.

**Parameters:** :math:`N = 4, 8, 16, 32, 64`, :math:`\alpha = 0.25`, the paper's initial state;
:math:`t = 10^5` by default, the paper's :math:`t = 10^8` with ``--full`` (about 10 CPU-hours for
:math:`N = 64`).

**Shows:** every orbit is regular: :math:`\lambda \sim 1/t` and SALI bounded away from zero.

**Run:** ``python examples/fig11_chaos_homogeneous.py [--out DIR] [--format pdf] [--full]``
"""
# sphinx_gallery_thumbnail_path = "figures/fig11_chaos_homogeneous.png"
import argparse

from fputlab.figures import FORMATS, fig11, figure_output

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--full", action="store_true")
    p.add_argument("--format", choices=FORMATS, default="png", help="png, or pdf/svg for a paper")
    p.add_argument("--dpi", type=float, default=110, help="resolution of PNG output")
    a = p.parse_args()
    with figure_output(a.format, a.dpi):
        print(fig11(a.out, full=a.full))
