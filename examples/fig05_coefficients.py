r"""
Fig. 5: the two-mode coefficients against the tolerance
=======================================================

**Equations:** keeping :math:`Q_1, Q_2` only (Eq. msvar), the quadratic part of the projected
force is :math:`a_1 Q_1^2 + a_2 Q_2^2 + a_3 Q_1 Q_2` (mode 1) and
:math:`b_1 Q_1^2 + b_2 Q_2^2 + b_3 Q_1 Q_2` (mode 2), computed as closed sums over the bonds;
:math:`A_i = a_i/\varepsilon`, :math:`B_i = b_i/\varepsilon` with
:math:`\varepsilon = \omega_2 - 2\omega_1`, and

.. math::

   \tilde A = \frac{A_3}{2\omega_1}, \qquad \tilde B = \frac{B_1}{2\omega_2}.

With :math:`v = 1 + (\tau/300) z` every coefficient is a quadratic form in :math:`v`, so
:math:`E[\tilde A]`, :math:`E[\tilde B]` and their variances are exact closed forms
(:math:`E z^2 = 1`, :math:`E z^4 = 3`) and each realisation is an exact quadratic in
:math:`\tau`.

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25` (model 3), :math:`R = 100` realisations
(seeds 1…100), :math:`\tau = 0 \dots 20\,\%`.

**Shows:** (a) :math:`\tilde A`, (b) :math:`\tilde B`: the mean over the realisations
(dash-dotted) with ±1 sd bands (band length two sd, as the paper), its quadratic fit (the paper's
regression), the exact expectation ±1 sd (black), :math:`\tilde B = 0` (dashed) and
:math:`\tau_c`: exact 10.2578 %, :math:`R = 100` fit 10.2036 % (paper 10.0749 %, a different set
of 100 draws). :math:`\tilde A(0) = 3.62805`, :math:`\tilde B(0) = 0.90728`.

**Run:** ``python examples/fig05_coefficients.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(5, __doc__)
