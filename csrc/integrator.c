/* The generic integrator handle: method registry, validation, sampling and streaming. The
 * numerical work is done by the back ends (backend_*.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "integrator_impl.h"

/* ---- method registry ------------------------------------------------------------------- */

#define MAX_METHODS 64
static fpl_method splitting_methods[MAX_METHODS];

/* Splitting methods are one per scheme table; build their entries on first use. Plain static
 * data filled idempotently with identical values, so concurrent first calls are harmless. */
static int n_splitting_methods(void)
{
    int n = fpl_splitting_count();
    for (int i = 0; i < n && i < MAX_METHODS; i++) {
        const fpl_splitting *s = fpl_splitting_at(i);
        splitting_methods[i] = (fpl_method){s->name, s->order, &fpl_backend_splitting, s};
    }
    return n;
}

static const fpl_method *const *other_tables(void)
{
    static const fpl_method *const tables[] = {fpl_methods_arkode, fpl_methods_cvode,
                                               fpl_methods_gsl, fpl_methods_sprk, NULL};
    return tables;
}

static const fpl_method *method_at(int index)
{
    int ns = n_splitting_methods();
    if (index < 0) return NULL;
    if (index < ns) return &splitting_methods[index];
    index -= ns;
    for (const fpl_method *const *t = other_tables(); *t; t++)
        for (const fpl_method *m = *t; m->name; m++)
            if (index-- == 0) return m;
    return NULL;
}

int fpl_method_count(void)
{
    int n = 0;
    while (method_at(n)) n++;
    return n;
}

const char *fpl_method_name(int index)
{
    const fpl_method *m = method_at(index);
    return m ? m->name : NULL;
}

static const fpl_method *find_method(const char *name)
{
    for (int i = 0;; i++) {
        const fpl_method *m = method_at(i);
        if (!m) return NULL;
        if (strcmp(m->name, name) == 0) return m;
    }
}

static int unknown_method(const char *name)
{
    int missing = fpl_sprk_missing(name);
    if (missing) return missing;
    char known[512] = "";
    for (int i = 0; method_at(i); i++) {
        if (i) strncat(known, ", ", sizeof known - strlen(known) - 1);
        strncat(known, method_at(i)->name, sizeof known - strlen(known) - 1);
    }
    return fpl_error(NULL, FPL_ERR_UNKNOWN, "method '%s' is unknown (known: %s)", name, known);
}

int fpl_method_info(const char *name, int *order, int *adaptive)
{
    if (!name) return fpl_error(NULL, FPL_ERR_ARG, "method: NULL name");
    const fpl_method *m = find_method(name);
    if (!m) return unknown_method(name);
    if (order) *order = m->order;
    if (adaptive) *adaptive = m->backend->adaptive;
    return FPL_OK;
}

/* ---- handle ---------------------------------------------------------------------------- */

void fpl_integrator_options_init(fpl_integrator_options *opt)
{
    if (!opt) return;
    opt->dt = 0.01;
    opt->rtol = 1e-10;
    opt->atol = 1e-12;
    opt->max_steps = 0;
    opt->compensated_sums = 0;
    opt->events = NULL;
}

/* Record an error on the integrator handle (the thread-local message is set by fpl_error). */
static int fail(fpl_integrator *h, int status)
{
    if (h) {
        strncpy(h->errmsg, fpl_last_error(), sizeof h->errmsg - 1);
        h->errmsg[sizeof h->errmsg - 1] = '\0';
    }
    return status;
}

