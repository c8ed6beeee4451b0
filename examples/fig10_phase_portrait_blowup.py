r"""
Fig. 10: phase portrait of the reduced system beyond the threshold
==================================================================

**Equations:** Eq. (reduced) as in Fig. 9, with the paper's
:math:`(\tilde A, \tilde B) = (5.3932, -0.0015)` (the mean fit at
:math:`\tau \approx 10.0833\,\% > \tau_c`) and :math:`C` from :math:`q_1(0) = Q_1(0)/2`,
:math:`q_2(0) = 0` (:math:`N = 64`): the well-defined region is
:math:`\Delta > r_1^2 = 8.125`, unbounded.

**Parameters:** :math:`N = 64`, :math:`\alpha = 0.25`, the values above.

**Shows:** :math:`\Delta_1 = 9.1274` (centre) and :math:`\Delta_2 = 15.4383` (saddle) at
:math:`\theta = \pi/2`, the separatrix through the saddle (orange), and the orbit of the initial
state (blue) starting at the bottom and escaping to :math:`\Delta \to \infty`: the finite-time
blow-up of the envelope equations.

**Run:** ``python examples/fig10_phase_portrait_blowup.py --out DIR [--format pdf]`` (about 1 s)
"""
from fputlab.figures_reduction import example_main

if __name__ == "__main__":
    example_main(10, __doc__)
