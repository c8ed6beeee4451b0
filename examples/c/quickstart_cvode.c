/* The disordered lattice of model 3 integrated by your own CVODE (BDF, Newton, dense linear
 * solver, our analytic Jacobian), checked against fputlab's DOP853. SUNDIALS 6.x or 7.x.
 * Build: cc quickstart_cvode.c $(pkg-config --cflags --libs fputlab) -lm */
#include <math.h>
#include <stdio.h>
#include <cvode/cvode.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <fputlab.h>
#include <fputlab/sundials.h>

int main(void)
{
    enum { N = 32, LEN = 2 * N };               /* y = [x, p]; with k deviation vectors 2N(1+k) */
    double v[N], y0[LEN], ref[LEN];
    fpl_lattice *lat = NULL;                     /* read-only physics: N, alpha, beta, model, v */
    fpl_system *sys = NULL;                      /* lattice + scratch (+ criteria): user data */
    if (fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, /*seed*/ 1, N, v) != 0 ||
        fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat) != 0 ||
        fpl_system_create(lat, /*events*/ NULL, &sys) != 0 ||
        fpl_modes_initial_state(lat, 1, 1.0, y0) != 0) {
        fprintf(stderr, "fputlab: %s\n", fpl_last_error());
        return 1;
    }
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);  /* NULL in SUNDIALS 6, SUN_COMM_NULL in 7 */
    N_Vector y = N_VNew_Serial(LEN, ctx);
    for (int i = 0; i < LEN; i++) NV_Ith_S(y, i) = y0[i];
    void *mem = CVodeCreate(CV_BDF, ctx);
    CVodeInit(mem, fpl_sun_rhs, 0.0, y);
    CVodeSetUserData(mem, sys);                  /* the callbacks' user data is the system */
    CVodeSStolerances(mem, 1e-10, 1e-12);
    CVodeSetMaxNumSteps(mem, 100000);
    SUNMatrix A = SUNDenseMatrix(LEN, LEN, ctx); /* or SUNBandMatrix: fpl_sun_band_widths */
    SUNLinearSolver LS = SUNLinSol_Dense(y, A, ctx);
    CVodeSetLinearSolver(mem, LS, A);            /* attach the linear solver first, */
    CVodeSetJacFn(mem, fpl_sun_jac);             /* then our Jacobian */
    double t = 0.0, err = 0.0;
    int flag = CVode(mem, 10.0, y, &t, CV_NORMAL);

    fpl_integrator *dop = NULL;                  /* the same run with fputlab's DOP853 */
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.rtol = 1e-12;
    opt.atol = 1e-14;
    int st = fpl_integrator_create(lat, "dop853", 0, &opt, 0.0, y0, &dop);
    if (st == 0) st = fpl_integrator_advance(dop, 10.0, ref);
    for (int i = 0; i < LEN; i++) err = fmax(err, fabs(NV_Ith_S(y, i) - ref[i]));
    printf("CVODE BDF to t = %g: flag %d, max |y - y_dop853| = %.2e\n", t, flag, err);
    fpl_integrator_free(&dop);
    CVodeFree(&mem);
    SUNLinSolFree(LS);
    SUNMatDestroy(A);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    fpl_system_free(&sys);
    fpl_lattice_free(&lat);
    return flag < 0 || st != 0 || !(err < 1e-6);
}
