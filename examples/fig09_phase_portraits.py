r"""
Fig. 9: phase portraits of the reduced system
=============================================

**Equations:** Eq. (reduced) (Eqs. delta3, theta3) in the slow time :math:`T`, in the
:math:`(\theta, \Delta)` plane, with
:math:`P = C + \frac{\tilde A - \tilde B}{\tilde A + \tilde B}\Delta`; its orbits are the level
sets of the second invariant

.. math::

   I = r_1^2 \left(1 + 2\tilde A r_2 \cos 2\theta\right), \qquad
   r_1^2 = \frac{P + \Delta}{2},\quad r_2^2 = \frac{P - \Delta}{2}

(with :math:`C` this makes the system integrable).

**Parameters:** (a) :math:`\tau = 0\,\%`: :math:`(\tilde A, \tilde B) = (3.63, 0.91)`;
(b) :math:`\tau = 10\,\%`: :math:`(4.97, 0.05)`, as the paper quotes them; :math:`C` from
:math:`q_1(0) = Q_1(0)/2`, :math:`q_2(0) = 0` (:math:`N = 64`).

**Shows:** level sets of :math:`I` (grey), the flow direction in :math:`T` (arrows), the
well-defined region (white), the equilibria — (a) :math:`(0, 5.0948)` and
:math:`(\pi/2, 4.3386)`, both centres (paper: 5.09, 4.34); (b) :math:`(0, 6.2978)`,
:math:`(\pi/2, 4.0294)` (paper, from the rounded :math:`\tilde A, \tilde B`: 6.27, 4.08) — and the
orbit of the initial state (blue; computed from Eq. msfinal2, since :math:`\theta` is undefined at
:math:`q_2 = 0`).

**Run:** ``python examples/fig09_phase_portraits.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(9, __doc__)
