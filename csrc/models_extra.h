/* Private: the kernels of the periodic chains (models_periodic.c), the Toda lattice
 * (model_toda.c) and the generic kernels for any model and boundary (models_any.c), for the
 * model tables of models.c and models_periodic.c. Not installed. */
#ifndef FPUTLAB_MODELS_EXTRA_H
#define FPUTLAB_MODELS_EXTRA_H

#include <math.h>
#include "internal.h"

/* The Toda bond: V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2), V'(r) = expm1(2 alpha r)/(2
 * alpha), V''(r) = e^{2 alpha r}, expm1 being fpl_expm1 (fpl_expm1.h) on every path. */
/* V(r), with its Taylor series for |2 alpha r| < 0.1, where expm1(u) - u cancels. */
double fpl_toda_bond_energy(double r, double alpha);

/* models_any.c: generic (non-hot) kernels for every model and boundary: the fixed or periodic
 * bond stretches, the polynomial or Toda bond force. */
void fpl_any_force(const fpl_lattice *lat, fpl_work *work, const double *x, double *f);
void fpl_any_tangent(const fpl_lattice *lat, fpl_work *work, const double *x, int n_dev,
                     const double *dx, double *df);
void fpl_any_jacobian_entries(const fpl_lattice *lat, const double *y, int n_dev,
                              void (*emit)(void *ctx, long row, long col, double value),
                              void *ctx);
/* The Hamiltonian (bond potential in the stretches R of cn; models 1, 2, Toda) and the energy of
 * Eq. (Hamilt) of model 3 (stretches of cl = the plain stretches). */
double fpl_any_energy_hamiltonian(const fpl_lattice *lat, const double *y);
double fpl_any_energy_plain(const fpl_lattice *lat, const double *y);

/* models_periodic.c: the drifts (shared with the Toda entries) and the periodic model table. */
void fpl_drift_unit_mass(void *ctx, double *y, int stage, double h);
void fpl_drift_masses(void *ctx, double *y, int stage, double h);
const fpl_model_ops *fpl_model_ops_periodic(int model);
/* models_periodic.c: the bond-array ring kick of models 2 and 3 (any N >= 2). */
void fpl_kick_generic_periodic(void *ctx, double *y, double h);
/* models.c: the fused ring kicks and steppers of models 2 and 3 (N >= 3; shorter rings go to
 * fpl_kick_generic_periodic). */
void fpl_kick_ring_hamiltonian(void *ctx, double *y, double h);
void fpl_kick_ring_nonlinear(void *ctx, double *y, double h);
void fpl_steps_ring_hamiltonian(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                                long nsteps);
void fpl_steps_ring_nonlinear(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                              long nsteps);
/* models.c: the homogeneous ring's fused stages and many-vector steps (returns 0, nothing done,
 * where they do not apply: N < 3, more than 2 vectors beyond the many-vector steps' reach). */
int fpl_steps_ring_homogeneous_fused(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                                     long nsteps);

/* model_toda.c: coefficients (all 1) and the kicks, p += h F(x), dp += h J(x) dx. */
void fpl_toda_coefficients(double v, double *cl, double *cn, double *s, double *minv);
void fpl_toda_kick_fixed(void *ctx, double *y, double h);
void fpl_toda_kick_periodic(void *ctx, double *y, double h);
/* The fused steppers (fpl_split_system.steps): n steps, bit-identical to the kicks above. */
void fpl_toda_steps_fixed(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                          long nsteps);
void fpl_toda_steps_periodic(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                             long nsteps);

#endif
