/* The SUNDIALS-form callbacks: consistency with the plain-array API, and a real CVODE (BDF,
 * analytic dense and band Jacobians) integration compared with an independent integrator. */
#include <string.h>
#include <cvode/cvode.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>
#include "check.h"
#include "fputlab.h"
#include "fputlab/sundials.h"
#include "fputlab/version.h"

static void test_callbacks(SUNContext ctx)
{
    const int n = 6, n_dev = 1, dim = 2 * n * (1 + n_dev);
    double v[6];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 15.0, 5, n, v));
    for (int model = 1; model <= 3; model++) {
        fpl_lattice *lat = NULL;
        CHECK_OK(fpl_lattice_create(n, 0.25, 0.1, model, v, &lat));
        fpl_system *sys = NULL; /* the callbacks' user_data: lattice + scratch (no criteria) */
        CHECK_OK(fpl_system_create(lat, NULL, &sys));
        CHECK(fpl_system_lattice(sys) == lat && fpl_system_event_count(sys) == 0, "system");
        N_Vector y = N_VNew_Serial(dim, ctx), yd = N_VNew_Serial(dim, ctx);
        N_Vector w = N_VNew_Serial(dim, ctx), jw = N_VNew_Serial(dim, ctx);
        double *ya = N_VGetArrayPointer(y), *wa = N_VGetArrayPointer(w);
        for (int i = 0; i < dim; i++) { ya[i] = 0.4 * check_uniform(); wa[i] = check_uniform(); }
        double ref[24], jac[24 * 24];
        CHECK(fpl_sun_rhs(0.0, y, yd, sys) == 0, "rhs");
        fpl_lattice_rhs(lat, ya, n_dev, ref);
        for (int i = 0; i < dim; i++) CHECK(N_VGetArrayPointer(yd)[i] == ref[i], "rhs[%d]", i);
        fpl_lattice_jacobian_dense(lat, ya, n_dev, jac);
        SUNMatrix D = SUNDenseMatrix(dim, dim, ctx);
        CHECK(fpl_sun_jac(0.0, y, yd, D, sys, NULL, NULL, NULL) == 0, "dense jac");
        sunindextype mu, ml;
        CHECK_OK(fpl_sun_band_widths(lat, n_dev, &mu, &ml));
        SUNMatrix B = SUNBandMatrix(dim, mu, ml, ctx);
        CHECK(fpl_sun_jac(0.0, y, yd, B, sys, NULL, NULL, NULL) == 0, "band jac: %s",
              fpl_system_errmsg(sys));
        CHECK(fpl_sun_jtimes(w, jw, 0.0, y, yd, sys, NULL) == 0, "jtimes");
        for (int r = 0; r < dim; r++) {
            double jv = 0.0;
            for (int c = 0; c < dim; c++) {
                jv += jac[r * dim + c] * wa[c];
                CHECK(SM_ELEMENT_D(D, r, c) == jac[r * dim + c], "dense (%d,%d)", r, c);
                double b = (c - r <= mu && r - c <= ml) ? SM_ELEMENT_B(B, r, c) : 0.0;
                CHECK(b == jac[r * dim + c], "band (%d,%d) %g vs %g", r, c, b, jac[r * dim + c]);
            }
            CHECK(fabs(N_VGetArrayPointer(jw)[r] - jv) < 1e-13, "jtimes row %d", r);
        }
        /* a vector whose length is not 2N(1+k) is refused */
        N_Vector bad = N_VNew_Serial(2 * n + 3, ctx);
        CHECK(fpl_sun_rhs(0.0, bad, bad, sys) < 0, "bad length refused");
        CHECK(strstr(fpl_system_errmsg(sys), "length") != NULL, "message names the length");
        N_VDestroy(bad);
        SUNMatDestroy(D);
        SUNMatDestroy(B);
        N_VDestroy(y); N_VDestroy(yd); N_VDestroy(w); N_VDestroy(jw);
        fpl_system_free(&sys);
    fpl_lattice_free(&lat);
    }
}

