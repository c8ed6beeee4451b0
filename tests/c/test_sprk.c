/* ARKODE SPRKStep methods ("sprk-*"): with SUNDIALS >= 6.6 the observed order of each table,
 * energy error, agreement with our splitting schemes and DOP853, deviation vectors against
 * finite differences of the same scheme, stopping criteria against the splitting locator,
 * off-grid samples, compensated sums and the public fpl_sun_force / fpl_sun_velocity; with 6.4
 * the names are refused with a clear message and not listed. */
#define _POSIX_C_SOURCE 200809L /* dup, dup2, fileno: test_silent */
#include <string.h>
#include <unistd.h>
#include <sundials/sundials_config.h>
#include "check.h"
#include "fputlab.h"
#include "fputlab/sundials.h"
#include "../../csrc/sundials_compat.h" /* FPL_HAVE_SPRKSTEP */

static const char *const sprk[] = {"sprk-mclachlan4", "sprk-yoshida6", "sprk-suzuki-umeno8",
                                   "sprk-sofroniou10"};
static const int sprk_order[] = {4, 6, 8, 10};

static int listed(const char *name)
{
    for (int i = 0; i < fpl_method_count(); i++)
        if (strcmp(fpl_method_name(i), name) == 0) return 1;
    return 0;
}

static void test_registry(void)
{
    for (int i = 0; i < 4; i++) {
        int order = 0, adaptive = -1;
        int st = fpl_method_info(sprk[i], &order, &adaptive);
        if (FPL_HAVE_SPRKSTEP) {
            CHECK(st == FPL_OK && order == sprk_order[i] && adaptive == 0, "%s: info", sprk[i]);
            CHECK(listed(sprk[i]), "%s listed", sprk[i]);
        } else {
            CHECK(st == FPL_ERR_UNKNOWN, "%s refused with SUNDIALS %s", sprk[i], SUNDIALS_VERSION);
            CHECK(strstr(fpl_last_error(), "SPRKStep") && strstr(fpl_last_error(), "6.6") &&
                  strstr(fpl_last_error(), SUNDIALS_VERSION),
                  "message says why: %s", fpl_last_error());
            CHECK(!listed(sprk[i]), "%s not listed", sprk[i]);
            fpl_lattice *lat = NULL;
            double y0[8] = {0.1};
            CHECK_OK(fpl_lattice_create(4, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat));
            fpl_integrator *h = NULL;
            CHECK(fpl_integrator_create(lat, sprk[i], 0, NULL, 0.0, y0, &h) == FPL_ERR_UNKNOWN &&
                  h == NULL, "create refused");
            CHECK(strstr(fpl_last_error(), "SUNDIALS") != NULL, "%s", fpl_last_error());
            fpl_lattice_free(&lat);
        }
    }
    if (!FPL_HAVE_SPRKSTEP) printf("SUNDIALS %s: sprk-* refused: %s\n", SUNDIALS_VERSION,
                                   fpl_last_error());
}

#if FPL_HAVE_SPRKSTEP
enum { N = 8, LEN = 2 * N };

static double max_abs_diff(const double *a, const double *b, long n)
{
    double m = 0.0;
    for (long i = 0; i < n; i++) m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

/* y(t_end) from y0 with method at step dt (rtol for adaptive ones); status returned. */
static int run(fpl_lattice *lat, const char *method, int n_dev, double dt, double rtol,
               int compensated, const double *y0, double t_end, double *y)
{
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.dt = dt;
    opt.rtol = rtol;
    opt.atol = rtol * 1e-2;
    opt.compensated_sums = compensated;
    fpl_integrator *h = NULL;
    int st = fpl_integrator_create(lat, method, n_dev, &opt, 0.0, y0, &h);
    if (st == 0) st = fpl_integrator_advance(h, t_end, y);
    if (st != 0) fprintf(stderr, "%s: %s\n", method, fpl_last_error());
    fpl_integrator_free(&h);
    return st;
}


/* A strongly nonlinear orbit of the homogeneous FPUT-alpha chain. */
static void orbit(fpl_lattice **lat, double *y0)
{
    CHECK_OK(fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, lat));
    CHECK_OK(fpl_modes_initial_state(*lat, 1, 3.0, y0));
}

