/* Fixed-step symplectic back end: ARKODE SPRKStep (SUNDIALS >= 6.6; with 6.4 the "sprk-*" names
 * are refused with a message saying why, and are not listed). Every SPRKStep call of the library
 * lives in this file; the part shared with ERKStep and CVODE is in sundials_common.c.
 *
 * The system is the partitioned one of fputlab/sundials.h: f1 = fpl_sun_force (momenta and
 * deviation momenta), f2 = fpl_sun_velocity (positions and deviation positions), so orbit and
 * deviation vectors are one separable system and the deviation vectors follow the tangent map
 * of the scheme itself. As for our splitting schemes the state stays on the grid t0 + n dt:
 * each advance takes whole steps (ARK_ONE_STEP) to the last grid time <= t_target, so the grid
 * states do not depend on how the run is sampled or restarted (bit for bit); a sample between
 * grid points is one step of the remaining length, after which the solver is reset to the grid
 * state. Stopping criteria use ARKODE's root-finding (g_i decreasing through zero), whose event
 * state comes from ARKODE's interpolant inside the step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fputlab/sundials.h"
#include "sundials_common.h"

/* Every SPRKStep name, also in builds without SPRKStep (to refuse them with a clear message). */
static const char *const sprk_names[] = {"sprk-mclachlan4", "sprk-yoshida6", "sprk-suzuki-umeno8",
                                         "sprk-sofroniou10", NULL};

int fpl_sprk_missing(const char *name)
{
    if (FPL_HAVE_SPRKSTEP) return 0;
    for (int i = 0; sprk_names[i]; i++)
        if (strcmp(sprk_names[i], name) == 0)
            return fpl_error(NULL, FPL_ERR_UNKNOWN,
                             "method '%s' needs ARKODE's SPRKStep (SUNDIALS >= 6.6); this fputlab "
                             "is built against SUNDIALS %s (rebuild with -Dsundials_dir=<SUNDIALS "
                             "7 prefix>, see tools/sundials7-prefix.sh)",
                             name, SUNDIALS_VERSION);
    return 0;
}

#if FPL_HAVE_SPRKSTEP
#include <arkode/arkode_sprkstep.h>

typedef struct sprk_method {
    const char *table;          /* ARKODE's table name (set by name: no table to own or free) */
} sprk_method;

/* SPRKStepSetUseCompensatedSums (6.6 to 7.1.1) clones its error accumulator from the state vector
 * and never zeroes it: the first steps then add whatever the allocator left there (measured:
 * energy errors 1e-3..1 instead of 1e-16, and right-hand-side failures under MALLOC_PERTURB_;
 * fixed in 7.2.0). The solver's vectors are clones of ours, so a clone operation that zeroes
 * fixes it.
 *
 * The same clone operation finds the accumulator (the "carry" of the compensated sums): SUNDIALS
 * has no function to read or set it (6.6 to 7.5: step_mem->yerr is private, SPRKStepReset zeroes
 * it), yet a restart without it is not bit for bit. SPRKStepSetUseCompensatedSums allocates it by
 * cloning the solver's state vector (6.6.0 to 7.5.0 alike; from 7.4 the call is
 * ARKodeSetUseCompensatedSums), so the one vector cloned during that call is the carry; sprk_init
 * checks that exactly one was. */
static _Thread_local N_Vector *clone_capture;
static _Thread_local int clone_captured;

static N_Vector clone_zeroed(N_Vector w)
{
    N_Vector v = N_VClone_Serial(w);
    if (v) N_VConst_Serial(0.0, v);
    if (v && clone_capture) {
        *clone_capture = v;
        clone_captured++;
    }
    return v;
}

/* Compensated sums: SPRKStep's carry vector and a copy of it kept across a solver reset. */
typedef struct sprk_carry {
    N_Vector yerr;              /* owned by SPRKStep */
    double *saved;              /* dim */
} sprk_carry;

static sprk_carry *carry_of(const fpl_integrator *h)
{
    const fpl_sun_data *d = h->data;
    return d ? d->extra : NULL;
}

static void sprk_release(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    if (d && d->mem) FPL_ARK(SPRKStep, Free)(&d->mem);
    if (d && d->extra) {
        free(((sprk_carry *)d->extra)->saved);
        free(d->extra);
        d->extra = NULL;
    }
    fpl_sun_data_free(h);
}

