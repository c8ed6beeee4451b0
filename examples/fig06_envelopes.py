r"""
Fig. 6: the two-mode system and its envelope equations
======================================================

**Equations:** Eq. (msvar), integrated in C with Yoshida 4,

.. math::

   \ddot Q_1 &= -\omega_1^2 Q_1 + \varepsilon (A_1 Q_1^2 + A_2 Q_2^2 + A_3 Q_1 Q_2),\\
   \ddot Q_2 &= -\omega_2^2 Q_2 + \varepsilon (B_1 Q_1^2 + B_2 Q_2^2 + B_3 Q_1 Q_2),

and Eq. (msfinal2) in the slow time :math:`T = \varepsilon t`
(:math:`\varepsilon = \omega_2 - 2\omega_1 < 0`), integrated with RK4:

.. math::

   i \frac{dq_1}{dT} = q_1 + \tilde A \bar q_1 q_2, \qquad
   i \frac{dq_2}{dT} = q_2 + \tilde B q_1^2, \qquad q_1(0) = Q_1(0)/2,\ q_2(0) = 0 .

At leading order :math:`Q_j(t) = 2\,\mathrm{Re}\left(q_j(T) e^{i(\omega_j t + T)}\right)`, so the
envelope of :math:`Q_j` is :math:`2|q_j|`.

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25`, :math:`Q_1(0) = \sqrt{(N+1)/2}`,
:math:`\tau = 0\,\%` and :math:`10\,\%` (seed 578), :math:`t \le 10^5`, :math:`dt = 0.05`
(quick; ``--full``: 0.01).

**Shows:** :math:`Q_1` (blue), :math:`Q_2` (orange, the colour of mode 2 in every figure) and
:math:`\pm 2|q_1|`, :math:`\pm 2|q_2|`
(black): the envelope equations follow the two-mode dynamics; at :math:`\tau = 10\,\%` almost no
energy reaches mode 2 (:math:`\tilde B = 0.051` is small).

**Run:** ``python examples/fig06_envelopes.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(6, __doc__)