/* Observed order of each table against srkn14a6 at a tiny step; agreement with DOP853. */
static void test_orders(void)
{
    fpl_lattice *lat = NULL;
    double y0[LEN], ref[LEN], dop[LEN], y[LEN];
    orbit(&lat, y0);
    const double T = 10.0;
    CHECK_OK(run(lat, "srkn14a6", 0, 0.002, 0, 0, y0, T, ref));
    CHECK_OK(run(lat, "dop853", 0, 0, 1e-13, 0, y0, T, dop));
    printf("srkn14a6 (dt 0.002) vs DOP853 (rtol 1e-13) at t = %g: %.2e\n", T,
           max_abs_diff(ref, dop, LEN));
    CHECK(max_abs_diff(ref, dop, LEN) < 1e-10, "references agree");
    /* steps where each table's error is well above the reference's and round-off */
    static const double dts[4][2] = {{0.1, 0.05}, {0.2, 0.1}, {0.4, 0.2}, {0.5, 0.4}};
    for (int i = 0; i < 4; i++) {
        double e[2];
        for (int k = 0; k < 2; k++) {
            CHECK_OK(run(lat, sprk[i], 0, dts[i][k], 0, 0, y0, T, y));
            e[k] = max_abs_diff(y, ref, LEN);
        }
        const double p = log(e[0] / e[1]) / log(dts[i][0] / dts[i][1]);
        printf("%-19s dt %.3g -> %.2e, dt %.3g -> %.2e: observed order %.2f (%d)\n", sprk[i],
               dts[i][0], e[0], dts[i][1], e[1], p, sprk_order[i]);
        CHECK(fabs(p - sprk_order[i]) < 0.6, "%s: observed order %.2f, expected %d", sprk[i], p,
              sprk_order[i]);
        CHECK(e[1] < 1e-5, "%s: error %.2e at dt %g", sprk[i], e[1], dts[i][1]);
    }
    /* against our splitting scheme of the same order at the same step */
    CHECK_OK(run(lat, "sprk-mclachlan4", 0, 0.01, 0, 0, y0, T, y));
    CHECK_OK(run(lat, "yoshida4", 0, 0.01, 0, 0, y0, T, dop));
    printf("sprk-mclachlan4 vs yoshida4 at dt 0.01: %.2e; vs reference %.2e\n",
           max_abs_diff(y, dop, LEN), max_abs_diff(y, ref, LEN));
    CHECK(max_abs_diff(y, dop, LEN) < 1e-6, "agrees with yoshida4");
    fpl_lattice_free(&lat);
}

/* Energy error over a long run: bounded, no drift; compensated sums shrink the round-off. */
static void test_energy(void)
{
    fpl_lattice *lat = NULL;
    double y0[LEN], y[LEN], e0, e;
    orbit(&lat, y0);
    CHECK_OK(fpl_lattice_energy(lat, y0, &e0));
    for (int i = 0; i < 4; i += 3) {
        fpl_integrator_options opt;
        fpl_integrator_options_init(&opt);
        opt.dt = i == 0 ? 0.05 : 0.2;
        fpl_integrator *h = NULL;
        CHECK_OK(fpl_integrator_create(lat, sprk[i], 0, &opt, 0.0, y0, &h));
        double first = 0.0, second = 0.0;
        for (int k = 1; k <= 200 && h; k++) {
            CHECK_OK(fpl_integrator_advance(h, 10.0 * k, y));
            CHECK_OK(fpl_lattice_energy(lat, y, &e));
            double err = fabs(e / e0 - 1.0);
            if (k <= 100) first = fmax(first, err); else second = fmax(second, err);
        }
        printf("%-19s dt %.2g, t <= 2000: max |dE/E| %.2e (first half), %.2e (second half)\n",
               sprk[i], opt.dt, first, second);
        CHECK(first < 1e-5 && second < 2.0 * first + 1e-13, "%s: bounded energy error", sprk[i]);
        fpl_integrator_free(&h);
    }
    /* round-off: tiny step, 10^5 steps of sofroniou10 (truncation error negligible) */
    double plain[LEN], comp[LEN], ep, ec;
    CHECK_OK(run(lat, "sprk-sofroniou10", 0, 0.005, 0, 0, y0, 500.0, plain));
    CHECK_OK(run(lat, "sprk-sofroniou10", 0, 0.005, 0, 1, y0, 500.0, comp));
    fpl_lattice_energy(lat, plain, &ep);
    fpl_lattice_energy(lat, comp, &ec);
    printf("sofroniou10 dt 0.005 to t = 500: |dE/E| %.2e plain, %.2e compensated sums\n",
           fabs(ep / e0 - 1.0), fabs(ec / e0 - 1.0));
    CHECK(fabs(ep / e0 - 1.0) < 1e-12, "round-off level (plain)");
    CHECK(fabs(ec / e0 - 1.0) < 1e-14, "compensated sums: round-off does not grow");
    CHECK(max_abs_diff(plain, comp, LEN) < 1e-9, "compensated sums change round-off only");
    fpl_lattice_free(&lat);
}

