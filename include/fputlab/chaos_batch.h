/* fputlab — chaos indicators for R orbits at once (batched lanes).
 *
 * R orbits of the same N, model, alpha and beta (each with its own disorder v, i.e. its own
 * lattice, and/or its own initial state) are advanced together with their deviation vectors by a
 * splitting scheme with the kinetic drift (fpl_chaos_batch_method_name lists them). The state is
 * stored as a structure of arrays with the orbits innermost (element [j][r] = particle j of orbit
 * r, r contiguous), so that the vector units work across orbits: small lattices (N = 4 .. 16),
 * whose own loops are too short for vectors, run several times faster per orbit than with
 * fpl_chaos. Each orbit ("lane") gets exactly the computation of fpl_chaos (fputlab/chaos.h) with
 * the same method, dt and initial deviation vectors: the same drift/kick arithmetic, the same
 * renormalisation times and bookkeeping (lambda, SALI, GALI_n_dev, log-spaced samples), so its
 * numbers agree with fpl_chaos to round-off (bit for bit with the default GCC build).
 *
 * Per lane:
 *   - blow-up: the lane stops when its state becomes non-finite or a bond stretch exceeds
 *     blowup_stretch (by default the potential's barrier, fpl_lattice_barrier; both checked at
 *     every renormalisation, before SALI, as
 *     fpl_chaos does) or when a stopping criterion of integrator_options->events fires
 *     (fputlab/events.h; kinds FPL_EVENT_MAX_STRETCH, FPL_EVENT_MAX_DISPLACEMENT and
 *     FPL_EVENT_ENERGY, checked every 16 steps as fpl_integrator does; the event time is then
 *     located exactly by replaying that lane's interval with fpl_integrator, as a single-orbit run
 *     would). One set of criteria serves every lane.
 *   - chaos: SALI < sali_threshold at a renormalisation marks the lane chaotic (t_chaotic = that
 *     time) once the orbit is still finite, without any criterion fired, at the next
 *     renormalisation (or at t_end): a SALI collapse in the last interval before an overflow is
 *     a blow-up, never chaos. With stop_when_chaotic the lane stops at that confirmation, one
 *     renorm_interval after t_chaotic (fpl_chaos stops at t_chaotic itself).
 *   - finished lanes (t_end, blow-up, chaotic with stop_when_chaotic) cost nothing afterwards:
 *     the running lanes are compacted into the first slots.
 *
 *   fpl_chaos_batch *b;
 *   fpl_chaos_batch_options opt;  fpl_chaos_batch_options_init(&opt);  opt.chaos.t_end = 1e6;
 *   fpl_chaos_batch_create(lattices, R, "srkn14a6", &io, 0.0, y0, NULL, &opt, &b);
 *   while (!fpl_chaos_batch_done(b)) fpl_chaos_batch_advance(b, t_next, t, mle, sali, gali);
 *   for (int r = 0; r < R; r++) fpl_chaos_batch_get_result(b, r, &res[r]);
 *   fpl_chaos_batch_free(&b);
 *
 * Sample arrays are R x n_samples, row-major (row r = orbit r), each entry written at its global
 * sample index exactly as fpl_chaos_advance does for one orbit.
 * The step never allocates; a handle belongs to one thread at a time (the lattices, read-only
 * and shareable, must outlive it). */
#ifndef FPUTLAB_CHAOS_BATCH_H
#define FPUTLAB_CHAOS_BATCH_H

#include "fputlab/chaos.h"
#include "fputlab/common.h"
#include "fputlab/integrator.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fpl_chaos_batch_options {
    fpl_chaos_options chaos;  /* per lane, as fpl_chaos (fputlab/chaos.h) with these differences:
                                 (t_end - t0)/dt must fit the 64-bit step count; t_first_sample 0
                                 means renorm_interval; seed gives the same random deviation
                                 vectors to every orbit when w0 is NULL; with stop_when_chaotic a
                                 lane stops one renorm_interval after t_chaotic (see above) */
    int compact;              /* non-zero (default): move running lanes together when lanes
                                 finish; 0: leave them in place and skip only all-finished
                                 groups of 4 (for measurements) */
} fpl_chaos_batch_options;

/* Why a lane blew up. */
enum {
    FPL_BATCH_BLOWUP_NONE = 0,
    FPL_BATCH_BLOWUP_EVENT = 1,      /* a stopping criterion (integrator_options->events) fired */
    FPL_BATCH_BLOWUP_NONFINITE = 2,  /* the state (orbit or deviation vectors) left the finite
                                        numbers, or a deviation vector became zero */
    FPL_BATCH_BLOWUP_STRETCH = 3     /* a bond stretch exceeded blowup_stretch at a
                                        renormalisation */
};

