/* The Lyapunov spectrum riding on any integrator (fputlab/spectrum.h): k deviation vectors,
 * Householder QR every renormalisation interval, log-sums of the diagonal of R. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include "internal.h"

void fpl_spectrum_options_init(fpl_spectrum_options *opt)
{
    if (!opt) return;
    memset(opt, 0, sizeof *opt);
    opt->t_end = NAN;
    opt->renorm_interval = 1.0;
    opt->n_exponents = 0;
    opt->n_samples = 100;
    opt->t_first_sample = 0.0;
    opt->seed = 1;
}

/* sum a_i b_i with four partial sums: independent chains (a single running sum waits for each
 * addition, and the compiler may not reorder it) */
static inline double dot(const double *restrict a, const double *restrict b, long n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    long i = 0;
    for (; i + 4 <= n; i += 4) {
        s0 += a[i] * b[i];
        s1 += a[i + 1] * b[i + 1];
        s2 += a[i + 2] * b[i + 2];
        s3 += a[i + 3] * b[i + 3];
    }
    for (; i < n; i++) s0 += a[i] * b[i];
    return (s0 + s1) + (s2 + s3);
}

static inline void axpy(double a, const double *restrict x, double *restrict y, long n)
{
    for (long i = 0; i < n; i++) y[i] += a * x[i];
}

/* Householder QR of the k columns of A (column c at a + c*len, overwritten) into q (k x len) and
 * r (k x k, row-major) with r_ii >= 0; v is k x len scratch for the reflectors. Returns the
 * first column that is zero after the projections (rank deficiency), or -1.
 * Each reflector H_j = I - 2 v_j v_j^T (|v_j| = 1, v_j zero above j) maps column j onto
 * alpha e_j with alpha = -sign(a_jj) |a_j|, which never cancels; the signs are then moved
 * from R to Q so that R has a positive diagonal (W = (Q D)(D R), D = diag(+-1)). */
FPL_HOT static int householder_qr(double *a, int k, long len, double *q, double *r, double *v)
{
    int bad = -1;
    memset(r, 0, sizeof(double) * (size_t)k * (size_t)k);
    for (int j = 0; j < k; j++) {
        double *aj = a + (size_t)j * len, *vj = v + (size_t)j * len;
        const double norm = sqrt(dot(aj + j, aj + j, len - j));
        for (long i = 0; i < j; i++) vj[i] = 0.0;
        if (!(norm > 0.0)) {         /* zero column: no reflection, R_jj = 0 */
            if (bad < 0) bad = j;
            for (long i = j; i < len; i++) vj[i] = 0.0;
            for (int c = j; c < k; c++) r[(size_t)j * k + c] = a[(size_t)c * len + j];
            continue;
        }
        const double alpha = aj[j] >= 0.0 ? -norm : norm;
        for (long i = j; i < len; i++) vj[i] = aj[i];
        vj[j] -= alpha;
        const double inv = 1.0 / sqrt(dot(vj + j, vj + j, len - j));
        for (long i = j; i < len; i++) vj[i] *= inv;
        r[(size_t)j * k + j] = alpha;
        for (int c = j + 1; c < k; c++) {
            double *ac = a + (size_t)c * len;
            axpy(-2.0 * dot(vj + j, ac + j, len - j), vj + j, ac + j, len - j);
            r[(size_t)j * k + c] = ac[j];
        }
    }
    /* q_i = H_0 H_1 ... H_{k-1} e_i; H_j with j > i leaves e_i alone (v_j vanishes above j) */
    for (int i = 0; i < k; i++) {
        double *qi = q + (size_t)i * len;
        for (long c = 0; c < len; c++) qi[c] = 0.0;
        qi[i] = 1.0;
        for (int j = i; j >= 0; j--) {
            const double *vj = v + (size_t)j * len;
            axpy(-2.0 * dot(vj + j, qi + j, len - j), vj + j, qi + j, len - j);
        }
    }
    for (int j = 0; j < k; j++) {
        if (r[(size_t)j * k + j] < 0.0) {
            for (int c = j; c < k; c++) r[(size_t)j * k + c] = -r[(size_t)j * k + c];
            double *qj = q + (size_t)j * len;
            for (long c = 0; c < len; c++) qj[c] = -qj[c];
        }
    }
    return bad;
}

