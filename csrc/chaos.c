/* Chaos indicators (mLE, SALI, GALI) riding on any integrator: O(k^2 N) work per
 * renormalisation interval on top of the integration itself. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include "internal.h"

void fpl_chaos_options_init(fpl_chaos_options *opt)
{
    if (!opt) return;
    memset(opt, 0, sizeof *opt);
    opt->t_end = NAN;
    opt->renorm_interval = 1.0;
    opt->n_samples = 200;
    opt->t_first_sample = 0.0;
    opt->n_dev = 2;
    opt->sali_threshold = 1e-8;
    opt->stop_when_chaotic = 0;
    opt->seed = 1;
}

static double norm2(const double *w, long len)
{
    double s = 0.0;
    for (long i = 0; i < len; i++) s += w[i] * w[i];
    return sqrt(s);
}

static double sali_unit(const double *a, const double *b, long len)
{
    double dm = 0.0, dp = 0.0;
    for (long i = 0; i < len; i++) {
        dm += (a[i] - b[i]) * (a[i] - b[i]);
        dp += (a[i] + b[i]) * (a[i] + b[i]);
    }
    return sqrt(fmin(dm, dp));
}

/* GALI_k of k unit vectors stored in q (overwritten): product of the diagonal of R in W = QR,
 * by modified Gram-Schmidt (accurate down to GALI ~ 1e-16, unlike det of the Gram matrix). */
static double gali_unit(double *q, int k, long len)
{
    double prod = 1.0;
    for (int i = 0; i < k; i++) {
        double *qi = q + (size_t)i * len;
        double r = norm2(qi, len);
        prod *= r;
        if (r == 0.0) return 0.0;
        for (long c = 0; c < len; c++) qi[c] /= r;
        for (int j = i + 1; j < k; j++) {
            double *qj = q + (size_t)j * len, dot = 0.0;
            for (long c = 0; c < len; c++) dot += qi[c] * qj[c];
            for (long c = 0; c < len; c++) qj[c] -= dot * qi[c];
        }
    }
    return prod;
}

int fpl_chaos_sali(const double *w1, const double *w2, long len, double *sali)
{
    if (!w1 || !w2 || !sali) return fpl_error(NULL, FPL_ERR_ARG, "w1/w2/sali: NULL pointer");
    if (len < 1) return fpl_error(NULL, FPL_ERR_ARG, "len must be >= 1 (got %ld)", len);
    double n1 = norm2(w1, len), n2 = norm2(w2, len);
    if (!(n1 > 0.0) || !(n2 > 0.0) || !isfinite(n1) || !isfinite(n2))
        return fpl_error(NULL, FPL_ERR_ARG, "w1 and w2 must be finite and non-zero");
    double dm = 0.0, dp = 0.0;
    for (long i = 0; i < len; i++) {
        double a = w1[i] / n1, b = w2[i] / n2;
        dm += (a - b) * (a - b);
        dp += (a + b) * (a + b);
    }
    *sali = sqrt(fmin(dm, dp));
    return FPL_OK;
}

int fpl_chaos_gali(const double *w, int k, long len, double *gali)
{
    if (!w || !gali) return fpl_error(NULL, FPL_ERR_ARG, "w/gali: NULL pointer");
    if (k < 1 || len < 1 || k > len)
        return fpl_error(NULL, FPL_ERR_ARG, "need 1 <= k <= len (got k = %d, len = %ld)", k, len);
    double *q = malloc(sizeof(double) * (size_t)k * (size_t)len);
    if (!q) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (GALI)");
    for (int i = 0; i < k; i++) {
        double n = norm2(w + (size_t)i * len, len);
        if (!(n > 0.0) || !isfinite(n)) {
            free(q);
            return fpl_error(NULL, FPL_ERR_ARG, "vector %d must be finite and non-zero", i);
        }
        for (long c = 0; c < len; c++) q[(size_t)i * len + c] = w[(size_t)i * len + c] / n;
    }
    *gali = gali_unit(q, k, len);
    free(q);
    return FPL_OK;
}

