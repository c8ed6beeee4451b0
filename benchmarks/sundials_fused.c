/* Issue 15, part 4: cost of the SUNDIALS path per particle and right-hand-side evaluation and
 * per particle and step: plain ERKStep with DOP853 (fputlab's table) on serial vectors, with
 * SUNDIALS' fused N_Vector operations (N_VEnableFusedOps_Serial), fputlab's dop853 (the same
 * ERKStep with fputlab's own N_VLinearCombination, backend_arkode.c) and gsl-rk8pd.
 * The benchmarks/README.md problem: homogeneous FPUT-alpha chain, mode 1, 2 deviation vectors,
 * rtol = atol = 1e-10, to T (default 20). Cost = process CPU time, best of 5.
 * Built and run by benchmarks/sundials_fused.sh against each SUNDIALS build. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <arkode/arkode_erkstep.h>
#include <fputlab.h>
#include <fputlab/sundials.h>

#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 1)
#define ERK(name) ARKode##name
#else
#define ERK(name) ERKStep##name
#endif
/* 7.2 deprecated ERKStepGetNumRhsEvals for ARKodeGetNumRhsEvals(mem, partition, &n). */
#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 2)
#define ERK_NUM_RHS(mem, n) ARKodeGetNumRhsEvals((mem), 0, (n))
#else
#define ERK_NUM_RHS(mem, n) ERKStepGetNumRhsEvals((mem), (n))
#endif

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void initial(fpl_lattice *lat, int n, double *y)
{
    fpl_modes_initial_state(lat, 1, 1.0, y);
    srand(1);
    for (int i = 2 * n; i < 6 * n; i++) y[i] = rand() / (double)RAND_MAX - 0.5;
}

/* ERKStep with our DOP853 table on fpl_sun_rhs; returns ns/(p*f), *per_step ns/(p*step). */
static double erk(fpl_lattice *lat, int n, int fused, double T, double *err_out, const double *ref,
                  double *per_step)
{
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);
    N_Vector y = N_VNew_Serial(6 * n, ctx);
    if (fused) N_VEnableFusedOps_Serial(y, SUNTRUE);
    initial(lat, n, N_VGetArrayPointer(y));
    double t0 = now();
    void *mem = ERKStepCreate(fpl_sun_rhs, 0.0, y, ctx);
    ARKodeButcherTable B = NULL;
    fpl_sun_erk_table("dop853", &B);
    ERKStepSetTable(mem, B);
    ARKodeButcherTable_Free(B);
    fpl_system *sys = NULL;                  /* the callbacks' user data */
    fpl_system_create(lat, NULL, &sys);
    ERK(SetUserData)(mem, sys);
    ERK(SStolerances)(mem, 1e-10, 1e-10);
    ERK(SetMaxNumSteps)(mem, 10000000);
    ERK(SetStopTime)(mem, T);
    double t = 0.0;
    ERK(Evolve)(mem, T, y, &t, ARK_NORMAL);
    double wall = now() - t0;
    long nfe = 0, nst = 0;
    ERK_NUM_RHS(mem, &nfe);
    ERK(GetNumSteps)(mem, &nst);
    *per_step = 1e9 * wall / ((double)nst * n);
    double err = 0.0;
    for (int i = 0; i < 6 * n; i++) err = fmax(err, fabs(NV_Ith_S(y, i) - ref[i]));
    *err_out = err;
    ERK(Free)(&mem);
    fpl_system_free(&sys);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return 1e9 * wall / ((double)nfe * n);
}

static double fpl(fpl_lattice *lat, int n, const char *method, double T, double *err_out,
                  const double *ref, double *per_step)
{
    double *y0 = malloc(sizeof(double) * 6 * n), *y = malloc(sizeof(double) * 6 * n);
    initial(lat, n, y0);
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.rtol = opt.atol = 1e-10;
    double t0 = now();
    fpl_integrator *h = NULL;
    fpl_integrator_create(lat, method, 2, &opt, 0.0, y0, &h);
    fpl_integrator_advance(h, T, y);
    double wall = now() - t0;
    long steps, nf;
    fpl_integrator_counters(h, &steps, &nf);
    *per_step = 1e9 * wall / ((double)steps * n);
    double err = 0.0;
    for (int i = 0; i < 6 * n && ref; i++) err = fmax(err, fabs(y[i] - ref[i]));
    *err_out = err;
    fpl_integrator_free(&h);
    free(y0);
    free(y);
    return 1e9 * wall / ((double)nf * n);
}

int main(int argc, char **argv)
{
    const double T = argc > 1 ? atof(argv[1]) : 20.0;
    printf("SUNDIALS %s, T = %g, rtol = atol = 1e-10, 2 deviation vectors: CPU time, best of 5 "
           "(error vs srkn14a6 dt 0.01)\n", fpl_sundials_version(), T);
    printf("%6s %14s %14s %14s %14s\n", "N", "ERKStep", "ERKStep+fused", "fpl dop853",
           "fpl gsl-rk8pd");
    for (int n = 512; n <= 4096; n *= 8) {
        fpl_lattice *lat = NULL;
        fpl_lattice_create(n, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat);
        double *y0 = malloc(sizeof(double) * 6 * n), *ref = malloc(sizeof(double) * 6 * n);
        initial(lat, n, y0);
        fpl_integrator_options opt;
        fpl_integrator_options_init(&opt);
        fpl_integrator *h = NULL;
        fpl_integrator_create(lat, "srkn14a6", 2, &opt, 0.0, y0, &h);
        fpl_integrator_advance(h, T, ref);
        fpl_integrator_free(&h);
        double best[4] = {1e300, 1e300, 1e300, 1e300}, err[4], step[4] = {1e300, 1e300, 1e300, 1e300};
        for (int r = 0; r < 5; r++) {
            double ps;
            best[0] = fmin(best[0], erk(lat, n, 0, T, &err[0], ref, &ps));
            step[0] = fmin(step[0], ps);
            best[1] = fmin(best[1], erk(lat, n, 1, T, &err[1], ref, &ps));
            step[1] = fmin(step[1], ps);
            best[2] = fmin(best[2], fpl(lat, n, "dop853", T, &err[2], ref, &ps));
            step[2] = fmin(step[2], ps);
            best[3] = fmin(best[3], fpl(lat, n, "gsl-rk8pd", T, &err[3], ref, &ps));
            step[3] = fmin(step[3], ps);
        }
        printf("%6d %14.1f %14.1f %14.1f %14.1f   ns/(p*f)\n", n, best[0], best[1], best[2], best[3]);
        printf("%6s %14.1f %14.1f %14.1f %14.1f   ns/(p*step)  (fpl dop853 / gsl %.2f per step)\n",
               "", step[0], step[1], step[2], step[3], step[2] / step[3]);
        printf("%6s %14.1e %14.1e %14.1e %14.1e   error\n", "", err[0], err[1], err[2], err[3]);
        free(y0);
        free(ref);
        fpl_lattice_free(&lat);
    }
    return 0;
}