/* Deviation vectors follow the tangent map of the scheme: compare with central differences of
 * two orbits of the same scheme (error O(eps^2)). Also model 2 (masses) and 3. */
static void test_deviations(void)
{
    for (int model = 1; model <= 3; model++) {
        double v[N];
        CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 3, N, v));
        fpl_lattice *lat = NULL;
        CHECK_OK(fpl_lattice_create(N, 0.25, 0.1, model, v, &lat));
        double y0[2 * LEN], y[2 * LEN], yp[LEN], ym[LEN], a[LEN], b[LEN];
        CHECK_OK(fpl_modes_initial_state(lat, 1, 1.5, y0));
        for (int i = 0; i < LEN; i++) y0[LEN + i] = cos(0.7 * i + model);
        const double eps = 1e-5;
        for (int i = 0; i < LEN; i++) {
            a[i] = y0[i] + eps * y0[LEN + i];
            b[i] = y0[i] - eps * y0[LEN + i];
        }
        CHECK_OK(run(lat, "sprk-yoshida6", 1, 0.05, 0, 0, y0, 20.0, y));
        CHECK_OK(run(lat, "sprk-yoshida6", 0, 0.05, 0, 0, a, 20.0, yp));
        CHECK_OK(run(lat, "sprk-yoshida6", 0, 0.05, 0, 0, b, 20.0, ym));
        double err = 0.0, scale = 0.0;
        for (int i = 0; i < LEN; i++) {
            err = fmax(err, fabs((yp[i] - ym[i]) / (2 * eps) - y[LEN + i]));
            scale = fmax(scale, fabs(y[LEN + i]));
        }
        /* the orbit is unchanged by carrying the vector */
        CHECK_OK(run(lat, "sprk-yoshida6", 0, 0.05, 0, 0, y0, 20.0, a));
        CHECK(max_abs_diff(a, y, LEN) == 0.0, "model %d: orbit independent of n_dev", model);
        printf("model %d: deviation vector vs finite differences %.2e (|w| ~ %.2g)\n", model, err,
               scale);
        CHECK(err < 1e-6 * scale, "model %d: tangent map (err %.2e)", model, err);
        fpl_lattice_free(&lat);
    }
}

/* Off-grid samples do not move the grid: a run sampled off the grid ends where an unsampled
 * one does (to round-off: ARKODE's reset puts its time exactly on the grid). */
static void test_off_grid(void)
{
    fpl_lattice *lat = NULL;
    double y0[LEN], y[LEN], z[LEN], ref[LEN];
    orbit(&lat, y0);
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.dt = 0.1;
    fpl_integrator *h = NULL;
    CHECK_OK(fpl_integrator_create(lat, "sprk-yoshida6", 0, &opt, 0.0, y0, &h));
    CHECK_OK(fpl_integrator_advance(h, 3.05, y));
    CHECK(fabs(fpl_integrator_time(h) - 3.0) < 1e-15 && fpl_integrator_steps(h) == 30,
          "grid state at t = 3 (t %.17g, %ld steps)", fpl_integrator_time(h),
          fpl_integrator_steps(h));
    CHECK_OK(run(lat, "srkn14a6", 0, 0.001, 0, 0, y0, 3.05, ref));
    CHECK(max_abs_diff(y, ref, LEN) < 1e-6, "off-grid sample accurate (%.2e)",
          max_abs_diff(y, ref, LEN));
    CHECK_OK(fpl_integrator_advance(h, 10.0, y));
    fpl_integrator_free(&h);
    CHECK_OK(run(lat, "sprk-yoshida6", 0, 0.1, 0, 0, y0, 10.0, z));
    printf("off-grid sample at 3.05 vs reference: ok; end state vs unsampled run %.2e\n",
           max_abs_diff(y, z, LEN));
    CHECK(max_abs_diff(y, z, LEN) == 0.0, "sampling does not perturb the run (%.2e)",
          max_abs_diff(y, z, LEN));
    fpl_lattice_free(&lat);
}

