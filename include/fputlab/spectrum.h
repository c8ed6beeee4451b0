/* fputlab — the Lyapunov spectrum of an orbit (Benettin, Galgani, Giorgilli & Strelcyn 1980;
 * Shimada & Nagashima 1979): k deviation vectors are carried by the integrator (the tangent map
 * of the splitting schemes, the variational equations of the adaptive methods) and
 * re-orthonormalised by a Householder QR every `renorm_interval`, W = Q R with R_ii > 0; the
 * deviation vectors become Q and
 *     lambda_i(t) = (1/(t - t0)) sum over the renormalisations of ln R_ii.
 * The exponents are in the order of the QR columns (the Oseledets order: descending once
 * converged, as ChaosTools.jl's lyapunovspectrum). Work per renormalisation: O(k^2 2N) for the
 * QR on top of the integration of the k vectors.
 *
 *   fpl_spectrum_options o;  fpl_spectrum_options_init(&o);  o.t_end = 1e4;
 *   fpl_spectrum *s;
 *   fpl_spectrum_create(lat, "yoshida4", &iopt, 0.0, y0, NULL, &o, &s);
 *   fpl_spectrum_advance(s, o.t_end, t, history);       // history: n_samples x k
 *   fpl_spectrum_exponents(s, lambda);                  // k exponents at t_end
 *   fpl_spectrum_free(&s);
 *
 * A checkpoint holds the integrator (fpl_spectrum_integrator, fputlab/io.h) and the
 * fpl_spectrum_n_accumulators(s) numbers of fpl_spectrum_save; restoring both continues bit
 * for bit. */
#ifndef FPUTLAB_SPECTRUM_H
#define FPUTLAB_SPECTRUM_H

#include "fputlab/common.h"
#include "fputlab/integrator.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fpl_spectrum_options {
    double t_end;             /* final time (> t0) */
    double renorm_interval;   /* time between QR re-orthonormalisations (> 0; default 1.0; for
                                 fixed-step methods a multiple of dt keeps them on the grid) */
    int n_exponents;          /* k, 1..2N; 0 (default): all 2N */
    int n_samples;            /* log-spaced samples of the exponents (>= 1; default 100) */
    double t_first_sample;    /* first sample time after t0 (> 0; 0 (default): renorm_interval) */
    unsigned long seed;       /* random initial deviation vectors when w0 is NULL (default 1) */
} fpl_spectrum_options;

typedef struct fpl_spectrum_result {
    int n_exponents;          /* k */
    int n_samples;            /* samples written */
    long n_renorm;            /* QR re-orthonormalisations done */
    double t_final;           /* time reached (the last renormalisation) */
    long steps;               /* integrator steps taken */
    int completed;            /* t_end reached */
} fpl_spectrum_result;

/* t_end NaN (must be set), renorm_interval 1.0, n_exponents 0 (all 2N), n_samples 100,
 * t_first_sample 0 (= renorm_interval), seed 1. */
FPL_API void fpl_spectrum_options_init(fpl_spectrum_options *opt);

typedef struct fpl_spectrum fpl_spectrum;

/* Follow the orbit y0 (length 2N) from t0 with k deviation vectors w0 (k x 2N, row-major,
 * linearly independent; NULL: Gaussian random vectors from opt->seed), orthonormalised by a
 * first QR before the run. */
FPL_API int fpl_spectrum_create(const fpl_lattice *lattice, const char *method,
                                const fpl_integrator_options *integrator_options, double t0,
                                const double *y0, const double *w0,
                                const fpl_spectrum_options *opt, fpl_spectrum **out);
FPL_API void fpl_spectrum_free(fpl_spectrum **spectrum);

/* Perform the renormalisations due up to t_until (capped at t_end) and write the log-spaced
 * samples they produce at their global indices 0 .. n_samples-1: t_out[i] and the k exponents
 * history_out[i*k .. i*k+k-1] (either may be NULL). A non-finite or degenerate deviation
 * vector is FPL_ERR_NONFINITE; a stopping criterion of the integrator is FPL_EVENT (> 0); the
 * samples before either are kept. */
FPL_API int fpl_spectrum_advance(fpl_spectrum *spectrum, double t_until, double *t_out,
                                 double *history_out);
/* 1 once t_end is reached (or a stopping criterion fired). */
FPL_API int fpl_spectrum_done(const fpl_spectrum *spectrum);
FPL_API int fpl_spectrum_get_result(const fpl_spectrum *spectrum, fpl_spectrum_result *result);
/* The k exponents at the last renormalisation (NaN before the first). */
FPL_API int fpl_spectrum_exponents(const fpl_spectrum *spectrum, double *exponents);
/* R of the last QR (k x k, row-major, upper triangular with a positive diagonal; the identity
 * before the first): W(t_m) = Q(t_m) R with Q the deviation vectors now held by the integrator.
 * What the backward iteration of covariant Lyapunov vectors (Ginelli et al. 2007) needs. */
FPL_API int fpl_spectrum_last_r(const fpl_spectrum *spectrum, double *r);
/* The state at the last renormalisation (y0 and the orthonormalised w0 before the first):
 * the orbit, then the k orthonormal vectors Q (length 2N (1 + k)). Unlike the integrator's
 * state, this is at the renormalisation time also between grid points of a fixed-step method. */
FPL_API int fpl_spectrum_state(const fpl_spectrum *spectrum, double *y);
FPL_API fpl_integrator *fpl_spectrum_integrator(fpl_spectrum *spectrum);
/* Number of accumulators of fpl_spectrum_save: FPL_SPECTRUM_N_COUNTERS + k (at most
 * FPL_CHECKPOINT_MAX_EXTRA for k <= 2N <= 8000). */
enum { FPL_SPECTRUM_N_COUNTERS = 5 };
FPL_API int fpl_spectrum_n_accumulators(const fpl_spectrum *spectrum);
FPL_API int fpl_spectrum_save(const fpl_spectrum *spectrum, double *accumulators);
FPL_API int fpl_spectrum_restore(fpl_spectrum *spectrum, const double *accumulators);

/* Householder QR of k vectors of length len (w: k x len, row-major, the vectors are the
 * columns of W = [w_0 ... w_{k-1}]): W = Q R with orthonormal q (k x len, row-major) and r
 * (k x k, row-major, upper triangular) with r_ii >= 0. q may be w (in place). Allocates its
 * scratch; FPL_ERR_ARG for k > len or a non-finite w. */
FPL_API int fpl_spectrum_qr(const double *w, int k, long len, double *q, double *r);

#ifdef __cplusplus
}
#endif
#endif