int fpl_spectrum_qr(const double *w, int k, long len, double *q, double *r)
{
    if (!w || !q || !r) return fpl_error(NULL, FPL_ERR_ARG, "w/q/r: NULL pointer");
    if (k < 1 || len < 1 || k > len)
        return fpl_error(NULL, FPL_ERR_ARG, "need 1 <= k <= len (got k = %d, len = %ld)", k, len);
    long bad;
    if (!fpl_is_finite_array(w, (long)k * len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "w[%ld] is not finite", bad);
    double *a = malloc(sizeof(double) * (size_t)k * (size_t)len * 2);
    if (!a) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (QR of %d x %ld)", k, len);
    memcpy(a, w, sizeof(double) * (size_t)k * (size_t)len);
    householder_qr(a, k, len, q, r, a + (size_t)k * (size_t)len);
    free(a);
    return FPL_OK;
}

struct fpl_spectrum {
    fpl_integrator *h;
    fpl_spectrum_options opt;
    int k;                /* exponents */
    long len;             /* 2N */
    double t0, T, t_first;
    double dt;            /* the step of a fixed-step method; 0 for an adaptive one */
    long n_renorm;        /* renormalisations up to t_end */
    long m;               /* renormalisations done */
    int next;             /* next log-spaced sample index */
    int done;
    fpl_spectrum_result res;
    double *logsum;       /* k: sum of ln R_ii */
    double *y;            /* the state, 2N (1 + k) */
    double *a, *v, *r;    /* QR scratch: k x 2N, k x 2N, k x k */
    double *rinv;         /* k x k: the map R^-1 for a renormalisation between grid points */
};

void fpl_spectrum_free(fpl_spectrum **sp)
{
    if (!sp || !*sp) return;
    fpl_spectrum *s = *sp;
    fpl_integrator_free(&s->h);
    free(s->logsum);
    free(s->y);
    free(s->a);
    free(s->v);
    free(s->r);
    free(s->rinv);
    free(s);
    *sp = NULL;
}

static int check_options(const fpl_spectrum_options *o, double t0, long len)
{
    if (!(o->t_end > t0) || !isfinite(o->t_end))
        return fpl_error(NULL, FPL_ERR_ARG, "t_end must be finite and > t0 = %g (got %g)", t0,
                         o->t_end);
    if (!(o->renorm_interval > 0.0) || !isfinite(o->renorm_interval))
        return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval must be finite and > 0 (got %g)",
                         o->renorm_interval);
    if (!((o->t_end - t0) / o->renorm_interval <= 9.0e15))
        return fpl_error(NULL, FPL_ERR_ARG, "t_end - t0 = %g needs %g renormalisations of "
                         "renorm_interval = %g: more than 9e15 (increase renorm_interval)",
                         o->t_end - t0, (o->t_end - t0) / o->renorm_interval, o->renorm_interval);
    if (o->n_exponents < 0 || o->n_exponents > len)
        return fpl_error(NULL, FPL_ERR_ARG, "n_exponents must be 0 (all) or 1..2N = %ld (got %d)",
                         len, o->n_exponents);
    if (o->n_samples < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_samples must be >= 1 (got %d)", o->n_samples);
    if (!(o->t_first_sample >= 0.0) || !isfinite(o->t_first_sample))
        return fpl_error(NULL, FPL_ERR_ARG, "t_first_sample must be finite and >= 0 (got %g)",
                         o->t_first_sample);
    return FPL_OK;
}

/* QR of the deviation vectors in s->y; on success they are replaced by Q in s->y and r holds
 * R. FPL_ERR_NONFINITE if a vector is not finite or they became linearly dependent. */
static int orthonormalise(fpl_spectrum *s, double t)
{
    const long len = s->len, kl = len * s->k;
    double *w = s->y + len;
    long bad;
    if (!fpl_is_finite_array(w, kl, &bad))
        return fpl_error(NULL, FPL_ERR_NONFINITE, "deviation vector %ld became non-finite at "
                         "t = %.10g", bad / len, t);
    memcpy(s->a, w, sizeof(double) * (size_t)kl);
    const int zero = householder_qr(s->a, s->k, len, w, s->r, s->v);
    if (zero >= 0)
        return fpl_error(NULL, FPL_ERR_NONFINITE, "the deviation vectors became linearly dependent "
                         "at t = %.10g (vector %d; renorm_interval = %g too long for the growth "
                         "of the vectors?)", t, zero, s->opt.renorm_interval);
    return FPL_OK;
}

int fpl_spectrum_create(const fpl_lattice *lattice, const char *method,
                        const fpl_integrator_options *integrator_options, double t0,
                        const double *y0, const double *w0, const fpl_spectrum_options *opt,
                        fpl_spectrum **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!opt) return fpl_error(NULL, FPL_ERR_ARG, "opt: NULL options");
    if (!y0) return fpl_error(NULL, FPL_ERR_ARG, "y0: NULL pointer");
    if (!isfinite(t0)) return fpl_error(NULL, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    const long len = 2L * lattice->n;
    int st = check_options(opt, t0, len);
    if (st) return st;
    const int k = opt->n_exponents ? opt->n_exponents : (int)len;
    double step = 0.0;
    {
        int order = 0, adaptive = 0;
        if ((st = fpl_method_info(method, &order, &adaptive))) return st;
        const double dt = integrator_options ? integrator_options->dt : 0.01;
        step = adaptive ? 0.0 : dt;
        if (!adaptive && opt->renorm_interval < dt * (1 - 1e-12))
            return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval = %g is smaller than the step "
                             "dt = %g (renormalise at most once per step)", opt->renorm_interval,
                             dt);
        if (!adaptive && !((opt->t_end - t0) / dt <= 9.0e15))
            return fpl_error(NULL, FPL_ERR_ARG, "t_end - t0 = %g needs %g steps of dt = %g: more "
                             "than the step counter holds exactly (9e15)", opt->t_end - t0,
                             (opt->t_end - t0) / dt, dt);
    }
    fpl_spectrum *s = calloc(1, sizeof *s);
    if (!s) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (spectrum)");
    const size_t kl = (size_t)k * (size_t)len;
    s->k = k;
    s->len = len;
    s->opt = *opt;
    s->logsum = calloc((size_t)k, sizeof(double));
    s->y = malloc(sizeof(double) * (size_t)len * (size_t)(k + 1));
    s->a = malloc(sizeof(double) * kl);
    s->v = malloc(sizeof(double) * kl);
    s->r = malloc(sizeof(double) * (size_t)k * (size_t)k);
    s->rinv = malloc(sizeof(double) * (size_t)k * (size_t)k);
    s->dt = step;
    if (!s->logsum || !s->y || !s->a || !s->v || !s->r || !s->rinv) {
        fpl_spectrum_free(&s);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (spectrum of %d exponents, N = %d)",
                         k, lattice->n);
    }
    memcpy(s->y, y0, sizeof(double) * (size_t)len);
    if (w0) {
        memcpy(s->y + len, w0, sizeof(double) * kl);
    } else {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        if (!rng) { fpl_spectrum_free(&s); return fpl_error(NULL, FPL_ERR_NOMEM, "RNG"); }
        gsl_rng_set(rng, opt->seed);
        for (size_t i = 0; i < kl; i++) s->y[len + (long)i] = gsl_ran_gaussian(rng, 1.0);
        gsl_rng_free(rng);
    }
    if ((st = orthonormalise(s, t0))) {
        fpl_spectrum_free(&s);
        return fpl_error(NULL, FPL_ERR_ARG, "w0 must be finite and linearly independent (%s)",
                         fpl_last_error());
    }
    /* R of the "last" QR: the identity until the first renormalisation */
    memset(s->r, 0, sizeof(double) * (size_t)k * (size_t)k);
    for (int i = 0; i < k; i++) s->r[(size_t)i * k + i] = 1.0;
    st = fpl_integrator_create(lattice, method, k, integrator_options, t0, s->y, &s->h);
    if (st) { fpl_spectrum_free(&s); return st; }
    s->t0 = t0;
    s->T = opt->t_end - t0;
    s->t_first = opt->t_first_sample > 0.0 ? opt->t_first_sample
                                           : fmin(opt->renorm_interval, s->T);
    s->n_renorm = (long)ceil(s->T / opt->renorm_interval - 1e-9);
    s->res = (fpl_spectrum_result){k, 0, 0, t0, 0, 0};
    *out = s;
    return FPL_OK;
}