/* A restart from a checkpoint (fpl_integrator_restore at step n) continues bit for bit, with
 * deviation vectors; with compensated sums only when the carry is restored too
 * (fpl_integrator_set_compensation), without it up to the dropped carry (round-off). Samples off
 * the grid do not perturb a compensated run either. */
static void test_restart(void)
{
    fpl_lattice *lat = NULL;
    double y0[2 * LEN], a[2 * LEN], b[2 * LEN], mid[2 * LEN], carry[2 * LEN], c[2 * LEN];
    orbit(&lat, y0);
    for (int i = 0; i < LEN; i++) y0[LEN + i] = sin(1.0 + i);
    for (int comp = 0; comp < 2; comp++) {
        fpl_integrator_options opt;
        fpl_integrator_options_init(&opt);
        opt.dt = 0.01;
        opt.compensated_sums = comp;
        fpl_integrator *h = NULL, *g = NULL;
        CHECK_OK(fpl_integrator_create(lat, "sprk-yoshida6", 1, &opt, 0.0, y0, &h));
        CHECK_OK(fpl_integrator_advance(h, 10.0, a));
        fpl_integrator_free(&h);
        CHECK_OK(fpl_integrator_create(lat, "sprk-yoshida6", 1, &opt, 0.0, y0, &h));
        CHECK_OK(fpl_integrator_advance(h, 3.705, mid)); /* off the grid: state kept at 3.70 */
        CHECK_OK(fpl_integrator_get_state(h, mid));
        const int got = fpl_integrator_get_compensation(h, carry);
        CHECK(comp ? got == FPL_OK : got == FPL_ERR_ARG, "get_compensation: status %d", got);
        if (!comp) CHECK(strstr(fpl_last_error(), "compensated") != NULL, "%s", fpl_last_error());
        double cmax = 0.0;
        for (int i = 0; comp && i < 2 * LEN; i++) cmax = fmax(cmax, fabs(carry[i]));
        if (comp) CHECK(cmax > 0.0 && cmax < 1e-14, "carry is round-off and non-zero (%.2e)", cmax);
        const long n = fpl_integrator_steps(h);
        const double t = fpl_integrator_time(h);
        CHECK_OK(fpl_integrator_advance(h, 10.0, b)); /* sampled run vs the unsampled one */
        CHECK(max_abs_diff(a, b, 2 * LEN) == 0.0, "an off-grid sample does not perturb the run "
              "(compensated sums %d: %.2e)", comp, max_abs_diff(a, b, 2 * LEN));
        fpl_integrator_free(&h);
        CHECK(n == 370, "grid step count %ld", n);
        /* restored into a run that has stepped (a carry of its own) or into a fresh one (a
         * resumed checkpoint; SUNDIALS >= 7.2 zeroes the carry when a solver first starts) */
        for (int with_carry = comp; with_carry >= 0; with_carry--)
        for (int fresh = 0; fresh < 2; fresh++) {
            CHECK_OK(fpl_integrator_create(lat, "sprk-yoshida6", 1, &opt, 0.0, y0, &g));
            if (!fresh) CHECK_OK(fpl_integrator_advance(g, 1.0, b));
            CHECK_OK(fpl_integrator_restore(g, n, t, mid));
            if (comp) {
                CHECK_OK(fpl_integrator_get_compensation(g, c));
                CHECK(max_abs_diff(c, (double[2 * LEN]){0}, 2 * LEN) == 0.0,
                      "restore zeroes the carry");
            }
            if (with_carry) CHECK_OK(fpl_integrator_set_compensation(g, carry));
            CHECK_OK(fpl_integrator_advance(g, 10.0, b));
            fpl_integrator_free(&g);
            const double d = max_abs_diff(a, b, 2 * LEN);
            printf("restart at step %ld (compensated sums %d, carry restored %d, fresh run %d): "
                   "max |difference| %.2e\n", n, comp, with_carry, fresh, d);
            if (comp && !with_carry)
                CHECK(d > 0.0 && d < 1e-14, "without the carry: round-off apart (%.2e)", d);
            else
                CHECK(d == 0.0, "restart continues bit for bit (%.2e)", d);
        }
    }
    /* compensated_sums is for SPRKStep only; a non-finite carry is refused */
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.compensated_sums = 1;
    fpl_integrator *h = NULL;
    CHECK(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y0, &h) == FPL_ERR_ARG && !h,
          "compensated_sums refused for yoshida4");
    CHECK(strstr(fpl_last_error(), "compensated_sums") != NULL, "%s", fpl_last_error());
    CHECK_OK(fpl_integrator_create(lat, "sprk-mclachlan4", 0, &opt, 0.0, y0, &h));
    for (int i = 0; i < LEN; i++) c[i] = i == 3 ? NAN : 0.0;
    CHECK(fpl_integrator_set_compensation(h, c) == FPL_ERR_ARG &&
          strstr(fpl_last_error(), "carry[3]") != NULL, "%s", fpl_last_error());
    fpl_integrator_free(&h);
    fpl_lattice_free(&lat);
}

