/* fputlab — fixed-step symplectic splitting integrators for  x' = p/m,  p' = F(x).
 *
 * A scheme is a constant table of drift (a_i) and kick (b_i) coefficients applied as
 *   drift a_0, kick b_0, drift a_1, ..., kick b_{s-1}, drift a_s
 * (symplectic for the Hamiltonian models 1-2; a consistent order-preserving scheme for model 3,
 * whose equations have the same x'' = F(x) form). Deviation vectors are carried with the
 * tangent map of the same scheme (Skokos & Gerlach 2010): each drift/kick is differentiated
 * exactly, so the deviation vectors are the derivative of the numerical map.
 * Schemes: "leapfrog" (Stormer-Verlet, order 2), "yoshida4" (Yoshida/Forest-Ruth, order 4),
 * "aba864" (Blanes et al. 2013 ABA(8,6,4), order 4, 7 force evaluations), "srkn14a6"
 * (Blanes & Moan 2002 SRKN_14^a, order 6, 14 force evaluations) and "aba864-harmonic" (the
 * ABA(8,6,4) coefficients on the split harmonic chain + anharmonic force: drift = exact flow of
 * the harmonic chain, kick = anharmonic force only; order 4, rising to 6-8 as the nonlinearity
 * shrinks; models 1 and 3 only, FPL_ERR_ARG for model 2).
 * The same registry holds two fixed-step explicit Runge-Kutta-Nystrom methods, "dprkn8" and
 * "dprkn12" (Dormand, El-Mikkawy & Prince 1987, orders 8 and 12, 9 and 17 force evaluations per
 * step): not symplectic, far fewer force evaluations than the compositions at tight accuracy;
 * run on the same drift and kick, so for every model and with their own tangent map. */
#ifndef FPUTLAB_SPLITTING_H
#define FPUTLAB_SPLITTING_H

#include "fputlab/common.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fpl_splitting fpl_splitting;

/* Find a scheme by name; FPL_ERR_UNKNOWN (naming the known schemes) if there is none. */
FPL_API int fpl_splitting_lookup(const char *name, const fpl_splitting **out);
/* Number of schemes and the i-th scheme (0-based), for listings. */
FPL_API int fpl_splitting_count(void);
FPL_API const fpl_splitting *fpl_splitting_at(int index);
FPL_API const char *fpl_splitting_name(const fpl_splitting *scheme);
FPL_API int fpl_splitting_order(const fpl_splitting *scheme);
/* Force evaluations per step. */
FPL_API int fpl_splitting_stages(const fpl_splitting *scheme);

/* Advance y (length 2N(1+n_dev)) in place by nsteps steps of size dt. Checks the state for
 * NaN/Inf at the end (FPL_ERR_NONFINITE); y is then left as computed. Allocates the scheme's
 * workspace once per call (none inside the steps). */
FPL_API int fpl_splitting_advance(const fpl_splitting *scheme, const fpl_lattice *lattice, double *y,
                                  int n_dev, double dt, long nsteps);

/* For sampled runs with any method use fpl_integrator_* (fputlab/integrator.h). */

#ifdef __cplusplus
}
#endif
#endif
