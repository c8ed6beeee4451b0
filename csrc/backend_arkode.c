/* Adaptive explicit Runge-Kutta back end: ARKODE ERKStep (SUNDIALS 6.x) with built-in tables
 * (Dormand-Prince 5(4), Verner 6(5), Fehlberg 8(7)) and Hairer's DOP853 as a custom table
 * (tables/dop853.c). Every ARKODE call of the library lives in this file. Tables are passed
 * through fsal_safe(), which works around an ERKStep 6.4 FSAL bug (see there).
 *
 * The solver integrates the orbit and its variational equations together (fpl_sun_rhs reads
 * n_dev from the vector length), so the step-size control also covers the deviation vectors.
 * Each advance sets the stop time to the target: the state lands on t_target (ARKODE's step
 * ends within a few ulps of it), never interpolated across a step. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>
#include "fputlab/sundials.h"
#include "integrator_impl.h"

ARKodeButcherTable fpl_dop853_table(void); /* tables/dop853.c */

typedef struct ark_method {
    int custom_dop853;          /* 1: our DOP853 table; 0: the built-in table below */
    ARKODE_ERKTableID table;
} ark_method;

typedef struct ark_data {
    SUNContext ctx;
    N_Vector y;                 /* solver output; h->y keeps the last good state */
    void *mem;
    long base_steps, base_rhs;  /* counters accumulated before the last ReInit */
    char msg[320];              /* last SUNDIALS error message */
} ark_data;

/* SUNDIALS 6.4 error handler: keep the message, never print. Warnings (e.g. "t + h = t") are
 * not errors and do not overwrite the message of a failure. */
static void ark_err_handler(int error_code, const char *module, const char *function, char *msg,
                            void *user_data)
{
    (void)module;
    ark_data *d = user_data;
    if (error_code == ARK_WARNING) return;
    snprintf(d->msg, sizeof d->msg, "%s (%s)", msg ? msg : "", function ? function : "?");
}

static void ark_release(fpl_integrator *h)
{
    ark_data *d = h->data;
    if (!d) return;
    if (d->mem) ERKStepFree(&d->mem);
    if (d->y) N_VDestroy(d->y);
    if (d->ctx) SUNContext_Free(&d->ctx);
    free(d);
    h->data = NULL;
}

/* SUNDIALS 6.4's ERKStep takes a table with last node c_s = 1 for first-same-as-last and
 * reuses the last stage's f as the first stage of the next step, even when that stage is not
 * evaluated at the new solution (a_sj != b_j). This affects Verner 8-5-6, Fehlberg 13-7-8 and
 * DOP853 (measured: DOP853 at fixed steps converges with order ~5.7 instead of 8). Such a
 * table gets one more stage, c = 1, a_(s+1)j = b_j, weight 0: f(t + h, y_new), which makes it
 * truly FSAL. It costs no extra evaluation: without the bug a non-FSAL table needs
 * f(t + h, y_new) for the next step anyway. Takes ownership of B; NULL if out of memory. */
static ARKodeButcherTable fsal_safe(ARKodeButcherTable B)
{
    if (!B) return NULL;
    const int s = B->stages;
    int fsal = 1;
    for (int j = 0; j < s; j++)
        if (B->A[s - 1][j] != B->b[j]) fsal = 0;
    if (B->c[s - 1] != 1.0 || fsal) return B;
    const int t = s + 1;
    double *buf = calloc((size_t)(t * t + 3 * t), sizeof(double));
    ARKodeButcherTable E = NULL;
    if (buf) {
        double *A = buf, *c = A + t * t, *b = c + t, *d = b + t;
        for (int i = 0; i < s; i++) {
            c[i] = B->c[i];
            b[i] = B->b[i];
            d[i] = B->d ? B->d[i] : 0.0;
            for (int j = 0; j < s; j++) A[i * t + j] = B->A[i][j];
            A[s * t + i] = B->b[i];
        }
        c[s] = 1.0;
        E = ARKodeButcherTable_Create(t, B->q, B->p, c, A, b, B->d ? d : NULL);
        free(buf);
    }
    ARKodeButcherTable_Free(B);
    return E;
}

