/* Jacobians, tangent forces and Hamilton's equations against central finite differences and
 * against the paper's equations of motion written out independently here. */
#include <string.h>
#include "check.h"
#include "fputlab.h"

#define NMAX 40

static double rel_err(double a, double b, double scale) { return fabs(a - b) / (fabs(b) + scale); }

/* Paper Eqs. (eqnmotions), (dis1), (varnonlin) plus the quartic term, and the Toda chain
 * (model 4), written from scratch: returns x_j'' for j = 1..n; ring: the neighbours of the end
 * particles are each other (periodic boundaries), else the fixed walls. */
static void paper_acceleration(int model, int n, double a, double b, const double *v,
                               const double *x, double *acc, int ring)
{
    double X[NMAX + 2], V[NMAX + 2];
    X[0] = X[n + 1] = 0.0;
    V[0] = V[n + 1] = 1.0;
    for (int j = 1; j <= n; j++) { X[j] = x[j - 1]; V[j] = v[j - 1]; }
    if (ring) {
        X[0] = X[n];
        V[0] = V[n];
        X[n + 1] = X[1];
        V[n + 1] = V[1];
    }
    for (int j = 1; j <= n; j++) {
        double dr = X[j + 1] - X[j], dl = X[j] - X[j - 1];
        double rr = V[j + 1] * X[j + 1] - V[j] * X[j], rl = V[j] * X[j] - V[j - 1] * X[j - 1];
        if (model == 4)
            acc[j - 1] = (exp(2 * a * dr) - exp(2 * a * dl)) / (2 * a);
        else if (model == 1)
            acc[j - 1] = dr + a * dr * dr + b * dr * dr * dr - dl - a * dl * dl - b * dl * dl * dl;
        else if (model == 2)
            acc[j - 1] = rr + a * rr * rr + b * rr * rr * rr - rl - a * rl * rl - b * rl * rl * rl;
        else
            acc[j - 1] = dr + a * rr * rr + b * rr * rr * rr - dl - a * rl * rl - b * rl * rl * rl;
    }
}

static void test_model(int model, int n, double beta, int boundary)
{
    double v[NMAX], y[6 * NMAX], f[NMAX], acc[NMAX], yd[6 * NMAX];
    const int ring = boundary == FPL_BOUNDARY_PERIODIC;
    for (int j = 0; j < n; j++) v[j] = model == 4 ? 1.0 : 1.0 + 0.2 * check_uniform();
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create_ex(n, 0.25, beta, model, v, boundary, &lat));
    CHECK(fpl_lattice_boundary(lat) == boundary, "boundary %d not kept", boundary);
    if (!lat) return;
    const int n_dev = 2, dim = 2 * n * (1 + n_dev);
    for (int i = 0; i < dim; i++) y[i] = 0.4 * check_uniform();

    /* force equals the paper's acceleration times the mass */
    CHECK_OK(fpl_lattice_force(lat, y, f));
    paper_acceleration(model, n, 0.25, beta, v, y, acc, ring);
    for (int i = 0; i < n; i++) {
        double mass = model == 2 ? v[i] : 1.0;
        CHECK(rel_err(f[i], mass * acc[i], 1e-12) < 1e-12, "model %d ring %d force[%d] %g vs "
              "paper %g", model, ring, i, f[i], mass * acc[i]);
    }

    /* dense Jacobian of the extended system (orbit + 2 vectors) vs central differences of rhs */
    static double jac[(6 * NMAX) * (6 * NMAX)];
    CHECK_OK(fpl_lattice_jacobian_dense(lat, y, n_dev, jac));
    double yp[6 * NMAX], ym[6 * NMAX], fp[6 * NMAX], fm[6 * NMAX];
    const double h = 1e-6;
    double worst = 0.0;
    for (int c = 0; c < dim; c++) {
        memcpy(yp, y, sizeof(double) * dim);
        memcpy(ym, y, sizeof(double) * dim);
        yp[c] += h;
        ym[c] -= h;
        fpl_lattice_rhs(lat, yp, n_dev, fp);
        fpl_lattice_rhs(lat, ym, n_dev, fm);
        for (int r = 0; r < dim; r++) {
            double fd = (fp[r] - fm[r]) / (2 * h);
            double e = fabs(jac[r * dim + c] - fd);
            if (e > worst) worst = e;
        }
    }
    CHECK(worst < 1e-8, "model %d N %d beta %g ring %d: dense Jacobian vs FD max error %g",
          model, n, beta, ring, worst);

    /* tridiagonal force Jacobian vs FD of the force (a ring's is not tridiagonal: refused) */
    double lo[NMAX], di[NMAX], up[NMAX], xp[NMAX], xm[NMAX], ffp[NMAX], ffm[NMAX];
    if (ring) CHECK(fpl_lattice_force_jacobian(lat, y, lo, di, up) == FPL_ERR_ARG &&
                    strstr(fpl_last_error(), "boundary"), "ring: tridiagonal Jacobian not refused");
    else CHECK_OK(fpl_lattice_force_jacobian(lat, y, lo, di, up));
    worst = 0.0;
    for (int c = 0; c < n && !ring; c++) {
        memcpy(xp, y, sizeof(double) * n);
        memcpy(xm, y, sizeof(double) * n);
        xp[c] += h;
        xm[c] -= h;
        fpl_lattice_force(lat, xp, ffp);
        fpl_lattice_force(lat, xm, ffm);
        for (int r = 0; r < n; r++) {
            double fd = (ffp[r] - ffm[r]) / (2 * h);
            double an = r == c ? di[r] : r == c - 1 ? up[r] : r == c + 1 ? lo[c] : 0.0;
            if (fabs(an - fd) > worst) worst = fabs(an - fd);
        }
    }
    CHECK(worst < 1e-8, "model %d: tridiagonal Jacobian vs FD max error %g", model, worst);

    /* tangent force vs directional finite differences, two vectors at once */
    double dx[2 * NMAX], df[2 * NMAX];
    for (int i = 0; i < 2 * n; i++) dx[i] = check_uniform();
    CHECK_OK(fpl_lattice_tangent_force(lat, y, 2, dx, df));
    worst = 0.0;
    for (int m = 0; m < 2; m++) {
        for (int i = 0; i < n; i++) { xp[i] = y[i] + h * dx[m * n + i]; xm[i] = y[i] - h * dx[m * n + i]; }
        fpl_lattice_force(lat, xp, ffp);
        fpl_lattice_force(lat, xm, ffm);
        for (int i = 0; i < n; i++) {
            double fd = (ffp[i] - ffm[i]) / (2 * h);
            if (fabs(df[m * n + i] - fd) > worst) worst = fabs(df[m * n + i] - fd);
        }
    }
    CHECK(worst < 1e-8, "model %d: tangent force vs FD max error %g", model, worst);

    /* rhs carries the variational equations: dx' = minv dp, dp' = J dx */
    CHECK_OK(fpl_lattice_rhs(lat, y, n_dev, yd));
    for (int m = 1; m <= n_dev; m++) {
        const double *w = y + 2 * n * m;
        double jd[NMAX];
        fpl_lattice_tangent_force(lat, y, 1, w, jd);
        for (int i = 0; i < n; i++) {
            double minv = model == 2 ? 1.0 / v[i] : 1.0;
            CHECK(rel_err(yd[2 * n * m + i], minv * w[n + i], 1e-14) < 1e-13, "dx' mismatch");
            CHECK(rel_err(yd[2 * n * m + n + i], jd[i], 1e-14) < 1e-13, "dp' mismatch");
        }
    }

    /* Hamilton's equations: p' = -dH/dx, x' = dH/dp for models 1-2 (H from fpl_lattice_energy) */
    if (model != 3) {
        worst = 0.0;
        for (int c = 0; c < 2 * n; c++) {
            double Hp, Hm;
            memcpy(yp, y, sizeof(double) * 2 * n);
            memcpy(ym, y, sizeof(double) * 2 * n);
            yp[c] += h;
            ym[c] -= h;
            fpl_lattice_energy(lat, yp, &Hp);
            fpl_lattice_energy(lat, ym, &Hm);
            double dH = (Hp - Hm) / (2 * h);
            double expect = c < n ? -yd[n + c] : yd[c - n];
            if (fabs(dH - expect) > worst) worst = fabs(dH - expect);
        }
        CHECK(worst < 1e-8, "model %d: Hamilton's equations vs FD of H, max error %g", model,
              worst);
    }
    fpl_lattice_free(&lat);
    CHECK(lat == NULL, "free must clear the handle");
}

