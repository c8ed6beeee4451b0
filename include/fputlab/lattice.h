/* fputlab — the lattice: N particles with fixed ends x_0 = x_{N+1} = 0 or on a ring (the
 * boundary conditions below), one of four models: the paper's three FPUT models and the Toda
 * chain FPL_MODEL_TODA (bond potential V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2), unit
 * masses).
 *
 * With bond potential V(s) = s^2/2 + alpha s^3/3 + beta s^4/4 (FPUT-alpha-beta; beta = 0 in
 * the paper), bond stretches d_j = x_{j+1} - x_j and weighted stretches
 * r_j = v_{j+1} x_{j+1} - v_j x_j (j = 0..N), the models are
 *
 *   FPL_MODEL_HOMOGENEOUS   (paper Eqs. Hamilt, eqnmotions)
 *       x_j'' = V'(d_j) - V'(d_{j-1})                              masses 1
 *   FPL_MODEL_HAMILTONIAN   (paper Eqs. dis1, Hamilt2mod; v in linear and nonlinear couplings)
 *       H = sum p_j^2/(2 v_j) + sum V(r_j);  x_j' = p_j/v_j,  p_j' = v_j [V'(r_j) - V'(r_{j-1})]
 *       so that x_j'' = V'(r_j) - V'(r_{j-1}) exactly as Eq. dis1.
 *   FPL_MODEL_NONLINEAR     (paper Eq. varnonlin; v only in the nonlinear terms, not Hamiltonian)
 *       x_j'' = d_j - d_{j-1} + alpha (r_j^2 - r_{j-1}^2) + beta (r_j^3 - r_{j-1}^3)
 *
 * State layout (everywhere): one contiguous array y = [x_1..x_N, p_1..p_N, dx^(1), dp^(1), ...],
 * length 2N(1 + n_dev) with n_dev deviation vectors sharing the layout of (x, p).
 * p is the canonical momentum: p = x' for models 1 and 3, p = v x' for model 2.
 *
 * A lattice is immutable physics (N, alpha, beta, model, v, fixed at create): every function
 * but create/free only reads it, so one lattice can be shared by several runs and threads.
 * Scratch belongs to the runs (integrators, chaos handles, fpl_system). The evaluation functions
 * below are one-shot conveniences that allocate a temporary workspace per call: not for hot
 * loops (integrate with fpl_integrator, or use the SUNDIALS callbacks with an fpl_system). */
#ifndef FPUTLAB_LATTICE_H
#define FPUTLAB_LATTICE_H

#include "fputlab/common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum fpl_model {
    FPL_MODEL_HOMOGENEOUS = 1,
    FPL_MODEL_HAMILTONIAN = 2,
    FPL_MODEL_NONLINEAR = 3,
    FPL_MODEL_TODA = 4
} fpl_model;

/* Boundary conditions. FIXED: N particles between two walls, N + 1 bonds (x_0 = x_{N+1} = 0 in
 * the paper's 1-based numbering). PERIODIC: a ring of N particles and N bonds, bond b joining
 * particle b-1 and b (0-based) with particle -1 the particle N-1; disorder coefficients are
 * indexed mod N. */
typedef enum fpl_boundary {
    FPL_BOUNDARY_FIXED = 0,
    FPL_BOUNDARY_PERIODIC = 1
} fpl_boundary;

typedef struct fpl_lattice fpl_lattice;

/* Create a lattice. v (length n) is the variability; NULL means v_j = 1 for all j.
 * Errors: n < 2, non-finite alpha/beta, v_j not finite or v_j <= 0 (model 2 uses v_j as a mass),
 * unknown model. */
FPL_API int fpl_lattice_create(int n, double alpha, double beta, int model, const double *v,
                               fpl_lattice **out);
/* The same with a boundary condition (FPL_BOUNDARY_FIXED or FPL_BOUNDARY_PERIODIC);
 * fpl_lattice_create is fpl_lattice_create_ex(..., FPL_BOUNDARY_FIXED, out).
 * FPL_MODEL_TODA refuses beta != 0 and a non-uniform v (the Toda chain is homogeneous). */
