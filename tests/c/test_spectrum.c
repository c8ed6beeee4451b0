/* Lyapunov spectrum: the Householder QR, the symplectic structure of the spectrum (sum and
 * pairing), lambda_1 = the mLE of fpl_chaos, bit-for-bit checkpoints. */
#define _POSIX_C_SOURCE 200809L
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "fputlab.h"

static void test_qr(void)
{
    enum { K = 5, L = 9 };
    double w[K * L], q[K * L], r[K * K];
    for (int i = 0; i < K * L; i++) w[i] = check_uniform();
    w[0] = 0.0;                                   /* a zero leading entry: sign choice */
    CHECK_OK(fpl_spectrum_qr(w, K, L, q, r));
    double worst_orth = 0, worst_rec = 0;
    for (int i = 0; i < K; i++) {
        CHECK(r[i * K + i] > 0, "r_%d%d = %g > 0", i, i, r[i * K + i]);
        for (int j = 0; j < i; j++) CHECK(r[i * K + j] == 0.0, "r below the diagonal");
        for (int j = 0; j < K; j++) {
            double d = 0;
            for (int c = 0; c < L; c++) d += q[i * L + c] * q[j * L + c];
            worst_orth = fmax(worst_orth, fabs(d - (i == j)));
        }
        /* column i of W = sum_j q_j r_ji */
        for (int c = 0; c < L; c++) {
            double s = 0;
            for (int j = 0; j <= i; j++) s += q[j * L + c] * r[j * K + i];
            worst_rec = fmax(worst_rec, fabs(s - w[i * L + c]));
        }
    }
    CHECK(worst_orth < 1e-14, "Q^T Q = I to %g", worst_orth);
    CHECK(worst_rec < 1e-14, "Q R = W to %g", worst_rec);
    /* in place */
    double w2[K * L];
    memcpy(w2, w, sizeof w);
    CHECK_OK(fpl_spectrum_qr(w2, K, L, w2, r));
    CHECK(memcmp(w2, q, sizeof q) == 0, "in-place QR gives the same Q");
    CHECK(fpl_spectrum_qr(w, L + 1, L, q, r) == FPL_ERR_ARG, "k > len refused");
}

static fpl_lattice *beta_chain(int n, double *y0)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.0, 1.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat));
    for (int i = 0; i < 2 * n; i++) y0[i] = 1.5 * check_uniform();
    return lat;
}

/* The tangent map of a symplectic scheme has determinant 1: the product of the R_ii of all 2N
 * vectors is 1, so the exponents sum to zero to round-off; they come in pairs +-lambda. */
static void test_symplectic_structure(void)
{
    enum { N = 4, L = 2 * N, S = 20 };
    double y0[L];
    fpl_lattice *lat = beta_chain(N, y0);
    fpl_spectrum_options o;
    fpl_spectrum_options_init(&o);
    o.t_end = 2e3;
    o.n_samples = S;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    io.dt = 0.02;
    fpl_spectrum *s = NULL;
    CHECK_OK(fpl_spectrum_create(lat, "yoshida4", &io, 0.0, y0, NULL, &o, &s));
    double t[S], hist[S * L], lam[L];
    CHECK_OK(fpl_spectrum_advance(s, o.t_end, t, hist));
    CHECK(fpl_spectrum_done(s), "done at t_end");
    fpl_spectrum_result res;
    CHECK_OK(fpl_spectrum_get_result(s, &res));
    CHECK(res.completed && res.n_exponents == L && res.t_final == o.t_end && res.n_samples == S &&
              res.n_renorm == 2000, "result %d %d %g %d %ld", res.completed, res.n_exponents,
          res.t_final, res.n_samples, res.n_renorm);
    CHECK_OK(fpl_spectrum_exponents(s, lam));
    CHECK(memcmp(lam, hist + (S - 1) * L, sizeof lam) == 0, "last sample = exponents");
    double sum = 0;
    for (int i = 0; i < L; i++) sum += lam[i];
    CHECK(fabs(sum) < 1e-12, "sum of the exponents %g", sum);
    CHECK(lam[0] > 0.05, "chaotic: lambda_1 = %g", lam[0]);
    for (int i = 0; i < N; i++)
        CHECK(fabs(lam[i] + lam[L - 1 - i]) < 0.02 * lam[0] + 2e-3, "pair %d: %g + %g", i, lam[i],
              lam[L - 1 - i]);
    for (int i = 0; i + 1 < N - 1; i++) CHECK(lam[i] >= lam[i + 1], "descending %d", i);
    double r[L * L];
    CHECK_OK(fpl_spectrum_last_r(s, r));
    CHECK(r[0] > 0 && r[L] == 0.0, "last R upper triangular");
    fpl_spectrum_free(&s);
    fpl_lattice_free(&lat);
}

