/* Normal modes: the FFT sine transform against the explicit matrix A, orthogonality, energies. */
#include <string.h>
#include "check.h"
#include "fputlab.h"

static void test_transform(int n)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, 1, NULL, &lat));
    double *x = calloc(n, sizeof *x), *q = calloc(n, sizeof *q), *back = calloc(n, sizeof *back);
    for (int j = 0; j < n; j++) x[j] = check_uniform();
    CHECK_OK(fpl_modes_transform(lat, x, q));
    double worst = 0.0;
    for (int k = 1; k <= n; k++) {
        double s = 0.0;
        for (int j = 1; j <= n; j++) s += sqrt(2.0 / (n + 1)) * sin(j * k * M_PI / (n + 1)) * x[j - 1];
        if (fabs(s - q[k - 1]) > worst) worst = fabs(s - q[k - 1]);
    }
    CHECK(worst < 1e-12 * sqrt(n), "N %d: FFT transform vs explicit A: %g", n, worst);
    /* A^{-1} = A: transforming twice gives back x; norms are preserved (orthogonality) */
    CHECK_OK(fpl_modes_transform(lat, q, back));
    double nx = 0, nq = 0;
    worst = 0.0;
    for (int j = 0; j < n; j++) {
        if (fabs(back[j] - x[j]) > worst) worst = fabs(back[j] - x[j]);
        nx += x[j] * x[j];
        nq += q[j] * q[j];
    }
    CHECK(worst < 1e-12, "N %d: A A != I (%g)", n, worst);
    CHECK(fabs(nx - nq) < 1e-11 * nx, "N %d: |Ax| != |x|", n);
    free(x); free(q); free(back);
    fpl_lattice_free(&lat);
}

static void test_energies(void)
{
    const int n = 31;
    double v[31];
    for (int j = 0; j < n; j++) v[j] = 1.0 + 0.1 * check_uniform();
    for (int model = 1; model <= 3; model++) {
        fpl_lattice *lat = NULL;
        CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, model, v, &lat));
        double y[62], e[31], xd[31];
        for (int i = 0; i < 2 * n; i++) y[i] = 0.3 * check_uniform();
        CHECK_OK(fpl_modes_energies(lat, y, e));
        fpl_lattice_velocity(lat, y, xd);
        /* harmonic energy of the homogeneous chain with velocities x' */
        double harm = 0.0, sum = 0.0;
        for (int j = 0; j < n; j++) harm += 0.5 * xd[j] * xd[j];
        for (int b = 0; b <= n; b++) {
            double d = (b < n ? y[b] : 0.0) - (b > 0 ? y[b - 1] : 0.0);
            harm += 0.5 * d * d;
        }
        for (int k = 0; k < n; k++) sum += e[k];
        CHECK(fabs(sum - harm) < 1e-13 * harm, "model %d: sum E_k %.15g vs harmonic %.15g",
              model, sum, harm);
        fpl_lattice_free(&lat);
    }
}

static void test_initial_condition(void)
{
    const int n = 64;
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, 1, NULL, &lat));
    double y[128], q[64], omega[64], e;
    const double amp = 1.7;
    CHECK_OK(fpl_modes_initial_state(lat, 1, amp, y));
    CHECK_OK(fpl_modes_transform(lat, y, q));
    CHECK(fabs(q[0] - amp * sqrt((n + 1) / 2.0)) < 1e-12, "Q1 = %.15g", q[0]);
    for (int k = 1; k < n; k++) CHECK(fabs(q[k]) < 1e-12, "Q%d = %g", k + 1, q[k]);
    for (int j = 0; j < n; j++) CHECK(y[n + j] == 0.0, "p must be 0");
    CHECK_OK(fpl_modes_omega(n, omega));
    CHECK(fabs(omega[0] - 2 * sin(M_PI / (2.0 * 65))) < 1e-15, "omega_1");
    /* the paper's energy of the N = 64 initial condition (alpha = 0.25): E = 0.03795 */
    CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, y));
    CHECK_OK(fpl_lattice_energy(lat, y, &e));
    CHECK(fabs(e - 0.03795) < 5e-6, "E = %.6f, paper 0.03795", e);
    fpl_lattice_free(&lat);
    /* Sec. 5 lists the energies of the same initial condition for the other N */
    const int ns[] = {4, 8, 16, 32};
    const double paper[] = {0.4775, 0.2714, 0.1447, 0.0747};
    for (int i = 0; i < 4; i++) {
        CHECK_OK(fpl_lattice_create(ns[i], 0.25, 0.0, 1, NULL, &lat));
        CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, y));
        CHECK_OK(fpl_lattice_energy(lat, y, &e));
        CHECK(fabs(e - paper[i]) < 6e-5, "N %d: E = %.5f, paper %.4f", ns[i], e, paper[i]);
        fpl_lattice_free(&lat);
    }
}