static void test_unit_variability(void)
{
    const int n = 12;
    double v[12], x[12], f[3][12];
    for (int j = 0; j < n; j++) { v[j] = 1.0; x[j] = 0.5 * check_uniform(); }
    for (int model = 1; model <= 3; model++) {
        fpl_lattice *lat = NULL;
        CHECK_OK(fpl_lattice_create(n, 0.25, 0.05, model, v, &lat));
        CHECK_OK(fpl_lattice_force(lat, x, f[model - 1]));
        fpl_lattice_free(&lat);
    }
    for (int j = 0; j < n; j++) {
        CHECK(f[0][j] == f[1][j] && f[0][j] == f[2][j], "v = 1: forces differ at %d: %g %g %g", j,
              f[0][j], f[1][j], f[2][j]);
    }
}

static void test_toda_refusals(void)
{
    fpl_lattice *lat = NULL;
    double v[4] = {1.0, 1.0, 1.1, 1.0};
    CHECK(fpl_lattice_create(4, 0.25, 0.1, FPL_MODEL_TODA, NULL, &lat) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "beta"), "Toda with beta != 0 not refused");
    CHECK(fpl_lattice_create(4, 0.0, 0.0, FPL_MODEL_TODA, NULL, &lat) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "alpha"), "Toda with alpha = 0 not refused");
    CHECK(fpl_lattice_create(4, 0.25, 0.0, FPL_MODEL_TODA, v, &lat) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "v[2]"), "Toda with disorder not refused");
    CHECK(fpl_lattice_create_ex(4, 0.25, 0.0, 1, NULL, 2, &lat) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "boundary"), "unknown boundary not refused");
    CHECK(lat == NULL, "no lattice on error");
    CHECK(fpl_lattice_boundary(NULL) == -1, "boundary of NULL");
}

int main(void)
{
    for (int boundary = FPL_BOUNDARY_FIXED; boundary <= FPL_BOUNDARY_PERIODIC; boundary++) {
        for (int model = 1; model <= 3; model++) {
            test_model(model, 8, 0.0, boundary);
            test_model(model, 17, 0.3, boundary);
            test_model(model, 2, 0.0, boundary);
        }
        test_model(FPL_MODEL_TODA, 8, 0.0, boundary);
        test_model(FPL_MODEL_TODA, 2, 0.0, boundary);
        test_model(FPL_MODEL_TODA, 17, 0.0, boundary);
    }
    test_toda_refusals();
    test_unit_variability();
    return check_report("derivatives");
}
