/* Stopping criteria for blow-up detection: g_i(y) > 0 while fine, crossing zero when firing. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "internal.h"

int fpl_lattice_set_events(fpl_lattice *lattice, const fpl_event_set *events)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    fpl_error_clear(lattice);
    if (!events || events->n == 0) {
        memset(&lattice->events, 0, sizeof lattice->events);
        return FPL_OK;
    }
    if (events->n < 0 || events->n > 8)
        return fpl_error(lattice, FPL_ERR_ARG, "events: n must be in 0..8 (got %d)", events->n);
    for (int i = 0; i < events->n; i++) {
        int kind = events->kind[i];
        double thr = events->threshold[i];
        if (kind < FPL_EVENT_ENERGY || kind > FPL_EVENT_MODE_ENERGY)
            return fpl_error(lattice, FPL_ERR_UNKNOWN, "events: kind[%d] = %d is unknown", i, kind);
        if (!(thr > 0.0) || !isfinite(thr))
            return fpl_error(lattice, FPL_ERR_ARG,
                             "events: threshold[%d] must be finite and > 0 (got %g)", i, thr);
        if (kind == FPL_EVENT_MODE_ENERGY && (events->mode[i] < 0 || events->mode[i] > lattice->n))
            return fpl_error(lattice, FPL_ERR_ARG, "events: mode[%d] must be in 0..N = %d (got %d)",
                             i, lattice->n, events->mode[i]);
    }
    lattice->events = *events;
    for (int i = 0; i < events->n; i++) {
        char *d = lattice->event_desc[i];
        double thr = events->threshold[i];
        switch (events->kind[i]) {
        case FPL_EVENT_ENERGY: snprintf(d, 96, "energy > %g", thr); break;
        case FPL_EVENT_MAX_DISPLACEMENT: snprintf(d, 96, "max |x_j| > %g", thr); break;
        case FPL_EVENT_MAX_STRETCH: snprintf(d, 96, "max |x_{j+1} - x_j| > %g", thr); break;
        default:
            if (events->mode[i] == 0) snprintf(d, 96, "max_k E_k > %g", thr);
            else snprintf(d, 96, "E_%d > %g", events->mode[i], thr);
        }
    }
    return FPL_OK;
}

int fpl_lattice_event_count(const fpl_lattice *lattice) { return lattice ? lattice->events.n : 0; }

const char *fpl_lattice_event_describe(const fpl_lattice *lattice, int index)
{
    if (!lattice || index < 0 || index >= lattice->events.n) return "";
    return lattice->event_desc[index];
}

void fpl_events_eval(fpl_lattice *lat, const double *y, double *g)
{
    const int n = lat->n;
    const fpl_event_set *ev = &lat->events;
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
            value = fmax(fabs(y[0]), fabs(y[n - 1]));
            for (int j = 1; j < n; j++) value = fmax(value, fabs(y[j] - y[j - 1]));
            break;
        default:
            if (!have_modes) {
                fpl_modes_energies(lat, y, lat->ek);
                have_modes = 1;
            }
            if (ev->mode[i] > 0) value = lat->ek[ev->mode[i] - 1];
            else
                for (int k = 0; k < n; k++) value = fmax(value, lat->ek[k]);
        }
        /* NaN/Inf counts as fired: a state that has left the finite numbers is past any bound */
        g[i] = isfinite(value) ? ev->threshold[i] - value : -INFINITY;
    }
}

int fpl_lattice_events_eval(fpl_lattice *lattice, const double *y, double *g)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!y || !g) return fpl_error(lattice, FPL_ERR_ARG, "y/g: NULL pointer");
    fpl_events_eval(lattice, y, g);
    return FPL_OK;
}