/* CVODE BDF with our Jacobian (dense or band) vs Yoshida 4 at a tiny step, model 3 (tau = 10%). */
static void test_cvode(SUNContext ctx, int band)
{
    const int n = 16, dim = 2 * n;
    double v[16], ysplit[32];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 1, n, v));
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat));
    fpl_system *sys = NULL;
    CHECK_OK(fpl_system_create(lat, NULL, &sys));
    CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, ysplit));
    N_Vector y = N_VNew_Serial(dim, ctx);
    memcpy(N_VGetArrayPointer(y), ysplit, sizeof ysplit);
    void *mem = CVodeCreate(CV_BDF, ctx);
    CHECK(CVodeInit(mem, fpl_sun_rhs, 0.0, y) == CV_SUCCESS, "CVodeInit");
    CVodeSetUserData(mem, sys);
    CVodeSStolerances(mem, 1e-11, 1e-13);
    CVodeSetMaxNumSteps(mem, 1000000);
    SUNMatrix A;
    SUNLinearSolver LS;
    if (band) {
        sunindextype mu, ml;
        fpl_sun_band_widths(lat, 0, &mu, &ml);
        A = SUNBandMatrix(dim, mu, ml, ctx);
        LS = SUNLinSol_Band(y, A, ctx);
    } else {
        A = SUNDenseMatrix(dim, dim, ctx);
        LS = SUNLinSol_Dense(y, A, ctx);
    }
    CVodeSetLinearSolver(mem, LS, A);
    CVodeSetJacFn(mem, fpl_sun_jac);
    double t = 0.0;
    int flag = CVode(mem, 20.0, y, &t, CV_NORMAL);
    CHECK(flag == CV_SUCCESS, "CVode flag %d", flag);
    long nje = 0;
    CVodeGetNumJacEvals(mem, &nje);
    CHECK(nje > 0, "the analytic Jacobian was used");
    const fpl_splitting *s = NULL;
    fpl_splitting_lookup("yoshida4", &s);
    CHECK_OK(fpl_splitting_advance(s, lat, ysplit, 0, 1e-3, 20000));
    double worst = 0.0;
    for (int i = 0; i < dim; i++) worst = fmax(worst, fabs(N_VGetArrayPointer(y)[i] - ysplit[i]));
    CHECK(worst < 1e-7, "CVODE BDF (%s) vs Yoshida 4: %g", band ? "band" : "dense", worst);
    printf("CVODE BDF %s Jacobian vs Yoshida 4 at t = 20: max difference %.2e (%ld Jacobians)\n",
           band ? "band" : "dense", worst, nje);
    CVodeFree(&mem);
    SUNLinSolFree(LS);
    SUNMatDestroy(A);
    N_VDestroy(y);
    fpl_system_free(&sys);
    fpl_lattice_free(&lat);
}

/* The compile-time version macros and the run-time strings agree with each other and with
 * the SUNDIALS headers this test was compiled against. */
static void test_versions(void)
{
    char v[64];
    snprintf(v, sizeof v, "%d.%d.%d", FPL_VERSION_MAJOR, FPL_VERSION_MINOR, FPL_VERSION_PATCH);
    CHECK(strcmp(v, fpl_version()) == 0 && strcmp(FPL_VERSION_STRING, fpl_version()) == 0,
          "FPL_VERSION_* %s vs fpl_version() %s", v, fpl_version());
    CHECK(FPL_VERSION_NUMBER == FPL_VERSION_ENCODE(FPL_VERSION_MAJOR, FPL_VERSION_MINOR,
                                                   FPL_VERSION_PATCH), "FPL_VERSION_NUMBER");
    CHECK(strcmp(fpl_sundials_version(), SUNDIALS_VERSION) == 0, "SUNDIALS %s vs headers %s",
          fpl_sundials_version(), SUNDIALS_VERSION);
    printf("fputlab %s (headers %s), SUNDIALS %s\n", fpl_version(), v, fpl_sundials_version());
}

/* A ring: the dense Jacobian through the callback equals fpl_lattice_jacobian_dense (whose
 * entries test_derivatives checks against finite differences); band matrices are refused with a
 * message, since the wrap-around bond couples x_0 and x_{N-1}. */
static void test_ring_jacobian(SUNContext ctx)
{
    const int n = 6, n_dev = 1, dim = 2 * n * (1 + n_dev);
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create_ex(n, 0.25, 0.1, FPL_MODEL_HOMOGENEOUS, NULL,
                                   FPL_BOUNDARY_PERIODIC, &lat));
    fpl_system *sys = NULL;
    CHECK_OK(fpl_system_create(lat, NULL, &sys));
    N_Vector y = N_VNew_Serial(dim, ctx), yd = N_VNew_Serial(dim, ctx);
    for (int i = 0; i < dim; i++) N_VGetArrayPointer(y)[i] = 0.3 * check_uniform();
    static double jac[24 * 24];
    CHECK_OK(fpl_lattice_jacobian_dense(lat, N_VGetArrayPointer(y), n_dev, jac));
    SUNMatrix D = SUNDenseMatrix(dim, dim, ctx);
    CHECK(fpl_sun_jac(0.0, y, yd, D, sys, NULL, NULL, NULL) == 0, "ring: dense jac");
    for (int r = 0; r < dim; r++)
        for (int c = 0; c < dim; c++)
            CHECK(SM_ELEMENT_D(D, r, c) == jac[r * dim + c], "ring: dense (%d,%d)", r, c);
    CHECK(jac[n * dim + (n - 1)] != 0.0, "ring: dF_0/dx_{N-1} is the wrap-around coupling");
    sunindextype mu = 0, ml = 0;
    CHECK(fpl_sun_band_widths(lat, n_dev, &mu, &ml) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "not banded"), "ring: band widths not refused");
    SUNMatrix B = SUNBandMatrix(dim, dim - 1, dim - 1, ctx);
    CHECK(fpl_sun_jac(0.0, y, yd, B, sys, NULL, NULL, NULL) == -1 &&
          strstr(fpl_system_errmsg(sys), "not banded"), "ring: band jac not refused");
    SUNMatDestroy(D);
    SUNMatDestroy(B);
    N_VDestroy(y);
    N_VDestroy(yd);
    fpl_system_free(&sys);
    fpl_lattice_free(&lat);
}

int main(void)
{
    test_versions();
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);
    test_callbacks(ctx);
    test_cvode(ctx, 0);
    test_cvode(ctx, 1);
    test_ring_jacobian(ctx);
    SUNContext_Free(&ctx);
    return check_report("sundials");
}
