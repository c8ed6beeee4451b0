/* Two-mode reduction: coefficients against the paper and a brute-force projection of the lattice
 * force, exact quadratic dependence on tau, Galerkin truncation against the full lattice and the
 * two-mode ODE, bad input and blow-up. */
#include <string.h>
#include "check.h"
#include "fputlab.h"

static const fpl_splitting *scheme(const char *name)
{
    const fpl_splitting *s = NULL;
    CHECK_OK(fpl_splitting_lookup(name, &s));
    return s;
}

static double shape(int n, int j, int k) /* A_jk, 1-based */
{
    return sqrt(2.0 / (n + 1.0)) * sin(M_PI * j * k / (n + 1.0));
}

static double omega(int n, int k) { return 2.0 * sin(k * M_PI / (2.0 * (n + 1))); }

/* Paper Sec. 4 (and NOTES.md): tau = 0, N = 64, alpha = 0.25 -> A~ = 3.62805, B~ = 0.90728. */
static void test_paper_values(void)
{
    double a[3], b[3], at, bt, A[3], B[3];
    CHECK_OK(fpl_reduction_coefficients(64, 0.25, FPL_MODEL_NONLINEAR, NULL, a, b));
    CHECK_OK(fpl_reduction_normalise(64, a, b, A, B, &at, &bt));
    CHECK(fabs(at - 3.62805) < 5e-6, "A~ = %.7f, paper 3.62805", at);
    CHECK(fabs(bt - 0.90728) < 5e-6, "B~ = %.7f, paper 0.90728", bt);
    /* selection rules of the homogeneous chain: only Q1 Q2 (mode 1) and Q1^2 (mode 2) couple */
    CHECK(fabs(a[0]) + fabs(a[1]) + fabs(b[1]) + fabs(b[2]) < 1e-18, "non-resonant a/b not 0");
    const double eps = omega(64, 2) - 2.0 * omega(64, 1);
    CHECK(fabs(A[2] - a[2] / eps) < 1e-12 && fabs(B[0] - b[0] / eps) < 1e-12, "A_i = a_i/eps");
    printf("tau = 0, N = 64: A~ = %.6f, B~ = %.6f (a3 = %.6e, b1 = %.6e, eps = %.6e)\n", at, bt,
           a[2], b[0], eps);
}

/* Brute force: the quadratic part of the projected acceleration is (acc(Q) + acc(-Q))/2 (the
 * linear and cubic parts are odd), evaluated with the lattice force and an explicit A. */
static void brute_force(fpl_lattice *lat, int n, const double *mass, double q1, double q2,
                        double *out)
{
    double x[64], f[64], acc[2][2];
    for (int sgn = 0; sgn < 2; sgn++) {
        double s = sgn ? -1.0 : 1.0;
        for (int j = 1; j <= n; j++) x[j - 1] = s * (q1 * shape(n, j, 1) + q2 * shape(n, j, 2));
        CHECK_OK(fpl_lattice_force(lat, x, f));
        for (int k = 1; k <= 2; k++) {
            double sum = 0.0;
            for (int j = 1; j <= n; j++) sum += shape(n, j, k) * f[j - 1] / mass[j - 1];
            acc[sgn][k - 1] = sum;
        }
    }
    out[0] = 0.5 * (acc[0][0] + acc[1][0]);
    out[1] = 0.5 * (acc[0][1] + acc[1][1]);
}

static void test_brute_force(int model)
{
    const int n = 17;
    double v[17], ones[17], a[3], b[3];
    for (int j = 0; j < n; j++) v[j] = 1.0 + 0.2 * check_uniform(), ones[j] = 1.0;
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.31, 0.07, model, v, &lat));
    CHECK_OK(fpl_reduction_coefficients(n, 0.31, model, v, a, b));
    const double *mass = model == FPL_MODEL_HAMILTONIAN ? v : ones;
    double q10[2], q01[2], q11[2];
    brute_force(lat, n, mass, 1.0, 0.0, q10);
    brute_force(lat, n, mass, 0.0, 1.0, q01);
    brute_force(lat, n, mass, 1.0, 1.0, q11);
    double ref_a[3] = {q10[0], q01[0], q11[0] - q10[0] - q01[0]};
    double ref_b[3] = {q10[1], q01[1], q11[1] - q10[1] - q01[1]};
    double worst = 0.0;
    for (int i = 0; i < 3; i++)
        worst = fmax(worst, fmax(fabs(a[i] - ref_a[i]), fabs(b[i] - ref_b[i])));
    CHECK(worst < 1e-13, "model %d: coefficients differ from the projected force by %g", model,
          worst);
    fpl_lattice_free(&lat);
}

