/* Adaptive multistep back end: CVODE (SUNDIALS 6.x).
 *   cvode-adams  Adams-Moulton up to order 12 with the fixed-point nonlinear solver: the
 *                high-accuracy choice for these non-stiff problems;
 *   cvode-bdf    BDF up to order 5, Newton iteration with a dense matrix, the dense direct
 *                linear solver and our analytic Jacobian (fpl_sun_jac, which includes the
 *                variational block when deviation vectors are carried).
 * Every CVODE call of the library lives in this file. Each advance sets the stop time to the
 * target, so the state lands on t_target. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>
#include "fputlab/sundials.h"
#include "integrator_impl.h"

typedef struct cv_method {
    int lmm;        /* CV_ADAMS or CV_BDF */
    int max_order;
} cv_method;

typedef struct cv_data {
    SUNContext ctx;
    N_Vector y;                 /* solver output; h->y keeps the last good state */
    void *mem;
    SUNMatrix A;                /* BDF only */
    SUNLinearSolver LS;         /* BDF only */
    SUNNonlinearSolver NLS;
    long base_steps, base_rhs;  /* counters accumulated before the last ReInit */
    char msg[320];              /* last SUNDIALS error message */
} cv_data;

/* SUNDIALS 6.4 error handler: keep the message, never print. */
static void cv_err_handler(int error_code, const char *module, const char *function, char *msg,
                           void *user_data)
{
    (void)module;
    cv_data *d = user_data;
    if (error_code == CV_WARNING) return;
    snprintf(d->msg, sizeof d->msg, "%s (%s)", msg ? msg : "", function ? function : "?");
}

static void cv_release(fpl_integrator *h)
{
    cv_data *d = h->data;
    if (!d) return;
    if (d->mem) CVodeFree(&d->mem);
    if (d->NLS) SUNNonlinSolFree(d->NLS);
    if (d->LS) SUNLinSolFree(d->LS);
    if (d->A) SUNMatDestroy(d->A);
    if (d->y) N_VDestroy(d->y);
    if (d->ctx) SUNContext_Free(&d->ctx);
    free(d);
    h->data = NULL;
}

static int setup_failed(fpl_integrator *h, const char *what, int flag)
{
    const cv_data *d = h->data;
    return fpl_error(NULL, FPL_ERR_BACKEND, "CVODE %s: %s failed (flag %d)%s%s",
                     h->method->name, what, flag, d && d->msg[0] ? ": " : "", d ? d->msg : "");
}

