/* Chaos indicators: closed-form SALI/GALI cases, regular and chaotic orbits, invariances. */
#include <string.h>
#include "check.h"
#include "fputlab.h"

static void test_indices(void)
{
    double a[4] = {1, 2, 3, 4}, b[4] = {-2, -4, -6, -8}, c[4] = {2, -1, 0, 0}, s, g;
    CHECK_OK(fpl_chaos_sali(a, a, 4, &s));
    CHECK(s < 1e-15, "SALI of identical vectors %g", s);
    CHECK_OK(fpl_chaos_sali(a, b, 4, &s));
    CHECK(s < 1e-15, "SALI of antiparallel vectors %g", s);
    CHECK_OK(fpl_chaos_sali(a, c, 4, &s));
    CHECK(fabs(s - sqrt(2.0)) < 1e-15, "SALI of orthogonal vectors %g", s);
    double w[3 * 4] = {1, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0, -2};
    CHECK_OK(fpl_chaos_gali(w, 3, 4, &g));
    CHECK(fabs(g - 1.0) < 1e-15, "GALI_3 of orthogonal vectors %g", g);
    /* two unit vectors at angle phi span an area sin(phi) */
    double phi = 0.3, u[2 * 4] = {1, 0, 0, 0, cos(phi), sin(phi), 0, 0};
    CHECK_OK(fpl_chaos_gali(u, 2, 4, &g));
    CHECK(fabs(g - sin(phi)) < 1e-15, "GALI_2 = %g vs sin(phi) = %g", g, sin(phi));
    double z[4] = {0};
    CHECK(fpl_chaos_sali(a, z, 4, &s) == FPL_ERR_ARG, "zero vector refused");
}

/* A harmonic chain (alpha = beta = 0) is linear: deviation vectors do not grow exponentially,
 * so lambda(t) t stays bounded. */
static void test_harmonic_chain(void)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(16, 0.0, 0.0, 1, NULL, &lat));
    double y0[32];
    CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, y0));
    fpl_chaos_options opt;
    fpl_chaos_options_init(&opt);
    opt.t_end = 1e4;
    opt.n_samples = 50;
    double t[50], mle[50], sali[50];
    fpl_chaos_result res;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, t, mle, sali, NULL, &res));
    CHECK(res.n_samples > 10, "samples %d", res.n_samples);
    for (int i = 0; i < res.n_samples; i++)
        CHECK(fabs(mle[i]) * t[i] < 10.0, "lambda t = %g at t = %g", mle[i] * t[i], t[i]);
    CHECK(!res.chaotic, "harmonic chain flagged chaotic");
    fpl_lattice_free(&lat);
}

/* FPUT-beta chain (no escape) at high energy: strongly chaotic. lambda(T) does not depend on the
 * renormalisation interval (renormalising is an exact linear rescaling) and, for long T, only
 * weakly on the initial deviation vectors. */
static void test_chaotic_orbit(void)
{
    const int n = 8;
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(n, 0.0, 1.0, 1, NULL, &lat));
    double y0[16];
    for (int i = 0; i < 16; i++) y0[i] = 1.5 * check_uniform();
    fpl_chaos_options opt;
    fpl_chaos_options_init(&opt);
    opt.t_end = 5e3;
    fpl_chaos_result r1, r2, r3;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, &r1));
    CHECK(r1.chaotic && r1.sali < 1e-8, "SALI %g", r1.sali);
    CHECK(r1.mle > 0.02, "lambda = %g", r1.mle);
    opt.renorm_interval = 7.0;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, &r2));
    CHECK(fabs(r2.mle - r1.mle) < 1e-9 * r1.mle, "renorm 1 vs 7: %.12g vs %.12g", r1.mle, r2.mle);
    opt.renorm_interval = 1.0;
    opt.seed = 99;
    opt.t_end = 5e4;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, &r3));
    opt.seed = 1;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, &r1));
    CHECK(fabs(r3.mle - r1.mle) < 0.03 * r1.mle, "seeds 1 vs 99: %g vs %g", r1.mle, r3.mle);
    printf("FPUT-beta N = 8: lambda(5e4) = %.4f (seed 1), %.4f (seed 99)\n", r1.mle, r3.mle);
    /* early termination: chaotic orbits stop paying for the full time */
    opt.stop_when_chaotic = 1;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, &r2));
    /* confirmed (and stopped) one renormalisation after SALI fell below the threshold */
    CHECK(r2.chaotic && r2.t_final < opt.t_end && r2.t_final == r2.t_chaotic + opt.renorm_interval,
          "stopped at %g (chaotic at %g)", r2.t_final, r2.t_chaotic);
    int cls = -1;
    CHECK_OK(fpl_chaos_classify(&r2, NULL, NULL, 0, NAN, &cls));
    CHECK(cls == FPL_ORBIT_CHAOTIC && !r2.blew_up, "class %d", cls);
    fpl_lattice_free(&lat);
}

