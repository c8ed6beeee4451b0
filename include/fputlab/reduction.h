/* fputlab — reduction to a few normal modes (paper Sec. 4): Galerkin truncation, the two-mode
 * coefficients of Eq. (msvar) with their exact moments over the disorder, and the two-mode ODE.
 *
 * Normal modes as in <fputlab/modes.h>: x = A Q, A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1)),
 * omega_k = 2 sin(k pi/(2(N+1))), E_k = (P_k^2 + omega_k^2 Q_k^2)/2 with P = Q' (velocities).
 *
 * Galerkin truncation to the first M modes (paper Eq. eqnmfsvarnonlin with Q_k = 0 for k > M):
 *     Q_k'' = [A a(A Q)]_k,  k = 1..M,
 * where a(x) = x'' is the full acceleration of the lattice model (linear + nonlinear, beta
 * included). For models 1 and 3 the linear part of a is diagonal in the sine modes, so this is
 * exactly  Q_k'' = -omega_k^2 Q_k + [A F^(A Q)]_k  with F^ the nonlinear force. For model 2 the
 * linear part  (v_{j+1}x_{j+1} - v_j x_j) - (v_j x_j - v_{j-1}x_{j-1})  is not diagonal: the
 * truncation is still the projection of x'' (Eq. dis1) onto the first M modes, so its linear part
 * couples the kept modes, and it is not the Galerkin truncation of the Hamiltonian (which would
 * carry the projected mass matrix). With M = N every model is the full lattice in mode
 * coordinates. Integrated with the splitting tables of <fputlab/splitting.h>:
 * drift Q += h P, kick P += h Q''(Q).
 *
 * Two-mode coefficients (paper Eq. msvar): keeping Q_1, Q_2 only, the quadratic part of the
 * projected acceleration is
 *     mode 1:  a_1 Q_1^2 + a_2 Q_2^2 + a_3 Q_1 Q_2,     mode 2:  b_1 Q_1^2 + b_2 Q_2^2 + b_3 Q_1 Q_2
 * (the "raw" coefficients, alpha included). With r_j = v_{j+1} X_{j+1} - v_j X_j (v = 1 for model 1)
 * and D_jk = A_{j+1,k} - A_{j,k} (A_{0k} = A_{N+1,k} = 0), summation by parts gives the closed sums
 *     coefficient of Q_l Q_m in mode k = -alpha (2 - delta_lm) sum_{j=0}^{N} D_jk rho_jl rho_jm,
 *     rho_jl = v_{j+1} A_{j+1,l} - v_j A_{j,l}.
 * Models 2 and 3 have the same quadratic part; beta only adds cubic terms, which Eq. (msvar) does
 * not have. The paper's coefficients are A_i = a_i/eps, B_i = b_i/eps with eps = omega_2 - 2 omega_1
 * (< 0), and A~ = A_3/(2 omega_1), B~ = B_1/(2 omega_2). Eq. (msvar) itself assumes a diagonal
 * linear part, i.e. models 1 and 3.
 *
 * Each raw coefficient is a quadratic form c = v^T M v with M symmetric tridiagonal (models 2, 3).
 * For v = 1 + s z with z_j i.i.d., symmetric, E z^2 = m2, E z^4 = m4 this gives, exactly,
 *     E c = 1^T M 1 + s^2 m2 tr M,
 *     Cov(c, c') = 4 s^2 m2 (M1).(M'1) + s^4 [2 m2^2 tr(M M') + (m4 - 3 m2^2) sum_i M_ii M'_ii].
 * The coefficient order everywhere is (a_1, a_2, a_3, b_1, b_2, b_3). */
#ifndef FPUTLAB_REDUCTION_H
#define FPUTLAB_REDUCTION_H

#include "fputlab/common.h"
#include "fputlab/lattice.h"
#include "fputlab/splitting.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Raw two-mode coefficients a[3], b[3] of an N-particle chain of the given model with
 * variability v (length n; ignored for model 1; NULL means v_j = 1). Errors: n < 2, alpha not
 * finite, unknown model, v_j not finite or <= 0. */
FPL_API int fpl_reduction_coefficients(int n, double alpha, int model, const double *v, double *a,
                                       double *b);

