/* Shared part of the SUNDIALS back ends (see sundials_common.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sundials_common.h"

int fpl_sun_data_create(fpl_integrator *h, const char *package)
{
    fpl_sun_data *d = calloc(1, sizeof *d);
    if (!d) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (%s back end)", package);
    d->package = package;
    h->data = d; /* from here on, fpl_integrator_free calls the back end's release on failure */
    if (fpl_sun_context_create(&d->ctx, &d->logger, &d->err) != 0)
        return fpl_error(NULL, FPL_ERR_BACKEND, "%s %s: SUNContext_Create failed", package,
                         h->method->name);
    d->y = N_VNew_Serial((sunindextype)h->dim, d->ctx);
    if (!d->y) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (%s state vector)", package);
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    return FPL_OK;
}

void fpl_sun_data_free(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    if (!d) return;
    if (d->NLS) SUNNonlinSolFree(d->NLS);
    if (d->LS) SUNLinSolFree(d->LS);
    if (d->A) SUNMatDestroy(d->A);
    if (d->y) N_VDestroy(d->y);
    fpl_sun_context_free(&d->ctx, &d->logger);
    free(d);
    h->data = NULL;
}

int fpl_sun_setup_failed(fpl_integrator *h, const char *what, int flag)
{
    const fpl_sun_data *d = h->data;
    return fpl_error(NULL, FPL_ERR_BACKEND, "%s %s: %s failed (flag %d)%s%s",
                     d ? d->package : "SUNDIALS", h->method->name, what, flag,
                     d && d->err.msg[0] ? ": " : "", d ? d->err.msg : "");
}

int fpl_sun_classify(fpl_integrator *h, const fpl_sun_ops *ops, int flag, double tret,
                     double t_target, double *y_out)
{
    fpl_sun_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    const double *yv = N_VGetArrayPointer(d->y);
    const int finite = fpl_is_finite_array(yv, h->dim, NULL);
    if (flag == ops->root_return && finite) {
        int found[8] = {0};
        ops->root_info(d->mem, found);
        h->event_index = 0;
        for (int i = fpl_system_event_count(h->sys) - 1; i >= 0; i--)
            if (found[i]) h->event_index = i;
        memcpy(h->y, yv, bytes);
        h->t = tret;
        memcpy(y_out, yv, bytes);
        return FPL_EVENT;
    }
    if (flag >= 0 && finite) {
        memcpy(h->y, yv, bytes);
        h->t = t_target;
        memcpy(y_out, yv, bytes);
        return FPL_OK;
    }

    /* Failure. On error the solver returns its last accepted state (at tret): keep it if
     * finite, so the handle holds the latest good state; then restart the solver from there. */
    const double t_start = h->t;
    if (flag < 0 && finite && tret > h->t && tret < t_target) {
        memcpy(h->y, yv, bytes);
        h->t = tret;
    }
    char *name = ops->flag_name(flag);
    char flag_name[32];
    snprintf(flag_name, sizeof flag_name, "%s", name ? name : "?");
    free(name);
    char sun_msg[sizeof d->err.msg];
    memcpy(sun_msg, d->err.msg, sizeof sun_msg);
    ops->restart(h);
    /* fpl_sun_rhs returns 1 (recoverable) only for a non-finite state; the solvers report it
     * as one of the right-hand-side errors. */
    if (!finite || flag == ops->rhs_errors[0] || flag == ops->rhs_errors[1] ||
        flag == ops->rhs_errors[2])
        return fpl_error(NULL, FPL_ERR_NONFINITE,
                         "state became non-finite between t = %.10g and t = %.10g (%s %s, "
                         "started at t = %.10g: flag %d (%s)%s%s)",
                         h->t, t_target, d->package, h->method->name, t_start, flag, flag_name,
                         sun_msg[0] ? ": " : "", sun_msg);
    return fpl_error(NULL, FPL_ERR_BACKEND, "%s %s failed at t = %.10g: flag %d (%s): %s",
                     d->package, h->method->name, tret, flag, flag_name,
                     sun_msg[0] ? sun_msg : "(no message)");
}