typedef struct fpl_chaos_batch_result {
    int n_samples;            /* samples written for this orbit */
    double t_final;           /* time of the last renormalisation (the time reached) */
    double mle;               /* lambda(t_final) */
    double sali;              /* SALI(t_final) (NaN if n_dev < 2) */
    double gali;              /* GALI_{n_dev}(t_final) (NaN if n_dev < 2) */
    int chaotic;              /* SALI < threshold on a finite orbit, confirmed (see above) */
    double t_chaotic;         /* first renormalisation time with SALI < threshold (NaN if none) */
    int blew_up;              /* the lane blew up (then chaotic is 0 unless confirmed before) */
    double t_blowup;          /* the event time, or the renormalisation time at which the stretch
                                 or the non-finite state was found (NaN if no blow-up) */
    int blowup_reason;        /* FPL_BATCH_BLOWUP_* */
    int event_index;          /* criterion that fired (index into integrator_options->events), or -1 */
    long steps;               /* integrator steps taken by this orbit */
    int done;                 /* the lane has finished (t_end, blow-up, or stopped chaotic) */
} fpl_chaos_batch_result;

typedef struct fpl_chaos_batch fpl_chaos_batch;

/* The methods the batch kernel runs (the splitting schemes with the kinetic drift), in the
 * registry's order: index 0..fpl_chaos_batch_method_count()-1; NULL for any other index. */
FPL_API int fpl_chaos_batch_method_count(void);
FPL_API const char *fpl_chaos_batch_method_name(int index);

/* chaos: fpl_chaos_options_init's defaults (t_end NaN: must be set); compact 1. */
FPL_API void fpl_chaos_batch_options_init(fpl_chaos_batch_options *opt);

/* lattices: n_orbits handles (the same N, model, alpha and beta; one may appear several times;
 * only read, as everywhere: the array is not const-qualified so that C callers need no cast);
 * method: a kinetic-drift splitting scheme; integrator_options: dt and events are used (NULL:
 * dt = 0.01, no criteria; mode-energy criteria are not supported); y0: n_orbits x 2N initial states; w0: n_orbits x n_dev x 2N deviation vectors
 * (NULL: Gaussian random from opt->seed, the same for every orbit). Errors name the parameter:
 * n_orbits < 1, lattices[r] NULL or different from lattices[0], unknown or unsupported method,
 * dt, t_end, renorm_interval (<= 0 or < dt), n_samples, n_dev, y0/w0 not finite. */
FPL_API int fpl_chaos_batch_create(fpl_lattice *const *lattices, int n_orbits, const char *method,
                                   const fpl_integrator_options *integrator_options, double t0,
                                   const double *y0, const double *w0,
                                   const fpl_chaos_batch_options *opt, fpl_chaos_batch **out);
FPL_API void fpl_chaos_batch_free(fpl_chaos_batch **batch);

/* Perform the renormalisations due up to t_until (capped at t_end) for every running lane and
 * write their samples (arrays n_orbits x n_samples, or NULL). Lane blow-ups are results, not
 * errors: the status is < 0 only for bad arguments or memory. */
FPL_API int fpl_chaos_batch_advance(fpl_chaos_batch *batch, double t_until, double *t_out,
                                    double *mle_out, double *sali_out, double *gali_out);
/* 1 once every lane has finished. */
FPL_API int fpl_chaos_batch_done(const fpl_chaos_batch *batch);
/* Number of orbits, and of lanes still running. */
FPL_API int fpl_chaos_batch_size(const fpl_chaos_batch *batch);
FPL_API int fpl_chaos_batch_running(const fpl_chaos_batch *batch);
/* Time of the running lanes (the last renormalisation time). */
FPL_API double fpl_chaos_batch_time(const fpl_chaos_batch *batch);
FPL_API int fpl_chaos_batch_get_result(const fpl_chaos_batch *batch, int orbit,
                                       fpl_chaos_batch_result *result);
/* Readable account of how the lane ended ("" while running or if it reached t_end), e.g.
 * "max |x_{j+1} - x_j| > 4 at t = 2545.0098". */
FPL_API const char *fpl_chaos_batch_message(const fpl_chaos_batch *batch, int orbit);
/* State of orbit r (2N(1 + n_dev): orbit, then the deviation vectors, as fpl_integrator) at the
 * last grid time reached (after its last renormalisation). For a lane that blew up: with
 * criteria, the state at the start of the interval in which it blew up; without, the state in
 * which the non-finite numbers were found. */
FPL_API int fpl_chaos_batch_get_state(const fpl_chaos_batch *batch, int orbit, double *y);

/* Checkpoint: fpl_chaos_batch_save_size doubles hold the whole run state (states, counters,
 * per-lane accumulators and results); restoring them into a handle created with the same
 * arguments continues bit for bit. */
FPL_API long fpl_chaos_batch_save_size(const fpl_chaos_batch *batch);
FPL_API int fpl_chaos_batch_save(const fpl_chaos_batch *batch, double *buffer);
FPL_API int fpl_chaos_batch_restore(fpl_chaos_batch *batch, const double *buffer, long len);

#ifdef __cplusplus
}
#endif
#endif