static int setup_failed(fpl_integrator *h, const char *what, int flag)
{
    const ark_data *d = h->data;
    return fpl_error(NULL, FPL_ERR_BACKEND, "ARKODE %s: %s failed (flag %d)%s%s",
                     h->method->name, what, flag, d && d->msg[0] ? ": " : "", d ? d->msg : "");
}

static int ark_init(fpl_integrator *h)
{
    const ark_method *m = h->method->data;
    ark_data *d = calloc(1, sizeof *d);
    if (!d) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (ARKODE back end)");
    h->data = d; /* from here on, fpl_integrator_free calls ark_release on failure */
    if (SUNContext_Create(NULL, &d->ctx) != 0 || !d->ctx)
        return fpl_error(NULL, FPL_ERR_BACKEND, "ARKODE %s: SUNContext_Create failed",
                         h->method->name);
    d->y = N_VNew_Serial((sunindextype)h->dim, d->ctx);
    if (!d->y) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (ARKODE state vector)");
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    d->mem = ERKStepCreate(fpl_sun_rhs, h->t, d->y, d->ctx);
    if (!d->mem) return fpl_error(NULL, FPL_ERR_NOMEM, "ARKODE %s: ERKStepCreate failed",
                                  h->method->name);
    int flag = ERKStepSetErrHandlerFn(d->mem, ark_err_handler, d);
    if (flag != ARK_SUCCESS) return setup_failed(h, "ERKStepSetErrHandlerFn", flag);
    if ((flag = ERKStepSetUserData(d->mem, h->lat)) != ARK_SUCCESS)
        return setup_failed(h, "ERKStepSetUserData", flag);
    ARKodeButcherTable B =
        fsal_safe(m->custom_dop853 ? fpl_dop853_table() : ARKodeButcherTable_LoadERK(m->table));
    if (!B) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (Butcher table)");
    flag = ERKStepSetTable(d->mem, B); /* ERKStep keeps its own copy */
    ARKodeButcherTable_Free(B);
    if (flag != ARK_SUCCESS) return setup_failed(h, "ERKStepSetTable", flag);
    if ((flag = ERKStepSStolerances(d->mem, h->opt.rtol, h->opt.atol)) != ARK_SUCCESS)
        return setup_failed(h, "ERKStepSStolerances", flag);
    if ((flag = ERKStepSetMaxNumSteps(d->mem, h->opt.max_steps)) != ARK_SUCCESS)
        return setup_failed(h, "ERKStepSetMaxNumSteps", flag);
    if (h->opt.dt > 0.0 && (flag = ERKStepSetInitStep(d->mem, h->opt.dt)) != ARK_SUCCESS)
        return setup_failed(h, "ERKStepSetInitStep", flag);
    /* Stopping criteria on the lattice: ARKODE's root-finding, g_i decreasing through zero. */
    const int n_events = fpl_lattice_event_count(h->lat);
    if (n_events > 0) {
        int dirs[8];
        for (int i = 0; i < n_events; i++) dirs[i] = -1;
        if ((flag = ERKStepRootInit(d->mem, n_events, fpl_sun_roots)) != ARK_SUCCESS)
            return setup_failed(h, "ERKStepRootInit", flag);
        if ((flag = ERKStepSetRootDirection(d->mem, dirs)) != ARK_SUCCESS)
            return setup_failed(h, "ERKStepSetRootDirection", flag);
        ERKStepSetNoInactiveRootWarn(d->mem);
    }
    return FPL_OK;
}

/* Restart the solver from (h->t, h->y), keeping the counters and the last step size. */
static int ark_restart(fpl_integrator *h)
{
    ark_data *d = h->data;
    double hlast = 0.0;
    ERKStepGetLastStep(d->mem, &hlast);
    d->base_steps = h->n_steps;
    d->base_rhs = h->n_force;
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    int flag = ERKStepReInit(d->mem, fpl_sun_rhs, h->t, d->y);
    if (flag != ARK_SUCCESS) return setup_failed(h, "ERKStepReInit", flag);
    if (hlast > 0.0) ERKStepSetInitStep(d->mem, hlast);
    return FPL_OK;
}

