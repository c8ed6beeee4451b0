/* Your own ARKODE ERKStep run with fputlab's FSAL-safe DOP853 table (fpl_sun_erk_table) on the
 * homogeneous FPUT-alpha chain, orbit plus one deviation vector: energy conservation and the
 * deviation vector against finite differences of two orbits. SUNDIALS 6.x or 7.x. */
#include <math.h>
#include <stdio.h>
#include <arkode/arkode_erkstep.h>
#include <fputlab.h>
#include <fputlab/sundials.h>

/* SUNDIALS 7.1 made the stepper-independent calls generic (ARKodeEvolve, ...); before, and for
 * the stepper-specific ones (ERKStepCreate, ERKStepSetTable), the names are ERKStep*. */
#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 1)
#define ERK(name) ARKode##name
#else
#define ERK(name) ERKStep##name
#endif

enum { N = 16, LEN = 2 * N * 2 };               /* orbit + 1 deviation vector */

/* Integrate y to t_end with adaptive DOP853; 0 on success. */
static int run(fpl_system *sys, SUNContext ctx, double *y, double t_end)
{
    N_Vector v = N_VMake_Serial(LEN, y, ctx);    /* works on y in place */
    void *mem = ERKStepCreate(fpl_sun_rhs, 0.0, v, ctx);
    ARKodeButcherTable B = NULL;
    if (fpl_sun_erk_table("dop853", &B) != 0) return -1;
    ERKStepSetTable(mem, B);                     /* ERKStep copies the table */
    ARKodeButcherTable_Free(B);
    ERK(SetUserData)(mem, sys);                  /* the callbacks' user data */
    ERK(SStolerances)(mem, 1e-12, 1e-14);
    ERK(SetMaxNumSteps)(mem, 1000000);
    ERK(SetStopTime)(mem, t_end);
    double t = 0.0;
    int flag = ERK(Evolve)(mem, t_end, v, &t, ARK_NORMAL);
    ERK(Free)(&mem);
    N_VDestroy(v);
    return flag < 0 ? flag : 0;
}

int main(void)
{
    fpl_lattice *lat = NULL;
    fpl_system *sys = NULL;
    double y[LEN] = {0}, yp[LEN] = {0}, ym[LEN] = {0}, e0, e1;
    const double eps = 1e-6, t_end = 50.0;
    if (fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat) != 0 ||
        fpl_system_create(lat, NULL, &sys) != 0 || fpl_modes_initial_state(lat, 1, 2.0, y) != 0) {
        fprintf(stderr, "fputlab: %s\n", fpl_last_error());
        return 1;
    }
    for (int i = 0; i < 2 * N; i++) y[2 * N + i] = sin(1.0 + i); /* deviation vector w */
    for (int i = 0; i < 2 * N; i++) {           /* two orbits y0 +- eps w (their w unused) */
        yp[i] = y[i] + eps * y[2 * N + i];
        ym[i] = y[i] - eps * y[2 * N + i];
    }
    fpl_lattice_energy(lat, y, &e0);
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);
    int flag = run(sys, ctx, y, t_end);
    if (flag == 0) flag = run(sys, ctx, yp, t_end);
    if (flag == 0) flag = run(sys, ctx, ym, t_end);
    fpl_lattice_energy(lat, y, &e1);
    double dev = 0.0, scale = 0.0;
    for (int i = 0; i < 2 * N; i++) {
        dev = fmax(dev, fabs((yp[i] - ym[i]) / (2 * eps) - y[2 * N + i]));
        scale = fmax(scale, fabs(y[2 * N + i]));
    }
    printf("ERKStep DOP853 to t = %g: flag %d, |dE/E| = %.2e, deviation vector vs finite "
           "differences %.2e (|w| ~ %.2g)\n", t_end, flag, fabs(e1 / e0 - 1.0), dev, scale);
    SUNContext_Free(&ctx);
    fpl_system_free(&sys);
    fpl_lattice_free(&lat);
    return flag != 0 || !(fabs(e1 / e0 - 1.0) < 1e-9) || !(dev < 1e-5 * scale);
}