/* lambda_1 is the mLE of fpl_chaos on the same orbit from the same first vector; with a step
 * that does not divide renorm_interval (renormalisations between grid points) too, and there the
 * exponents still sum to zero. */
static void test_first_is_mle(double dt)
{
    enum { N = 6, L = 2 * N };
    double y0[L], w0[3 * L];
    fpl_lattice *lat = beta_chain(N, y0);
    for (int i = 0; i < 3 * L; i++) w0[i] = check_uniform();
    fpl_spectrum_options o;
    fpl_spectrum_options_init(&o);
    o.t_end = 500;
    o.n_exponents = 3;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    io.dt = dt;
    fpl_spectrum *s = NULL;
    CHECK_OK(fpl_spectrum_create(lat, "yoshida4", &io, 0.0, y0, w0, &o, &s));
    CHECK_OK(fpl_spectrum_advance(s, o.t_end, NULL, NULL));
    double lam[3], mle;
    CHECK_OK(fpl_spectrum_exponents(s, lam));
    fpl_chaos_options co;
    fpl_chaos_options_init(&co);
    co.t_end = o.t_end;
    co.n_dev = 1;
    co.n_samples = 1;
    co.blowup_stretch = -1;
    fpl_chaos_result cr;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", &io, 0.0, y0, w0, &co, NULL, &mle, NULL, NULL, &cr));
    CHECK(fabs(lam[0] - cr.mle) < 1e-9 * fabs(cr.mle), "dt %g: lambda_1 %.15g vs mLE %.15g", dt,
          lam[0], cr.mle);
    fpl_spectrum_free(&s);
    o.n_exponents = 0;
    CHECK_OK(fpl_spectrum_create(lat, "yoshida4", &io, 0.0, y0, NULL, &o, &s));
    CHECK_OK(fpl_spectrum_advance(s, o.t_end, NULL, NULL));
    double all[L], sum = 0;
    CHECK_OK(fpl_spectrum_exponents(s, all));
    for (int i = 0; i < L; i++) sum += all[i];
    CHECK(fabs(sum) < 1e-11, "dt %g: sum of the exponents %g", dt, sum);
    fpl_spectrum_free(&s);
    fpl_lattice_free(&lat);
}

