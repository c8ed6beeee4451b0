/* fputlab — chaos indicators along an orbit: maximum Lyapunov exponent (Benettin et al. 1980,
 * renormalisation every `renorm_interval`), SALI (Skokos 2001) and GALI_k (Skokos, Bountis &
 * Antonopoulos 2007). Works with every integration method: the tangent map for splitting schemes,
 * the variational equations for the adaptive ones.
 *
 * Deviation vectors are normalised (never orthogonalised) at every renormalisation, which changes
 * nothing in the linear tangent dynamics but the bookkeeping:
 *   lambda(t) = (1/t) sum ln ||w_1|| over the renormalisations (w_1 the first vector),
 *   SALI(t)   = min(||w1^ - w2^||, ||w1^ + w2^||),  GALI_k(t) = sqrt(det(W^T W)) for the k
 *               normalised vectors W (the product of its singular values). */
#ifndef FPUTLAB_CHAOS_H
#define FPUTLAB_CHAOS_H

#include "fputlab/common.h"
#include "fputlab/integrator.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fpl_chaos_options {
    double t_end;             /* final time (> t0) */
    double renorm_interval;   /* time between renormalisations (> 0; default 1.0). For fixed-step
                                 methods a multiple of dt keeps renormalisation on the grid. */
    int n_samples;            /* number of log-spaced output samples (>= 1; default 200) */
    double t_first_sample;    /* first output time after t0 (> 0; default renorm_interval) */
    int n_dev;                /* deviation vectors (1 = mLE only, >= 2 adds SALI and GALI_n_dev) */
    double sali_threshold;    /* SALI below this marks the orbit chaotic (default 1e-8) */
    int stop_when_chaotic;    /* non-zero: stop as soon as SALI < sali_threshold */
    unsigned long seed;       /* random initial deviation vectors when w0 is NULL */
    double blowup_stretch;    /* a bond stretch |x_{j+1} - x_j| above this at a renormalisation
                                 ends the run as a blow-up (checked before SALI, so a runaway orbit
                                 is never called chaotic). 0 (default): automatic, the nearest
                                 barrier of the bond potential (fpl_lattice_barrier: 1/alpha for
                                 FPUT-alpha, none for alpha^2 <= 4 beta or Toda); < 0: none. */
} fpl_chaos_options;

/* Exactly one class per orbit (fpl_chaos_classify). */
typedef enum fpl_orbit_class {
    FPL_ORBIT_UNDECIDED = 0,  /* neither test passed yet (e.g. lambda t still growing) */
    FPL_ORBIT_REGULAR = 1,    /* lambda(t) follows the 1/t law of regular orbits, SALI stays up */
    FPL_ORBIT_CHAOTIC = 2,    /* SALI < threshold on a finite orbit, before any blow-up */
    FPL_ORBIT_BLOWUP = 3      /* a stopping criterion fired or the state became non-finite */
} fpl_orbit_class;

typedef struct fpl_chaos_result {
    int n_samples;            /* samples written */
    double t_final;           /* time reached */
    double mle;               /* lambda(t_final) */
    double sali;              /* SALI(t_final) (NaN if n_dev < 2) */
    double gali;              /* GALI_{n_dev}(t_final) (NaN if n_dev < 2) */
    int chaotic;              /* SALI fell below sali_threshold on a finite orbit, before any
                                 blow-up (never set at or after a blow-up) */
    double t_chaotic;         /* first renormalisation time with SALI < threshold (NaN if none);
                                 confirmed one renormalisation later on a still-finite orbit
                                 inside the barrier (or at t_end) */
    long steps;               /* integrator steps taken */
    int blew_up;              /* the run ended in a blow-up: a stopping criterion (event),
                                 blowup_stretch exceeded, or a non-finite state */
    double t_blowup;          /* when: the event time, or the renormalisation time at which the
                                 stretch or non-finite state was found (NaN if none) */
    int completed;            /* t_end reached, or stopped chaotic (stop_when_chaotic) */
} fpl_chaos_result;

/* renorm_interval 1.0, n_samples 200, t_first_sample 0 (= renorm_interval), n_dev 2,
 * sali_threshold 1e-8, stop_when_chaotic 0, seed 1, blowup_stretch 0 (automatic);
 * t_end must be set. */
