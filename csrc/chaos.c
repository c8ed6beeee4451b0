/* Chaos indicators (mLE, SALI, GALI) riding on any integrator: O(k^2 N) work per
 * renormalisation interval on top of the integration itself. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include "internal.h"
#include "chaos_terms.h"

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
    opt->blowup_stretch = 0.0;
}

/* Largest bond stretch of the orbit x (fixed ends x_0 = x_{N+1} = 0, or a ring: the
 * wrap-around bond x_0 - x_{N-1}); NaN if x is not finite (fmax would drop a NaN, so non-finite
 * values are propagated by hand). */
static double max_stretch(const double *x, int n, int ring)
{
    double s = ring ? fabs(x[0] - x[n - 1]) : fabs(x[0]), nonfinite = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        const double d = fabs(x[j + 1] - x[j]);
        s = d > s ? d : s;
        nonfinite += x[j] - x[j];        /* 0, or NaN as soon as one x_j is Inf/NaN */
    }
    if (!ring) s = fabs(x[n - 1]) > s ? fabs(x[n - 1]) : s;
    return s + nonfinite + (x[n - 1] - x[n - 1]);
}

const char *fpl_orbit_class_name(int orbit_class)
{
    switch (orbit_class) {
    case FPL_ORBIT_UNDECIDED: return "undecided";
    case FPL_ORBIT_REGULAR: return "regular";
    case FPL_ORBIT_CHAOTIC: return "chaotic";
    case FPL_ORBIT_BLOWUP: return "blow-up";
    default: return NULL;
    }
}

int fpl_chaos_classify(const fpl_chaos_result *r, const double *t, const double *mle, int n,
                       double t_eval, int *orbit_class)
{
    if (!r || !orbit_class) return fpl_error(NULL, FPL_ERR_ARG, "result/orbit_class: NULL pointer");
    if (n < 0) return fpl_error(NULL, FPL_ERR_ARG, "n must be >= 0 (got %d)", n);
    if (n > 0 && (!t || !mle)) return fpl_error(NULL, FPL_ERR_ARG, "t/mle: NULL pointer");
    if (t_eval != t_eval) t_eval = r->blew_up ? fmax(r->t_final, r->t_blowup) : r->t_final;
    if (!isfinite(t_eval))
        return fpl_error(NULL, FPL_ERR_ARG, "t_eval must be finite or NaN (got %g)", t_eval);
    /* blow-up and chaos are dated: whichever came first by t_eval decides (chaos is never set at
     * or after a blow-up, so at most one of them can be first) */
    if (r->blew_up && r->t_blowup <= t_eval) { *orbit_class = FPL_ORBIT_BLOWUP; return FPL_OK; }
    if (r->chaotic && r->t_chaotic <= t_eval) { *orbit_class = FPL_ORBIT_CHAOTIC; return FPL_OK; }
    *orbit_class = FPL_ORBIT_UNDECIDED;
    /* regular needs the run to have reached t_eval and enough samples of the last decade */
    if (!(r->t_final >= t_eval * (1 - 1e-12))) return FPL_OK;
    int last = -1;
    for (int i = 0; i < n; i++)
        if (t[i] <= t_eval * (1 + 1e-12)) last = i;
    if (last < 2) return FPL_OK;
    int first = last;
    while (first > 0 && t[first - 1] >= t[last] / 10) first--;
    const double lt_first = mle[first] * t[first], lt_last = mle[last] * t[last];
    if (!isfinite(lt_first) || !isfinite(lt_last)) return FPL_OK;
    /* regular: ln ||w|| grows like ln t (lambda ~ 1/t), at most ~ln 10 per decade plus slack;
     * chaotic orbits grow it linearly in t */
    if (lt_last <= 3.0 * fmax(lt_first, 1.0) + 2.0 * log(10.0)) *orbit_class = FPL_ORBIT_REGULAR;
    return FPL_OK;
}

/* The sums of chaos_terms.h on contiguous doubles (chaos_batch.c runs the same on lanes). */
#define AT_W(r) w[r]
#define AT_A(r) a[r]
#define AT_B(r) b[r]
#define AT_Q(i, r) q[(size_t)(i) * (size_t)len + (size_t)(r)]
#define SQRT_D(v) ((v) = sqrt(v))
#define NOTE_ZERO(r) (zero |= (r) == 0.0)

static double norm2(const double *w, long len)
{
    double s = 0.0;
    FPL_SUM_SQUARES(s, len, AT_W);
    return sqrt(s);
}

static double sali_unit(const double *a, const double *b, long len)
{
    double dm = 0.0, dp = 0.0;
    FPL_SALI_SUMS(dm, dp, len, AT_A, AT_B);
    return sqrt(fmin(dm, dp));
}

