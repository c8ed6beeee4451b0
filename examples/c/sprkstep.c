/* Your own ARKODE SPRKStep run (SUNDIALS >= 6.6) on fputlab's split callbacks: the homogeneous
 * FPUT-alpha chain with Yoshida's 6th-order table at a fixed step, energy error over a long run,
 * and the same run with fputlab's own "sprk-yoshida6" method. fpl_sun_force is f1 (momenta,
 * depends on positions), fpl_sun_velocity is f2 (positions, depends on momenta). */
#include <math.h>
#include <stdio.h>
#include <arkode/arkode_sprkstep.h>
#include <fputlab.h>
#include <fputlab/sundials.h>

/* SUNDIALS 7.1 made the stepper-independent calls generic (ARKodeEvolve, ...). */
#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 1)
#define SPRK(name) ARKode##name
#else
#define SPRK(name) SPRKStep##name
#endif

enum { N = 16, LEN = 2 * N };

int main(void)
{
    fpl_lattice *lat = NULL;
    fpl_system *sys = NULL;                            /* the callbacks' user data */
    double y0[LEN], ref[LEN], e0, e, max_err = 0.0;
    const double dt = 0.1, t_end = 1000.0;
    if (fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat) != 0 ||
        fpl_system_create(lat, NULL, &sys) != 0 || fpl_modes_initial_state(lat, 1, 2.0, y0) != 0 ||
        fpl_lattice_energy(lat, y0, &e0) != 0) {
        fprintf(stderr, "fputlab: %s\n", fpl_last_error());
        return 1;
    }
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);
    N_Vector y = N_VNew_Serial(LEN, ctx);
    for (int i = 0; i < LEN; i++) NV_Ith_S(y, i) = y0[i];
    void *mem = SPRKStepCreate(fpl_sun_force, fpl_sun_velocity, 0.0, y, ctx);
    SPRKStepSetMethodName(mem, "ARKODE_SPRK_YOSHIDA_6_8");
    SPRK(SetUserData)(mem, sys);
    SPRK(SetFixedStep)(mem, dt);
    SPRK(SetMaxNumSteps)(mem, 100000);
    int flag = 0;
    double t = 0.0;
    for (int k = 1; k <= 100 && flag >= 0; k++) {     /* a sample every 10 time units */
        flag = SPRK(Evolve)(mem, 10.0 * k, y, &t, ARK_NORMAL);
        fpl_lattice_energy(lat, N_VGetArrayPointer(y), &e);
        max_err = fmax(max_err, fabs(e / e0 - 1.0));
    }
    fpl_integrator *h = NULL;                          /* the same with fputlab's method */
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.dt = dt;
    int st = fpl_integrator_create(lat, "sprk-yoshida6", 0, &opt, 0.0, y0, &h);
    if (st == 0) st = fpl_integrator_advance(h, t_end, ref);
    double diff = 0.0;
    for (int i = 0; i < LEN; i++) diff = fmax(diff, fabs(NV_Ith_S(y, i) - ref[i]));
    printf("SPRKStep Yoshida 6, dt = %g to t = %g: flag %d, max |dE/E| = %.2e, "
           "vs fputlab sprk-yoshida6 %.2e\n", dt, t, flag, max_err, diff);
    fpl_integrator_free(&h);
    SPRK(Free)(&mem);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    fpl_system_free(&sys);
    fpl_lattice_free(&lat);
    return flag < 0 || st != 0 || !(max_err < 1e-7) || !(diff < 1e-8);
}