/* Same draws z, v = 1 + (tau/300) z: every coefficient is a quadratic in tau, so the value at
 * tau = 30 is the extrapolation f(3h) = f(0) - 3 f(h) + 3 f(2h) from tau = 0, 10, 20. */
static void test_quadratic_in_tau(void)
{
    const int n = 64;
    double z[64], v[64], c[4][6];
    const double taus[4] = {0.0, 10.0, 20.0, 30.0};
    CHECK_OK(fpl_disorder_standard(FPL_DISORDER_GAUSSIAN, 11, n, z));
    for (int t = 0; t < 4; t++) {
        for (int j = 0; j < n; j++) v[j] = 1.0 + taus[t] / 300.0 * z[j];
        CHECK_OK(fpl_reduction_coefficients(n, 0.25, FPL_MODEL_NONLINEAR, v, c[t], c[t] + 3));
    }
    for (int i = 0; i < 6; i++) {
        double pred = c[0][i] - 3.0 * c[1][i] + 3.0 * c[2][i];
        CHECK(fabs(pred - c[3][i]) < 1e-12 * fabs(c[0][0] - c[0][2]) + 1e-20,
              "coefficient %d is not quadratic in tau: %g vs %g", i, pred, c[3][i]);
    }
    /* the tridiagonal forms give the same numbers: c = v^T M v */
    double diag[6 * 64], off[6 * 63];
    CHECK_OK(fpl_reduction_quadratic_forms(n, 0.25, diag, off));
    for (int i = 0; i < 6; i++) {
        double q = 0.0;
        for (int j = 0; j < n; j++) q += diag[i * n + j] * v[j] * v[j];
        for (int j = 0; j < n - 1; j++) q += 2.0 * off[i * (n - 1) + j] * v[j] * v[j + 1];
        CHECK(fabs(q - c[3][i]) < 1e-12 * fabs(c[0][2]), "form %d: %g vs %g", i, q, c[3][i]);
    }
    /* moments at tau = 0 are the homogeneous coefficients, with no spread */
    double mean[6], cov[36];
    CHECK_OK(fpl_reduction_moments(n, 0.25, FPL_MODEL_NONLINEAR, FPL_DISORDER_GAUSSIAN, 0.0, mean,
                                   cov));
    for (int i = 0; i < 6; i++) CHECK(fabs(mean[i] - c[0][i]) < 1e-15, "mean %d at tau 0", i);
    for (int i = 0; i < 36; i++) CHECK(cov[i] == 0.0, "cov %d at tau 0", i);
}

