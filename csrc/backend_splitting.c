/* Back end for our fixed-step splitting schemes: the state stays on the grid t0 + n dt. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "integrator_impl.h"

typedef struct split_data {
    fpl_split_run run;    /* the lattice as a split system (with the integrator's workspace and
                             n_dev), and the scheme's state */
    double *start;        /* dim: last finite state / start of the current block */
} split_data;

static int split_init(fpl_integrator *h)
{
    split_data *d = calloc(1, sizeof *d);
    if (!d) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (splitting back end)");
    h->data = d;
    int st = fpl_split_run_init(&d->run, h->method->data, h->lat, h->sys->work, h->n_dev);
    if (!st) st = fpl_work_reserve_vectors(h->sys->work, h->n_dev);
    if (st) return st;
    d->start = malloc(sizeof(double) * (size_t)h->dim);
    if (!d->start) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (splitting back end)");
    return FPL_OK;
}

static void split_release(fpl_integrator *h)
{
    split_data *d = h->data;
    fpl_split_run_release(&d->run);
    free(d->start);
    free(d);
    h->data = NULL;
}

/* min_i g_i of the orbit in y, -inf if the orbit is not finite; *which gets the argmin. */
static double event_min(fpl_integrator *h, const double *y, int *which)
{
    double g[8];
    if (!fpl_is_finite_array(y, 2L * h->lat->n, NULL)) {
        *which = 0;
        return -INFINITY;
    }
    fpl_events_eval(h->lat, h->sys->work, &h->sys->events, y, g);
    double best = g[0];
    *which = 0;
    for (int i = 1; i < h->sys->events.n; i++)
        if (g[i] < best) { best = g[i]; *which = i; }
    return best;
}

/* An event fired inside the step from y_start (time t_start, already in h->scratch-free buffer
 * `start`) of length dt: find the first zero of G(s) = min_i g_i(Phi_s(y_start)) for s in (0, dt]
 * by the Illinois method (bisection while G is not finite), leave the event state in h->y. */
static int locate_event(fpl_integrator *h, const double *start, double dt, double g_a, double *work)
{
    const fpl_split_run *run = &((const split_data *)h->data)->run;
    const fpl_splitting *s = run->scheme;
    const double t_start = h->t;
    double a = 0.0, b = dt, ga = g_a, gb = -INFINITY;
    int which = 0, side = 0;
    const double tol = 1e-13 * fmax(fabs(t_start) + dt, 1.0);
    for (int it = 0; it < 300 && b - a > tol; it++) {
        double m;
        if (isfinite(gb)) {
            m = (a * gb - b * ga) / (gb - ga);            /* regula falsi */
            if (!(m > a && m < b)) m = 0.5 * (a + b);
        } else {
            m = 0.5 * (a + b);                             /* G(b) = -inf: bisect */
        }
        memcpy(work, start, sizeof(double) * (size_t)h->dim);
        fpl_split_step(s, &run->sys, work, m);
        h->n_force += s->n_kicks;
        double gm = event_min(h, work, &which);
        if (gm > 0.0) {
            a = m; ga = gm;
            if (side == 1 && isfinite(gb)) gb *= 0.5;      /* Illinois: avoid one-sided stalls */
            side = 1;
        } else {
            b = m; gb = gm;
            if (side == -1) ga *= 0.5;
            side = -1;
        }
    }
    /* the event state: the earliest point found past the crossing */
    memcpy(h->y, start, sizeof(double) * (size_t)h->dim);
    fpl_split_step(s, &run->sys, h->y, b);
    h->n_force += s->n_kicks;
    double gfinal = event_min(h, h->y, &which);
    if (!isfinite(gfinal)) {
        /* The state left the finite numbers before any criterion reached zero: that is an
         * integration failure, not an event. Keep the last finite grid state (start). */
        memcpy(h->y, start, sizeof(double) * (size_t)h->dim);
        return fpl_error(NULL, FPL_ERR_NONFINITE,
                         "state became non-finite near t = %.10g before any stopping criterion "
                         "fired (blow-up too fast for dt = %g, or a NaN)", t_start + a, dt);
    }
    h->event_index = which;
    h->t = t_start + b;
    return FPL_EVENT;
}