int fpl_integrator_create(const fpl_lattice *lattice, const char *method, int n_dev,
                          const fpl_integrator_options *opt, double t0, const double *y0,
                          fpl_integrator **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!method) return fpl_error(NULL, FPL_ERR_ARG, "method: NULL name");
    const fpl_method *m = find_method(method);
    if (!m) return unknown_method(method);
    long dim;
    int sst = fpl_state_length(fpl_lattice_size(lattice), n_dev, &dim);
    if (sst) return sst;
    if (!isfinite(t0)) return fpl_error(NULL, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    if (!y0) return fpl_error(NULL, FPL_ERR_ARG, "y0: NULL pointer");
    fpl_integrator_options o;
    fpl_integrator_options_init(&o);
    if (opt) o = *opt;
    if (!m->backend->adaptive) {
        if (!(o.dt > 0.0) || !isfinite(o.dt))
            return fpl_error(NULL, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", o.dt);
    } else {
        if (!(o.dt >= 0.0) || !isfinite(o.dt))
            return fpl_error(NULL, FPL_ERR_ARG,
                             "dt (initial step) must be finite and >= 0 (got %g)", o.dt);
        if (!(o.rtol > 0.0) || !isfinite(o.rtol))
            return fpl_error(NULL, FPL_ERR_ARG, "rtol must be finite and > 0 (got %g)", o.rtol);
        if (!(o.atol > 0.0) || !isfinite(o.atol))
            return fpl_error(NULL, FPL_ERR_ARG, "atol must be finite and > 0 (got %g)", o.atol);
    }
    if (o.max_steps < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "max_steps must be >= 0 (got %ld)", o.max_steps);
    if (o.compensated_sums && !m->backend->set_compensation)
        return fpl_error(NULL, FPL_ERR_ARG, "compensated_sums applies only to ARKODE's SPRKStep "
                         "methods (sprk-*), not to '%s'", m->name);
    o.compensated_sums = o.compensated_sums != 0;
    if (o.max_steps == 0) o.max_steps = 100000000L;
    long bad = -1;
    if (!fpl_is_finite_array(y0, dim, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "y0[%ld] is not finite (%g)", bad, y0[bad]);

    fpl_system *sys = NULL;
    int st = fpl_system_create(lattice, o.events, &sys);
    if (st) return st;
    o.events = NULL; /* copied into sys; the caller's set need not outlive the call */
    fpl_integrator *h = calloc(1, sizeof *h);
    if (!h) {
        fpl_system_free(&sys);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating the integrator");
    }
    h->lat = lattice;
    h->sys = sys;
    h->method = m;
    h->n_dev = n_dev;
    h->dim = dim;
    h->t0 = h->t = t0;
    h->opt = o;
    h->y = malloc(sizeof(double) * (size_t)dim);
    h->scratch = malloc(sizeof(double) * (size_t)dim);
    if (!h->y || !h->scratch) {
        fpl_integrator_free(&h);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (state of length %ld)", dim);
    }
    memcpy(h->y, y0, sizeof(double) * (size_t)dim);
    st = m->backend->init(h);
    if (st) {
        fpl_integrator_free(&h);
        return st;
    }
    *out = h;
    return FPL_OK;
}

void fpl_integrator_free(fpl_integrator **integrator)
{
    if (!integrator || !*integrator) return;
    fpl_integrator *h = *integrator;
    if (h->data && h->method->backend->release) h->method->backend->release(h);
    free(h->y);
    free(h->scratch);
    fpl_system_free(&h->sys);
    free(h);
    *integrator = NULL;
}

const char *fpl_integrator_errmsg(const fpl_integrator *h) { return h ? h->errmsg : "integrator: NULL handle"; }
const char *fpl_integrator_method(const fpl_integrator *h) { return h ? h->method->name : ""; }
int fpl_integrator_n_dev(const fpl_integrator *h) { return h ? h->n_dev : 0; }
double fpl_integrator_time(const fpl_integrator *h) { return h ? h->t : NAN; }

int fpl_integrator_get_state(const fpl_integrator *h, double *y)
{
    if (!h || !y) return fpl_error(NULL, FPL_ERR_ARG, "integrator/y: NULL pointer");
    memcpy(y, h->y, sizeof(double) * (size_t)h->dim);
    return FPL_OK;
}

int fpl_integrator_counters(const fpl_integrator *h, long *steps, long *force_evals)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    if (steps) *steps = h->n_steps;
    if (force_evals) *force_evals = h->n_force;
    return FPL_OK;
}

int fpl_integrator_event(const fpl_integrator *h, int *index, double *t)
{
    if (!h) return 0;
    if (index) *index = h->stopped ? h->event_index : -1;
    if (t) *t = h->stopped ? h->t : NAN;
    return h->stopped;
}

int fpl_integrator_event_count(const fpl_integrator *h) { return h ? h->sys->events.n : 0; }

const char *fpl_integrator_event_describe(const fpl_integrator *h, int index)
{
    return h ? fpl_system_event_describe(h->sys, index) : "";
}

int fpl_integrator_events_eval(fpl_integrator *h, const double *y, double *g)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    if (!y || !g) return fail(h, fpl_error(NULL, FPL_ERR_ARG, "y/g: NULL pointer"));
    fpl_events_eval(h->lat, h->sys->work, &h->sys->events, y, g);
    return FPL_OK;
}

