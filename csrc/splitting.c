/* Splitting schemes: the generic drift/kick step, the scheme registry and the fixed-step run
 * loop. Each scheme's coefficient table lives in its own file under integrators/. */
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

/* x^(m) += h minv p^(m) for the orbit and every deviation vector (the drift is linear, so its
 * tangent map is itself). */
FPL_HOT static void drift(const fpl_lattice *lat, double *y, int n_dev, double h)
{
    const int n = lat->n;
    const double *restrict minv = lat->minv;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict x = y + 2 * (size_t)n * m;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++)
            x[i] += h * minv[i] * p[i];
    }
}

void fpl_step_aba(const fpl_split_run *run, double *y, int n_dev, double dt)
{
    const fpl_splitting *scheme = run->scheme;
    const fpl_lattice *lat = run->lat;
    const int s = scheme->n_kicks;
    for (int i = 0; i < s; i++) {
        drift(lat, y, n_dev, scheme->drift[i] * dt);
        lat->ops->kick(lat, run->work, y, n_dev, scheme->kick[i] * dt);
    }
    drift(lat, y, n_dev, scheme->drift[s] * dt);
}

int fpl_split_run_init(fpl_split_run *run, const fpl_splitting *scheme, const fpl_lattice *lat,
                       fpl_work *work)
{
    *run = (fpl_split_run){scheme, lat, work, NULL};
    return scheme->state_create ? scheme->state_create(scheme, lat, &run->state) : FPL_OK;
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
    if (n_dev < 0) return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 0 (got %d)", n_dev);
    if (nsteps < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "nsteps must be >= 0 (got %ld)", nsteps);
    if (!(dt > 0.0) || !isfinite(dt))
        return fpl_error(NULL, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", dt);
    long len = 2L * lattice->n * (n_dev + 1), bad = -1;
    if (!fpl_is_finite_array(y, len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "y[%ld] is not finite (%g)", bad, y[bad]);
    fpl_work *work = NULL;
    int st = fpl_work_create(lattice->n, 0, &work);
    if (st) return st;
    fpl_split_run run;
    st = fpl_split_run_init(&run, scheme, lattice, work);
    if (!st) {
        for (long k = 0; k < nsteps; k++)
            scheme->step(&run, y, n_dev, dt);
        if (!fpl_is_finite_array(y, len, &bad))
            st = fpl_error(NULL, FPL_ERR_NONFINITE,
                           "state became non-finite (y[%ld] = %g) within %ld steps of dt = %g",
                           bad, y[bad], nsteps, dt);
    }
    fpl_split_run_release(&run);
    fpl_work_free(&work);
    return st;
}
