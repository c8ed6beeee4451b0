/* Adaptive explicit Runge-Kutta back end: ARKODE ERKStep (SUNDIALS 6.4 or 7.x; the differences
 * are in sundials_compat.h) with built-in tables (Dormand-Prince 5(4), Verner 6(5), Fehlberg
 * 8(7)) and Hairer's DOP853 as a custom table (integrators/dop853.c). Every ERKStep call of the
 * library lives in this file; the part shared with CVODE (data, failures, classification of a
 * return) is in sundials_common.c. Tables are passed through fpl_sun_erk_fsal_safe(), which
 * works around an ERKStep 6.4 FSAL bug (see there; exported with fpl_sun_erk_table).
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
#include "sundials_common.h"

ARKodeButcherTable fpl_dop853_table(void); /* integrators/dop853.c */

typedef struct ark_method {
    int custom_dop853;          /* 1: our DOP853 table; 0: the built-in table below */
    ARKODE_ERKTableID table;
} ark_method;

static void ark_release(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    if (d && d->mem) FPL_ARK(ERKStep, Free)(&d->mem);
    fpl_sun_data_free(h);
}

/* SUNDIALS 6.4's ERKStep takes a table with last node c_s = 1 for first-same-as-last and
 * reuses the last stage's f as the first stage of the next step, even when that stage is not
 * evaluated at the new solution (a_sj != b_j). This affects Verner 8-5-6, Fehlberg 13-7-8 and
 * DOP853 (measured: DOP853 at fixed steps converges with order ~5.7 instead of 8). Such a
 * table gets one more stage, c = 1, a_(s+1)j = b_j, weight 0: f(t + h, y_new), which makes it
 * truly FSAL. It costs no extra evaluation: without the bug a non-FSAL table needs
 * f(t + h, y_new) for the next step anyway. Exported for embedders (fputlab/sundials.h). */
int fpl_sun_erk_fsal_safe(ARKodeButcherTable B, ARKodeButcherTable *safe)
{
    if (!safe) return fpl_error(NULL, FPL_ERR_ARG, "safe: NULL pointer");
    *safe = NULL;
    if (!B || B->stages < 1 || !B->A || !B->b || !B->c)
        return fpl_error(NULL, FPL_ERR_ARG, "table: NULL or incomplete Butcher table");
    const int s = B->stages;
    int fsal = 1;
    for (int j = 0; j < s; j++)
        if (B->A[s - 1][j] != B->b[j]) fsal = 0;
    if (B->c[s - 1] != 1.0 || fsal) {
        *safe = ARKodeButcherTable_Copy(B);
        return *safe ? FPL_OK : fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (Butcher table)");
    }
    const int t = s + 1;
    double *buf = calloc((size_t)(t * t + 3 * t), sizeof(double));
    if (!buf) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (Butcher table)");
    double *A = buf, *c = A + t * t, *b = c + t, *d = b + t;
    for (int i = 0; i < s; i++) {
        c[i] = B->c[i];
        b[i] = B->b[i];
        d[i] = B->d ? B->d[i] : 0.0;
        for (int j = 0; j < s; j++) A[i * t + j] = B->A[i][j];
        A[s * t + i] = B->b[i];
    }
    c[s] = 1.0;
    *safe = ARKodeButcherTable_Create(t, B->q, B->p, c, A, b, B->d ? d : NULL);
    free(buf);
    return *safe ? FPL_OK : fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (Butcher table)");
}

static const fpl_method *find_erk_method(const char *name);

int fpl_sun_erk_table(const char *method, ARKodeButcherTable *table)
{
    if (!table) return fpl_error(NULL, FPL_ERR_ARG, "table: NULL pointer");
    *table = NULL;
    if (!method) return fpl_error(NULL, FPL_ERR_ARG, "method: NULL name");
    const fpl_method *fm = find_erk_method(method);
    if (!fm)
        return fpl_error(NULL, FPL_ERR_UNKNOWN,
                         "method '%s' has no ERKStep table (known: dopri5, verner65, fehlberg87, "
                         "dop853)", method);
    const ark_method *m = fm->data;
    ARKodeButcherTable B =
        m->custom_dop853 ? fpl_dop853_table() : ARKodeButcherTable_LoadERK(m->table);
    if (!B) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (Butcher table)");
    int st = fpl_sun_erk_fsal_safe(B, table);
    ARKodeButcherTable_Free(B);
    return st;
}