/* GALI_k of k unit vectors stored in q (overwritten), chaos_terms.h's modified Gram-Schmidt. */
static double gali_unit(double *q, int k, long len)
{
    double prod = 1.0;
    int zero = 0;
    FPL_GALI_MGS(k, len, AT_Q, prod, 0.0, SQRT_D, NOTE_ZERO);
    return zero ? 0.0 : prod;
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
    int mst = fpl_check_alloc((size_t)k * (size_t)len, sizeof(double), "GALI's k x len matrix");
    if (mst) return mst;
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
    if ((o->t_end - t0) / o->renorm_interval > 9e18)    /* unbounded work; n_renorm is a long */
        return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval = %g up to t_end = %g means %g "
                         "renormalisations, more than 9e18", o->renorm_interval, o->t_end,
                         (o->t_end - t0) / o->renorm_interval);
    if (o->n_samples < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_samples must be >= 1 (got %d)", o->n_samples);
    if (!(o->t_first_sample >= 0.0) || !isfinite(o->t_first_sample))
        return fpl_error(NULL, FPL_ERR_ARG, "t_first_sample must be finite and >= 0 (got %g)",
                         o->t_first_sample);
    if (o->n_dev < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 1 (got %d)", o->n_dev);
    if (!(o->sali_threshold >= 0.0) || !isfinite(o->sali_threshold))
        return fpl_error(NULL, FPL_ERR_ARG, "sali_threshold must be finite and >= 0 (got %g)",
                         o->sali_threshold);
    if (o->blowup_stretch != o->blowup_stretch || o->blowup_stretch == INFINITY)
        return fpl_error(NULL, FPL_ERR_ARG, "blowup_stretch must be finite (got %g; < 0 turns the "
                         "check off)", o->blowup_stretch);
    /* a renormalisation per step or more often would only repeat the work; and the count of
     * renormalisations must fit a long and stay exact in a double */
    const double n_renorm = (o->t_end - t0) / o->renorm_interval;
    if (!(n_renorm <= 9.0e15))
        return fpl_error(NULL, FPL_ERR_ARG, "t_end - t0 = %g needs %g renormalisations of "
                         "renorm_interval = %g: more than 9e15 (increase renorm_interval)",
                         o->t_end - t0, n_renorm, o->renorm_interval);
    return FPL_OK;
}

struct fpl_chaos {
    fpl_integrator *h;
    const fpl_lattice *lattice;
    fpl_chaos_options opt;
    double t0, T, t_first;
    long len, n_renorm;
    long m;               /* renormalisations done */
    double logsum;        /* sum of ln ||w_1|| over them */
    double stretch_limit; /* blow-up check at each renormalisation (0: none) */
    int n;                /* particles */
    int next;             /* next log-spaced sample index */
    int done;             /* t_end reached, stopped chaotic, or blew up */
    double t_pending;     /* SALI < threshold seen here, chaos not yet confirmed (NaN: none) */
    double megno_acc[3];  /* MEGNO (fpl_megno_step): the integrals of ell(s) = ln ||w_1(s)||
                             (unrenormalised) and of Y(s), and Y at the previous renormalisation */
    fpl_chaos_result res;
    double *y, *q, *scale;
};

void fpl_chaos_free(fpl_chaos **cp)
{
    if (!cp || !*cp) return;
    fpl_chaos *c = *cp;
    fpl_integrator_free(&c->h);
    free(c->y);
    free(c->q);
    free(c->scale);
    free(c);
    *cp = NULL;
}

int fpl_chaos_create(const fpl_lattice *lattice, const char *method,
                     const fpl_integrator_options *integrator_options, double t0, const double *y0,
                     const double *w0, const fpl_chaos_options *opt, fpl_chaos **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!opt) return fpl_error(NULL, FPL_ERR_ARG, "opt: NULL options");
    if (!y0) return fpl_error(NULL, FPL_ERR_ARG, "y0: NULL pointer");
    if (!isfinite(t0)) return fpl_error(NULL, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    int st = check_options(opt, t0);
    if (st) return st;
    const int k = opt->n_dev;
    const long len = 2L * lattice->n;
    long dim;
    if (k > len)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev = %d exceeds the phase-space dimension 2N = %ld",
                         k, len);
    if ((st = fpl_state_length(lattice->n, k, &dim)) ||
        (st = fpl_check_alloc((size_t)k * (size_t)k, sizeof(double), "the chaos run's n_dev^2 scales")))
        return st;
    fpl_chaos *c = calloc(1, sizeof *c);
    if (!c) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (chaos)");
    c->y = malloc(sizeof(double) * (size_t)dim);
    c->q = malloc(sizeof(double) * (size_t)(len * k));
    c->scale = calloc((size_t)k * (size_t)k, sizeof(double));
    if (!c->y || !c->q || !c->scale) {
        fpl_chaos_free(&c);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (chaos run, N = %d)", lattice->n);
    }
    double *y = c->y;
    memcpy(y, y0, sizeof(double) * (size_t)len);
    if (w0) {
        memcpy(y + len, w0, sizeof(double) * (size_t)(len * k));
    } else {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        if (!rng) { fpl_chaos_free(&c); return fpl_error(NULL, FPL_ERR_NOMEM, "RNG"); }
        gsl_rng_set(rng, opt->seed);
        for (long i = 0; i < len * k; i++) y[len + i] = gsl_ran_gaussian(rng, 1.0);
        gsl_rng_free(rng);
    }
    /* start from unit vectors so ln||w|| sums measure growth from 1 */
    for (int i = 0; i < k; i++) {
        double *w = y + len * (i + 1), n = norm2(w, len);
        if (!(n > 0.0) || !isfinite(n)) {
            fpl_chaos_free(&c);
            return fpl_error(NULL, FPL_ERR_ARG, "deviation vector w0[%d] must be finite and non-zero", i);
        }
        for (long col = 0; col < len; col++) w[col] /= n;
    }
    st = fpl_integrator_create(lattice, method, k, integrator_options, t0, y, &c->h);
    if (st) { fpl_chaos_free(&c); return st; }
    c->opt = *opt;
    c->n = lattice->n;
    c->lattice = lattice;
    /* automatic (0): the potential's nearest barrier, none if it has none (fpl_lattice_barrier) */
    const double barrier = fpl_barrier_stretch(lattice);
    c->stretch_limit = opt->blowup_stretch > 0 ? opt->blowup_stretch
                     : opt->blowup_stretch == 0 && isfinite(barrier) ? barrier : 0.0;
    {
        int order = 0, adaptive = 0;
        const double dt = integrator_options ? integrator_options->dt : 0.01;
        if (fpl_method_info(method, &order, &adaptive) == FPL_OK && !adaptive &&
            opt->renorm_interval < dt * (1 - 1e-12)) {
            fpl_chaos_free(&c);
            return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval = %g is smaller than the step "
                             "dt = %g (renormalise at most once per step)", opt->renorm_interval, dt);
        }
        /* the step count is a 64-bit integer and times t0 + n dt must stay exact */
        if (!adaptive && !((opt->t_end - t0) / dt <= 9.0e15)) {
            fpl_chaos_free(&c);
            return fpl_error(NULL, FPL_ERR_ARG, "t_end - t0 = %g needs %g steps of dt = %g: more "
                             "than the step counter holds exactly (9e15)", opt->t_end - t0,
                             (opt->t_end - t0) / dt, dt);
        }
    }
    c->t0 = t0;
    c->t_pending = NAN;
    c->len = len;
    c->T = opt->t_end - t0;
    c->t_first = opt->t_first_sample > 0.0 ? opt->t_first_sample : fmin(opt->renorm_interval, c->T);
    c->n_renorm = (long)ceil(c->T / opt->renorm_interval - 1e-9);
    c->res = (fpl_chaos_result){0, t0, NAN, NAN, NAN, 0, NAN, 0, 0, NAN, 0, NAN};
    *out = c;
    return FPL_OK;
}

