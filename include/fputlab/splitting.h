/* fputlab — fixed-step symplectic splitting integrators for  x' = p/m,  p' = F(x).
 *
 * A scheme is a constant table of drift (a_i) and kick (b_i) coefficients applied as
 *   drift a_0, kick b_0, drift a_1, ..., kick b_{s-1}, drift a_s
 * (symplectic for the Hamiltonian models 1-2; a consistent order-preserving scheme for model 3,
 * whose equations have the same x'' = F(x) form). Deviation vectors are carried with the
 * tangent map of the same scheme (Skokos & Gerlach 2010): each drift/kick is differentiated
 * exactly, so the deviation vectors are the derivative of the numerical map.
 * Schemes: "leapfrog" (Stormer-Verlet, order 2), "yoshida4" (Yoshida/Forest-Ruth, order 4). */
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
 * NaN/Inf at the end (FPL_ERR_NONFINITE); y is then left as computed. */
FPL_API int fpl_splitting_advance(const fpl_splitting *scheme, fpl_lattice *lattice, double *y,
                                  int n_dev, double dt, long nsteps);

/* Integrate the orbit y0 (length 2N, not modified) from t0 with fixed step dt and sample it at
 * the increasing times t_samples[0..n_samples-1] (each >= t0). The trajectory stays on the grid
 * t0 + n dt (time is n*dt, never accumulated); a sample between grid points is taken by one
 * extra partial step from a copy of the state. Outputs (any may be NULL):
 *   mode_energies  n_samples x N   E_k at each sample (row-major)
 *   energies       n_samples       energy as fpl_lattice_energy
 *   states         n_samples x 2N  the state
 * *n_done receives the number of samples written. If the state becomes non-finite the run stops,
 * returns FPL_ERR_NONFINITE with the time interval in the message, and every sample written
 * before that is finite. */
FPL_API int fpl_splitting_run(const fpl_splitting *scheme, fpl_lattice *lattice, const double *y0,
                              double t0, double dt, const double *t_samples, int n_samples,
                              double *mode_energies, double *energies, double *states,
                              int *n_done);

#ifdef __cplusplus
}
#endif
#endif