static int sprk_start(fpl_integrator *h);

static int sprk_init(fpl_integrator *h)
{
    const sprk_method *m = h->method->data;
    int flag = fpl_sun_data_create(h, "ARKODE");
    if (flag != FPL_OK) return flag;
    fpl_sun_data *d = h->data;
    if (h->opt.compensated_sums) d->y->ops->nvclone = clone_zeroed;
    d->mem = SPRKStepCreate(fpl_sun_force, fpl_sun_velocity, h->t, d->y, d->ctx);
    if (!d->mem) return fpl_error(NULL, FPL_ERR_NOMEM, "ARKODE %s: SPRKStepCreate failed",
                                  h->method->name);
    if ((flag = SPRKStepSetMethodName(d->mem, m->table)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "SPRKStepSetMethodName", flag);
    if ((flag = FPL_ARK(SPRKStep, SetUserData)(d->mem, h->sys)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "SPRKStepSetUserData", flag);
    if ((flag = FPL_ARK(SPRKStep, SetFixedStep)(d->mem, h->opt.dt)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "SPRKStepSetFixedStep", flag);
    if ((flag = FPL_ARK(SPRKStep, SetMaxNumSteps)(d->mem, h->opt.max_steps)) != ARK_SUCCESS)
        return fpl_sun_setup_failed(h, "SPRKStepSetMaxNumSteps", flag);
    if (h->opt.compensated_sums) {
        sprk_carry *c = calloc(1, sizeof *c);
        if (!c || !(d->extra = c) || !(c->saved = calloc((size_t)h->dim, sizeof(double))))
            return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (compensated sums)");
        clone_capture = &c->yerr;
        clone_captured = 0;
        flag = FPL_SPRK_SET_COMPENSATED_SUMS(d->mem, SUNTRUE);
        clone_capture = NULL;
        if (flag != ARK_SUCCESS)
            return fpl_sun_setup_failed(h, "SPRKStepSetUseCompensatedSums", flag);
        if (clone_captured != 1 || N_VGetLength(c->yerr) != (sunindextype)h->dim)
            return fpl_error(NULL, FPL_ERR_BACKEND,
                             "ARKODE %s: compensated_sums: this SUNDIALS (%s) allocates the "
                             "compensation carry other than SUNDIALS 6.6-7.5 do (%d vectors "
                             "cloned), so it could not be checkpointed", h->method->name,
                             SUNDIALS_VERSION, clone_captured);
    }
    const int n_events = fpl_system_event_count(h->sys);
    if (n_events > 0) {
        int dirs[8];
        for (int i = 0; i < n_events; i++) dirs[i] = -1;
        if ((flag = FPL_ARK(SPRKStep, RootInit)(d->mem, n_events, fpl_sun_roots)) != ARK_SUCCESS)
            return fpl_sun_setup_failed(h, "SPRKStepRootInit", flag);
        if ((flag = FPL_ARK(SPRKStep, SetRootDirection)(d->mem, dirs)) != ARK_SUCCESS)
            return fpl_sun_setup_failed(h, "SPRKStepSetRootDirection", flag);
        FPL_ARK(SPRKStep, SetNoInactiveRootWarn)(d->mem);
    }
    return h->opt.compensated_sums ? sprk_start(h) : FPL_OK;
}

/* What a solver reset does with the compensated sums' carry (SPRKStepReset zeroes it). */
enum carry_mode {
    CARRY_ZERO,         /* start afresh (a restore without a carry) */
    CARRY_KEEP,         /* keep it (saved first: a sample off the grid) */
    CARRY_SAVED,        /* put back the one saved by the last CARRY_KEEP/CARRY_ORBIT */
    CARRY_ORBIT,        /* keep the orbit's, zero the deviation vectors' (they were replaced) */
};

/* Put the solver back at (h->t, h->y), options and fixed step kept. */
static int sprk_restart_carry(fpl_integrator *h, enum carry_mode mode)
{
    fpl_sun_data *d = h->data;
    sprk_carry *c = carry_of(h);
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    if (c && (mode == CARRY_KEEP || mode == CARRY_ORBIT))
        memcpy(c->saved, N_VGetArrayPointer(c->yerr), bytes);
    memcpy(N_VGetArrayPointer(d->y), h->y, bytes);
    int flag = FPL_ARK(SPRKStep, Reset)(d->mem, h->t, d->y);
    if (flag != ARK_SUCCESS) return fpl_sun_setup_failed(h, "SPRKStepReset", flag);
    if (c && mode != CARRY_ZERO) {
        const size_t keep = mode == CARRY_ORBIT ? (size_t)(h->dim / (h->n_dev + 1)) : (size_t)h->dim;
        memcpy(N_VGetArrayPointer(c->yerr), c->saved, sizeof(double) * keep);
    }
    return FPL_OK;
}

/* SUNDIALS >= 7.2 zeroes the compensated sums' carry when the solver starts (sprkStep_Init on
 * ARKODE's first initialisation, which is also what a reset before the first step becomes), so a
 * carry set before the first step (fpl_integrator_restore, a resumed checkpoint) would be lost.
 * A compensated solver therefore takes one step when it is created and is put back at the start
 * (zero carry): later resets keep the carry fputlab sets. The step leaves no trace in the state,
 * the carry or fputlab's counters (the force count is taken as differences). */
static int sprk_start(fpl_integrator *h)
{
    fpl_sun_data *d = h->data;
    double tret = h->t;
    (void)FPL_ARK(SPRKStep, Evolve)(d->mem, h->t + h->opt.dt, d->y, &tret, ARK_ONE_STEP);
    d->err.msg[0] = '\0';      /* whatever the outcome: the run starts at (h->t, h->y) */
    int st = sprk_restart_carry(h, CARRY_ZERO);
    if (st == FPL_OK)
        memset(N_VGetArrayPointer(carry_of(h)->yerr), 0, sizeof(double) * (size_t)h->dim);
    return st;
}

/* The back end's reset: after the deviation vectors were transformed in place (their carry no
 * longer belongs to them), after a failure, and from fpl_integrator_restore (which then sets
 * or zeroes the carry through sprk_set_compensation). */
static int sprk_restart(fpl_integrator *h) { return sprk_restart_carry(h, CARRY_ORBIT); }

static int sprk_get_compensation(const fpl_integrator *h, double *carry)
{
    const sprk_carry *c = carry_of(h);
    if (!c) return FPL_ERR_ARG;
    memcpy(carry, N_VGetArrayPointer(c->yerr), sizeof(double) * (size_t)h->dim);
    return FPL_OK;
}

static int sprk_set_compensation(fpl_integrator *h, const double *carry)
{
    sprk_carry *c = carry_of(h);
    if (!c) return FPL_ERR_ARG;
    double *v = N_VGetArrayPointer(c->yerr);
    if (carry) memcpy(v, carry, sizeof(double) * (size_t)h->dim);
    else memset(v, 0, sizeof(double) * (size_t)h->dim);
    return FPL_OK;
}

static const fpl_sun_ops sprk_ops = {
    .root_return = ARK_ROOT_RETURN,
    .rhs_errors = {ARK_UNREC_RHSFUNC_ERR, ARK_REPTD_RHSFUNC_ERR, ARK_FIRST_RHSFUNC_ERR},
    .root_info = FPL_ARK(SPRKStep, GetRootInfo),
    .flag_name = FPL_ARK(SPRKStep, GetReturnFlagName),
    .restart = sprk_restart,
};

/* n fixed steps (ARK_ONE_STEP: never shortened or interpolated, so the state after n steps
 * depends on the start state only, as for our splitting schemes, and a restart from a checkpoint
 * continues bit for bit). *done gets the steps completed; counts force calls. */
static int steps(fpl_integrator *h, long n, double t_target, long *done, double *tret)
{
    fpl_sun_data *d = h->data;
    long nf1 = 0, nf1_after = 0;
    FPL_SPRK_NUM_F1(d->mem, &nf1);
    d->err.msg[0] = '\0';
    *tret = h->t;
    *done = 0;
    int flag = ARK_SUCCESS;
    while (*done < n) {
        flag = FPL_ARK(SPRKStep, Evolve)(d->mem, t_target, d->y, tret, ARK_ONE_STEP);
        if (flag != ARK_SUCCESS) break;
        ++*done;
    }
    FPL_SPRK_NUM_F1(d->mem, &nf1_after);
    h->n_force += nf1_after >= nf1 ? nf1_after - nf1 : nf1_after;
    return flag;
}

/* Restart at (h->t, h->y) with fixed step dt_step (a Reset makes a new fixed step take effect). */
static int restart_with_step(fpl_integrator *h, double dt_step, enum carry_mode mode)
{
    fpl_sun_data *d = h->data;
    int flag = FPL_ARK(SPRKStep, SetFixedStep)(d->mem, dt_step);
    if (flag != ARK_SUCCESS) return fpl_sun_setup_failed(h, "SPRKStepSetFixedStep", flag);
    return sprk_restart_carry(h, mode);
}

static int sprk_advance(fpl_integrator *h, double t_target, double *y_out)
{
    fpl_sun_data *d = h->data;
    const double dt = h->opt.dt;
    const size_t bytes = sizeof(double) * (size_t)h->dim;
    const double target = (t_target - h->t0) / dt;
    if (target > 9e18)
        return fpl_error(NULL, FPL_ERR_ARG, "t_target = %g needs more than 9e18 steps of dt = %g",
                         t_target, dt);
    /* Grid index counted from t0, never accumulated (as the splitting back end). */
    const long n_target = (long)floor(target + 1e-9);
    double tret;
    long done;
    if (n_target > h->n_steps) {
        const double t_grid = h->t0 + (double)n_target * dt;
        int flag = steps(h, n_target - h->n_steps, t_grid, &done, &tret);
        const long n_reached = h->n_steps + done;
        /* on success the time is the grid time, not ARKODE's accumulated one; on a failure
         * ARKODE returns the last accepted state, the grid state after `done` steps */
        if (flag == ARK_SUCCESS) tret = t_grid;
        else if (flag < 0) tret = h->t0 + (double)n_reached * dt;
        int st = fpl_sun_classify(h, &sprk_ops, flag, tret, t_grid, y_out);
        h->n_steps = n_reached;
        if (st != FPL_OK) return st;
        h->t = t_grid;
    } else {
        memcpy(y_out, h->y, bytes);
    }
    const double rest = t_target - h->t;
    if (rest <= 1e-9 * dt) return FPL_OK;
    /* Off the grid: one step of length rest from the grid state, then back to the grid with
     * the grid state's carry (so that sampling does not change the run, compensated or not). */
    int st = restart_with_step(h, rest, CARRY_KEEP);
    if (st != FPL_OK) return st;
    int flag = steps(h, 1, t_target, &done, &tret);
    const double *yv = N_VGetArrayPointer(d->y);
    if (flag == ARK_SUCCESS && fpl_is_finite_array(yv, h->dim, NULL)) {
        memcpy(y_out, yv, bytes);
        return restart_with_step(h, dt, CARRY_SAVED);
    }
    if (flag < 0) tret = h->t;
    const long n_grid = h->n_steps;
    st = fpl_sun_classify(h, &sprk_ops, flag, tret, t_target, y_out);
    h->n_steps = n_grid;
    if (flag != ARK_ROOT_RETURN) restart_with_step(h, dt, CARRY_SAVED);
    return st;
}

static const fpl_backend backend_sprk = {
    .family = "sprk",
    .adaptive = 0,
    .init = sprk_init,
    .advance = sprk_advance,
    .reset = sprk_restart,
    .release = sprk_release,
    .get_compensation = sprk_get_compensation,
    .set_compensation = sprk_set_compensation,
};

static const sprk_method m_mclachlan4 = {"ARKODE_SPRK_MCLACHLAN_4_4"};
static const sprk_method m_yoshida6 = {"ARKODE_SPRK_YOSHIDA_6_8"};
static const sprk_method m_suzuki_umeno8 = {"ARKODE_SPRK_SUZUKI_UMENO_8_16"};
static const sprk_method m_sofroniou10 = {"ARKODE_SPRK_SOFRONIOU_10_36"};

const fpl_method fpl_methods_sprk[] = {
    {"sprk-mclachlan4", 4, &backend_sprk, &m_mclachlan4},
    {"sprk-yoshida6", 6, &backend_sprk, &m_yoshida6},
    {"sprk-suzuki-umeno8", 8, &backend_sprk, &m_suzuki_umeno8},
    {"sprk-sofroniou10", 10, &backend_sprk, &m_sofroniou10},
    {NULL, 0, NULL, NULL},
};
#else
const fpl_method fpl_methods_sprk[] = {{NULL, 0, NULL, NULL}};
#endif