fpl_integrator *fpl_spectrum_integrator(fpl_spectrum *s) { return s ? s->h : NULL; }

int fpl_spectrum_state(const fpl_spectrum *s, double *y)
{
    if (!s || !y) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/y: NULL pointer");
    memcpy(y, s->y, sizeof(double) * (size_t)s->len * (size_t)(s->k + 1));
    return FPL_OK;
}

int fpl_spectrum_done(const fpl_spectrum *s) { return s ? s->done : 1; }

int fpl_spectrum_get_result(const fpl_spectrum *s, fpl_spectrum_result *result)
{
    if (!s || !result) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/result: NULL pointer");
    *result = s->res;
    fpl_integrator_counters(s->h, &result->steps, NULL);
    return FPL_OK;
}

int fpl_spectrum_exponents(const fpl_spectrum *s, double *exponents)
{
    if (!s || !exponents) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/exponents: NULL pointer");
    const double span = s->res.t_final - s->t0;
    for (int i = 0; i < s->k; i++) exponents[i] = s->m > 0 ? s->logsum[i] / span : NAN;
    return FPL_OK;
}

int fpl_spectrum_last_r(const fpl_spectrum *s, double *r)
{
    if (!s || !r) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/r: NULL pointer");
    memcpy(r, s->r, sizeof(double) * (size_t)s->k * (size_t)s->k);
    return FPL_OK;
}