/* ERKStep forms every stage and the solution as N_VLinearCombination(y_n, F_1, ..., F_i) with
 * the coefficients h a_ij (zeros included). Serial vectors without fused operations run that as
 * N_VScale + one N_VLinearSum per term, i.e. one pass over z per term, and the serial fused
 * version does the same; with DOP853 (13 stages) that is ~120 passes over the state per step and
 * 60-75 % of the solver's time (perf, SUNDIALS 6.4.1 and 7.1.1). This operation (set on our
 * state vector, so ERKStep's clones inherit it) makes one pass per four terms and skips terms
 * whose coefficient is exactly 0. The sums are formed in the same order as SUNDIALS' fallback,
 * z = c_0 X_0 + c_1 X_1 + ..., term by term without contraction, so each element is the same
 * double (a skipped 0 x_j changes at most the sign of an exact zero). */
static int lincomb_fallback(int nvec, sunrealtype *c, N_Vector *X, N_Vector z)
{
    N_VScale_Serial(c[0], X[0], z);
    for (int j = 1; j < nvec; j++) N_VLinearSum_Serial(c[j], X[j], 1.0, z, z);
    return 0;
}

FPL_HOT static void lincomb_pass(sunindextype n, double *z, int first, double c0, const double *x0,
                                 int m, const double *a, const double *const *x)
{
    /* z = (first ? c0 x0 : z) + a_0 x_0 + ... + a_{m-1} x_{m-1}, left to right */
    switch (m) {
    case 0:
        for (sunindextype k = 0; k < n; k++) z[k] = c0 * x0[k];
        break;
    case 1:
        if (first)
            for (sunindextype k = 0; k < n; k++) z[k] = c0 * x0[k] + a[0] * x[0][k];
        else
            for (sunindextype k = 0; k < n; k++) z[k] = z[k] + a[0] * x[0][k];
        break;
    case 2:
        if (first)
            for (sunindextype k = 0; k < n; k++)
                z[k] = (c0 * x0[k] + a[0] * x[0][k]) + a[1] * x[1][k];
        else
            for (sunindextype k = 0; k < n; k++)
                z[k] = (z[k] + a[0] * x[0][k]) + a[1] * x[1][k];
        break;
    case 3:
        if (first)
            for (sunindextype k = 0; k < n; k++)
                z[k] = ((c0 * x0[k] + a[0] * x[0][k]) + a[1] * x[1][k]) + a[2] * x[2][k];
        else
            for (sunindextype k = 0; k < n; k++)
                z[k] = ((z[k] + a[0] * x[0][k]) + a[1] * x[1][k]) + a[2] * x[2][k];
        break;
    default:
        if (first)
            for (sunindextype k = 0; k < n; k++)
                z[k] = (((c0 * x0[k] + a[0] * x[0][k]) + a[1] * x[1][k]) + a[2] * x[2][k]) +
                       a[3] * x[3][k];
        else
            for (sunindextype k = 0; k < n; k++)
                z[k] = (((z[k] + a[0] * x[0][k]) + a[1] * x[1][k]) + a[2] * x[2][k]) +
                       a[3] * x[3][k];
        break;
    }
}

static int lincomb(int nvec, sunrealtype *c, N_Vector *X, N_Vector z)
{
    enum { MAX_TERMS = 32 };
    if (nvec < 1 || nvec > MAX_TERMS) return lincomb_fallback(nvec, c, X, z);
    for (int j = 1; j < nvec; j++) /* z among the later terms: the fallback's semantics */
        if (X[j] == z) return lincomb_fallback(nvec, c, X, z);
    double a[MAX_TERMS];
    const double *x[MAX_TERMS];
    int m = 0;
    for (int j = 1; j < nvec; j++)
        if (c[j] != 0.0) {
            a[m] = c[j];
            x[m++] = NV_DATA_S(X[j]);
        }
    const sunindextype n = NV_LENGTH_S(z);
    double *zd = NV_DATA_S(z);
    int done = m < 4 ? m : 4;
    lincomb_pass(n, zd, 1, c[0], NV_DATA_S(X[0]), done, m ? a : NULL, m ? x : NULL);
    while (done < m) {
        const int k = m - done < 4 ? m - done : 4;
        lincomb_pass(n, zd, 0, 0.0, NULL, k, a + done, x + done);
        done += k;
    }
    return 0;
}

