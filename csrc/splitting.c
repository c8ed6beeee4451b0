/* Splitting schemes: the generic drift/kick step, the scheme registry and the fixed-step run
 * loop. Each scheme's coefficient table lives in its own file under integrators/. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

static const fpl_splitting *const schemes[] = {
    &fpl_scheme_leapfrog,
    &fpl_scheme_yoshida4,
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
static void drift(const fpl_lattice *lat, double *y, int n_dev, double h)
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

void fpl_step_aba(const fpl_splitting *scheme, fpl_lattice *lat, double *y, int n_dev, double dt)
{
    const int s = scheme->n_kicks;
    for (int i = 0; i < s; i++) {
        drift(lat, y, n_dev, scheme->drift[i] * dt);
        lat->ops->kick(lat, y, n_dev, scheme->kick[i] * dt);
    }
    drift(lat, y, n_dev, scheme->drift[s] * dt);
}

static int check_step(fpl_lattice *lat, double dt)
{
    if (!(dt > 0.0) || !isfinite(dt))
        return fpl_error(lat, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", dt);
    return FPL_OK;
}

int fpl_splitting_advance(const fpl_splitting *scheme, fpl_lattice *lattice, double *y, int n_dev,
                          double dt, long nsteps)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    fpl_error_clear(lattice);
    if (!scheme) return fpl_error(lattice, FPL_ERR_ARG, "scheme: NULL");
    if (!y) return fpl_error(lattice, FPL_ERR_ARG, "y: NULL pointer");
    if (n_dev < 0) return fpl_error(lattice, FPL_ERR_ARG, "n_dev must be >= 0 (got %d)", n_dev);
    if (nsteps < 0)
        return fpl_error(lattice, FPL_ERR_ARG, "nsteps must be >= 0 (got %ld)", nsteps);
    int st = check_step(lattice, dt);
    if (st) return st;
    long len = 2L * lattice->n * (n_dev + 1), bad = -1;
    if (!fpl_is_finite_array(y, len, &bad))
        return fpl_error(lattice, FPL_ERR_ARG, "y[%ld] is not finite (%g)", bad, y[bad]);
    for (long k = 0; k < nsteps; k++)
        scheme->step(scheme, lattice, y, n_dev, dt);
    if (!fpl_is_finite_array(y, len, &bad))
        return fpl_error(lattice, FPL_ERR_NONFINITE,
                         "state became non-finite (y[%ld] = %g) within %ld steps of dt = %g", bad,
                         y[bad], nsteps, dt);
    return FPL_OK;
}

/* How often (in steps) the run loop looks for NaN/Inf between samples, so that a blow-up is
 * caught early and located in time. */
#define FINITE_CHECK_INTERVAL 1024

int fpl_splitting_run(const fpl_splitting *scheme, fpl_lattice *lattice, const double *y0,
                      double t0, double dt, const double *t_samples, int n_samples,
                      double *mode_energies, double *energies, double *states, int *n_done)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    fpl_error_clear(lattice);
    if (n_done) *n_done = 0;
    if (!scheme) return fpl_error(lattice, FPL_ERR_ARG, "method: NULL scheme");
    if (!y0) return fpl_error(lattice, FPL_ERR_ARG, "y0: NULL pointer");
    if (!isfinite(t0)) return fpl_error(lattice, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    int st = check_step(lattice, dt);
    if (st) return st;
    if (n_samples < 0)
        return fpl_error(lattice, FPL_ERR_ARG, "n_samples must be >= 0 (got %d)", n_samples);
    if (n_samples > 0 && !t_samples)
        return fpl_error(lattice, FPL_ERR_ARG, "t_samples: NULL pointer");
    for (int i = 0; i < n_samples; i++) {
        double prev = i ? t_samples[i - 1] : t0;
        if (!isfinite(t_samples[i]) || t_samples[i] < prev)
            return fpl_error(lattice, FPL_ERR_ARG,
                             "t_samples[%d] = %g: sample times must be finite, >= t0 and "
                             "non-decreasing", i, t_samples[i]);
        if ((t_samples[i] - t0) / dt > 1e17)
            return fpl_error(lattice, FPL_ERR_ARG,
                             "t_samples[%d] = %g needs more than 1e17 steps of dt = %g", i,
                             t_samples[i], dt);
    }
    const int n = lattice->n;
    const long len = 2L * n;
    long bad = -1;
    if (!fpl_is_finite_array(y0, len, &bad))
        return fpl_error(lattice, FPL_ERR_ARG, "y0[%ld] is not finite (%g)", bad, y0[bad]);

    double *y = malloc(sizeof(double) * (size_t)len * 2);
    if (!y) return fpl_error(lattice, FPL_ERR_NOMEM, "out of memory (state of N = %d)", n);
    double *partial = y + len;
    memcpy(y, y0, sizeof(double) * (size_t)len);

    long step = 0;                 /* the trajectory is at t0 + step*dt */
    double t_finite = t0;          /* last time the state was seen finite */
    int done = 0;
    st = FPL_OK;
    for (int i = 0; i < n_samples && st == FPL_OK; i++) {
        double target = (t_samples[i] - t0) / dt;
        long n_target = (long)floor(target + 1e-9);
        while (step < n_target) {
            long chunk = n_target - step;
            if (chunk > FINITE_CHECK_INTERVAL) chunk = FINITE_CHECK_INTERVAL;
            for (long k = 0; k < chunk; k++)
                scheme->step(scheme, lattice, y, 0, dt);
            step += chunk;
            if (!fpl_is_finite_array(y, len, NULL)) {
                st = fpl_error(lattice, FPL_ERR_NONFINITE,
                               "state became non-finite between t = %.10g and t = %.10g "
                               "(blow-up or dt = %g too large)", t_finite, t0 + step * dt, dt);
                break;
            }
            t_finite = t0 + step * dt;
        }
        if (st) break;
        const double *sample = y;
        double rest = (target - (double)n_target) * dt;
        if (rest > 1e-9 * dt) {
            memcpy(partial, y, sizeof(double) * (size_t)len);
            scheme->step(scheme, lattice, partial, 0, rest);
            sample = partial;
            if (!fpl_is_finite_array(partial, len, NULL)) {
                st = fpl_error(lattice, FPL_ERR_NONFINITE,
                               "state became non-finite between t = %.10g and t = %.10g "
                               "(blow-up or dt = %g too large)", t_finite, t_samples[i], dt);
                break;
            }
        }
        if (mode_energies) {
            st = fpl_modes_energies(lattice, sample, mode_energies + (size_t)i * n);
            if (st) break;
        }
        if (energies) energies[i] = lattice->ops->energy(lattice, sample);
        if (states) memcpy(states + (size_t)i * len, sample, sizeof(double) * (size_t)len);
        /* a finite but huge state can still overflow its energies */
        if ((mode_energies && !fpl_is_finite_array(mode_energies + (size_t)i * n, n, NULL)) ||
            (energies && !isfinite(energies[i]))) {
            st = fpl_error(lattice, FPL_ERR_NONFINITE,
                           "energies overflowed at t = %.10g (blow-up)", t_samples[i]);
            break;
        }
        done = i + 1;
    }
    free(y);
    if (n_done) *n_done = done;
    return st;
}