/* Stopping criterion (max stretch) at a blow-up: ARKODE's root-finding vs the splitting
 * locator (yoshida4, fine step) and DOP853's root-finding. */
static void test_events(void)
{
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_lattice_create(4, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat));
    double z0[8], z[8];
    CHECK_OK(fpl_modes_initial_state(lat, 1, 30.0, z0));
    fpl_event_set ev = {1, {FPL_EVENT_MAX_STRETCH}, {25.0}, {0}}; /* 17.6 at t = 0 */
    static const char *const m[] = {"yoshida4", "dop853", "sprk-suzuki-umeno8", "sprk-mclachlan4"};
    static const double dts[] = {0.0005, 0.0, 0.01, 0.005};
    double t_ev[4] = {0}, stretch[4] = {0};
    for (int i = 0; i < 4; i++) {
        fpl_integrator_options opt;
        fpl_integrator_options_init(&opt);
        if (dts[i] > 0) opt.dt = dts[i];
        opt.rtol = 1e-12;
        opt.atol = 1e-14;
        opt.events = &ev;
        fpl_integrator *h = NULL;
        CHECK_OK(fpl_integrator_create(lat, m[i], 0, &opt, 0.0, z0, &h));
        if (!h) continue;
        int st = fpl_integrator_advance(h, 100.0, z);
        int idx = -1;
        CHECK(st == FPL_EVENT && fpl_integrator_event(h, &idx, &t_ev[i]) && idx == 0,
              "%s: event (status %d: %s)", m[i], st, fpl_integrator_errmsg(h));
        stretch[i] = fmax(fabs(z[0]), fabs(z[3])); /* max |x_{j+1} - x_j|, fixed ends included */
        for (int j = 1; j < 4; j++) stretch[i] = fmax(stretch[i], fabs(z[j] - z[j - 1]));
        printf("%-19s event at t = %.10f, max stretch there %.8f\n", m[i], t_ev[i], stretch[i]);
        fpl_integrator_free(&h);
    }
    for (int i = 1; i < 4; i++) {
        CHECK(fabs(t_ev[i] - t_ev[0]) < 1e-5, "%s event time %.10f vs yoshida4 %.10f", m[i],
              t_ev[i], t_ev[0]);
        CHECK(fabs(stretch[i] - 25.0) < 1e-4, "%s: criterion at its threshold (%.8f)", m[i],
              stretch[i]);
    }
    fpl_lattice_free(&lat);
}

