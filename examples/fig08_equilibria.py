r"""
Fig. 8: the equilibria of the reduced system over the parameter plane
=====================================================================

**Equations:** Eq. (deltaequi) for the paper's initial state
(:math:`C(\tilde A + \tilde B) = 2\tilde B r_1^2`, :math:`r_1^2 = (N+1)/8`):

.. math::

   \Delta_j = \frac{\left(6\tilde A^2 C - 3\tilde A\tilde B C - (-1)^j
   \sqrt{1 + 6\tilde A(\tilde A + \tilde B) C} - 1\right)(\tilde A + \tilde B)}
   {18\tilde A^2\tilde B},

with :math:`\Delta_1` evaluated without the cancellation at small :math:`\tilde B` (it tends to
:math:`r_1^2` as :math:`\tilde B \to 0`).

**Parameters:** :math:`N = 64`, :math:`\tilde A, \tilde B \in [-1, 1]`.

**Shows:** (a) :math:`\Delta_1`, (b) :math:`\tanh(\Delta_2/100)` (:math:`\Delta_2` diverges as
:math:`\tilde B \to 0`); white where no equilibria exist
(:math:`1 + 12\tilde A\tilde B r_1^2 < 0`); the curves of Fig. 7.

**Run:** ``python examples/fig08_equilibria.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(8, __doc__)