static double sample_target(const fpl_spectrum *s, int i)
{
    const int n = s->opt.n_samples;
    return n == 1 ? s->T : s->t_first * pow(s->T / s->t_first, (double)i / (n - 1));
}

static double renorm_time(const fpl_spectrum *s, long m)
{
    return m == s->n_renorm ? s->opt.t_end : s->t0 + (double)m * s->opt.renorm_interval;
}

/* Give the integrator the orthonormal vectors Q of time t. On the grid (or for an adaptive
 * method, which stops at t) they replace its deviation vectors. Between grid points of a
 * fixed-step method its state is the grid point t_g before t (t was reached by a partial step
 * from a copy), where the deviation vectors W_g satisfy Phi W_g = W(t) = Q R: they become
 * W_g R^-1, which the tangent map carries to Q (a linear map commutes with it). */
static int put_back(fpl_spectrum *s, double t)
{
    if (!(s->dt > 0.0) || !(t - fpl_integrator_time(s->h) > 1e-9 * s->dt))
        return fpl_integrator_set_deviations(s->h, s->y + s->len);
    const int k = s->k;
    const double *r = s->r;
    /* X = R^-1 (upper triangular) by back substitution, column by column; then
     * q_i = sum_j w_j X_ji, i.e. m[i][j] = X_ji */
    double *m = s->rinv;
    memset(m, 0, sizeof(double) * (size_t)k * (size_t)k);
    for (int c = 0; c < k; c++) {
        for (int i = c; i >= 0; i--) {
            double acc = i == c ? 1.0 : 0.0;
            for (int j = i + 1; j <= c; j++) acc -= r[(size_t)i * k + j] * m[(size_t)c * k + j];
            m[(size_t)c * k + i] = acc / r[(size_t)i * k + i];
        }
    }
    return fpl_integrator_transform_deviations(s->h, m);
}

