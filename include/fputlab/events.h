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
 A set of criteria is an option of a run, never a property of the lattice: pass it in
 * fpl_integrator_options.events (fputlab/integrator.h; the chaos handles take the same options),
 * or to fpl_system_create for the SUNDIALS callbacks of fputlab/sundials.h.
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
    int mode[8];              /* FPL_EVENT_MODE_ENERGY only: k in 1..N (a periodic chain: the
                                 wavenumber, 1..N-1), or 0 for the maximum */
} fpl_event_set;

/* The {lattice, criteria, workspace} of one run, for embedders of the SUNDIALS callbacks
 * (fputlab/sundials.h: the user_data of every fpl_sun_* function). It holds the kernels' scratch,
 * so it belongs to one thread at a time; the lattice (read-only, shareable) must outlive it.
 * events may be NULL (no criteria); it is copied. Errors: NULL lattice or out, n outside 0..8,
 * unknown kind, threshold not finite and > 0, mode outside 0..N. */
typedef struct fpl_system fpl_system;
FPL_API int fpl_system_create(const fpl_lattice *lattice, const fpl_event_set *events,
                              fpl_system **out);
FPL_API void fpl_system_free(fpl_system **system);
/* Message of the last failing call or callback on this handle ("" if none). */
FPL_API const char *fpl_system_errmsg(const fpl_system *system);
FPL_API const fpl_lattice *fpl_system_lattice(const fpl_system *system);
/* Number of criteria (the nrtfn of fpl_sun_roots). */
FPL_API int fpl_system_event_count(const fpl_system *system);
/* Readable description of criterion i, e.g. "max |x_{j+1} - x_j| > 4" ("" out of range). */
FPL_API const char *fpl_system_event_describe(const fpl_system *system, int index);
/* g_i(y) for the criteria (y of length >= 2N; only the orbit is read). */
FPL_API int fpl_system_events_eval(fpl_system *system, const double *y, double *g);

#ifdef __cplusplus
}
#endif
#endif
