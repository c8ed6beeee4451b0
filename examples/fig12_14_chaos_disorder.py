r"""
Figs. 12–14: chaos in the disordered chain grows with N
=======================================================

**Equations:** paper Eq. varnonlin, fixed ends, :math:`\alpha = 0.25`,

.. math::

   \ddot x_j = (x_{j+1} - 2x_j + x_{j-1})
   + \alpha\left[(v_{j+1}x_{j+1} - v_j x_j)^2 - (v_j x_j - v_{j-1}x_{j-1})^2\right],

and its variational equations (tangent map) for two deviation vectors.

**Parameters:** :math:`N = 4, 8, 16, 32, 64`; 30 disorder realisations (seeds 1…30,
:math:`v_j = 1 + (\tau/300) z_j`, :math:`\tau = 10\,\%`); initial state
:math:`x_j = \sin(\pi j/(N+1))`, :math:`p = 0`; srkn14a6 at :math:`dt = 0.5` (validated against
Yoshida 4 at :math:`dt = 0.01` and DOP853, the paper's method); renormalisation every unit of
time; an orbit stops when SALI :math:`< 10^{-8}` (chaotic) or a bond passes the barrier
:math:`1/\alpha` (blow-up, never counted as chaos).

**Shows:** :math:`\lambda(t)` with the :math:`1/t` law and SALI(t) per realisation (Figs. 12, 13)
and the chaotic and blow-up percentages against :math:`N` (Fig. 14), at the time every orbit has
reached. The study is resumable: the quick default goes to :math:`t = 10^5` (about a minute on
two cores); ``--t-end 1e8`` (or ``--full``) continues the same work directory to the paper's
length (hours; kill and rerun at will).

**Run:** ``python examples/fig12_14_chaos_disorder.py [--out DIR] [--format pdf] [--work-dir D] [--t-end T]``
"""
# sphinx_gallery_thumbnail_path = "figures/fig12_chaos_N4_8_16.png"
import argparse

from fputlab.figures import FORMATS, fig12_13, figure_output

if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="figures")
    p.add_argument("--work-dir", help="study directory (default OUT/chaos_study)")
    p.add_argument("--full", action="store_true", help="continue to t = 1e8")
    p.add_argument("--t-end", type=float, help="how far to go in this call (default 1e5)")
    p.add_argument("--format", choices=FORMATS, default="png", help="png, or pdf/svg for a paper")
    p.add_argument("--dpi", type=float, default=110, help="resolution of PNG output")
    a = p.parse_args()
    with figure_output(a.format, a.dpi):
        for path in fig12_13(a.out, full=a.full, work_dir=a.work_dir, t_until=a.t_end):
            print(path)