static int ark_reset(fpl_integrator *h)
{
    return ark_restart(h);
}

static int ark_advance(fpl_integrator *h, double t_target, double *y_out)
{
    ark_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    if (t_target == h->t) {
        memcpy(y_out, h->y, bytes);
        return FPL_OK;
    }
    d->msg[0] = '\0';
    int flag = ERKStepSetStopTime(d->mem, t_target);
    double tret = h->t;
    if (flag == ARK_SUCCESS) flag = ERKStepEvolve(d->mem, t_target, d->y, &tret, ARK_NORMAL);
    long nst = 0, nfe = 0;
    ERKStepGetNumSteps(d->mem, &nst);
    ERKStepGetNumRhsEvals(d->mem, &nfe);
    h->n_steps = d->base_steps + nst;
    h->n_force = d->base_rhs + nfe;
    const double *yv = N_VGetArrayPointer(d->y);
    const int finite = fpl_is_finite_array(yv, h->dim, NULL);
    if (flag == ARK_ROOT_RETURN && finite) {
        int found[8] = {0};
        ERKStepGetRootInfo(d->mem, found);
        h->event_index = 0;
        for (int i = fpl_lattice_event_count(h->lat) - 1; i >= 0; i--)
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

    /* Failure. On error ARKODE returns its last accepted state (at tret): keep it if finite,
     * so the handle holds the latest good state; then restart the solver from there. */
    const double t_start = h->t;
    if (flag < 0 && finite && tret > h->t && tret < t_target) {
        memcpy(h->y, yv, bytes);
        h->t = tret;
    }
    char *name = ERKStepGetReturnFlagName(flag);
    char flag_name[32];
    snprintf(flag_name, sizeof flag_name, "%s", name ? name : "?");
    free(name);
    char sun_msg[sizeof d->msg];
    memcpy(sun_msg, d->msg, sizeof sun_msg);
    ark_restart(h);
    /* fpl_sun_rhs returns 1 (recoverable) only for a non-finite state, which ERKStep reports
     * as an unrecoverable right-hand-side error. */
    if (!finite || flag == ARK_UNREC_RHSFUNC_ERR || flag == ARK_REPTD_RHSFUNC_ERR ||
        flag == ARK_FIRST_RHSFUNC_ERR)
        return fpl_error(NULL, FPL_ERR_NONFINITE,
                         "state became non-finite between t = %.10g and t = %.10g (ARKODE %s, "
                         "started at t = %.10g: flag %d (%s)%s%s)",
                         h->t, t_target, h->method->name, t_start, flag, flag_name,
                         sun_msg[0] ? ": " : "", sun_msg);
    return fpl_error(NULL, FPL_ERR_BACKEND, "ARKODE %s failed at t = %.10g: flag %d (%s): %s",
                     h->method->name, tret, flag, flag_name,
                     sun_msg[0] ? sun_msg : "(no message)");
}

static const fpl_backend backend_arkode = {
    .family = "arkode",
    .adaptive = 1,
    .init = ark_init,
    .advance = ark_advance,
    .reset = ark_reset,
    .release = ark_release,
};

static const ark_method m_dopri5 = {0, ARKODE_DORMAND_PRINCE_7_4_5};
static const ark_method m_verner65 = {0, ARKODE_VERNER_8_5_6};
static const ark_method m_fehlberg87 = {0, ARKODE_FEHLBERG_13_7_8};
static const ark_method m_dop853 = {1, ARKODE_ERK_NONE};

const fpl_method fpl_methods_arkode[] = {
    {"dopri5", 5, &backend_arkode, &m_dopri5},
    {"verner65", 6, &backend_arkode, &m_verner65},
    {"fehlberg87", 8, &backend_arkode, &m_fehlberg87},
    {"dop853", 8, &backend_arkode, &m_dop853},
    {NULL, 0, NULL, NULL},
};