fpl_integrator *fpl_chaos_integrator(fpl_chaos *c) { return c ? c->h : NULL; }

int fpl_chaos_done(const fpl_chaos *c) { return c ? c->done : 1; }

int fpl_chaos_get_result(const fpl_chaos *c, fpl_chaos_result *result)
{
    if (!c || !result) return fpl_error(NULL, FPL_ERR_ARG, "chaos/result: NULL pointer");
    *result = c->res;
    fpl_integrator_counters(c->h, &result->steps, NULL);
    return FPL_OK;
}

static double sample_target(const fpl_chaos *c, int i)
{
    const int n = c->opt.n_samples;
    return n == 1 ? c->T : c->t_first * pow(c->T / c->t_first, (double)i / (n - 1));
}

/* End the run as a blow-up at t: the class is decided (fpl_chaos_classify), the message says when
 * and why, and the status is informational (FPL_EVENT), like a stopping criterion. */
static int blew_up(fpl_chaos *c, double t, const char *fmt, ...)
{
    char msg[FPL_ERRMSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    c->res.blew_up = 1;
    c->res.t_blowup = t;
    c->done = 1;
    return fpl_error(NULL, FPL_EVENT, "%s", msg);
}

int fpl_chaos_advance(fpl_chaos *c, double t_until, double *t_out, double *mle_out,
                      double *sali_out, double *gali_out)
{
    return fpl_chaos_advance_megno(c, t_until, t_out, mle_out, sali_out, gali_out, NULL);
}

/* MEGNO from the log-growth ell of the first vector at the renormalisation times t_m (Cincotta &
 * Simo 2000): Y(t) = (2/t) int_0^t s dell(s) = 2 ell(t) - (2/t) int_0^t ell(s) ds (by parts), and
 * <Y>(t) = (1/t) int_0^t Y(s) ds, both integrals by the trapezoid rule on the renormalisation
 * grid (fpl_megno_step; exact for ell linear in s, which is what the limits need). ell = ln s
 * (regular: linear growth) gives Y = 2; ell = lambda s gives Y = lambda t and <Y> = lambda t / 2;
 * a stable periodic orbit gives 0. */
int fpl_chaos_advance_megno(fpl_chaos *c, double t_until, double *t_out, double *mle_out,
                            double *sali_out, double *gali_out, double *megno_out)
{
    if (!c) return fpl_error(NULL, FPL_ERR_ARG, "chaos: NULL handle");
    if (!(t_until == t_until)) return fpl_error(NULL, FPL_ERR_ARG, "t_until must not be NaN");
    const int k = c->opt.n_dev;
    const long len = c->len;
    const double tau = c->opt.renorm_interval;
    double *y = c->y, *q = c->q, *scale = c->scale;
    fpl_chaos_result *res = &c->res;
    int st = FPL_OK;
    while (!c->done && st == FPL_OK) {
        const long m = c->m + 1;
        double t = m == c->n_renorm ? c->opt.t_end : c->t0 + (double)m * tau;
        if (t > t_until) break;
        st = fpl_integrator_advance(c->h, t, y);
        if (st == FPL_EVENT) {            /* a stopping criterion (integrator_options->events) */
            int index = 0;
            double t_event = t;
            fpl_integrator_event(c->h, &index, &t_event);
            return blew_up(c, t_event, "blow-up: stopping criterion '%s' fired at t = %.10g",
                           fpl_integrator_event_describe(c->h, index), t_event);
        }
        if (st == FPL_ERR_NONFINITE)      /* the orbit itself overflowed within this interval */
            return blew_up(c, t, "blow-up: the state became non-finite before t = %.10g (%s)", t,
                           fpl_last_error());
        if (st) break;
        if (c->stretch_limit > 0) {       /* before SALI: a runaway orbit aligns the vectors */
            const double s = max_stretch(y, c->n, c->lattice->boundary == FPL_BOUNDARY_PERIODIC);
            if (!(s <= c->stretch_limit))
                return blew_up(c, t, "blow-up: a bond stretch |x_{j+1} - x_j| = %.4g exceeds %.4g "
                               "(%s) at t = %.10g", s, c->stretch_limit,
                               c->opt.blowup_stretch > 0 ? "blowup_stretch"
                                                         : "the potential's barrier", t);
        }
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
            for (long col = 0; col < len; col++) q[(size_t)i * len + col] = y[len * (i + 1) + col] / n;
        }
        if (st) break;
        {
            const double ell_prev = c->logsum;
            const double t_prev = c->m == 0 ? c->t0 : c->t0 + (double)c->m * tau;
            c->logsum += log(n1);
            res->megno = fpl_megno_step(c->megno_acc, t - t_prev, t - c->t0, ell_prev, c->logsum);
        }
        res->mle = c->logsum / (t - c->t0);
        res->t_final = t;
        if (k >= 2) {
            res->sali = sali_unit(q, q + len, len);
            res->gali = gali_unit(q, k, len); /* destroys q; SALI already taken */
            /* SALI below the threshold is confirmed as chaos at the next renormalisation if the
             * orbit is still finite and inside the barrier then (or at once at t_end): near a
             * blow-up the runaway direction aligns the vectors too, within an interval of the
             * overflow, and that is not chaos */
            if (!res->chaotic && c->t_pending == c->t_pending) {
                res->chaotic = 1;
                res->t_chaotic = c->t_pending;
            } else if (!res->chaotic && res->sali < c->opt.sali_threshold) {
                c->t_pending = t;
                if (m == c->n_renorm) {
                    res->chaotic = 1;
                    res->t_chaotic = t;
                }
            }
        }
        st = fpl_integrator_transform_deviations(c->h, scale);
        if (st) break;
        c->m = m;
        /* log-spaced output: t_first (T/t_first)^(i/(n-1)) after t0 */
        int stop = c->opt.stop_when_chaotic && res->chaotic;
        const int n_samples = c->opt.n_samples;
        if (c->next < n_samples &&
            (t - c->t0 >= sample_target(c, c->next) * (1 - 1e-12) || m == c->n_renorm || stop)) {
            if (t_out) t_out[res->n_samples] = t;
            if (mle_out) mle_out[res->n_samples] = res->mle;
            if (sali_out) sali_out[res->n_samples] = res->sali;
            if (gali_out) gali_out[res->n_samples] = res->gali;
            if (megno_out) megno_out[res->n_samples] = res->megno;
            res->n_samples++;
            while (c->next < n_samples && sample_target(c, c->next) <= (t - c->t0) * (1 + 1e-12))
                c->next++;
        }
        if (stop || m == c->n_renorm) c->done = c->res.completed = 1;
    }
    return st;
}