static int check_options(const fpl_chaos_options *o, double t0)
{
    if (!(o->t_end > t0) || !isfinite(o->t_end))
        return fpl_error(NULL, FPL_ERR_ARG, "t_end must be finite and > t0 = %g (got %g)", t0,
                         o->t_end);
    if (!(o->renorm_interval > 0.0) || !isfinite(o->renorm_interval))
        return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval must be finite and > 0 (got %g)",
                         o->renorm_interval);
    if (o->n_samples < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_samples must be >= 1 (got %d)", o->n_samples);
    if (!(o->t_first_sample >= 0.0) || !isfinite(o->t_first_sample))
        return fpl_error(NULL, FPL_ERR_ARG, "t_first_sample must be finite and >= 0 (got %g)",
                         o->t_first_sample);
    if (o->n_dev < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 1 (got %d)", o->n_dev);
    if (!(o->sali_threshold >= 0.0))
        return fpl_error(NULL, FPL_ERR_ARG, "sali_threshold must be >= 0 (got %g)",
                         o->sali_threshold);
    return FPL_OK;
}

int fpl_chaos_run(fpl_lattice *lattice, const char *method,
                  const fpl_integrator_options *integrator_options, double t0, const double *y0,
                  const double *w0, const fpl_chaos_options *opt, double *t_out, double *mle_out,
                  double *sali_out, double *gali_out, fpl_chaos_result *result)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!opt) return fpl_error(NULL, FPL_ERR_ARG, "opt: NULL options");
    if (!y0) return fpl_error(NULL, FPL_ERR_ARG, "y0: NULL pointer");
    if (!isfinite(t0)) return fpl_error(NULL, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    int st = check_options(opt, t0);
    if (st) return st;
    const int k = opt->n_dev;
    const long len = 2L * lattice->n, dim = len * (k + 1);
    if (k > len)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev = %d exceeds the phase-space dimension 2N = %ld",
                         k, len);

    double *y = malloc(sizeof(double) * (size_t)dim);
    double *q = malloc(sizeof(double) * (size_t)(len * k));
    double *scale = calloc((size_t)k * (size_t)k, sizeof(double));
    if (!y || !q || !scale) {
        free(y); free(q); free(scale);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (chaos run, N = %d)", lattice->n);
    }
    memcpy(y, y0, sizeof(double) * (size_t)len);
    if (w0) {
        memcpy(y + len, w0, sizeof(double) * (size_t)(len * k));
    } else {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        if (!rng) { free(y); free(q); free(scale); return fpl_error(NULL, FPL_ERR_NOMEM, "RNG"); }
        gsl_rng_set(rng, opt->seed);
        for (long i = 0; i < len * k; i++) y[len + i] = gsl_ran_gaussian(rng, 1.0);
        gsl_rng_free(rng);
    }
    /* start from unit vectors so ln||w|| sums measure growth from 1 */
    for (int i = 0; i < k; i++) {
        double *w = y + len * (i + 1), n = norm2(w, len);
        if (!(n > 0.0) || !isfinite(n)) {
            free(y); free(q); free(scale);
            return fpl_error(NULL, FPL_ERR_ARG, "deviation vector w0[%d] must be finite and non-zero", i);
        }
        for (long c = 0; c < len; c++) w[c] /= n;
    }

    fpl_integrator *h = NULL;
    st = fpl_integrator_create(lattice, method, k, integrator_options, t0, y, &h);
    if (st) { free(y); free(q); free(scale); return st; }

    const double T = opt->t_end - t0, tau = opt->renorm_interval;
    const double t_first = opt->t_first_sample > 0.0 ? opt->t_first_sample : fmin(tau, T);
    const long n_renorm = (long)ceil(T / tau - 1e-9);
    fpl_chaos_result res = {0, t0, NAN, NAN, NAN, 0, NAN, 0};
    double logsum = 0.0;
    int next = 0; /* next log-spaced sample index */
    for (long m = 1; m <= n_renorm && st == FPL_OK; m++) {
        double t = m == n_renorm ? opt->t_end : t0 + (double)m * tau;
        st = fpl_integrator_advance(h, t, y);
        if (st) break;
        double n1 = 0.0;
        for (int i = 0; i < k; i++) {
            double n = norm2(y + len * (i + 1), len);
            if (!(n > 0.0) || !isfinite(n)) {
                st = fpl_error(NULL, FPL_ERR_NONFINITE,
                               "deviation vector %d became %s at t = %g", i, n == 0 ? "zero" : "non-finite", t);
                break;
            }
            if (i == 0) n1 = n;
            scale[(size_t)i * k + i] = 1.0 / n;
            for (long c = 0; c < len; c++) q[(size_t)i * len + c] = y[len * (i + 1) + c] / n;
        }
        if (st) break;
        logsum += log(n1);
        res.mle = logsum / (t - t0);
        res.t_final = t;
        if (k >= 2) {
            res.sali = sali_unit(q, q + len, len);
            res.gali = gali_unit(q, k, len); /* destroys q; SALI already taken */
            if (!res.chaotic && res.sali < opt->sali_threshold) {
                res.chaotic = 1;
                res.t_chaotic = t;
            }
        }
        st = fpl_integrator_transform_deviations(h, scale);
        if (st) break;
        /* log-spaced output: t_first (T/t_first)^(i/(n-1)) after t0 */
        int stop = opt->stop_when_chaotic && res.chaotic;
        double target = opt->n_samples == 1 ? T
                      : t_first * pow(T / t_first, (double)next / (opt->n_samples - 1));
        if (next < opt->n_samples && (t - t0 >= target * (1 - 1e-12) || m == n_renorm || stop)) {
            if (t_out) t_out[res.n_samples] = t;
            if (mle_out) mle_out[res.n_samples] = res.mle;
            if (sali_out) sali_out[res.n_samples] = res.sali;
            if (gali_out) gali_out[res.n_samples] = res.gali;
            res.n_samples++;
            while (next < opt->n_samples &&
                   t_first * pow(T / t_first, (double)next / fmax(1, opt->n_samples - 1)) <=
                       (t - t0) * (1 + 1e-12))
                next++;
        }
        if (stop) break;
    }
    fpl_integrator_counters(h, &res.steps, NULL);
    fpl_integrator_free(&h);
    free(y);
    free(q);
    free(scale);
    if (result) *result = res;
    return st;
}
