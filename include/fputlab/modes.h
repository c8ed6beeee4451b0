/* fputlab — normal modes of the fixed-end chain.
 *
 * x = A Q, p = A P with A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1)): A is symmetric and orthogonal,
 * A^{-1} = A (a type-I discrete sine transform, computed here by FFT in O(N log N)).
 * omega_k = 2 sin(k pi / (2(N+1))),  E_k = (P_k^2 + omega_k^2 Q_k^2)/2 with P the mode
 * transform of the velocities x' (equal to p for models 1 and 3). */
#ifndef FPUTLAB_MODES_H
#define FPUTLAB_MODES_H

#include "fputlab/common.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

/* omega_k, k = 1..n, into omega[0..n-1]. */
FPL_API int fpl_modes_omega(int n, double *omega);

/* fpl_modes_transform and fpl_modes_energies allocate a temporary FFT workspace per call: for
 * many states prefer fpl_integrator_sample (mode energies from the integrator's workspace). */

/* Q = A x (also x = A Q, since A^{-1} = A). x and q of length N; may alias. */
FPL_API int fpl_modes_transform(const fpl_lattice *lattice, const double *x, double *q);

/* Mode energies E_k, k = 1..N, of the state y (length 2N) into energies[0..N-1]. */
FPL_API int fpl_modes_energies(const fpl_lattice *lattice, const double *y, double *energies);

/* Single-mode initial state (length 2N): x_j = amplitude sin(pi k j/(N+1)), p = 0.
 * Its only non-zero mode coordinate is Q_k = amplitude sqrt((N+1)/2). */
FPL_API int fpl_modes_initial_state(const fpl_lattice *lattice, int k, double amplitude,
                                    double *y);

/* The same mode shape in the variables of the linear coupling, v_j x_j = amplitude sin(...) for
 * model 2 (x_j = amplitude sin(...)/v_j); identical to fpl_modes_initial_state for models 1, 3.
 * For model 2 with disorder, x = sin(...) itself is far from a single normal mode of the
 * disordered chain (at tau = 10% about half its energy sits in high-frequency modes); this
 * state is the smooth one. */
FPL_API int fpl_modes_initial_state_coupled(const fpl_lattice *lattice, int k, double amplitude,
                                            double *y);

#ifdef __cplusplus
}
#endif
#endif