static void test_bad_input(void)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(4, 0.25, 0.0, 1, NULL, &lat));
    double y0[8] = {0};
    fpl_chaos_options opt;
    fpl_chaos_options_init(&opt);
    CHECK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, NULL)
              == FPL_ERR_ARG && strstr(fpl_last_error(), "t_end"), "t_end unset: %s", fpl_last_error());
    opt.t_end = 10.0;
    opt.renorm_interval = -1.0;
    CHECK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, NULL)
              == FPL_ERR_ARG && strstr(fpl_last_error(), "renorm_interval"), "renorm");
    opt.renorm_interval = 1.0;
    opt.n_dev = 9;
    CHECK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, NULL, NULL, NULL, NULL, NULL)
              == FPL_ERR_ARG && strstr(fpl_last_error(), "n_dev"), "n_dev");
    opt.n_dev = 2;
    double w0[16] = {0};
    CHECK(fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, w0, &opt, NULL, NULL, NULL, NULL, NULL)
              == FPL_ERR_ARG && strstr(fpl_last_error(), "w0[0]"), "zero w0: %s", fpl_last_error());
    fpl_lattice_free(&lat);
}

/* tau = 20 % > tau_c (paper Fig. 3): the orbit escapes over the cubic barrier near t ~ 2.5e3.
 * Its deviation vectors align with the runaway just before the overflow; that is a blow-up,
 * never chaos, whether the barrier check or only the non-finite state catches it. */
static void test_blowup_is_not_chaos(void)
{
    enum { N = 64 };
    double v[N], y0[2 * N], t[100], mle[100];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 20.0, 1, N, v));
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat));
    CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, y0));  /* the paper's x_j = sin(pi j/(N+1)) */
    for (int pass = 0; pass < 2; pass++) {
        fpl_chaos_options opt;
        fpl_chaos_options_init(&opt);
        opt.t_end = 1e4;
        opt.n_samples = 100;
        opt.blowup_stretch = pass == 0 ? 0.0 : -1.0;    /* automatic barrier 4 / off */
        fpl_chaos_result r;
        int st = fpl_chaos_run(lat, "yoshida4", NULL, 0.0, y0, NULL, &opt, t, mle, NULL, NULL, &r);
        CHECK(st == FPL_EVENT && strstr(fpl_last_error(), "blow-up"), "status %d: %s", st,
              fpl_last_error());
        CHECK(r.blew_up && !r.chaotic && r.t_blowup > 1e3 && r.t_blowup < 1e4 && !r.completed,
              "pass %d: blew_up %d at %g, chaotic %d at %g", pass, r.blew_up, r.t_blowup,
              r.chaotic, r.t_chaotic);
        int cls = -1;
        CHECK_OK(fpl_chaos_classify(&r, t, mle, r.n_samples, NAN, &cls));
        CHECK(cls == FPL_ORBIT_BLOWUP, "pass %d: class %s", pass, fpl_orbit_class_name(cls));
    }
    fpl_lattice_free(&lat);
}

int main(void)
{
    test_blowup_is_not_chaos();
    test_indices();
    test_harmonic_chain();
    test_chaotic_orbit();
    test_bad_input();
    return check_report("chaos");
}