int fpl_spectrum_advance(fpl_spectrum *s, double t_until, double *t_out, double *history_out)
{
    if (!s) return fpl_error(NULL, FPL_ERR_ARG, "spectrum: NULL handle");
    if (!(t_until == t_until)) return fpl_error(NULL, FPL_ERR_ARG, "t_until must not be NaN");
    const int k = s->k;
    int st = FPL_OK;
    while (!s->done) {
        const long m = s->m + 1;
        const double t = renorm_time(s, m);
        if (t > t_until) break;
        st = fpl_integrator_advance(s->h, t, s->y);
        if (st == FPL_EVENT) {
            s->done = 1;
            int index = 0;
            double t_event = t;
            fpl_integrator_event(s->h, &index, &t_event);
            return fpl_error(NULL, FPL_EVENT, "stopping criterion '%s' fired at t = %.10g",
                             fpl_integrator_event_describe(s->h, index), t_event);
        }
        if (st) return st;
        if ((st = orthonormalise(s, t))) return st;
        if ((st = put_back(s, t))) return st;
        for (int i = 0; i < k; i++) s->logsum[i] += log(s->r[(size_t)i * k + i]);
        s->m = m;
        s->res.n_renorm = m;
        s->res.t_final = t;
        const int n_samples = s->opt.n_samples;
        if (s->next < n_samples &&
            (t - s->t0 >= sample_target(s, s->next) * (1 - 1e-12) || m == s->n_renorm)) {
            const int i = s->res.n_samples;
            if (t_out) t_out[i] = t;
            if (history_out) fpl_spectrum_exponents(s, history_out + (size_t)i * k);
            s->res.n_samples++;
            while (s->next < n_samples && sample_target(s, s->next) <= (t - s->t0) * (1 + 1e-12))
                s->next++;
        }
        if (m == s->n_renorm) s->done = s->res.completed = 1;
    }
    return st;
}

int fpl_spectrum_n_accumulators(const fpl_spectrum *s)
{
    return s ? FPL_SPECTRUM_N_COUNTERS + s->k : 0;
}

/* Accumulators, in this order: m, next, n_samples, done, completed, then the k log-sums
 * (doubles hold the counts exactly up to 2^53). */
int fpl_spectrum_save(const fpl_spectrum *s, double *acc)
{
    if (!s || !acc) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/acc: NULL pointer");
    acc[0] = (double)s->m;
    acc[1] = s->next;
    acc[2] = s->res.n_samples;
    acc[3] = s->done;
    acc[4] = s->res.completed;
    memcpy(acc + FPL_SPECTRUM_N_COUNTERS, s->logsum, sizeof(double) * (size_t)s->k);
    return FPL_OK;
}

int fpl_spectrum_restore(fpl_spectrum *s, const double *acc)
{
    if (!s || !acc) return fpl_error(NULL, FPL_ERR_ARG, "spectrum/acc: NULL pointer");
    if (!(acc[0] >= 0 && acc[0] <= s->n_renorm) || acc[0] != floor(acc[0]) ||
        !(acc[1] >= 0 && acc[1] <= s->opt.n_samples) || !(acc[2] >= 0 && acc[2] <= s->opt.n_samples))
        return fpl_error(NULL, FPL_ERR_ARG, "spectrum accumulators do not fit this run "
                         "(renormalisation %g of %ld, sample %g of %d)", acc[0], s->n_renorm,
                         acc[2], s->opt.n_samples);
    const double t = renorm_time(s, (long)acc[0]);
    /* a fixed-step integrator is at the grid point at or before t */
    const double lag = t - fpl_integrator_time(s->h);
    if (s->dt > 0.0 ? !(lag >= -1e-9 * s->dt && lag < s->dt * (1 + 1e-9)) : lag != 0.0)
        return fpl_error(NULL, FPL_ERR_ARG, "spectrum accumulators are for t = %.17g, the "
                         "integrator is at t = %.17g (restore the integrator from the same "
                         "checkpoint first)", t, fpl_integrator_time(s->h));
    s->m = (long)acc[0];
    s->next = (int)acc[1];
    s->res.n_samples = (int)acc[2];
    s->done = acc[3] != 0;
    s->res.completed = acc[4] != 0;
    s->res.n_renorm = s->m;
    s->res.t_final = t;
    memcpy(s->logsum, acc + FPL_SPECTRUM_N_COUNTERS, sizeof(double) * (size_t)s->k);
    const int k = s->k;
    memset(s->r, 0, sizeof(double) * (size_t)k * (size_t)k);
    for (int i = 0; i < k; i++) s->r[(size_t)i * k + i] = 1.0;
    return FPL_OK;
}
