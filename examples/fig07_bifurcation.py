r"""
Fig. 7: bifurcation diagram of the reduced system
=================================================

**Equations:** with :math:`q_1 = r_1 e^{i\phi_1}`, :math:`q_2 = r_2 e^{2i\phi_2}`,
:math:`P = r_1^2 + r_2^2`, :math:`\Delta = r_1^2 - r_2^2`, :math:`\theta = \phi_2 - \phi_1`
(Eq. reduced):

.. math::

   P' &= \frac{\tilde A - \tilde B}{\tilde A + \tilde B} \Delta', \qquad
   \Delta' = \sqrt{2(P - \Delta)}\, \sin 2\theta\, (P + \Delta) \frac{\tilde A + \tilde B}{2},\\
   \theta' &= -\frac{2\tilde A \cos 2\theta\, (\Delta - P) + \tilde B \cos 2\theta\, (\Delta + P)
   - \sqrt{2(P - \Delta)}}{2\sqrt{2(P - \Delta)}},

with the constant :math:`C = P - \frac{\tilde A - \tilde B}{\tilde A + \tilde B}\Delta`, well
defined where :math:`P - \Delta > 0` and :math:`P + \Delta \ge 0`. Equilibria: Eqs.
(theta_1_2, deltaequi); eigenvalues (eigequi); they exist where
:math:`1 + 6\tilde A(\tilde A + \tilde B) C \ge 0`.

**Parameters:** the paper's initial state :math:`q_1(0) = Q_1(0)/2`, :math:`q_2(0) = 0`,
:math:`r_1^2 = (N+1)/8 = 8.125`.

**Shows:** the regions by the equilibria inside the well-defined region and their type; the
curves :math:`1 + 12\tilde A\tilde B r_1^2 = 0` (blue; solid above :math:`\tilde A + \tilde B = 0`,
dashed below), :math:`1 - 4\tilde A\tilde B r_1^2 = 0` (red; :math:`\Delta_2` turns from centre to
saddle, and leaves the well-defined region for :math:`\tilde B > 0`) and
:math:`\tilde A + \tilde B = 0` (black dashed). Right: a wider view with the exact
:math:`E[\tilde A]`, :math:`E[\tilde B]` for :math:`\tau = 0 \dots 20\,\%` and the paper's
points.

**Run:** ``python examples/fig07_bifurcation.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(7, __doc__)