static int ark_init(fpl_integrator *h)
{
    int flag = fpl_sun_data_create(h, "ARKODE");
    if (flag != FPL_OK) return flag;
    fpl_sun_data *d = h->data;
    d->y->ops->nvlinearcombination = lincomb;
    d->mem = ERKStepCreate(fpl_sun_rhs, h->t, d->y, d->ctx);
    if (!d->mem) return fpl_error(NULL, FPL_ERR_NOMEM, "ARKODE %s: ERKStepCreate failed",
                                  h->method->name);
    flag = FPL_SUN_SET_ERR_HANDLER(ERKStepSetErrHandlerFn, d->mem, &d->err);
    if (flag != ARK_SUCCESS) return fpl_sun_setup_failed(h, "ERKStepSetErrHandlerFn", flag);
    if ((flag = FPL_ARK(ERKStep, SetUserData)(d->mem, h->sys)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "ERKStepSetUserData", flag);
    ARKodeButcherTable B = NULL;
    if ((flag = fpl_sun_erk_table(h->method->name, &B)) != FPL_OK) return flag;
    flag = ERKStepSetTable(d->mem, B); /* ERKStep keeps its own copy */
    ARKodeButcherTable_Free(B);
    if (flag != ARK_SUCCESS) return fpl_sun_setup_failed(h, "ERKStepSetTable", flag);
    if ((flag = FPL_ARK(ERKStep, SStolerances)(d->mem, h->opt.rtol, h->opt.atol)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "ERKStepSStolerances", flag);
    if ((flag = FPL_ARK(ERKStep, SetMaxNumSteps)(d->mem, h->opt.max_steps)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "ERKStepSetMaxNumSteps", flag);
    if (h->opt.dt > 0.0 &&
        (flag = FPL_ARK(ERKStep, SetInitStep)(d->mem, h->opt.dt)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "ERKStepSetInitStep", flag);
    /* Stopping criteria on the lattice: ARKODE's root-finding, g_i decreasing through zero. */
    const int n_events = fpl_system_event_count(h->sys);
    if (n_events > 0) {
        int dirs[8];
        for (int i = 0; i < n_events; i++) dirs[i] = -1;
        if ((flag = FPL_ARK(ERKStep, RootInit)(d->mem, n_events, fpl_sun_roots)) != ARK_SUCCESS)
            return fpl_sun_setup_failed(h, "ERKStepRootInit", flag);
        if ((flag = FPL_ARK(ERKStep, SetRootDirection)(d->mem, dirs)) != ARK_SUCCESS)
            return fpl_sun_setup_failed(h, "ERKStepSetRootDirection", flag);
        FPL_ARK(ERKStep, SetNoInactiveRootWarn)(d->mem);
    }
    return FPL_OK;
}

/* Restart the solver from (h->t, h->y), keeping the counters and the last step size. */
static int ark_restart(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    double hlast = 0.0;
    FPL_ARK(ERKStep, GetLastStep)(d->mem, &hlast);
    d->base_steps = h->n_steps;
    d->base_rhs = h->n_force;
    memcpy(N_VGetArrayPointer(d->y), h->y, sizeof(double) * (size_t)h->dim);
    int flag = ERKStepReInit(d->mem, fpl_sun_rhs, h->t, d->y);
    if (flag != ARK_SUCCESS) return fpl_sun_setup_failed(h, "ERKStepReInit", flag);
    if (hlast > 0.0) FPL_ARK(ERKStep, SetInitStep)(d->mem, hlast);
    return FPL_OK;
}

static int ark_reset(fpl_integrator *h)
{
    return ark_restart(h);
}

static const fpl_sun_ops ark_ops = {
    .root_return = ARK_ROOT_RETURN,
    .rhs_errors = {ARK_UNREC_RHSFUNC_ERR, ARK_REPTD_RHSFUNC_ERR, ARK_FIRST_RHSFUNC_ERR},
    .root_info = FPL_ARK(ERKStep, GetRootInfo),
    .flag_name = FPL_ARK(ERKStep, GetReturnFlagName),
    .restart = ark_restart,
};

static int ark_advance(fpl_integrator *h, double t_target, double *y_out)
{
    fpl_sun_data *d = h->data;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    if (t_target == h->t) {
        memcpy(y_out, h->y, bytes);
        return FPL_OK;
    }
    d->err.msg[0] = '\0';
    int flag = FPL_ARK(ERKStep, SetStopTime)(d->mem, t_target);
    double tret = h->t;
    if (flag == ARK_SUCCESS)
        flag = FPL_ARK(ERKStep, Evolve)(d->mem, t_target, d->y, &tret, ARK_NORMAL);
    long nst = 0, nfe = 0;
    FPL_ARK(ERKStep, GetNumSteps)(d->mem, &nst);
    FPL_ERK_NUM_RHS(d->mem, &nfe);
    h->n_steps = d->base_steps + nst;
    h->n_force = d->base_rhs + nfe;
    return fpl_sun_classify(h, &ark_ops, flag, tret, t_target, y_out);
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

static const fpl_method *find_erk_method(const char *name)
{
    for (const fpl_method *m = fpl_methods_arkode; m->name; m++)
        if (strcmp(m->name, name) == 0) return m;
    return NULL;
}
