/* fputlab — stopping criteria (events) for finite-time blow-up, by root-finding.
 *
 * Each criterion is a function g(y) that is positive while the run is fine and crosses zero
 * (downwards) when the criterion fires:
 *   FPL_EVENT_ENERGY            g = threshold - E(y)   (E as fpl_lattice_energy: for model 3 the
 *                                                       energy of Eq. Hamilt, not conserved)
 *   FPL_EVENT_MAX_DISPLACEMENT  g = threshold - max_j |x_j|
 *   FPL_EVENT_MAX_STRETCH       g = threshold - max_b |x_{b+1} - x_b|  (the cubic potential's
 *                                                       barrier sits at stretch -1/alpha)
 *   FPL_EVENT_MODE_ENERGY       g = threshold - E_k (mode k >= 1), or - max_k E_k (mode 0)
 * The criteria live on the lattice (fpl_lattice_set_events), so the SUNDIALS root function
 * fpl_sun_roots (fputlab/sundials.h) sees them through the same user_data as fpl_sun_rhs.
 * Integrators stop at the first crossing: ARKODE/CVODE by their root-finding, the splitting
 * schemes by checking every step and refining inside the step (partial steps from the state
 * at the start of the step, Illinois root-finding to 1e-12 relative in time). */
#ifndef FPUTLAB_EVENTS_H
#define FPUTLAB_EVENTS_H

#include "fputlab/common.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum fpl_event_kind {
    FPL_EVENT_ENERGY = 0,
    FPL_EVENT_MAX_DISPLACEMENT = 1,
    FPL_EVENT_MAX_STRETCH = 2,
    FPL_EVENT_MODE_ENERGY = 3
} fpl_event_kind;

/* At most 8 criteria at once. */
typedef struct fpl_event_set {
    int n;
    int kind[8];
    double threshold[8];
    int mode[8];              /* FPL_EVENT_MODE_ENERGY only: k in 1..N, or 0 for the maximum */
} fpl_event_set;

/* Attach criteria to the lattice (copied; NULL or n = 0 removes them). Errors: n outside 0..8,
 * unknown kind, threshold not finite and > 0, mode outside 0..N. */
FPL_API int fpl_lattice_set_events(fpl_lattice *lattice, const fpl_event_set *events);
FPL_API int fpl_lattice_event_count(const fpl_lattice *lattice);
/* g_i(y) for the attached criteria (y of length >= 2N; only the orbit is read). */
FPL_API int fpl_lattice_events_eval(fpl_lattice *lattice, const double *y, double *g);
/* Readable description of criterion i, e.g. "max |x_{j+1} - x_j| > 4". */
FPL_API const char *fpl_lattice_event_describe(const fpl_lattice *lattice, int index);

#ifdef __cplusplus
}
#endif
#endif
