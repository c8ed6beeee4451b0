/* fputlab — normal modes.
 *
 * Fixed ends: x = A Q, p = A P with A_jk = sqrt(2/(N+1)) sin(jk pi/(N+1)) (j, k = 1..N): A is
 * symmetric and orthogonal, A^{-1} = A (a type-I discrete sine transform).
 * omega_k = 2 sin(k pi / (2(N+1))); arrays hold mode k at index k-1.
 * Periodic: the Fourier modes as real standing waves, the orthonormal discrete Hartley transform
 * A_jk = N^{-1/2} cas(2 pi jk/N), cas = cos + sin (j, k = 0..N-1), again symmetric with
 * A^{-1} = A. omega_k = 2 sin(pi k/N); arrays hold wavenumber k at index k (k and N-k are
 * degenerate: cas_k and cas_{N-k} span cos and sin of wavenumber k). k = 0 is the zero mode:
 * omega_0 = 0, E_0 = P_0^2/2 = (sum_j x'_j)^2/(2N), the kinetic energy of the centre of mass, a
 * constant of the motion of every model (sum_j x'_j is conserved on a ring).
 * Both: E_k = (P_k^2 + omega_k^2 Q_k^2)/2 with P the mode transform of the velocities x'
 * (equal to p but for model 2); sum_k E_k is the harmonic energy. Computed by a real FFT in
 * O(N log N) for every N (Bluestein's algorithm for lengths with a large prime factor). */
#ifndef FPUTLAB_MODES_H
#define FPUTLAB_MODES_H

#include "fputlab/common.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

/* omega_k, k = 1..n, of the fixed-end chain into omega[0..n-1]. */
FPL_API int fpl_modes_omega(int n, double *omega);

/* The lattice's mode frequencies (length N) in the order of fpl_modes_energies: the fixed-end
 * chain's omega_k, k = 1..N, or the ring's 2 sin(pi k/N), k = 0..N-1. */
FPL_API int fpl_modes_frequencies(const fpl_lattice *lattice, double *omega);

/* fpl_modes_transform and fpl_modes_energies allocate a temporary FFT workspace per call: for
 * many states prefer fpl_integrator_sample (mode energies from the integrator's workspace). */

/* Q = A x (also x = A Q, since A^{-1} = A). x and q of length N; may alias. */
FPL_API int fpl_modes_transform(const fpl_lattice *lattice, const double *x, double *q);

/* Mode energies E_k, k = 1..N, of the state y (length 2N) into energies[0..N-1]. */
FPL_API int fpl_modes_energies(const fpl_lattice *lattice, const double *y, double *energies);

/* Single-mode initial state (length 2N): x_j = amplitude sin(pi k j/(N+1)), p = 0, k = 1..N;
 * its only non-zero mode coordinate is Q_k = amplitude sqrt((N+1)/2). Periodic: x_j = amplitude
 * sin(2 pi k j/N + pi/4) = amplitude cas(2 pi k j/N)/sqrt(2) (j = 0..N-1), k = 1..N-1; its only
 * non-zero mode coordinate is Q_k = amplitude sqrt(N/2). */
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
