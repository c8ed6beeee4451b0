/* Adaptive back end on GSL odeiv2: "gsl-rk8pd", the embedded Prince-Dormand 8(9) pair
 * (gsl_odeiv2_step_rk8pd) with the standard error control (|err_i| <= atol + rtol |y_i|).
 * An implementation independent of SUNDIALS, for cross-checks. Every GSL odeiv2 call of the
 * library lives in this file.
 *
 * gsl_odeiv2_evolve_apply with t1 = t_target shortens the last step so that t == t_target
 * exactly. A non-finite stage makes the right-hand side return GSL_EBADFUNC; the step is then
 * retried a few times with a smaller step before the failure is reported. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include "integrator_impl.h"

/* Retries, each with a 10x smaller step, after a non-finite stage before giving up. */
#define BADFUNC_RETRIES 8

typedef struct gsl_data {
    gsl_odeiv2_system sys;
    gsl_odeiv2_step *step;
    gsl_odeiv2_control *control;
    gsl_odeiv2_evolve *evolve;
    double *y;                  /* working state; h->y keeps the last good state */
    double hstep;               /* step size carried between advances */
} gsl_data;

/* y' = f(y) in GSL's form; params is the integrator handle. */
static int gsl_rhs(double t, const double y[], double dydt[], void *params)
{
    (void)t;
    fpl_integrator *h = params;
    h->n_force++;
    if (!fpl_is_finite_array(y, h->dim, NULL)) return GSL_EBADFUNC;
    fpl_kernel_rhs(h->lat, h->sys->work, y, h->n_dev, dydt);
    return GSL_SUCCESS;
}

static void gsl_release(fpl_integrator *h)
{
    gsl_data *d = h->data;
    if (!d) return;
    if (d->evolve) gsl_odeiv2_evolve_free(d->evolve);
    if (d->control) gsl_odeiv2_control_free(d->control);
    if (d->step) gsl_odeiv2_step_free(d->step);
    free(d->y);
    free(d);
    h->data = NULL;
}

/* Initial step when none is given: h0 = 0.01 |y| / |f(y)| in the error norm (Hairer,
 * Norsett & Wanner, Sec. II.4), with a fallback for a state at rest. */
static double initial_step(fpl_integrator *h, double *f)
{
    fpl_kernel_rhs(h->lat, h->sys->work, h->y, h->n_dev, f);
    h->n_force++;
    double d0 = 0.0, d1 = 0.0;
    for (long i = 0; i < h->dim; i++) {
        const double sc = h->opt.atol + h->opt.rtol * fabs(h->y[i]);
        d0 += (h->y[i] / sc) * (h->y[i] / sc);
        d1 += (f[i] / sc) * (f[i] / sc);
    }
    d0 = sqrt(d0 / (double)h->dim);
    d1 = sqrt(d1 / (double)h->dim);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    return isfinite(h0) && h0 > 0.0 ? h0 : 1e-6;
}

static int gsl_init(fpl_integrator *h)
{
    gsl_set_error_handler_off(); /* never abort (also done by lattice creation) */
    if (fpl_system_event_count(h->sys) > 0) /* silently ignoring them would be wrong */
        return fpl_error(NULL, FPL_ERR_ARG, "method gsl-rk8pd does not support stopping criteria "
                         "(events); use a splitting, ARKODE or CVODE method");
    gsl_data *d = calloc(1, sizeof *d);
    if (!d) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (GSL back end)");
    h->data = d; /* from here on, fpl_integrator_free calls gsl_release on failure */
    const size_t dim = (size_t)h->dim;
    d->y = malloc(sizeof(double) * dim);
    d->step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, dim);
    d->control = gsl_odeiv2_control_standard_new(h->opt.atol, h->opt.rtol, 1.0, 0.0);
    d->evolve = gsl_odeiv2_evolve_alloc(dim);
    if (!d->y || !d->step || !d->control || !d->evolve)
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (GSL rk8pd, dimension %zu)", dim);
    d->sys = (gsl_odeiv2_system){gsl_rhs, NULL, dim, h};
    /* h->scratch is free during creation */
    d->hstep = h->opt.dt > 0.0 ? h->opt.dt : initial_step(h, h->scratch);
    return FPL_OK;
}

static void gsl_restart(gsl_data *d)
{
    gsl_odeiv2_evolve_reset(d->evolve);
    gsl_odeiv2_step_reset(d->step);
}

static int gsl_reset(fpl_integrator *h)
{
    gsl_restart(h->data);
    return FPL_OK;
}

static int gsl_advance(fpl_integrator *h, double t_target, double *y_out)
{
    gsl_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    const double t_start = h->t;
    memcpy(d->y, h->y, bytes);
    double t = h->t;
    long steps = 0;
    int retries = 0;
    while (t < t_target) {
        if (steps >= h->opt.max_steps) {
            memcpy(h->y, d->y, bytes); /* the state reached is good: keep it */
            h->t = t;
            return fpl_error(NULL, FPL_ERR_BACKEND,
                             "GSL %s failed at t = %.10g: max_steps = %ld steps taken "
                             "before reaching t = %.10g (started at t = %.10g)",
                             h->method->name, t, h->opt.max_steps, t_target, t_start);
        }
        if (!(d->hstep > 0.0)) d->hstep = 1e-6; /* never hand GSL a zero or NaN step */
        const double h_before = d->hstep;
        const int shortened = t_target - t < h_before; /* GSL cuts this step to end on t1 */
        const int st = gsl_odeiv2_evolve_apply(d->evolve, d->control, d->step, &d->sys, &t,
                                               t_target, &d->hstep, d->y);
        if (st == GSL_SUCCESS && fpl_is_finite_array(d->y, h->dim, NULL)) {
            /* a step cut short to land on a sample time says nothing about the step size */
            if (shortened && t == t_target && d->hstep < h_before) d->hstep = h_before;
            steps++;
            h->n_steps++;
            retries = 0;
            memcpy(h->y, d->y, bytes);
            h->t = t;
            continue;
        }
        /* t and y are restored to the start of the failed step on error; a successful step
         * that overflowed is undone here */
        if (st == GSL_SUCCESS) {
            memcpy(d->y, h->y, bytes);
            t = h->t;
        }
        gsl_restart(d);
        if ((st == GSL_SUCCESS || st == GSL_EBADFUNC) && retries < BADFUNC_RETRIES) {
            retries++;
            d->hstep *= 0.1;
            continue;
        }
        if (st == GSL_SUCCESS || st == GSL_EBADFUNC)
            return fpl_error(NULL, FPL_ERR_NONFINITE,
                             "state became non-finite between t = %.10g and t = %.10g (GSL %s, "
                             "started at t = %.10g: %s, after %d step reductions)",
                             h->t, t_target, h->method->name, t_start, gsl_strerror(GSL_EBADFUNC), retries);
        return fpl_error(NULL, FPL_ERR_BACKEND,
                         "GSL %s failed at t = %.10g: error %d (%s), step size %g",
                         h->method->name, h->t, st, gsl_strerror(st), d->hstep);
    }
    h->t = t_target; /* evolve_apply ends on t1 exactly */
    memcpy(y_out, h->y, bytes);
    return FPL_OK;
}

static const fpl_backend backend_gsl = {
    .family = "gsl",
    .adaptive = 1,
    .init = gsl_init,
    .advance = gsl_advance,
    .reset = gsl_reset,
    .release = gsl_release,
};

const fpl_method fpl_methods_gsl[] = {
    {"gsl-rk8pd", 8, &backend_gsl, NULL},
    {NULL, 0, NULL, NULL},
};