/* Accumulators, in this order: m, logsum, next, n_samples, chaotic, t_chaotic, mle, sali, gali,
 * t_final, done, blew_up, t_blowup, completed, t_pending, then MEGNO's ell_int, y_int, y_prev,
 * megno (doubles represent the counts exactly up to 2^53). */
int fpl_chaos_save(const fpl_chaos *c, double *acc)
{
    if (!c || !acc) return fpl_error(NULL, FPL_ERR_ARG, "chaos/acc: NULL pointer");
    const fpl_chaos_result *r = &c->res;
    const double a[FPL_CHAOS_N_ACCUMULATORS] = {
        (double)c->m, c->logsum, c->next, r->n_samples, r->chaotic, r->t_chaotic,
        r->mle, r->sali, r->gali, r->t_final, c->done, r->blew_up, r->t_blowup, r->completed,
        c->t_pending, c->megno_acc[0], c->megno_acc[1], c->megno_acc[2], r->megno};
    memcpy(acc, a, sizeof a);
    return FPL_OK;
}

int fpl_chaos_restore(fpl_chaos *c, const double *acc)
{
    if (!c || !acc) return fpl_error(NULL, FPL_ERR_ARG, "chaos/acc: NULL pointer");
    if (!(acc[0] >= 0 && acc[0] <= c->n_renorm) || acc[0] != floor(acc[0]) ||
        !(acc[2] >= 0 && acc[2] <= c->opt.n_samples) || !(acc[3] >= 0 && acc[3] <= c->opt.n_samples))
        return fpl_error(NULL, FPL_ERR_ARG, "chaos accumulators do not fit this run (renormalisation "
                         "%g of %ld, sample %g of %d)", acc[0], c->n_renorm, acc[3], c->opt.n_samples);
    const double t = acc[0] == c->n_renorm ? c->opt.t_end : c->t0 + acc[0] * c->opt.renorm_interval;
    if (acc[0] > 0 && fpl_integrator_time(c->h) != t)
        return fpl_error(NULL, FPL_ERR_ARG, "chaos accumulators are for t = %.17g, the integrator "
                         "is at t = %.17g (restore the integrator from the same checkpoint first)",
                         t, fpl_integrator_time(c->h));
    c->m = (long)acc[0];
    c->logsum = acc[1];
    c->next = (int)acc[2];
    c->res.n_samples = (int)acc[3];
    c->res.chaotic = acc[4] != 0;
    c->res.t_chaotic = acc[5];
    c->res.mle = acc[6];
    c->res.sali = acc[7];
    c->res.gali = acc[8];
    c->res.t_final = acc[9];
    c->done = acc[10] != 0;
    c->res.blew_up = acc[11] != 0;
    c->res.t_blowup = acc[12];
    c->res.completed = acc[13] != 0;
    c->t_pending = acc[14];
    c->megno_acc[0] = acc[15];
    c->megno_acc[1] = acc[16];
    c->megno_acc[2] = acc[17];
    c->res.megno = acc[18];
    return FPL_OK;
}

int fpl_chaos_run(const fpl_lattice *lattice, const char *method,
                  const fpl_integrator_options *integrator_options, double t0, const double *y0,
                  const double *w0, const fpl_chaos_options *opt, double *t_out, double *mle_out,
                  double *sali_out, double *gali_out, fpl_chaos_result *result)
{
    fpl_chaos *c = NULL;
    int st = fpl_chaos_create(lattice, method, integrator_options, t0, y0, w0, opt, &c);
    if (st) return st;
    st = fpl_chaos_advance(c, opt->t_end, t_out, mle_out, sali_out, gali_out);
    if (result) fpl_chaos_get_result(c, result);
    fpl_chaos_free(&c);
    return st;
}