/* Stopped at t_c, saved, restored into a fresh handle: the same bits as one run. */
static void test_checkpoint(void)
{
    enum { N = 5, L = 2 * N, S = 30 };
    double y0[L];
    fpl_lattice *lat = beta_chain(N, y0);
    fpl_spectrum_options o;
    fpl_spectrum_options_init(&o);
    o.t_end = 300;
    o.n_samples = S;
    o.renorm_interval = 0.5;
    double t_ref[S], h_ref[S * L], lam_ref[L], t[S], h[S * L], lam[L];
    fpl_spectrum *s = NULL;
    CHECK_OK(fpl_spectrum_create(lat, "srkn14a6", NULL, 0.0, y0, NULL, &o, &s));
    CHECK_OK(fpl_spectrum_advance(s, o.t_end, t_ref, h_ref));
    CHECK_OK(fpl_spectrum_exponents(s, lam_ref));
    fpl_spectrum_result res;
    CHECK_OK(fpl_spectrum_get_result(s, &res));
    const int n_ref = res.n_samples;
    fpl_spectrum_free(&s);

    char ck[] = "/tmp/fpl_spectrum_ckXXXXXX";
    int fd = mkstemp(ck);
    CHECK(fd >= 0, "temporary file");
    close(fd);
    CHECK_OK(fpl_spectrum_create(lat, "srkn14a6", NULL, 0.0, y0, NULL, &o, &s));
    CHECK_OK(fpl_spectrum_advance(s, 123.4, t, h));
    const int na = fpl_spectrum_n_accumulators(s);
    CHECK(na == FPL_SPECTRUM_N_COUNTERS + L, "accumulators %d", na);
    double acc[FPL_SPECTRUM_N_COUNTERS + L];
    CHECK_OK(fpl_spectrum_save(s, acc));
    fpl_run_info info;
    fpl_run_info_init(&info);
    info.kind = "spectrum";
    CHECK_OK(fpl_checkpoint_write(ck, fpl_spectrum_integrator(s), &info, acc, na, NULL));
    fpl_spectrum_free(&s);

    CHECK_OK(fpl_spectrum_create(lat, "srkn14a6", NULL, 0.0, y0, NULL, &o, &s));
    double back[FPL_SPECTRUM_N_COUNTERS + L];
    int n_back = 0;
    CHECK_OK(fpl_checkpoint_load(ck, fpl_spectrum_integrator(s), &info, back, na, &n_back));
    CHECK(n_back == na, "accumulators read back %d", n_back);
    CHECK_OK(fpl_spectrum_restore(s, back));
    CHECK_OK(fpl_spectrum_advance(s, o.t_end, t, h));
    CHECK_OK(fpl_spectrum_exponents(s, lam));
    CHECK(memcmp(lam, lam_ref, sizeof lam) == 0, "restart bit for bit: %.17g vs %.17g", lam[0],
          lam_ref[0]);
    CHECK_OK(fpl_spectrum_get_result(s, &res));
    CHECK(res.n_samples == n_ref && n_ref > 20, "samples %d vs %d", res.n_samples, n_ref);
    for (int i = 0; i < n_ref; i++)
        CHECK(memcmp(h + i * L, h_ref + i * L, sizeof(double) * L) == 0 && t[i] == t_ref[i],
              "sample %d bit for bit: t %.17g vs %.17g, %.17g vs %.17g", i, t[i], t_ref[i],
              h[i * L], h_ref[i * L]);
    back[0] = 1e9;
    CHECK(fpl_spectrum_restore(s, back) == FPL_ERR_ARG, "foreign accumulators refused");
    fpl_spectrum_free(&s);
    unlink(ck);
    fpl_lattice_free(&lat);
}

static void test_errors(void)
{
    double y0[8] = {0.1, 0, 0, 0, 0, 0, 0, 0};
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(4, 0.0, 1.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat));
    fpl_spectrum_options o;
    fpl_spectrum_options_init(&o);
    fpl_spectrum *s = NULL;
    CHECK(fpl_spectrum_create(lat, "yoshida4", NULL, 0, y0, NULL, &o, &s) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "t_end"), "t_end unset: %s", fpl_last_error());
    o.t_end = 10;
    o.n_exponents = 9;
    CHECK(fpl_spectrum_create(lat, "yoshida4", NULL, 0, y0, NULL, &o, &s) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "n_exponents"), "k > 2N: %s", fpl_last_error());
    o.n_exponents = 2;
    double w0[16] = {1, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0};
    CHECK(fpl_spectrum_create(lat, "yoshida4", NULL, 0, y0, w0, &o, &s) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "linearly independent"), "dependent w0: %s",
          fpl_last_error());
    CHECK(fpl_spectrum_create(lat, "nope", NULL, 0, y0, NULL, &o, &s) == FPL_ERR_UNKNOWN,
          "unknown method");
    CHECK(s == NULL, "no handle on failure");
    fpl_lattice_free(&lat);
}

int main(void)
{
    test_qr();
    test_symplectic_structure();
    test_first_is_mle(0.01);
    test_first_is_mle(0.03);
    test_checkpoint();
    test_errors();
    return check_report("spectrum");
}