/* Criteria are evaluated every FPL_EVENT_BLOCK steps (internal.h); a block in which one fired
 * is replayed step by step from its start to find the step, then refined inside it. A criterion
 * that crosses and uncrosses within one block (FPL_EVENT_BLOCK dt) is not seen. */

static int split_advance_events(fpl_integrator *h, long n_target, double *work)
{
    split_data *d = h->data;
    const fpl_split_run *run = &d->run;
    const fpl_splitting *s = run->scheme;
    const double dt = h->opt.dt;
    double *start = d->start;
    int which;
    double g = event_min(h, h->y, &which);
    if (g <= 0.0) {
        h->event_index = which;
        return FPL_EVENT;
    }
    while (h->n_steps < n_target) {
        long block = n_target - h->n_steps;
        if (block > FPL_EVENT_BLOCK) block = FPL_EVENT_BLOCK;
        memcpy(start, h->y, sizeof(double) * (size_t)h->dim);
        fpl_split_steps(s, &run->sys, h->y, dt, block);
        double g_new = event_min(h, h->y, &which);
        if (g_new <= 0.0) {
            /* replay the block one step at a time */
            memcpy(h->y, start, sizeof(double) * (size_t)h->dim);
            for (long k = 0; k < block; k++) {
                memcpy(start, h->y, sizeof(double) * (size_t)h->dim);
                fpl_split_step(s, &run->sys, h->y, dt);
                g_new = event_min(h, h->y, &which);
                if (g_new <= 0.0) {
                    memcpy(h->y, start, sizeof(double) * (size_t)h->dim);
                    return locate_event(h, start, dt, g, work);
                }
                g = g_new;
                h->n_steps++;
                h->n_force += s->n_kicks;
                h->t = h->t0 + (double)h->n_steps * dt;
            }
            continue; /* crossed and uncrossed within the block: nothing fired at its end */
        }
        if (h->n_dev && !fpl_is_finite_array(h->y, h->dim, NULL)) {
            memcpy(h->y, start, sizeof(double) * (size_t)h->dim);
            return fpl_error(NULL, FPL_ERR_NONFINITE,
                             "deviation vectors became non-finite between t = %.10g and t = %.10g",
                             h->t, h->t + (double)block * dt);
        }
        g = g_new;
        h->n_steps += block;
        h->n_force += block * s->n_kicks;
        h->t = h->t0 + (double)h->n_steps * dt;
    }
    return FPL_OK;
}

static int split_advance(fpl_integrator *h, double t_target, double *y_out)
{
    split_data *d = h->data;
    const fpl_split_run *run = &d->run;
    const fpl_splitting *s = run->scheme;
    const double dt = h->opt.dt;
    double *backup = d->start;
    const double target = (t_target - h->t0) / dt;
    if (target > 9e18)
        return fpl_error(NULL, FPL_ERR_ARG, "t_target = %g needs more than 9e18 steps of dt = %g",
                         t_target, dt);
    /* Grid index counted from t0, never accumulated: no drift over 1e10 steps. */
    const long n_target = (long)floor(target + 1e-9);
    if (h->sys->events.n > 0) {
        int st = split_advance_events(h, n_target, y_out);
        if (st) return st;
    }
    const long start = h->n_steps;
    long bad = 0;
    int st = fpl_split_grid_advance(s, &run->sys, h->y, backup, &h->n_steps, n_target, dt, &bad);
    h->n_force += (h->n_steps - start) * s->n_kicks;
    if (h->n_steps != start) h->t = h->t0 + (double)h->n_steps * dt;
    if (st)
        return fpl_error(NULL, FPL_ERR_NONFINITE,
                         "state became non-finite between t = %.10g and t = %.10g "
                         "(blow-up, or dt = %g too large)", h->t, h->t0 + (double)bad * dt, dt);
    memcpy(y_out, h->y, sizeof(double) * (size_t)h->dim);
    const double rest = t_target - h->t;
    if (rest > 1e-9 * dt) {
        fpl_split_step(s, &run->sys, y_out, rest);
        h->n_force += s->n_kicks;
        if (h->sys->events.n > 0) {
            int which;
            if (event_min(h, y_out, &which) <= 0.0) {
                memcpy(backup, h->y, sizeof(double) * (size_t)h->dim);
                double g0 = event_min(h, backup, &which);
                return locate_event(h, backup, rest, g0, y_out);
            }
        }
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
