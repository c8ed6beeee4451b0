/* fputlab — one integration API for every method: our fixed-step splitting schemes and the
 * adaptive SUNDIALS (ARKODE, CVODE) and GSL back ends, for any model, with n_dev deviation
 * vectors carried along (tangent map for splitting schemes, variational equations otherwise).
 *
 *   fpl_integrator *h;
 *   fpl_integrator_options opt;  fpl_integrator_options_init(&opt);  opt.dt = 0.01;
 *   fpl_integrator_create(lat, "yoshida4", n_dev, &opt, 0.0, y0, &h);
 *   fpl_integrator_advance(h, 100.0, y);        // y = state at t = 100
 *   fpl_integrator_free(&h);
 *
 * Samples can be streamed to a callback (fpl_integrator_run) or written to arrays
 * (fpl_integrator_sample); the trajectory itself is never stored.
 * Fixed-step methods keep the internal state on the grid t0 + n dt (n is a 64-bit step count,
 * so time never drifts); a sample between grid points is one partial step from a copy.
 * Adaptive methods stop exactly at each requested time (no interpolation). */
#ifndef FPUTLAB_INTEGRATOR_H
#define FPUTLAB_INTEGRATOR_H

#include "fputlab/common.h"
#include "fputlab/events.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fpl_integrator fpl_integrator;

typedef struct fpl_integrator_options {
    double dt;        /* fixed-step methods: the step (> 0); adaptive: initial step (0 = automatic) */
    double rtol;      /* adaptive methods: relative tolerance (> 0) */
    double atol;      /* adaptive methods: absolute tolerance (> 0) */
    long max_steps;   /* adaptive methods: internal steps allowed per advance (0 = 10^8) */
    int compensated_sums; /* ARKODE SPRKStep methods ("sprk-*") only: compensated summation of
                             the increments (non-zero), which removes most round-off growth;
                             refused (FPL_ERR_ARG) for every other method */
    const fpl_event_set *events; /* stopping criteria (fputlab/events.h; copied at create), or
                             NULL for none: the run stops with FPL_EVENT when one fires */
} fpl_integrator_options;

/* dt = 0.01, rtol = 1e-10, atol = 1e-12, max_steps = 0, compensated_sums = 0, events = NULL. */
FPL_API void fpl_integrator_options_init(fpl_integrator_options *opt);

/* Methods by name: fpl_method_count / fpl_method_name list them; fpl_method_info tells order
 * and whether the method is adaptive (FPL_ERR_UNKNOWN for an unknown name). */
FPL_API int fpl_method_count(void);
FPL_API const char *fpl_method_name(int index);
FPL_API int fpl_method_info(const char *name, int *order, int *adaptive);

/* Create an integrator at (t0, y0); y0 has length 2N(1 + n_dev). The lattice is only read: it
 * must outlive the integrator and may be shared by several integrators and threads (each
 * integrator owns its scratch). opt NULL means defaults. Errors also for invalid opt->events. */
FPL_API int fpl_integrator_create(const fpl_lattice *lattice, const char *method, int n_dev,
                                  const fpl_integrator_options *opt, double t0, const double *y0,
                                  fpl_integrator **out);
FPL_API void fpl_integrator_free(fpl_integrator **integrator);
FPL_API const char *fpl_integrator_errmsg(const fpl_integrator *integrator);
FPL_API const char *fpl_integrator_method(const fpl_integrator *integrator);
FPL_API int fpl_integrator_n_dev(const fpl_integrator *integrator);

/* Integrate to t_target (>= the current time) and write the state there into y_out (length
 * 2N(1+n_dev); may be NULL). FPL_ERR_NONFINITE if the state became NaN/Inf (the message says
 * between which times; the internal state is then the last finite one); FPL_ERR_BACKEND with
 * the SUNDIALS/GSL flag and message if the back end failed; FPL_EVENT if a stopping criterion
 * fired first (y_out is then the state at the event). */
FPL_API int fpl_integrator_advance(fpl_integrator *integrator, double t_target, double *y_out);

/* At most `seconds` of wall time per advance/sample/run call inside an adaptive multistep solve
 * (CVODE: cvode-adams, cvode-bdf, whose steps at large N take milliseconds each and whose
 * sample intervals can take minutes): when it runs out before the target, the call returns
 * FPL_PAUSED with the integrator at its last internal step (fpl_integrator_time; sample and run
 * also give the samples done) and the same call, made again, continues exactly as if it had
 * not paused. An embedder sets it to see signals (Ctrl-C) between calls. 0 (the default): no
 * budget. Other methods ignore it (a fixed-step run can be advanced piecewise instead).
 * FPL_ERR_ARG for a negative or non-finite value. */