/* Galerkin with M = 2 is the two-mode ODE: Q_k'' = -omega_k^2 Q_k + quadratic (beta = 0). */
static void test_galerkin_two_modes(void)
{
    const int n = 32;
    double v[32], a[3], b[3];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 4, n, v));
    fpl_lattice *lat = NULL;
    fpl_galerkin *g = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat));
    CHECK_OK(fpl_galerkin_create(lat, 2, &g));
    CHECK(fpl_galerkin_modes(g) == 2 && fpl_galerkin_size(g) == n, "sizes");
    CHECK_OK(fpl_reduction_coefficients(n, 0.25, FPL_MODEL_NONLINEAR, v, a, b));
    const double q[2] = {1.3, -0.7};
    double acc[2];
    CHECK_OK(fpl_galerkin_acceleration(g, q, acc));
    double w1 = omega(n, 1), w2 = omega(n, 2);
    double ref1 = -w1 * w1 * q[0] + a[0] * q[0] * q[0] + a[1] * q[1] * q[1] + a[2] * q[0] * q[1];
    double ref2 = -w2 * w2 * q[1] + b[0] * q[0] * q[0] + b[1] * q[1] * q[1] + b[2] * q[0] * q[1];
    CHECK(fabs(acc[0] - ref1) < 1e-14 && fabs(acc[1] - ref2) < 1e-14,
          "M = 2 acceleration (%g, %g) vs two-mode (%g, %g)", acc[0], acc[1], ref1, ref2);

    /* and the two runs agree sample by sample (off-grid sample times included) */
    const double ts[3] = {0.0, 123.456, 1000.0};
    double z0[4] = {sqrt((n + 1) / 2.0), 0.0, 0.0, 0.0}, s1[12], s2[12], e[6];
    double w[2] = {w1, w2};
    int done1 = 0, done2 = 0;
    CHECK_OK(fpl_galerkin_run(scheme("yoshida4"), g, z0, 0.0, 0.05, ts, 3, e, s1, &done1));
    CHECK_OK(fpl_reduction_two_mode_run(scheme("yoshida4"), w, a, b, z0, 0.0, 0.05, ts, 3, s2,
                                        &done2));
    CHECK(done1 == 3 && done2 == 3, "samples %d %d", done1, done2);
    double worst = 0.0;
    for (int i = 0; i < 12; i++) worst = fmax(worst, fabs(s1[i] - s2[i]));
    CHECK(worst < 1e-10, "Galerkin M = 2 vs two-mode ODE: %g", worst);
    CHECK(fabs(e[0] - 0.5 * w1 * w1 * z0[0] * z0[0]) < 1e-15 && e[1] == 0.0, "E_k at t = 0");
    fpl_galerkin_free(&g);
    fpl_lattice_free(&lat);
}

/* M = N is the full lattice in mode coordinates: same scheme, same dt, round-off agreement. */
static void test_galerkin_full(int model)
{
    const int n = 16;
    double v[16], y[32], z[32], x[16];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 9, n, v));
    fpl_lattice *lat = NULL;
    fpl_galerkin *g = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.1, model, v, &lat));
    CHECK_OK(fpl_galerkin_create(lat, n, &g));
    for (int j = 0; j < n; j++) x[j] = 0.8 * check_uniform();
    /* y = (x, p) with p = m x' and x' = 0.1 sin(...); z = (A x, A x') by explicit sums */
    for (int j = 1; j <= n; j++) {
        double xd = 0.1 * sin(0.3 * j);
        y[j - 1] = x[j - 1];
        y[n + j - 1] = (model == FPL_MODEL_HAMILTONIAN ? v[j - 1] : 1.0) * xd;
    }
    for (int k = 1; k <= n; k++) {
        double q = 0.0, p = 0.0;
        for (int j = 1; j <= n; j++) {
            q += shape(n, j, k) * x[j - 1];
            p += shape(n, j, k) * 0.1 * sin(0.3 * j);
        }
        z[k - 1] = q, z[n + k - 1] = p;
    }
    CHECK_OK(fpl_splitting_advance(scheme("yoshida4"), lat, y, 0, 0.01, 2000));
    CHECK_OK(fpl_galerkin_advance(scheme("yoshida4"), g, z, 0.01, 2000));
    double worst = 0.0, scale = 0.0;
    for (int j = 1; j <= n; j++) {
        double xj = 0.0;
        for (int k = 1; k <= n; k++) xj += shape(n, j, k) * z[k - 1];
        worst = fmax(worst, fabs(xj - y[j - 1]));
        scale = fmax(scale, fabs(y[j - 1]));
    }
    CHECK(worst < 1e-12 * fmax(scale, 1.0), "model %d: Galerkin M = N vs lattice: %g", model,
          worst);
    printf("model %d: Galerkin M = N vs full lattice at t = 20: max |dx| = %.1e\n", model, worst);
    fpl_galerkin_free(&g);
    fpl_lattice_free(&lat);
}

static void expect_error(int status, int expected, const char *word)
{
    CHECK(status == expected, "status %d, expected %d (%s)", status, expected, word);
    CHECK(strstr(fpl_last_error(), word) != NULL, "message '%s' lacks '%s'", fpl_last_error(),
          word);
}