static int cv_init(fpl_integrator *h)
{
    const cv_method *m = h->method->data;
    cv_data *d = calloc(1, sizeof *d);
    if (!d) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE back end)");
    h->data = d; /* from here on, fpl_integrator_free calls cv_release on failure */
    if (SUNContext_Create(NULL, &d->ctx) != 0 || !d->ctx)
        return fpl_error(NULL, FPL_ERR_BACKEND, "CVODE %s: SUNContext_Create failed",
                         h->method->name);
    const sunindextype dim = (sunindextype)h->dim;
    d->y = N_VNew_Serial(dim, d->ctx);
    if (!d->y) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE state vector)");
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    d->mem = CVodeCreate(m->lmm, d->ctx);
    if (!d->mem) return fpl_error(NULL, FPL_ERR_NOMEM, "CVODE %s: CVodeCreate failed",
                                  h->method->name);
    int flag = CVodeSetErrHandlerFn(d->mem, cv_err_handler, d);
    if (flag != CV_SUCCESS) return setup_failed(h, "CVodeSetErrHandlerFn", flag);
    if ((flag = CVodeInit(d->mem, fpl_sun_rhs, h->t, d->y)) != CV_SUCCESS)
        return setup_failed(h, "CVodeInit", flag);
    if ((flag = CVodeSetUserData(d->mem, h->lat)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSetUserData", flag);
    if ((flag = CVodeSStolerances(d->mem, h->opt.rtol, h->opt.atol)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSStolerances", flag);
    if ((flag = CVodeSetMaxNumSteps(d->mem, h->opt.max_steps)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSetMaxNumSteps", flag);
    if ((flag = CVodeSetMaxOrd(d->mem, m->max_order)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSetMaxOrd", flag);
    if (h->opt.dt > 0.0 && (flag = CVodeSetInitStep(d->mem, h->opt.dt)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSetInitStep", flag);
    if (m->lmm == CV_ADAMS) {
        d->NLS = SUNNonlinSol_FixedPoint(d->y, 0, d->ctx);
        if (!d->NLS) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE fixed point)");
    } else {
        d->A = SUNDenseMatrix(dim, dim, d->ctx);
        if (!d->A) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE dense matrix)");
        d->LS = SUNLinSol_Dense(d->y, d->A, d->ctx);
        if (!d->LS) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE dense solver)");
        d->NLS = SUNNonlinSol_Newton(d->y, d->ctx);
        if (!d->NLS) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (CVODE Newton)");
    }
    if ((flag = CVodeSetNonlinearSolver(d->mem, d->NLS)) != CV_SUCCESS)
        return setup_failed(h, "CVodeSetNonlinearSolver", flag);
    if (d->LS) {
        if ((flag = CVodeSetLinearSolver(d->mem, d->LS, d->A)) != CV_SUCCESS)
            return setup_failed(h, "CVodeSetLinearSolver", flag);
        if ((flag = CVodeSetJacFn(d->mem, fpl_sun_jac)) != CV_SUCCESS)
            return setup_failed(h, "CVodeSetJacFn", flag);
    }
    /* Stopping criteria on the lattice: CVODE's root-finding, g_i decreasing through zero. */
    const int n_events = fpl_lattice_event_count(h->lat);
    if (n_events > 0) {
        int dirs[8];
        for (int i = 0; i < n_events; i++) dirs[i] = -1;
        if ((flag = CVodeRootInit(d->mem, n_events, fpl_sun_roots)) != CV_SUCCESS)
            return setup_failed(h, "CVodeRootInit", flag);
        if ((flag = CVodeSetRootDirection(d->mem, dirs)) != CV_SUCCESS)
            return setup_failed(h, "CVodeSetRootDirection", flag);
        CVodeSetNoInactiveRootWarn(d->mem);
    }
    return FPL_OK;
}

/* Restart the solver from (h->t, h->y), keeping the counters. */
static int cv_restart(fpl_integrator *h)
{
    cv_data *d = h->data;
    d->base_steps = h->n_steps;
    d->base_rhs = h->n_force;
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    int flag = CVodeReInit(d->mem, h->t, d->y);
    return flag == CV_SUCCESS ? FPL_OK : setup_failed(h, "CVodeReInit", flag);
}

static int cv_reset(fpl_integrator *h)
{
    return cv_restart(h);
}

static int cv_advance(fpl_integrator *h, double t_target, double *y_out)
{
    cv_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    if (t_target == h->t) {
        memcpy(y_out, h->y, bytes);
        return FPL_OK;
    }
    d->msg[0] = '\0';
    /* Steps shorter than a few ulps of the time are no steps at all: near a blow-up CVODE would
     * otherwise go on with t + h == t (warnings only) until max_steps, minutes of work. With
     * this floor it stops with an error-test, convergence or right-hand-side failure. */
    const double hmin = 4.0 * DBL_EPSILON * fmax(fabs(h->t), fabs(t_target));
    int flag = CVodeSetMinStep(d->mem, hmin);
    if (flag == CV_SUCCESS) flag = CVodeSetStopTime(d->mem, t_target);
    double tret = h->t;
    if (flag == CV_SUCCESS) flag = CVode(d->mem, t_target, d->y, &tret, CV_NORMAL);
    long nst = 0, nfe = 0;
    CVodeGetNumSteps(d->mem, &nst);
    CVodeGetNumRhsEvals(d->mem, &nfe);
    h->n_steps = d->base_steps + nst;
    h->n_force = d->base_rhs + nfe;
    const double *yv = N_VGetArrayPointer(d->y);
    const int finite = fpl_is_finite_array(yv, h->dim, NULL);
    if (flag == CV_ROOT_RETURN && finite) {
        int found[8] = {0};
        CVodeGetRootInfo(d->mem, found);
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

    /* Failure. On error CVODE returns its last accepted state (at tret): keep it if finite,
     * so the handle holds the latest good state; then restart the solver from there. */
    const double t_start = h->t;
    if (flag < 0 && finite && tret > h->t && tret < t_target) {
        memcpy(h->y, yv, bytes);
        h->t = tret;
    }
    char *name = CVodeGetReturnFlagName(flag);
    char flag_name[32];
    snprintf(flag_name, sizeof flag_name, "%s", name ? name : "?");
    free(name);
    char sun_msg[sizeof d->msg];
    memcpy(sun_msg, d->msg, sizeof sun_msg);
    cv_restart(h);
    /* fpl_sun_rhs returns 1 (recoverable) only for a non-finite state: CVODE retries with a
     * smaller step and gives up with one of the right-hand-side errors. */
    if (!finite || flag == CV_REPTD_RHSFUNC_ERR || flag == CV_UNREC_RHSFUNC_ERR ||
        flag == CV_FIRST_RHSFUNC_ERR)
        return fpl_error(NULL, FPL_ERR_NONFINITE,
                         "state became non-finite between t = %.10g and t = %.10g (CVODE %s, "
                         "started at t = %.10g: flag %d (%s)%s%s)",
                         h->t, t_target, h->method->name, t_start, flag, flag_name,
                         sun_msg[0] ? ": " : "", sun_msg);
    return fpl_error(NULL, FPL_ERR_BACKEND, "CVODE %s failed at t = %.10g: flag %d (%s): %s",
                     h->method->name, tret, flag, flag_name,
                     sun_msg[0] ? sun_msg : "(no message)");
}

static const fpl_backend backend_cvode = {
    .family = "cvode",
    .adaptive = 1,
    .init = cv_init,
    .advance = cv_advance,
    .reset = cv_reset,
    .release = cv_release,
};

static const cv_method m_adams = {CV_ADAMS, 12};
static const cv_method m_bdf = {CV_BDF, 5};

const fpl_method fpl_methods_cvode[] = {
    {"cvode-adams", 12, &backend_cvode, &m_adams},
    {"cvode-bdf", 5, &backend_cvode, &m_bdf},
    {NULL, 0, NULL, NULL},
};