/* The ring's modes: the orthonormal Hartley transform against its explicit matrix, A A = I,
 * and mode energies against the explicit sum (sizes with a large prime factor go through
 * Bluestein's algorithm, the others through GSL's mixed radix). */
static void test_ring(int n)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create_ex(n, 0.25, 0.0, 1, NULL, FPL_BOUNDARY_PERIODIC, &lat));
    double *y = calloc(2 * (size_t)n, sizeof *y), *q = calloc(n, sizeof *q);
    double *back = calloc(n, sizeof *back), *e = calloc(n, sizeof *e), *w = calloc(n, sizeof *w);
    for (int j = 0; j < 2 * n; j++) y[j] = check_uniform();
    CHECK_OK(fpl_modes_transform(lat, y, q));
    CHECK_OK(fpl_modes_transform(lat, q, back));
    CHECK_OK(fpl_modes_energies(lat, y, e));
    CHECK_OK(fpl_modes_frequencies(lat, w));
    double worst = 0.0, worst_e = 0.0, worst_back = 0.0, emax = 0.0;
    for (int k = 0; k < n; k++) {
        double qx = 0.0, qp = 0.0;
        for (int j = 0; j < n; j++) {
            const double th = 2.0 * M_PI * (double)(((long)j * k) % n) / n;
            const double cas = (cos(th) + sin(th)) / sqrt((double)n);
            qx += cas * y[j];
            qp += cas * y[n + j];
        }
        const double wk = 2.0 * sin(M_PI * k / n);
        const double ek = 0.5 * (qp * qp + wk * wk * qx * qx);
        worst = fmax(worst, fabs(qx - q[k]));
        worst_e = fmax(worst_e, fabs(ek - e[k]));
        emax = fmax(emax, ek);
        worst_back = fmax(worst_back, fabs(back[k] - y[k]));
        CHECK(fabs(w[k] - wk) < 1e-15, "ring N %d: omega_%d %g vs %g", n, k, w[k], wk);
    }
    CHECK(worst < 1e-12 * sqrt(n), "ring N %d: FFT Hartley transform vs explicit: %g", n, worst);
    CHECK(worst_e < 1e-12 * emax, "ring N %d: mode energies vs explicit: %g", n, worst_e);
    CHECK(worst_back < 1e-12, "ring N %d: A A != I (%g)", n, worst_back);
    free(y); free(q); free(back); free(e); free(w);
    fpl_lattice_free(&lat);
}

int main(void)
{
    /* 102, 1020: N + 1 prime, the sine transform's length 2(N+1) goes through Bluestein */
    int sizes[] = {2, 3, 8, 63, 64, 100, 102, 1020, 4096};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) test_transform(sizes[i]);
    int ring_sizes[] = {2, 3, 4, 7, 64, 211, 998, 1021};
    for (size_t i = 0; i < sizeof ring_sizes / sizeof ring_sizes[0]; i++) test_ring(ring_sizes[i]);
    test_energies();
    test_initial_condition();
    return check_report("modes");
}