FPL_API int fpl_lattice_create_ex(int n, double alpha, double beta, int model, const double *v,
                                  int boundary, fpl_lattice **out);
FPL_API void fpl_lattice_free(fpl_lattice **lattice);

/* A shared, read-only lattice keeps no message of its own: this is fpl_last_error(), the message
 * of the last failing call in this thread ("" if none). */
FPL_API const char *fpl_lattice_errmsg(const fpl_lattice *lattice);

FPL_API int fpl_lattice_size(const fpl_lattice *lattice);
FPL_API double fpl_lattice_alpha(const fpl_lattice *lattice);
FPL_API double fpl_lattice_beta(const fpl_lattice *lattice);
FPL_API int fpl_lattice_model(const fpl_lattice *lattice);
/* FPL_BOUNDARY_FIXED or FPL_BOUNDARY_PERIODIC (-1 for a NULL lattice). */
FPL_API int fpl_lattice_boundary(const fpl_lattice *lattice);
FPL_API const char *fpl_model_name(int model);
/* Copy the variability into v (length n must equal N). */
FPL_API int fpl_lattice_get_v(const fpl_lattice *lattice, double *v, int n);

/* The top of the bond potential's barrier on either side of r = 0: *lower < 0 < *upper are
 * the nearest non-zero roots of V'(r), -INFINITY / INFINITY where there is none. FPUT-alpha-beta:
 * the roots of 1 + alpha r + beta r^2 (beta = 0: -1/alpha; alpha^2 <= 4 beta: none); Toda: none.
 * Past a barrier a bond has left the well around r = 0 (the default blow-up criterion). For
 * models 2 and 3 it is the barrier of V in the weighted stretch r_j (v_j = 1: the plain one). */
FPL_API int fpl_lattice_barrier(const fpl_lattice *lattice, double *lower, double *upper);

/* Force F(x) = p' (length N). */
FPL_API int fpl_lattice_force(const fpl_lattice *lattice, const double *x, double *force);

/* Tridiagonal Jacobian dF/dx at x: lower[j] = dF_{j+1}/dx_j, diag[j] = dF_j/dx_j,
 * upper[j] = dF_j/dx_{j+1} (0-based; lower and upper have N-1 entries). Symmetric for models 1-2.
 * Fixed ends only: a periodic chain's is not tridiagonal (FPL_ERR_ARG; use the dense Jacobian). */
FPL_API int fpl_lattice_force_jacobian(const fpl_lattice *lattice, const double *x, double *lower,
                                       double *diag, double *upper);

/* Tangent force: dforce = (dF/dx)(x) . dx for n_dev vectors dx stored back to back (n_dev*N). */
FPL_API int fpl_lattice_tangent_force(const fpl_lattice *lattice, const double *x, int n_dev,
                                      const double *dx, double *dforce);

/* First-order right-hand side y' = f(y) with n_dev deviation vectors (variational equations):
 * x' = p/m, p' = F(x), dx' = dp/m, dp' = (dF/dx) dx.  y and ydot have length 2N(1+n_dev). */
FPL_API int fpl_lattice_rhs(const fpl_lattice *lattice, const double *y, int n_dev, double *ydot);

/* Dense Jacobian d f / d y of the first-order system with n_dev deviation vectors, row-major,
 * (2N(1+n_dev))^2 entries; includes the second-derivative coupling of deviation vectors to x. */
FPL_API int fpl_lattice_jacobian_dense(const fpl_lattice *lattice, const double *y, int n_dev,
                                       double *jac);

/* Energy of the state (length 2N). Models 1-2: the Hamiltonian (conserved). Model 3: the
 * energy of Eq. (Hamilt), 1/2 sum p^2 + sum V(d_j), a diagnostic that is not conserved. */
FPL_API int fpl_lattice_energy(const fpl_lattice *lattice, const double *y, double *energy);

/* Velocities x' = p/m (length N) from the state (length 2N). */
FPL_API int fpl_lattice_velocity(const fpl_lattice *lattice, const double *y, double *xdot);

/* Check that every entry of y (length len) is finite; FPL_ERR_NONFINITE names the first bad index. */
FPL_API int fpl_state_check_finite(const double *y, long len);

#ifdef __cplusplus
}
#endif
#endif
