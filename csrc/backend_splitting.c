/* Back end for our fixed-step splitting schemes: the state stays on the grid t0 + n dt. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "integrator_impl.h"

/* How often (in steps) to look for NaN/Inf: a blow-up is caught early, placed in time, and the
 * state rolled back to the last finite checkpoint (a copy every chunk costs ~1/1000 of the work). */
#define FINITE_CHECK_INTERVAL 1024

static int split_init(fpl_integrator *h)
{
    h->data = malloc(sizeof(double) * (size_t)h->dim); /* last finite state */
    if (!h->data) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (splitting back end)");
    return FPL_OK;
}

static void split_release(fpl_integrator *h)
{
    free(h->data);
    h->data = NULL;
}

static int split_advance(fpl_integrator *h, double t_target, double *y_out)
{
    const fpl_splitting *s = h->method->data;
    const double dt = h->opt.dt;
    double *backup = h->data;
    const double target = (t_target - h->t0) / dt;
    if (target > 9e18)
        return fpl_error(NULL, FPL_ERR_ARG, "t_target = %g needs more than 9e18 steps of dt = %g",
                         t_target, dt);
    /* Grid index counted from t0, never accumulated: no drift over 1e10 steps. */
    const long n_target = (long)floor(target + 1e-9);
    while (h->n_steps < n_target) {
        long chunk = n_target - h->n_steps;
        if (chunk > FINITE_CHECK_INTERVAL) chunk = FINITE_CHECK_INTERVAL;
        memcpy(backup, h->y, sizeof(double) * (size_t)h->dim);
        for (long k = 0; k < chunk; k++)
            s->step(s, h->lat, h->y, h->n_dev, dt);
        if (!fpl_is_finite_array(h->y, h->dim, NULL)) {
            memcpy(h->y, backup, sizeof(double) * (size_t)h->dim);
            return fpl_error(NULL, FPL_ERR_NONFINITE,
                             "state became non-finite between t = %.10g and t = %.10g "
                             "(blow-up, or dt = %g too large)",
                             h->t, h->t0 + (double)(h->n_steps + chunk) * dt, dt);
        }
        h->n_steps += chunk;
        h->n_force += chunk * s->n_kicks;
        h->t = h->t0 + (double)h->n_steps * dt;
    }
    memcpy(y_out, h->y, sizeof(double) * (size_t)h->dim);
    const double rest = t_target - h->t;
    if (rest > 1e-9 * dt) {
        s->step(s, h->lat, y_out, h->n_dev, rest);
        h->n_force += s->n_kicks;
        if (!fpl_is_finite_array(y_out, h->dim, NULL))
            return fpl_error(NULL, FPL_ERR_NONFINITE,
                             "state became non-finite between t = %.10g and t = %.10g "
                             "(blow-up, or dt = %g too large)", h->t, t_target, dt);
    }
    return FPL_OK;
}

const fpl_backend fpl_backend_splitting = {
    .family = "splitting",
    .adaptive = 0,
    .init = split_init,
    .advance = split_advance,
    .reset = NULL,
    .release = split_release,
};