/* The public SPRKStep callbacks: f1 + f2 = fpl_sun_rhs, each zero in the other's blocks. */
static void test_callbacks(void)
{
    SUNContext ctx;
    SUNContext_Create(FPL_SUN_COMM_NULL, &ctx);
    double v[6];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 15.0, 5, 6, v));
    for (int model = 1; model <= 3; model++) {
        fpl_lattice *lat = NULL;
        CHECK_OK(fpl_lattice_create(6, 0.25, 0.1, model, v, &lat));
        fpl_system *sys = NULL;                    /* the callbacks' user data */
        CHECK_OK(fpl_system_create(lat, NULL, &sys));
        const int dim = 2 * 6 * 3;                 /* 2 deviation vectors */
        N_Vector y = N_VNew_Serial(dim, ctx), f1 = N_VNew_Serial(dim, ctx);
        N_Vector f2 = N_VNew_Serial(dim, ctx), f = N_VNew_Serial(dim, ctx);
        for (int i = 0; i < dim; i++) {
            NV_Ith_S(y, i) = 0.3 * sin(1.3 * i + model);
            NV_Ith_S(f1, i) = NV_Ith_S(f2, i) = 99.0;
        }
        CHECK(fpl_sun_force(0.0, y, f1, sys) == 0 && fpl_sun_velocity(0.0, y, f2, sys) == 0 &&
              fpl_sun_rhs(0.0, y, f, sys) == 0, "callbacks");
        for (int i = 0; i < dim; i++) {
            const int momentum = (i % 12) >= 6;
            CHECK((momentum ? NV_Ith_S(f2, i) : NV_Ith_S(f1, i)) == 0.0, "zero block at %d", i);
            CHECK(fabs(NV_Ith_S(f1, i) + NV_Ith_S(f2, i) - NV_Ith_S(f, i)) <=
                  1e-15 * (1 + fabs(NV_Ith_S(f, i))), "f1 + f2 = rhs at %d", i);
        }
        N_Vector bad = N_VNew_Serial(13, ctx);
        CHECK(fpl_sun_force(0.0, bad, bad, sys) < 0 && fpl_sun_velocity(0.0, bad, bad, sys) < 0,
              "bad length refused");
        CHECK(strstr(fpl_system_errmsg(sys), "length") != NULL, "message: %s",
              fpl_system_errmsg(sys));
        N_VDestroy(bad);
        N_VDestroy(y); N_VDestroy(f1); N_VDestroy(f2); N_VDestroy(f);
        fpl_system_free(&sys);
        fpl_lattice_free(&lat);
    }
    SUNContext_Free(&ctx);
}

/* The library never prints: a blow-up (SPRKStep's unrecoverable right-hand-side failure), with
 * and without compensated sums (whose solver takes a step at creation), leaves nothing on
 * stdout/stderr and its message on the handle. */
static void test_silent(void)
{
    check_capture cap;
    int opened = check_capture_begin(&cap) == 0;
    CHECK(opened, "tmpfile");
    if (!opened) return;
    fpl_lattice *lat = NULL;
    double y0[LEN], y[LEN];
    int failed = 0, named = 0;
    fpl_lattice_create(N, 0.25, 1.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat);
    fpl_modes_initial_state(lat, 1, 1e6, y0);
    for (int comp = 0; comp < 2; comp++) {
        fpl_integrator_options opt;
        fpl_integrator_options_init(&opt);
        opt.dt = 0.5;
        opt.compensated_sums = comp;
        fpl_integrator *h = NULL;
        if (fpl_integrator_create(lat, "sprk-yoshida6", 0, &opt, 0.0, y0, &h) == FPL_OK) {
            failed += fpl_integrator_advance(h, 100.0, y) < 0;
            named += strstr(fpl_integrator_errmsg(h), "ARK_RHSFUNC_FAIL") != NULL;
        }
        fpl_integrator_free(&h);
    }
    fpl_lattice_free(&lat);
    char head[200];
    long printed = check_capture_end(&cap, head, sizeof head);
    CHECK(failed == 2 && named == 2, "both runs failed with SPRKStep's flag (%d, %d)", failed,
          named);
    CHECK(printed == 0, "the library printed %ld bytes: %s", printed, head);
}
#endif

int main(void)
{
    printf("SUNDIALS %s\n", fpl_sundials_version());
    test_registry();
#if FPL_HAVE_SPRKSTEP
    test_callbacks();
    test_orders();
    test_energy();
    test_deviations();
    test_off_grid();
    test_restart();
    test_events();
    test_silent();
#endif
    return check_report("sprk");
}
