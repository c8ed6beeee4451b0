/* Stopping criteria for blow-up detection: g_i(y) > 0 while fine, crossing zero when firing;
 * and fpl_system, the {lattice, criteria, workspace} of one run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

int fpl_events_check(const fpl_event_set *events, int n)
{
    if (!events) return FPL_OK;
    if (events->n < 0 || events->n > 8)
        return fpl_error(NULL, FPL_ERR_ARG, "events: n must be in 0..8 (got %d)", events->n);
    for (int i = 0; i < events->n; i++) {
        int kind = events->kind[i];
        double thr = events->threshold[i];
        if (kind < FPL_EVENT_ENERGY || kind > FPL_EVENT_MODE_ENERGY)
            return fpl_error(NULL, FPL_ERR_UNKNOWN, "events: kind[%d] = %d is unknown", i, kind);
        if (!(thr > 0.0) || !isfinite(thr))
            return fpl_error(NULL, FPL_ERR_ARG,
                             "events: threshold[%d] must be finite and > 0 (got %g)", i, thr);
        if (kind == FPL_EVENT_MODE_ENERGY && (events->mode[i] < 0 || events->mode[i] > n))
            return fpl_error(NULL, FPL_ERR_ARG, "events: mode[%d] must be in 0..N = %d (got %d)",
                             i, n, events->mode[i]);
    }
    return FPL_OK;
}

void fpl_events_describe(const fpl_event_set *events, int index, char *d, size_t size)
{
    const double thr = events->threshold[index];
    switch (events->kind[index]) {
    case FPL_EVENT_ENERGY: snprintf(d, size, "energy > %g", thr); break;
    case FPL_EVENT_MAX_DISPLACEMENT: snprintf(d, size, "max |x_j| > %g", thr); break;
    case FPL_EVENT_MAX_STRETCH: snprintf(d, size, "max |x_{j+1} - x_j| > %g", thr); break;
    default:
        if (events->mode[index] == 0) snprintf(d, size, "max_k E_k > %g", thr);
        else snprintf(d, size, "E_%d > %g", events->mode[index], thr);
    }
}

void fpl_events_eval(const fpl_lattice *lat, fpl_work *work, const fpl_event_set *ev,
                     const double *y, double *g)
{
    const int n = lat->n;
    int have_modes = 0;
    for (int i = 0; i < ev->n; i++) {
        double value = 0.0;
        switch (ev->kind[i]) {
        case FPL_EVENT_ENERGY:
            value = lat->ops->energy(lat, y);
            break;
        case FPL_EVENT_MAX_DISPLACEMENT:
            for (int j = 0; j < n; j++) value = fmax(value, fabs(y[j]));
            break;
        case FPL_EVENT_MAX_STRETCH:
            /* the bonds to the walls, or the ring's wrap-around bond */
            value = lat->boundary == FPL_BOUNDARY_PERIODIC ? fabs(y[0] - y[n - 1])
                                                            : fmax(fabs(y[0]), fabs(y[n - 1]));
            for (int j = 1; j < n; j++) value = fmax(value, fabs(y[j] - y[j - 1]));
            break;
        default:
            if (!have_modes) {
                fpl_modes_energies_work(lat, work, y, work->ek);
                have_modes = 1;
            }
            /* fixed ends: mode k at index k-1; a ring: wavenumber k at index k */
            if (ev->mode[i] > 0)
                value = work->ek[ev->mode[i] - (lat->boundary == FPL_BOUNDARY_PERIODIC ? 0 : 1)];
            else
                for (int k = 0; k < n; k++) value = fmax(value, work->ek[k]);
        }
        /* NaN/Inf counts as fired: a state that has left the finite numbers is past any bound */
        g[i] = isfinite(value) ? ev->threshold[i] - value : -INFINITY;
    }
}

/* ---- fpl_system ----------------------------------------------------------------------------- */

int fpl_system_create(const fpl_lattice *lattice, const fpl_event_set *events, fpl_system **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    int st = fpl_events_check(events, lattice->n);
    if (st) return st;
    /* a ring's modes are wavenumbers 0..N-1 (E_0 the constant centre-of-mass energy) */
    for (int i = 0; events && i < events->n; i++)
        if (lattice->boundary == FPL_BOUNDARY_PERIODIC && events->kind[i] == FPL_EVENT_MODE_ENERGY &&
            events->mode[i] >= lattice->n)
            return fpl_error(NULL, FPL_ERR_ARG, "events: mode[%d] must be a wavenumber in 1..N-1 = "
                             "%d for a periodic chain, or 0 for the maximum (got %d)", i,
                             lattice->n - 1, events->mode[i]);
    fpl_system *sys = calloc(1, sizeof *sys);
    if (!sys) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating the system");
    st = fpl_work_create(lattice->n, FPL_WORK_MODES_OF(lattice), &sys->work);
    if (st) {
        free(sys);
        return st;
    }
    sys->lat = lattice;
    if (events) sys->events = *events;
    for (int i = 0; i < sys->events.n; i++)
        fpl_events_describe(&sys->events, i, sys->event_desc[i], sizeof sys->event_desc[i]);
    *out = sys;
    return FPL_OK;
}

void fpl_system_free(fpl_system **system)
{
    if (!system || !*system) return;
    fpl_work_free(&(*system)->work);
    free(*system);
    *system = NULL;
}

const char *fpl_system_errmsg(const fpl_system *system)
{
    return system ? system->errmsg : "system: NULL handle";
}

const fpl_lattice *fpl_system_lattice(const fpl_system *system)
{
    return system ? system->lat : NULL;
}

int fpl_system_event_count(const fpl_system *system) { return system ? system->events.n : 0; }

const char *fpl_system_event_describe(const fpl_system *system, int index)
{
    if (!system || index < 0 || index >= system->events.n) return "";
    return system->event_desc[index];
}

int fpl_system_events_eval(fpl_system *system, const double *y, double *g)
{
    if (!system) return fpl_error(NULL, FPL_ERR_ARG, "system: NULL handle");
    system->errmsg[0] = '\0';
    if (!y || !g) return fpl_error(system->errmsg, FPL_ERR_ARG, "y/g: NULL pointer");
    fpl_events_eval(system->lat, system->work, &system->events, y, g);
    return FPL_OK;
}