/* Advance through the back end; after an event the integrator stays where it stopped. */
static int backend_advance(fpl_integrator *h, double t_target, double *y_out)
{
    if (h->stopped)
        return fpl_error(NULL, FPL_ERR_ARG, "the integrator was stopped by an event (%s) at t = %.17g",
                         fpl_system_event_describe(h->sys, h->event_index), h->t);
    int st = h->method->backend->advance(h, t_target, y_out);
    if (st == FPL_EVENT) {
        h->stopped = 1;
        memcpy(y_out, h->y, sizeof(double) * (size_t)h->dim);
        fpl_error(NULL, FPL_EVENT, "event: %s at t = %.17g",
                  fpl_system_event_describe(h->sys, h->event_index), h->t);
    }
    return st;
}

int fpl_integrator_advance(fpl_integrator *h, double t_target, double *y_out)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    if (!isfinite(t_target) || t_target < h->t)
        return fail(h, fpl_error(NULL, FPL_ERR_ARG,
                                 "t_target = %.17g must be finite and >= the current time %.17g",
                                 t_target, h->t));
    double *out = y_out ? y_out : h->scratch;
    int st = backend_advance(h, t_target, out);
    return st != 0 ? fail(h, st) : st;
}

long fpl_integrator_steps(const fpl_integrator *h) { return h ? h->n_steps : -1; }

int fpl_integrator_set_budget(fpl_integrator *h, double seconds)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    if (!(seconds >= 0.0) || !isfinite(seconds))
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "seconds must be finite and >= 0 (got %g)",
                                 seconds));
    h->budget = seconds;
    return FPL_OK;
}

int fpl_integrator_restore(fpl_integrator *h, long n_steps, double t, const double *y)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    if (!y) return fail(h, fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer"));
    if (n_steps < 0)
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "n_steps must be >= 0 (got %ld)", n_steps));
    if (!isfinite(t) || t < h->t0)
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "t = %.17g must be finite and >= t0 = %.17g",
                                 t, h->t0));
    if (!h->method->backend->adaptive && t != h->t0 + (double)n_steps * h->opt.dt)
        return fail(h, fpl_error(NULL, FPL_ERR_ARG,
                                 "t = %.17g is not t0 + n_steps dt = %.17g (checkpoint of another "
                                 "run or step?)", t, h->t0 + (double)n_steps * h->opt.dt));
    long bad;
    if (!fpl_is_finite_array(y, h->dim, &bad))
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "y[%ld] is not finite", bad));
    memcpy(h->y, y, sizeof(double) * (size_t)h->dim);
    h->n_steps = n_steps;
    h->t = t;
    h->stopped = 0;
    int st = h->method->backend->reset ? h->method->backend->reset(h) : FPL_OK;
    if (st >= 0 && h->opt.compensated_sums) h->method->backend->set_compensation(h, NULL);
    return st < 0 ? fail(h, st) : st;
}

static int no_compensation(const fpl_integrator *h)
{
    return fpl_error(NULL, FPL_ERR_ARG, "integrator (method %s) does not use compensated sums "
                     "(compensated_sums = 0)", h->method->name);
}

int fpl_integrator_get_compensation(const fpl_integrator *h, double *carry)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    if (!carry) return fpl_error(NULL, FPL_ERR_ARG, "carry: NULL pointer");
    if (!h->opt.compensated_sums) return no_compensation(h);
    return h->method->backend->get_compensation(h, carry);
}

int fpl_integrator_set_compensation(fpl_integrator *h, const double *carry)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    if (!carry) return fail(h, fpl_error(NULL, FPL_ERR_ARG, "carry: NULL pointer"));
    if (!h->opt.compensated_sums) return fail(h, no_compensation(h));
    long bad;
    if (!fpl_is_finite_array(carry, h->dim, &bad))
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "carry[%ld] is not finite", bad));
    return h->method->backend->set_compensation(h, carry);
}

