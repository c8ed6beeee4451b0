r"""
Fig. 4: Galerkin truncation of the disordered lattice to its first M modes
==========================================================================

**Equations:** model 3 (Eq. varnonlin),
:math:`\ddot x_j = (x_{j+1} - x_j) - (x_j - x_{j-1}) + \alpha (r_j^2 - r_{j-1}^2)`,
:math:`r_j = v_{j+1} x_{j+1} - v_j x_j`, fixed ends. In normal modes :math:`x = A Q`,
:math:`A_{jk} = \sqrt{2/(N+1)} \sin(jk\pi/(N+1))`, the truncation keeps :math:`Q_1 \dots Q_M`
(Eq. eqnmfsvarnonlin with :math:`Q_k = 0` for :math:`k > M`):

.. math::

   \ddot Q_k = -\omega_k^2 Q_k + [A F(A Q)]_k, \qquad k \le M,

integrated in C with Yoshida 4 (drift :math:`Q \mathrel{+}= h P`, kick
:math:`P \mathrel{+}= h \ddot Q`).

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25`, :math:`M = 2, 4, 8` (columns),
:math:`\tau = 0, 5, 10\,\%` (rows), :math:`v = 1 + (\tau/300) z` with the :math:`z` of seed 578
(the realisation whose :math:`(\tilde A, \tilde B)` at :math:`\tau = 10\,\%` is closest to the
paper's :math:`(4.97, 0.05)`), initial state :math:`Q_1(0) = \sqrt{(N+1)/2}`
(:math:`x_j = \sin(\pi j/(N+1))`), :math:`t \le 1.5\times 10^5`, :math:`dt = 0.1` (quick;
``--full``: the paper's :math:`dt = 0.01`).

**Shows:** :math:`E_k = (P_k^2 + \omega_k^2 Q_k^2)/2` for :math:`k = 1 \dots 4`. Two modes
already recur (with a shorter period than the full chain); as :math:`\tau` grows the energy stays
in mode 1 (localisation).

**Run:** ``python examples/fig04_galerkin.py --out DIR [--format pdf]`` (about 10 s on 2 cores)
"""
# sphinx_gallery_thumbnail_path = "figures/fig04_galerkin.png"
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(4, __doc__)
