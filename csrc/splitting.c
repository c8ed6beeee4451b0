/* Splitting schemes: the scheme registry, the one drift/kick step and fixed-step grid driver for
 * every second-order system (the lattice here; the Galerkin truncation and the two-mode ODE in
 * reduction.c), and the lattice as such a system. Each scheme's coefficient table lives in its
 * own file under integrators/. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

static const fpl_splitting *const schemes[] = {
    &fpl_scheme_leapfrog,
    &fpl_scheme_yoshida4,
    &fpl_scheme_aba864,
    &fpl_scheme_aba864_harmonic,
    &fpl_scheme_srkn14a6,
    &fpl_scheme_dprkn8,
    &fpl_scheme_dprkn12,
};
#define N_SCHEMES ((int)(sizeof schemes / sizeof schemes[0]))

int fpl_splitting_count(void) { return N_SCHEMES; }

const fpl_splitting *fpl_splitting_at(int index)
{
    return index >= 0 && index < N_SCHEMES ? schemes[index] : NULL;
}

const char *fpl_splitting_name(const fpl_splitting *scheme) { return scheme ? scheme->name : ""; }
int fpl_splitting_order(const fpl_splitting *scheme) { return scheme ? scheme->order : 0; }
int fpl_splitting_stages(const fpl_splitting *scheme) { return scheme ? scheme->n_kicks : 0; }

int fpl_splitting_lookup(const char *name, const fpl_splitting **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!name) return fpl_error(NULL, FPL_ERR_ARG, "method: NULL name");
    for (int i = 0; i < N_SCHEMES; i++) {
        if (strcmp(schemes[i]->name, name) == 0) {
            *out = schemes[i];
            return FPL_OK;
        }
    }
    char known[256] = "";
    for (int i = 0; i < N_SCHEMES; i++) {
        strncat(known, schemes[i]->name, sizeof known - strlen(known) - 1);
        if (i + 1 < N_SCHEMES) strncat(known, ", ", sizeof known - strlen(known) - 1);
    }
    return fpl_error(NULL, FPL_ERR_UNKNOWN, "method '%s' is unknown (known: %s)", name, known);
}

void fpl_split_step(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                    double dt)
{
    if (sys->steps) {
        sys->steps(scheme, sys->ctx, y, dt, 1);
        return;
    }
    const int s = scheme->n_kicks;
    if (sys->begin_step) sys->begin_step(sys->ctx, scheme, dt);
    for (int i = 0; i < s; i++) {
        sys->drift(sys->ctx, y, i, scheme->drift[i] * dt);
        sys->kick(sys->ctx, y, scheme->kick[i] * dt);
    }
    sys->drift(sys->ctx, y, s, scheme->drift[s] * dt);
}

void fpl_split_steps(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                     double dt, long n)
{
    if (sys->steps)
        sys->steps(scheme, sys->ctx, y, dt, n);
    else
        for (long k = 0; k < n; k++) fpl_split_step(scheme, sys, y, dt);
}

int fpl_split_grid_advance(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                           double *backup, long *step, long n_target, double dt, long *step_bad)
{
    const size_t bytes = sizeof(double) * (size_t)sys->dim;
    while (*step < n_target) {
        long chunk = n_target - *step;
        if (chunk > FPL_FINITE_CHECK_INTERVAL) chunk = FPL_FINITE_CHECK_INTERVAL;
        memcpy(backup, y, bytes);
        fpl_split_steps(scheme, sys, y, dt, chunk);
        if (!fpl_is_finite_array(y, sys->dim, NULL)) {
            memcpy(y, backup, bytes);
            *step_bad = *step + chunk;
            return FPL_ERR_NONFINITE;
        }
        *step += chunk;
    }
    return FPL_OK;
}

/* ---- the lattice as a split system --------------------------------------------------------- */

int fpl_split_run_init(fpl_split_run *run, const fpl_splitting *scheme, const fpl_lattice *lat,
                       fpl_work *work, int n_dev)
{
    *run = (fpl_split_run){{lat, work, n_dev}, scheme, NULL, {0, NULL, NULL, NULL, NULL, NULL}};
    run->sys = (fpl_split_system){2L * lat->n * (n_dev + 1), lat->ops->drift, lat->ops->kick,
                                  NULL, run, lat->ops->steps};
    return scheme->run_setup ? scheme->run_setup(scheme, run) : FPL_OK;
}

void fpl_split_run_release(fpl_split_run *run)
{
    if (run->state && run->scheme->state_free) run->scheme->state_free(run->state);
    run->state = NULL;
}

int fpl_splitting_advance(const fpl_splitting *scheme, const fpl_lattice *lattice, double *y,
                          int n_dev, double dt, long nsteps)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!scheme) return fpl_error(NULL, FPL_ERR_ARG, "scheme: NULL");
    if (!y) return fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer");
    long len;
    int sst = fpl_state_length(lattice->n, n_dev, &len);
    if (sst) return sst;
    if (nsteps < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "nsteps must be >= 0 (got %ld)", nsteps);
    if (!(dt > 0.0) || !isfinite(dt))
        return fpl_error(NULL, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", dt);
    long bad = -1;
    if (!fpl_is_finite_array(y, len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "y[%ld] is not finite (%g)", bad, y[bad]);
    fpl_work *work = NULL;
    int st = fpl_work_create(lattice->n, 0, &work);
    if (!st) st = fpl_work_reserve_vectors(work, n_dev);
    if (st) {
        fpl_work_free(&work);
        return st;
    }
    fpl_split_run run;
    st = fpl_split_run_init(&run, scheme, lattice, work, n_dev);
    if (!st) {
        fpl_split_steps(scheme, &run.sys, y, dt, nsteps);
        if (!fpl_is_finite_array(y, len, &bad))
            st = fpl_error(NULL, FPL_ERR_NONFINITE,
                           "state became non-finite (y[%ld] = %g) within %ld steps of dt = %g",
                           bad, y[bad], nsteps, dt);
    }
    fpl_split_run_release(&run);
    fpl_work_free(&work);
    return st;
}