int fpl_integrator_transform_deviations(fpl_integrator *h, const double *m)
{
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    if (!m) return fail(h, fpl_error(NULL, FPL_ERR_ARG, "m: NULL pointer"));
    const int k = h->n_dev;
    if (k == 0) return FPL_OK;
    long bad;
    if (!fpl_is_finite_array(m, (long)k * k, &bad))
        return fail(h, fpl_error(NULL, FPL_ERR_ARG, "m[%ld] is not finite", bad));
    const long len = h->dim / (k + 1);
    double *w = h->y + len, *tmp = h->scratch;
    for (int i = 0; i < k; i++) {
        double *row = tmp + (size_t)i * len;
        for (long c = 0; c < len; c++) row[c] = 0.0;
        for (int j = 0; j < k; j++) {
            const double mij = m[(size_t)i * k + j];
            const double *wj = w + (size_t)j * len;
            for (long c = 0; c < len; c++) row[c] += mij * wj[c];
        }
    }
    memcpy(w, tmp, sizeof(double) * (size_t)(len * k));
    int st = h->method->backend->reset ? h->method->backend->reset(h) : FPL_OK;
    return st < 0 ? fail(h, st) : st;
}

int fpl_integrator_set_deviations(fpl_integrator *h, const double *w)
{
    const int k = h->n_dev;
    if (k == 0) return FPL_OK;
    const long len = h->dim / (k + 1);
    memcpy(h->y + len, w, sizeof(double) * (size_t)(len * k));
    int st = h->method->backend->reset ? h->method->backend->reset(h) : FPL_OK;
    return st < 0 ? fail(h, st) : st;
}

static int check_samples(fpl_integrator *h, const double *ts, int n)
{
    if (n < 0) return fpl_error(NULL, FPL_ERR_ARG, "n_samples must be >= 0 (got %d)", n);
    if (n > 0 && !ts) return fpl_error(NULL, FPL_ERR_ARG, "t_samples: NULL pointer");
    for (int i = 0; i < n; i++) {
        double prev = i ? ts[i - 1] : h->t;
        if (!isfinite(ts[i]) || ts[i] < prev)
            return fpl_error(NULL, FPL_ERR_ARG,
                             "t_samples[%d] = %.17g: sample times must be finite, >= the current "
                             "time %.17g and non-decreasing", i, ts[i], h->t);
    }
    return FPL_OK;
}

int fpl_integrator_sample(fpl_integrator *h, const double *t_samples, int n_samples,
                          double *states, double *mode_energies, double *energies, int *n_done)
{
    if (n_done) *n_done = 0;
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    int st = check_samples(h, t_samples, n_samples);
    if (st) return fail(h, st);
    const int n = fpl_lattice_size(h->lat);
    double *y = h->scratch;
    for (int i = 0; i < n_samples; i++) {
        st = backend_advance(h, t_samples[i], y);
        if (st != 0) return fail(h, st);
        double *ek = mode_energies ? mode_energies + (size_t)i * n : NULL;
        if (ek && (st = fpl_modes_energies_work(h->lat, h->sys->work, y, ek)) != 0)
            return fail(h, st);
        double e = 0.0;
        if (energies) e = h->lat->ops->energy(h->lat, y);
        /* a finite but huge state can still overflow its energies */
        if ((ek && !fpl_is_finite_array(ek, n, NULL)) || (energies && !isfinite(e)))
            return fail(h, fpl_error(NULL, FPL_ERR_NONFINITE,
                                     "energies overflowed at t = %.10g (blow-up)", t_samples[i]));
        if (energies) energies[i] = e;
        if (states) memcpy(states + (size_t)i * h->dim, y, sizeof(double) * (size_t)h->dim);
        if (n_done) *n_done = i + 1;
    }
    return FPL_OK;
}

int fpl_integrator_run(fpl_integrator *h, const double *t_samples, int n_samples,
                       fpl_sample_fn callback, void *ctx, int *n_done)
{
    if (n_done) *n_done = 0;
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    h->errmsg[0] = '\0';
    if (!callback) return fail(h, fpl_error(NULL, FPL_ERR_ARG, "callback: NULL function"));
    int st = check_samples(h, t_samples, n_samples);
    if (st) return fail(h, st);
    for (int i = 0; i < n_samples; i++) {
        st = backend_advance(h, t_samples[i], h->scratch);
        if (st != 0) return fail(h, st);
        if (n_done) *n_done = i + 1;
        if (callback(ctx, t_samples[i], h->scratch, h->n_dev)) return FPL_EVENT;
    }
    return FPL_OK;
}