static void test_errors(void)
{
    fpl_lattice *lat = NULL;
    fpl_galerkin *g = NULL;
    CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, FPL_MODEL_NONLINEAR, NULL, &lat));
    expect_error(fpl_galerkin_create(lat, 0, &g), FPL_ERR_ARG, "M");
    CHECK(g == NULL, "handle on error");
    expect_error(fpl_galerkin_create(lat, 9, &g), FPL_ERR_ARG, "M");
    expect_error(fpl_galerkin_create(NULL, 2, &g), FPL_ERR_ARG, "lattice");
    CHECK_OK(fpl_galerkin_create(lat, 3, &g));
    double z[6] = {1, 0, 0, 0, NAN, 0}, e[3], ts[1] = {1.0};
    int done = -1;
    expect_error(fpl_galerkin_run(scheme("leapfrog"), g, z, 0.0, 0.1, ts, 1, e, NULL, &done),
                 FPL_ERR_ARG, "z0[4]");
    CHECK(strstr(fpl_galerkin_errmsg(g), "z0[4]") != NULL, "handle message '%s'",
          fpl_galerkin_errmsg(g));
    z[4] = 0.0;
    expect_error(fpl_galerkin_advance(scheme("leapfrog"), g, z, 0.0, 1), FPL_ERR_ARG, "dt");
    expect_error(fpl_galerkin_run(scheme("leapfrog"), g, z, 0.0, 0.1, ts, -1, e, NULL, &done),
                 FPL_ERR_ARG, "n_samples");
    double q[3] = {0, INFINITY, 0}, acc[3];
    expect_error(fpl_galerkin_acceleration(g, q, acc), FPL_ERR_ARG, "q[1]");
    fpl_galerkin_free(&g);
    fpl_galerkin_free(&g); /* idempotent */

    double a[3], b[3], v[8] = {1, 1, 1, NAN, 1, 1, 1, 1};
    expect_error(fpl_reduction_coefficients(8, 0.25, FPL_MODEL_NONLINEAR, v, a, b), FPL_ERR_ARG,
                 "v[3]");
    expect_error(fpl_reduction_coefficients(1, 0.25, FPL_MODEL_NONLINEAR, NULL, a, b), FPL_ERR_ARG,
                 "N");
    expect_error(fpl_reduction_coefficients(8, NAN, FPL_MODEL_NONLINEAR, NULL, a, b), FPL_ERR_ARG,
                 "alpha");
    expect_error(fpl_reduction_coefficients(8, 0.25, 7, NULL, a, b), FPL_ERR_UNKNOWN, "model");
    double mean[6];
    expect_error(fpl_reduction_moments(8, 0.25, 3, FPL_DISORDER_GAUSSIAN, -1.0, mean, NULL),
                 FPL_ERR_ARG, "tau");
    expect_error(fpl_reduction_moments(8, 0.25, 3, 9, 1.0, mean, NULL), FPL_ERR_UNKNOWN, "kind");

    /* blow-up: a large amplitude in the two-mode ODE stops with the time interval */
    double w[2] = {0.05, 0.1}, a2[3] = {0.5, 0.0, 0.0}, b2[3] = {0.0, 0.0, 0.0};
    double z0[4] = {1.0, 0.0, 0.0, 0.0}, t2[3] = {1.0, 50.0, 1e4}, st[12];
    done = -1;
    expect_error(fpl_reduction_two_mode_run(scheme("yoshida4"), w, a2, b2, z0, 0.0, 0.01, t2, 3,
                                            st, &done), FPL_ERR_NONFINITE, "between t =");
    CHECK(done >= 1 && done < 3, "samples before the blow-up: %d", done);
    for (int i = 0; i < 4 * done; i++) CHECK(isfinite(st[i]), "sample %d finite", i);
    fpl_lattice_free(&lat);
}

int main(void)
{
    test_paper_values();
    test_brute_force(FPL_MODEL_HOMOGENEOUS);
    test_brute_force(FPL_MODEL_HAMILTONIAN);
    test_brute_force(FPL_MODEL_NONLINEAR);
    test_quadratic_in_tau();
    test_galerkin_two_modes();
    test_galerkin_full(FPL_MODEL_HOMOGENEOUS);
    test_galerkin_full(FPL_MODEL_HAMILTONIAN);
    test_galerkin_full(FPL_MODEL_NONLINEAR);
    test_errors();
    return check_report("reduction");
}
