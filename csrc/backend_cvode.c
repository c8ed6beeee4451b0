/* Adaptive multistep back end: CVODE (SUNDIALS 6.4 or 7.x; differences in sundials_compat.h).
 *   cvode-adams  Adams-Moulton up to order 12 with the fixed-point nonlinear solver: the
 *                high-accuracy choice for these non-stiff problems;
 *   cvode-bdf    BDF up to order 5, Newton iteration with a dense matrix, the dense direct
 *                linear solver and our analytic Jacobian (fpl_sun_jac, which includes the
 *                variational block when deviation vectors are carried).
 * Every CVODE call of the library lives in this file (the part shared with ARKODE: data,
 * failures, classification of a return, is in sundials_common.c). Each advance sets the stop
 * time to the target, so the state lands on t_target. */
#define _POSIX_C_SOURCE 200809L   /* clock_gettime */
#include <float.h>
#include <math.h>
#include <time.h>
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
#include "sundials_common.h"

typedef struct cv_method {
    int lmm;        /* CV_ADAMS or CV_BDF */
    int max_order;
} cv_method;

static void cv_release(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    if (d && d->mem) CVodeFree(&d->mem);
    fpl_sun_data_free(h);
}

static int cv_init(fpl_integrator *h)
{
    const cv_method *m = h->method->data;
    int flag = fpl_sun_data_create(h, "CVODE");
    if (flag != FPL_OK) return flag;
    fpl_sun_data *d = h->data;
    const sunindextype dim = (sunindextype)h->dim;
    d->mem = CVodeCreate(m->lmm, d->ctx);
    if (!d->mem) return fpl_error(NULL, FPL_ERR_NOMEM, "CVODE %s: CVodeCreate failed",
                                  h->method->name);
    flag = FPL_SUN_SET_ERR_HANDLER(CVodeSetErrHandlerFn, d->mem, &d->err);
    if (flag != CV_SUCCESS) return fpl_sun_setup_failed(h, "CVodeSetErrHandlerFn", flag);
    if ((flag = CVodeInit(d->mem, fpl_sun_rhs, h->t, d->y)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeInit", flag);
    if ((flag = CVodeSetUserData(d->mem, h->sys)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeSetUserData", flag);
    if ((flag = CVodeSStolerances(d->mem, h->opt.rtol, h->opt.atol)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeSStolerances", flag);
    if ((flag = CVodeSetMaxNumSteps(d->mem, h->opt.max_steps)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeSetMaxNumSteps", flag);
    if ((flag = CVodeSetMaxOrd(d->mem, m->max_order)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeSetMaxOrd", flag);
    if (h->opt.dt > 0.0 && (flag = CVodeSetInitStep(d->mem, h->opt.dt)) != CV_SUCCESS)
        return fpl_sun_setup_failed(h, "CVodeSetInitStep", flag);
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
        return fpl_sun_setup_failed(h, "CVodeSetNonlinearSolver", flag);
    if (d->LS) {
        if ((flag = CVodeSetLinearSolver(d->mem, d->LS, d->A)) != CV_SUCCESS)
            return fpl_sun_setup_failed(h, "CVodeSetLinearSolver", flag);
        if ((flag = CVodeSetJacFn(d->mem, fpl_sun_jac)) != CV_SUCCESS)
            return fpl_sun_setup_failed(h, "CVodeSetJacFn", flag);
    }
    /* Stopping criteria on the lattice: CVODE's root-finding, g_i decreasing through zero. */
    const int n_events = fpl_system_event_count(h->sys);
    if (n_events > 0) {
        int dirs[8];
        for (int i = 0; i < n_events; i++) dirs[i] = -1;
        if ((flag = CVodeRootInit(d->mem, n_events, fpl_sun_roots)) != CV_SUCCESS)
            return fpl_sun_setup_failed(h, "CVodeRootInit", flag);
        if ((flag = CVodeSetRootDirection(d->mem, dirs)) != CV_SUCCESS)
            return fpl_sun_setup_failed(h, "CVodeSetRootDirection", flag);
        CVodeSetNoInactiveRootWarn(d->mem);
    }
    return FPL_OK;
}

/* Restart the solver from (h->t, h->y), keeping the counters. */
static int cv_restart(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    d->base_steps = h->n_steps;
    d->base_rhs = h->n_force;
    h->paused_steps = 0;
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    int flag = CVodeReInit(d->mem, h->t, d->y);
    return flag == CV_SUCCESS ? FPL_OK : fpl_sun_setup_failed(h, "CVodeReInit", flag);
}

static int cv_reset(fpl_integrator *h)
{
    return cv_restart(h);
}

static const fpl_sun_ops cv_ops = {
    .root_return = CV_ROOT_RETURN,
    .rhs_errors = {CV_REPTD_RHSFUNC_ERR, CV_UNREC_RHSFUNC_ERR, CV_FIRST_RHSFUNC_ERR},
    .root_info = CVodeGetRootInfo,
    .flag_name = CVodeGetReturnFlagName,
    .restart = cv_restart,
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cv_advance(fpl_integrator *h, double t_target, double *y_out)
{
    fpl_sun_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    if (t_target == h->t) {
        memcpy(y_out, h->y, bytes);
        return FPL_OK;
    }
    d->err.msg[0] = '\0';
    /* Steps shorter than a few ulps of the time are no steps at all: near a blow-up CVODE would
     * otherwise go on with t + h == t (warnings only) until max_steps, minutes of work. With
     * this floor it stops with an error-test, convergence or right-hand-side failure. */
    const double hmin = 4.0 * DBL_EPSILON * fmax(fabs(h->t), fabs(t_target));
    int flag = CVodeSetMinStep(d->mem, hmin);
    if (flag == CV_SUCCESS) flag = CVodeSetStopTime(d->mem, t_target);
    double tret = h->t;
    int paused = 0;
    if (flag == CV_SUCCESS && h->budget > 0.0) {
        /* A time budget (fpl_integrator_set_budget): one internal step per CVode call, the clock
         * read after each. These are the steps CV_NORMAL takes (both modes stop at the stop
         * time t_target the same way), so a run that pauses and goes on is the same run. */
        const double start = now_seconds();
        long taken = h->paused_steps;
        do {
            flag = CVode(d->mem, t_target, d->y, &tret, CV_ONE_STEP);
            taken++;
        } while (flag == CV_SUCCESS && tret < t_target && taken < h->opt.max_steps &&
                 now_seconds() - start < h->budget);
        if (flag == CV_SUCCESS && tret < t_target) {
            if (taken >= h->opt.max_steps) {   /* as CV_NORMAL would, with its message */
                flag = CV_TOO_MUCH_WORK;
                snprintf(d->err.msg, sizeof d->err.msg, "At t = %.17g, mxstep steps taken before "
                         "reaching tout.", tret);
            } else {
                paused = 1;
            }
        }
        h->paused_steps = paused ? taken : 0;
    } else if (flag == CV_SUCCESS) {
        flag = CVode(d->mem, t_target, d->y, &tret, CV_NORMAL);
    }
    long nst = 0, nfe = 0;
    CVodeGetNumSteps(d->mem, &nst);
    CVodeGetNumRhsEvals(d->mem, &nfe);
    h->n_steps = d->base_steps + nst;
    h->n_force = d->base_rhs + nfe;
    if (paused && fpl_is_finite_array(N_VGetArrayPointer(d->y), h->dim, NULL)) {
        const size_t bytes = sizeof(double) * (size_t)h->dim;
        memcpy(h->y, N_VGetArrayPointer(d->y), bytes);
        memcpy(y_out, h->y, bytes);
        h->t = tret;
        return fpl_error(NULL, FPL_PAUSED, "paused at t = %.17g on the way to %.17g (time budget "
                         "of %g s per call)", tret, t_target, h->budget);
    }
    return fpl_sun_classify(h, &cv_ops, flag, tret, t_target, y_out);
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