FPL_API void fpl_chaos_options_init(fpl_chaos_options *opt);

/* Follow the orbit y0 (length 2N) from t0 with n_dev deviation vectors w0 (n_dev x 2N, row-major;
 * NULL: Gaussian random vectors from the seed) and write lambda, SALI, GALI at log-spaced times
 * into the arrays (each of length opt->n_samples, or NULL). A blow-up ends the run cleanly: the
 * status is FPL_EVENT (> 0), result->blew_up is set with t_blowup, the message (fpl_last_error)
 * says when and why, and the samples up to it are kept. */
FPL_API int fpl_chaos_run(const fpl_lattice *lattice, const char *method,
                          const fpl_integrator_options *integrator_options, double t0,
                          const double *y0, const double *w0, const fpl_chaos_options *opt,
                          double *t_out, double *mle_out, double *sali_out, double *gali_out,
                          fpl_chaos_result *result);

/* The same computation as a handle that can be advanced piecewise and checkpointed:
 *   fpl_chaos_create(...); while (!fpl_chaos_done(c)) fpl_chaos_advance(c, t_next, ...);
 * fpl_chaos_advance performs the renormalisations due up to t_until (capped at t_end) and writes
 * the log-spaced samples they produce at their global indices (0 .. n_samples-1) of the arrays
 * (each of length opt->n_samples, or NULL); fpl_chaos_get_result tells how many there are.
 * A checkpoint holds the integrator (fpl_chaos_integrator, see fputlab/io.h) and the
 * FPL_CHAOS_N_ACCUMULATORS numbers of fpl_chaos_save; restoring both continues bit for bit. */
typedef struct fpl_chaos fpl_chaos;
enum { FPL_CHAOS_N_ACCUMULATORS = 15 };
FPL_API int fpl_chaos_create(const fpl_lattice *lattice, const char *method,
                             const fpl_integrator_options *integrator_options, double t0,
                             const double *y0, const double *w0, const fpl_chaos_options *opt,
                             fpl_chaos **out);
FPL_API void fpl_chaos_free(fpl_chaos **chaos);
FPL_API int fpl_chaos_advance(fpl_chaos *chaos, double t_until, double *t_out, double *mle_out,
                              double *sali_out, double *gali_out);
/* 1 once t_end is reached, the orbit was found chaotic with stop_when_chaotic, or it blew up. */
FPL_API int fpl_chaos_done(const fpl_chaos *chaos);
FPL_API int fpl_chaos_get_result(const fpl_chaos *chaos, fpl_chaos_result *result);
FPL_API fpl_integrator *fpl_chaos_integrator(fpl_chaos *chaos);
FPL_API int fpl_chaos_save(const fpl_chaos *chaos, double *accumulators);
FPL_API int fpl_chaos_restore(fpl_chaos *chaos, const double *accumulators);

/* The class of an orbit at time t_eval (NaN: the end of the run, t_final or t_blowup) from its result and its samples
 * (t, mle: n log-spaced samples as written by fpl_chaos_run/advance; samples after t_eval are
 * ignored). In this order: blow-up if it blew up by t_eval; chaotic if SALI fell below the
 * threshold by t_eval; regular if the run reached t_eval and lambda t (the log of the deviation
 * vector's growth) grew over the last decade of samples by no more than a regular orbit's linear
 * growth allows (lambda t <= 3 max(lambda t at t_eval/10, 1) + 2 ln 10); otherwise undecided. */
FPL_API int fpl_chaos_classify(const fpl_chaos_result *result, const double *t, const double *mle,
                               int n, double t_eval, int *orbit_class);
/* "undecided", "regular", "chaotic", "blow-up" (NULL for other values). */
FPL_API const char *fpl_orbit_class_name(int orbit_class);

/* SALI of two vectors of length len (each normalised first); 0 for parallel, sqrt(2) for
 * orthogonal vectors. */
FPL_API int fpl_chaos_sali(const double *w1, const double *w2, long len, double *sali);

/* GALI_k of k vectors (k x len, row-major), each normalised first. */
FPL_API int fpl_chaos_gali(const double *w, int k, long len, double *gali);

#ifdef __cplusplus
}
#endif
#endif