/* Paper normalisation: a_paper = a/eps, b_paper = b/eps (the A_i, B_i), and
 * *a_tilde = A_3/(2 omega_1), *b_tilde = B_1/(2 omega_2). Any output may be NULL. */
FPL_API int fpl_reduction_normalise(int n, const double *a, const double *b, double *a_paper,
                                    double *b_paper, double *a_tilde, double *b_tilde);

/* The tridiagonal quadratic forms c = v^T M v of the six raw coefficients (models 2 and 3):
 * diag (6 x n, row-major: M_ii of coefficient c in diag[c*n + i]) and off (6 x (n-1): M_{i,i+1}). */
FPL_API int fpl_reduction_quadratic_forms(int n, double alpha, double *diag, double *off);

/* Exact mean[6] and covariance cov[6 x 6] (row-major) of the raw coefficients over the disorder
 * of the given kind at tolerance tau (percent), as drawn by fpl_disorder_draw: Gaussian
 * (s = tau/300, m2 = 1, m4 = 3), truncated Gaussian (|z| <= 3; its m2, m4) or uniform
 * (s = tau/100, m2 = 1/3, m4 = 1/5). Model 1 has no disorder: cov = 0. cov may be NULL. */
FPL_API int fpl_reduction_moments(int n, double alpha, int model, int kind, double tau,
                                  double *mean, double *cov);

/* Integrate the two-mode ODE (paper Eq. msvar with eps A_i = a_i, eps B_i = b_i)
 *     Q_1'' = -omega_1^2 Q_1 + a_1 Q_1^2 + a_2 Q_2^2 + a_3 Q_1 Q_2,
 *     Q_2'' = -omega_2^2 Q_2 + b_1 Q_1^2 + b_2 Q_2^2 + b_3 Q_1 Q_2
 * from z0 = (Q_1, Q_2, P_1, P_2) at t0 with fixed step dt of the splitting scheme, sampling
 * states (n_samples x 4, row-major) at the non-decreasing times t_samples (>= t0; off-grid samples
 * by one partial step from a copy, as fpl_splitting_run). omega[2], a[3], b[3] are free
 * parameters. FPL_ERR_NONFINITE (with the time interval) if the solution blows up; *n_done
 * receives the number of samples written (all finite). */
FPL_API int fpl_reduction_two_mode_run(const fpl_splitting *scheme, const double *omega,
                                       const double *a, const double *b, const double *z0,
                                       double t0, double dt, const double *t_samples,
                                       int n_samples, double *states, int *n_done);

/* Galerkin truncation of a lattice to its first M normal modes (see above). The handle keeps its
 * own copy of the lattice and scratch space: use one handle per thread. */
typedef struct fpl_galerkin fpl_galerkin;

/* Errors: NULL lattice, m < 1 or m > N. */
FPL_API int fpl_galerkin_create(const fpl_lattice *lattice, int m, fpl_galerkin **out);
FPL_API void fpl_galerkin_free(fpl_galerkin **galerkin);
/* Message of the last failing call on this handle ("" if none). */
FPL_API const char *fpl_galerkin_errmsg(const fpl_galerkin *galerkin);
FPL_API int fpl_galerkin_modes(const fpl_galerkin *galerkin);
FPL_API int fpl_galerkin_size(const fpl_galerkin *galerkin);

/* Truncated acceleration Q'' (length M) at Q (length M). */
FPL_API int fpl_galerkin_acceleration(fpl_galerkin *galerkin, const double *q, double *qddot);

/* Advance z = (Q_1..Q_M, P_1..P_M) in place by nsteps steps of size dt. */
FPL_API int fpl_galerkin_advance(const fpl_splitting *scheme, fpl_galerkin *galerkin, double *z,
                                 double dt, long nsteps);

/* As fpl_splitting_run for the truncated system: z0 (length 2M) from t0, samples at t_samples.
 * Outputs (either may be NULL): mode_energies (n_samples x M, E_k of the kept modes) and states
 * (n_samples x 2M). */
FPL_API int fpl_galerkin_run(const fpl_splitting *scheme, fpl_galerkin *galerkin,
                             const double *z0, double t0, double dt, const double *t_samples,
                             int n_samples, double *mode_energies, double *states, int *n_done);

#ifdef __cplusplus
}
#endif
#endif