FPL_API int fpl_integrator_set_budget(fpl_integrator *integrator, double seconds);

/* Time of the internal state (for fixed-step methods the last grid point reached). */
FPL_API double fpl_integrator_time(const fpl_integrator *integrator);
/* Copy the internal state (length 2N(1+n_dev)). */
FPL_API int fpl_integrator_get_state(const fpl_integrator *integrator, double *y);

/* Restart from a checkpoint: put the integrator (created with the original t0 and options) at
 * step count n_steps, time t and state y (length 2N(1+n_dev)). For fixed-step methods t must be
 * t0 + n_steps dt (as fpl_integrator_time reported it), which makes the continuation bit-for-bit
 * identical to an uninterrupted run; adaptive methods restart their step-size control at t. */
FPL_API int fpl_integrator_restore(fpl_integrator *integrator, long n_steps, double t,
                                   const double *y);
/* Compensated sums (opt.compensated_sums, "sprk-*" methods): the carry of the compensated
 * summation (length 2N(1+n_dev)), the round-off the next step adds back. A checkpoint must keep
 * it for a bit-for-bit restart: fpl_integrator_restore zeroes it, then set it from the
 * checkpoint (fpl_checkpoint_write/_load do both). SUNDIALS has no function for it (6.6-7.5):
 * fputlab finds the vector as SPRKStep allocates it (a clone of the state vector), and refuses
 * compensated_sums at creation where that fails. FPL_ERR_ARG if the integrator does not use
 * compensated sums.
 * Transforming the deviation vectors zeroes their part of the carry (the orbit's is kept). */
FPL_API int fpl_integrator_get_compensation(const fpl_integrator *integrator, double *carry);
FPL_API int fpl_integrator_set_compensation(fpl_integrator *integrator, const double *carry);

/* Internal step count (with fpl_integrator_time and the state: what a checkpoint must keep). */
FPL_API long fpl_integrator_steps(const fpl_integrator *integrator);

/* Replace the deviation vectors w_i by sum_j m[i*n_dev + j] w_j (a linear map, which commutes
 * with the linear tangent dynamics: used for renormalisation and Gram-Schmidt). */
FPL_API int fpl_integrator_transform_deviations(fpl_integrator *integrator, const double *m);

/* Events (fputlab/events.h, the criteria of opt->events): when a criterion fires,
 * advance/sample/run return FPL_EVENT and stop there; the internal state and time are those of
 * the event, and any later advance is refused. fpl_integrator_event returns 1 (and the criterion
 * index and time) if an event stopped the integrator, else 0. */
FPL_API int fpl_integrator_event(const fpl_integrator *integrator, int *index, double *t);
/* Number of criteria, and the readable description of criterion i ("" out of range). */
FPL_API int fpl_integrator_event_count(const fpl_integrator *integrator);
FPL_API const char *fpl_integrator_event_describe(const fpl_integrator *integrator, int index);
/* g_i(y) of the criteria (y of length >= 2N; only the orbit is read), with the integrator's
 * scratch: not while another thread uses the integrator. */
FPL_API int fpl_integrator_events_eval(fpl_integrator *integrator, const double *y, double *g);

/* Steps taken and right-hand-side (force) evaluations so far. */
FPL_API int fpl_integrator_counters(const fpl_integrator *integrator, long *steps,
                                    long *force_evals);

/* Sample at increasing times: any output may be NULL; rows are per sample:
 * states n x 2N(1+n_dev), mode_energies n x N (of the orbit), energies n. *n_done gets the number
 * of samples written; all are finite. */
FPL_API int fpl_integrator_sample(fpl_integrator *integrator, const double *t_samples,
                                  int n_samples, double *states, double *mode_energies,
                                  double *energies, int *n_done);

/* Stream samples to a callback; a non-zero return from it stops the run with FPL_EVENT. */
typedef int (*fpl_sample_fn)(void *ctx, double t, const double *y, int n_dev);
FPL_API int fpl_integrator_run(fpl_integrator *integrator, const double *t_samples, int n_samples,
                               fpl_sample_fn callback, void *ctx, int *n_done);

#ifdef __cplusplus
}
#endif
#endif
