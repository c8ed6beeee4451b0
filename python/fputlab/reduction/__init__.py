"""Reduction of the FPUT lattice to a few normal modes (paper Sec. 4).

Pieces, in the order of the paper, one module each (every name is importable from here):

* `Galerkin` (`fputlab.reduction.modal`): the lattice truncated to its first M normal modes
  (Eq. eqnmfsvarnonlin with Q_k = 0 for k > M), integrated in C with the splitting schemes
  (paper Fig. 4).
* `two_mode_coefficients` (`fputlab.reduction.coefficients`): the raw coefficients a_i, b_i of
  the two-mode system (Eq. msvar), alpha included, as closed sums; the paper's A_i = a_i/eps,
  B_i = b_i/eps with eps = omega_2 - 2 omega_1 < 0, and A~ = A_3/(2 omega_1),
  B~ = B_1/(2 omega_2).
* `coefficient_moments`, `realisation_quadratics`, `ensemble_statistics`, `critical_tolerance`
  (`fputlab.reduction.statistics`): A~, B~ over the disorder v = 1 + (tau/300) z (Fig. 5): the
  exact expectation and variance in closed form (the coefficients are quadratic forms in v),
  sample statistics over R realisations, and tau_c (B~ = 0) three ways.
* `two_mode_run` (Eq. msvar, in C; `fputlab.reduction.modal`) and `envelope_run` (Eq. msfinal2;
  `fputlab.reduction.envelope`) with q_1(0) = Q_1(0)/2, q_2(0) = 0;
  Q_j(t) ~ 2 Re(q_j(T) exp(i(omega_j t + T))), T = eps t (Fig. 6).
* `ReducedSystem` (`fputlab.reduction.reduced`): the (P, Delta, theta) system (Eq. reduced),
  its constant C, well-defined region, equilibria (Eqs. theta_1_2, deltaequi), eigenvalues
  (eigequi) and their type; `equilibrium_map`, `bifurcation_curves`, `classify` for Figs. 7-8;
  phase portraits (Figs. 9-10) in `fputlab.figures_reduction`.

Only numpy is needed here (no scipy): the slow envelope equations are integrated with a fixed-step
RK4 in the slow time."""
from __future__ import annotations

from .coefficients import (COEFFICIENT_NAMES, frequencies, detuning, r1_squared,
                           TwoModeCoefficients, two_mode_coefficients, quadratic_forms)
from .statistics import (CoefficientMoments, coefficient_moments, RealisationQuadratics,
                         realisation_quadratics, EnsembleStatistics, ensemble_statistics,
                         quadratic_fit, CriticalTolerance, critical_tolerance)
from .modal import ModalRun, two_mode_run, Galerkin
from .envelope import envelope_rhs, EnvelopeRun, ENVELOPE_MAX_STEPS, envelope_run, envelope_error
from .reduced import (to_reduced, Equilibrium, ReducedSystem, equilibrium_map, bifurcation_curves,
                      REGIONS, classify)

__all__ = ["COEFFICIENT_NAMES", "frequencies", "detuning", "r1_squared", "TwoModeCoefficients",
           "two_mode_coefficients", "quadratic_forms", "CoefficientMoments",
           "coefficient_moments", "RealisationQuadratics", "realisation_quadratics",
           "EnsembleStatistics", "ensemble_statistics", "quadratic_fit", "CriticalTolerance",
           "critical_tolerance", "ModalRun", "two_mode_run", "Galerkin", "envelope_rhs",
           "EnvelopeRun", "ENVELOPE_MAX_STEPS", "envelope_run", "envelope_error", "to_reduced",
           "Equilibrium", "ReducedSystem", "equilibrium_map", "bifurcation_curves", "REGIONS",
           "classify"]
