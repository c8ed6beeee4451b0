/* Batched chaos indicators: every lane against the single-orbit fpl_chaos run of the same orbit
 * (same method, dt, initial deviation vectors), lanes that finish early, blow-up lanes (never
 * chaotic), a known chaotic orbit, checkpoints, and bad input. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "fputlab.h"

#define NS 60

/* The largest relative difference of two sample series (NaN = NaN counts as equal). */
static double rel_diff(const double *a, const double *b, int n)
{
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        if (isnan(a[i]) && isnan(b[i])) continue;
        double d = fabs(a[i] - b[i]) / fmax(fabs(b[i]), 1e-300);
        if (!(d <= worst)) worst = d;
    }
    return worst;
}

static fpl_lattice *disordered(int n, int model, double tau, unsigned long seed)
{
    double *v = malloc(sizeof(double) * (size_t)n);
    fpl_lattice *lat = NULL;
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, tau, seed, n, v));
    CHECK_OK(fpl_lattice_create(n, 0.25, 0.0, model, v, &lat));
    free(v);
    return lat;
}

/* R lanes against R single-orbit runs: samples, final lambda/SALI/GALI, flags, steps. */
static void compare_with_single(fpl_lattice **lats, int R, const char *method, double dt,
                                const double *y0, const double *w0, fpl_chaos_batch_options *bo,
                                double tol, const char *what)
{
    const int n = fpl_lattice_size(lats[0]), len = 2 * n;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    io.dt = dt;
    double *bt = calloc((size_t)R * bo->chaos.n_samples, sizeof(double));
    double *bm = calloc((size_t)R * bo->chaos.n_samples, sizeof(double));
    double *bs = calloc((size_t)R * bo->chaos.n_samples, sizeof(double));
    double *bg = calloc((size_t)R * bo->chaos.n_samples, sizeof(double));
    fpl_chaos_batch *b = NULL;
    CHECK_OK(fpl_chaos_batch_create(lats, R, method, &io, 0.0, y0, w0, bo, &b));
    if (!b) return;
    /* in three segments, as a resumable run would */
    CHECK_OK(fpl_chaos_batch_advance(b, bo->chaos.t_end / 3, bt, bm, bs, bg));
    CHECK_OK(fpl_chaos_batch_advance(b, bo->chaos.t_end / 2, bt, bm, bs, bg));
    CHECK_OK(fpl_chaos_batch_advance(b, bo->chaos.t_end, bt, bm, bs, bg));
    CHECK(fpl_chaos_batch_done(b), "%s: batch not done", what);
    fpl_chaos_options so;
    fpl_chaos_options_init(&so);
    so.t_end = bo->chaos.t_end;
    so.renorm_interval = bo->chaos.renorm_interval;
    so.n_samples = bo->chaos.n_samples;
    so.n_dev = bo->chaos.n_dev;
    so.seed = bo->chaos.seed;
    so.sali_threshold = bo->chaos.sali_threshold;
    double worst = 0.0;
    for (int r = 0; r < R; r++) {
        double st[NS], sm[NS], ss[NS], sg[NS];
        fpl_chaos_result sres;
        fpl_chaos_batch_result bres;
        int status = fpl_chaos_run(lats[r], method, &io, 0.0, y0 + (size_t)r * len,
                                   w0 ? w0 + (size_t)r * bo->chaos.n_dev * len : NULL, &so, st, sm, ss,
                                   sg, &sres);
        CHECK(status == FPL_OK, "%s: single run %d: %s", what, r, fpl_last_error());
        CHECK_OK(fpl_chaos_batch_get_result(b, r, &bres));
        CHECK(bres.n_samples == sres.n_samples, "%s lane %d: %d samples vs %d", what, r,
              bres.n_samples, sres.n_samples);
        const size_t o = (size_t)r * bo->chaos.n_samples;
        int ns = sres.n_samples < bres.n_samples ? sres.n_samples : bres.n_samples;
        CHECK(rel_diff(bt + o, st, ns) == 0.0, "%s lane %d: sample times differ", what, r);
        double d = fmax(rel_diff(bm + o, sm, ns), rel_diff(bs + o, ss, ns));
        d = fmax(d, rel_diff(bg + o, sg, ns));
        d = fmax(d, fabs(bres.mle - sres.mle) / fabs(sres.mle));
        worst = fmax(worst, d);
        CHECK(d <= tol, "%s lane %d: lambda/SALI/GALI differ by %.3g (relative)", what, r, d);
        /* MEGNO: the lanes run fpl_chaos's update on the same log-norms */
        CHECK(fabs(bres.megno - sres.megno) <= tol * fmax(1.0, fabs(sres.megno)),
              "%s lane %d: MEGNO %.17g vs %.17g", what, r, bres.megno, sres.megno);
        CHECK(bres.t_final == sres.t_final && bres.steps == sres.steps,
              "%s lane %d: t_final %g vs %g, steps %ld vs %ld", what, r, bres.t_final,
              sres.t_final, bres.steps, sres.steps);
        CHECK(bres.chaotic == sres.chaotic && !bres.blew_up && bres.done,
              "%s lane %d: chaotic %d vs %d, blew_up %d", what, r, bres.chaotic, sres.chaotic,
              bres.blew_up);
        if (sres.chaotic)
            CHECK(bres.t_chaotic == sres.t_chaotic, "%s lane %d: t_chaotic %g vs %g", what, r,
                  bres.t_chaotic, sres.t_chaotic);
    }
    printf("%-44s R = %2d: largest relative difference to fpl_chaos %.3g\n", what, R, worst);
    fpl_chaos_batch_free(&b);
    free(bt);
    free(bm);
    free(bs);
    free(bg);
}

static double *mode_states(fpl_lattice **lats, int R, const double *amp)
{
    const int n = fpl_lattice_size(lats[0]);
    double *y0 = malloc(sizeof(double) * 2 * (size_t)n * R);
    for (int r = 0; r < R; r++) CHECK_OK(fpl_modes_initial_state(lats[r], 1, amp[r], y0 + 2 * (size_t)n * r));
    return y0;
}

static void test_agreement(void)
{
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.n_samples = NS;
    const double amp[6] = {1, 1, 1, 1, 1, 1};
    /* model 3 (the paper's chaos study), 6 disorder draws, Yoshida 4 */
    {
        fpl_lattice *l[6];
        for (int r = 0; r < 6; r++) l[r] = disordered(16, FPL_MODEL_NONLINEAR, 10.0, (unsigned long)r + 1);
        double *y0 = mode_states(l, 6, amp);
        bo.chaos.t_end = 2000.0;
        compare_with_single(l, 6, "yoshida4", 0.01, y0, NULL, &bo, 1e-12, "nonlinear N=16 yoshida4");
        /* srkn14a6 at dt = 0.4: renormalisations at t = 1, 2, ... fall off the grid (partial
         * steps from copies) */
        bo.chaos.t_end = 5000.3;
        compare_with_single(l, 6, "srkn14a6", 0.4, y0, NULL, &bo, 1e-12, "nonlinear N=16 srkn14a6 dt=0.4");
        /* three deviation vectors (GALI_3) and given w0 */
        double *w0 = malloc(sizeof(double) * 6 * 3 * 32);
        for (int i = 0; i < 6 * 3 * 32; i++) w0[i] = check_uniform();
        bo.chaos.n_dev = 3;
        bo.chaos.t_end = 1000.0;
        compare_with_single(l, 6, "aba864", 0.0625, y0, w0, &bo, 1e-12, "nonlinear N=16 aba864 n_dev=3 w0");
        bo.chaos.n_dev = 1;
        compare_with_single(l, 5, "leapfrog", 0.005, y0, w0, &bo, 1e-12, "nonlinear N=16 leapfrog n_dev=1");
        bo.chaos.n_dev = 2;
        free(w0);
        /* a group holding one running lane at N >= 12 is stepped by the single-orbit code */
        fpl_lattice *l64 = disordered(64, FPL_MODEL_NONLINEAR, 10.0, 5);
        double *y64 = mode_states(&l64, 1, amp);
        bo.chaos.t_end = 500.0;
        compare_with_single(&l64, 1, "yoshida4", 0.01, y64, NULL, &bo, 1e-12, "nonlinear N=64 one lane");
        free(y64);
        fpl_lattice_free(&l64);
        free(y0);
        for (int r = 0; r < 6; r++) fpl_lattice_free(&l[r]);
    }
    /* model 2 and model 1, N = 5 (odd: padding lanes), renorm_interval 2.5 */
    {
        fpl_lattice *l[3];
        for (int r = 0; r < 3; r++) l[r] = disordered(5, FPL_MODEL_HAMILTONIAN, 20.0, (unsigned long)r + 7);
        const double a3[3] = {1.0, 2.0, 3.0};
        double *y0 = mode_states(l, 3, a3);
        bo.chaos.t_end = 3000.0;
        bo.chaos.renorm_interval = 2.5;
        compare_with_single(l, 3, "yoshida4", 0.01, y0, NULL, &bo, 1e-12, "hamiltonian N=5 yoshida4");
        free(y0);
        for (int r = 0; r < 3; r++) fpl_lattice_free(&l[r]);
        fpl_lattice *h = NULL;
        CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &h));
        fpl_lattice *hl[9];
        double a9[9];
        for (int r = 0; r < 9; r++) { hl[r] = h; a9[r] = 0.5 + 0.5 * r; }
        y0 = mode_states(hl, 9, a9);
        bo.chaos.renorm_interval = 1.0;
        bo.chaos.t_end = 4000.0;
        compare_with_single(hl, 9, "srkn14a6", 0.4, y0, NULL, &bo, 1e-12, "homogeneous N=8 srkn14a6 amplitudes");
        free(y0);
        fpl_lattice_free(&h);
    }
}

/* Rings (models 1-3) and the Toda lattice (fixed ends and ring): every lane against the
 * single-orbit run, which steps them through models_periodic.c / model_toda.c. N = 5 (padding
 * lanes) and 16, two deviation vectors, and three with given w0 on a ring. */
static fpl_lattice *ring_or_toda(int n, int model, int boundary, double tau, unsigned long seed)
{
    double *v = malloc(sizeof(double) * (size_t)n);
    fpl_lattice *lat = NULL;
    if (model == FPL_MODEL_HAMILTONIAN || model == FPL_MODEL_NONLINEAR)
        CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, tau, seed, n, v));
    CHECK_OK(fpl_lattice_create_ex(n, model == FPL_MODEL_TODA ? 0.5 : 0.25, 0.0, model,
                                   model == FPL_MODEL_HAMILTONIAN || model == FPL_MODEL_NONLINEAR
                                       ? v : NULL, boundary, &lat));
    free(v);
    return lat;
}

static void test_rings_and_toda(void)
{
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.n_samples = NS;
    bo.chaos.t_end = 1000.0;
    static const int models[] = {FPL_MODEL_HOMOGENEOUS, FPL_MODEL_HAMILTONIAN,
                                 FPL_MODEL_NONLINEAR, FPL_MODEL_TODA, FPL_MODEL_TODA};
    static const int bounds[] = {FPL_BOUNDARY_PERIODIC, FPL_BOUNDARY_PERIODIC,
                                 FPL_BOUNDARY_PERIODIC, FPL_BOUNDARY_PERIODIC, FPL_BOUNDARY_FIXED};
    for (int c = 0; c < 5; c++)
        for (int in = 0; in < 2; in++) {
            const int n = in ? 16 : 5, R = 5;
            fpl_lattice *l[5];
            for (int r = 0; r < R; r++)
                l[r] = ring_or_toda(n, models[c], bounds[c], 10.0, (unsigned long)r + 3);
            /* a random state of small energy per orbit; on the disordered rings a translation
             * stretches the bonds (R_b = (cn_b - cn_{b-1}) x), and the drift of the centre runs
             * them over the barrier from t ~ 15 on: t_end = 10 there */
            double *y0 = malloc(sizeof(double) * 2 * (size_t)n * R);
            for (int i = 0; i < 2 * n * R; i++) y0[i] = 0.4 * (check_uniform() - 0.5);
            bo.chaos.t_end = c == 1 || c == 2 ? 10.0 : 400.0;
            char what[64];
            snprintf(what, sizeof what, "%s model %d N=%d", bounds[c] ? "ring" : "fixed",
                     models[c], n);
            compare_with_single(l, R, c % 2 ? "srkn14a6" : "yoshida4", c % 2 ? 0.1 : 0.01, y0,
                                NULL, &bo, 1e-12, what);
            if (c == 2 && in) {   /* GALI_3 with given w0 on a ring */
                double *w0 = malloc(sizeof(double) * (size_t)R * 3 * 2 * n);
                for (int i = 0; i < R * 3 * 2 * n; i++) w0[i] = check_uniform();
                bo.chaos.n_dev = 3;
                compare_with_single(l, R, "aba864", 0.05, y0, w0, &bo, 1e-12,
                                    "ring model 3 N=16 aba864 n_dev=3 w0");
                bo.chaos.n_dev = 2;
                free(w0);
            }
            free(y0);
            for (int r = 0; r < R; r++) fpl_lattice_free(&l[r]);
        }
}

/* The known chaotic orbit (homogeneous N = 8, mode 1 at amplitude 4) next to a regular one: it
 * reaches SALI < 1e-8 at the time the single-orbit run finds, and stops with stop_when_chaotic. */
static void test_chaotic_orbit(void)
{
    fpl_lattice *h = NULL;
    CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &h));
    fpl_lattice *l[2] = {h, h};
    const double amp[2] = {4.0, 1.0};
    double *y0 = mode_states(l, 2, amp);
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 6e4; /* SALI < 1e-8 at t ~ 5.4e4 */
    bo.chaos.n_samples = NS;
    bo.chaos.stop_when_chaotic = 1;
    double sali[2 * NS];
    fpl_chaos_batch *b = NULL;
    CHECK_OK(fpl_chaos_batch_create(l, 2, "yoshida4", NULL, 0.0, y0, NULL, &bo, &b));
    CHECK_OK(fpl_chaos_batch_advance(b, bo.chaos.t_end, NULL, NULL, sali, NULL));
    fpl_chaos_batch_result res[2];
    for (int r = 0; r < 2; r++) CHECK_OK(fpl_chaos_batch_get_result(b, r, &res[r]));
    fpl_chaos_options so;
    fpl_chaos_options_init(&so);
    so.t_end = bo.chaos.t_end;
    so.n_samples = NS;
    so.stop_when_chaotic = 1;
    fpl_chaos_result single;
    CHECK_OK(fpl_chaos_run(h, "yoshida4", NULL, 0.0, y0, NULL, &so, NULL, NULL, NULL, NULL, &single));
    CHECK(single.chaotic, "single-orbit run not chaotic");
    CHECK(res[0].chaotic && res[0].sali < 1e-7 && !res[0].blew_up,
          "amplitude 4: chaotic %d, SALI %g", res[0].chaotic, res[0].sali);
    CHECK(res[0].t_chaotic == single.t_chaotic, "t_chaotic %g vs single %g", res[0].t_chaotic,
          single.t_chaotic);
    /* stopped one renormalisation after the SALI collapse (the confirmation) */
    CHECK(res[0].t_final == res[0].t_chaotic + 1.0 && res[0].t_final < bo.chaos.t_end,
          "stopped at %g (chaotic at %g)", res[0].t_final, res[0].t_chaotic);
    CHECK(sali[res[0].n_samples - 1] < 1e-7, "last sample SALI %g", sali[res[0].n_samples - 1]);
    CHECK(!res[1].chaotic && res[1].t_final == bo.chaos.t_end, "amplitude 1: chaotic %d, t_final %g",
          res[1].chaotic, res[1].t_final);
    printf("homogeneous N=8 amplitude 4: chaotic at t = %g (single-orbit run: %g), lambda = %.4f\n",
           res[0].t_chaotic, single.t_chaotic, res[0].mle);
    fpl_chaos_batch_free(&b);
    free(y0);
    fpl_lattice_free(&h);
}

/* Lanes that stop early (chaotic, stop_when_chaotic) do not disturb the others: the regular
 * lanes come out bit for bit as in a batch of the regular orbits only, and compact = 0
 * (finished lanes left in place) gives the same numbers. FPUT-beta chain (alpha = 0, beta = 1):
 * large random states turn chaotic within t ~ 100, small ones stay regular. */
static void test_early_exit(void)
{
    fpl_lattice *h = NULL;
    CHECK_OK(fpl_lattice_create(8, 0.0, 1.0, FPL_MODEL_HOMOGENEOUS, NULL, &h));
    fpl_lattice *l[6] = {h, h, h, h, h, h};
    double y0[6 * 16];
    const int big[6] = {0, 1, 0, 0, 1, 0};
    for (int i = 0; i < 6 * 16; i++) y0[i] = (big[i / 16] ? 1.5 : 0.02) * check_uniform();
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 2000.0;
    bo.chaos.n_samples = NS;
    bo.chaos.stop_when_chaotic = 1;
    double mle[6 * NS], sali[6 * NS];
    fpl_chaos_batch *b = NULL;
    CHECK_OK(fpl_chaos_batch_create(l, 6, "yoshida4", NULL, 0.0, y0, NULL, &bo, &b));
    CHECK_OK(fpl_chaos_batch_advance(b, bo.chaos.t_end, NULL, mle, sali, NULL));
    fpl_chaos_batch_result res[6];
    for (int r = 0; r < 6; r++) {
        CHECK_OK(fpl_chaos_batch_get_result(b, r, &res[r]));
        CHECK(res[r].chaotic == big[r] && (res[r].t_final < bo.chaos.t_end) == big[r],
              "lane %d: chaotic %d, t_final %g", r, res[r].chaotic, res[r].t_final);
    }
    fpl_lattice *l4[4] = {h, h, h, h};
    const int reg[4] = {0, 2, 3, 5};
    double y4[4 * 16], m4[4 * NS], s4[4 * NS];
    for (int i = 0; i < 4; i++) memcpy(y4 + 16 * i, y0 + 16 * reg[i], sizeof(double) * 16);
    fpl_chaos_batch *b4 = NULL;
    CHECK_OK(fpl_chaos_batch_create(l4, 4, "yoshida4", NULL, 0.0, y4, NULL, &bo, &b4));
    CHECK_OK(fpl_chaos_batch_advance(b4, bo.chaos.t_end, NULL, m4, s4, NULL));
    for (int i = 0; i < 4; i++) {
        fpl_chaos_batch_result r4;
        CHECK_OK(fpl_chaos_batch_get_result(b4, i, &r4));
        CHECK(r4.n_samples == res[reg[i]].n_samples &&
              memcmp(m4 + i * NS, mle + reg[i] * NS, sizeof(double) * (size_t)r4.n_samples) == 0 &&
              memcmp(s4 + i * NS, sali + reg[i] * NS, sizeof(double) * (size_t)r4.n_samples) == 0,
              "regular lane %d disturbed by the lanes that stopped", reg[i]);
    }
    fpl_chaos_batch *b0 = NULL;
    bo.compact = 0;
    double m0[6 * NS];
    CHECK_OK(fpl_chaos_batch_create(l, 6, "yoshida4", NULL, 0.0, y0, NULL, &bo, &b0));
    CHECK_OK(fpl_chaos_batch_advance(b0, bo.chaos.t_end, NULL, m0, NULL, NULL));
    for (int r = 0; r < 6; r++)
        CHECK(memcmp(m0 + r * NS, mle + r * NS, sizeof(double) * (size_t)res[r].n_samples) == 0,
              "compact = 0: lane %d differs", r);
    fpl_chaos_batch_free(&b0);
    fpl_chaos_batch_free(&b4);
    fpl_chaos_batch_free(&b);
    fpl_lattice_free(&h);
}

/* Model 3, tau = 20 %, N = 64, seed 1 blows up before t = 1e4 (Yoshida 4, dt = 0.01): blow-up,
 * never chaotic, with and without the bond-stretch criterion; the lanes next to it unaffected. */
static void test_blowup(void)
{
    fpl_lattice *l[3];
    l[0] = disordered(64, FPL_MODEL_NONLINEAR, 10.0, 2);
    l[1] = disordered(64, FPL_MODEL_NONLINEAR, 20.0, 1);
    l[2] = disordered(64, FPL_MODEL_NONLINEAR, 10.0, 3);
    const double amp[3] = {1, 1, 1};
    double *y0 = mode_states(l, 3, amp);
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 3000.0;
    bo.chaos.n_samples = NS;
    /* variant 0: the default stretch check at renormalisations (1/alpha); 1: no check, only the
     * non-finite state; 2: the bond-stretch criterion as a lattice event */
    for (int variant = 0; variant < 3; variant++) {
        const int with_event = variant == 2;
        bo.chaos.blowup_stretch = variant == 1 ? -1.0 : 0.0;
        /* the criteria are a run option: one set for the batch and the single-orbit runs */
        fpl_event_set ev = {1, {FPL_EVENT_MAX_STRETCH}, {4.0}, {0}};
        fpl_integrator_options io;
        fpl_integrator_options_init(&io);
        io.events = with_event ? &ev : NULL;
        for (int stop = 0; stop < 2; stop++) {
            bo.chaos.stop_when_chaotic = stop;
            fpl_chaos_batch *b = NULL;
            double mle[3 * NS];
            CHECK_OK(fpl_chaos_batch_create(l, 3, "yoshida4", &io, 0.0, y0, NULL, &bo, &b));
            CHECK_OK(fpl_chaos_batch_advance(b, bo.chaos.t_end, NULL, mle, NULL, NULL));
            fpl_chaos_batch_result r;
            CHECK_OK(fpl_chaos_batch_get_result(b, 1, &r));
            CHECK(r.blew_up && !r.chaotic && isnan(r.t_chaotic) && r.done,
                  "tau 20 lane: blew_up %d chaotic %d (t_chaotic %g), events %d, stop %d",
                  r.blew_up, r.chaotic, r.t_chaotic, with_event, stop);
            const int want = variant == 0 ? FPL_BATCH_BLOWUP_STRETCH
                           : variant == 1 ? FPL_BATCH_BLOWUP_NONFINITE : FPL_BATCH_BLOWUP_EVENT;
            CHECK(r.blowup_reason == want, "variant %d: reason %d", variant, r.blowup_reason);
            {
                /* the single-orbit path ends the same orbit the same way at the same time */
                fpl_chaos_options so;
                fpl_chaos_options_init(&so);
                so.t_end = bo.chaos.t_end;
                so.n_samples = NS;
                so.stop_when_chaotic = stop;
                so.blowup_stretch = bo.chaos.blowup_stretch;
                fpl_chaos_result sr;
                int st = fpl_chaos_run(l[1], "yoshida4", &io, 0.0, y0 + 128, NULL, &so, NULL, NULL,
                                       NULL, NULL, &sr);
                CHECK(st == FPL_EVENT && sr.blew_up && !sr.chaotic && sr.t_blowup == r.t_blowup &&
                          sr.t_final == r.t_final,
                      "variant %d: single-orbit run status %d blew_up %d t_blowup %.10g (batch %.10g) "
                      "t_final %g (batch %g)", variant, st, sr.blew_up, sr.t_blowup, r.t_blowup,
                      sr.t_final, r.t_final);
            }
            CHECK(r.t_blowup > 2000.0 && r.t_blowup < 2600.0 && r.t_final <= r.t_blowup,
                  "t_blowup %g, t_final %g", r.t_blowup, r.t_final);
            if (with_event) {
                /* the event time of a single-orbit integration of the same orbit */
                fpl_integrator *h = NULL;
                double y[384];
                CHECK_OK(fpl_integrator_create(l[1], "yoshida4", 0, &io, 0.0, y0 + 128, &h));
                CHECK(fpl_integrator_advance(h, 3000.0, y) == FPL_EVENT, "single run: no event");
                int idx;
                double tev;
                CHECK(fpl_integrator_event(h, &idx, &tev) == 1 && fabs(tev - r.t_blowup) < 1e-6,
                      "event at %.10g, single-orbit integration %.10g", r.t_blowup, tev);
                fpl_integrator_free(&h);
                CHECK(strstr(fpl_chaos_batch_message(b, 1), "x_{j+1} - x_j") != NULL, "message '%s'",
                      fpl_chaos_batch_message(b, 1));
            }
            if (!stop)
                printf("tau = 20 %% lane: %s (t_blowup %g)\n", fpl_chaos_batch_message(b, 1), r.t_blowup);
            for (int o = 0; o < 3; o += 2) {
                fpl_chaos_batch_result ro;
                CHECK_OK(fpl_chaos_batch_get_result(b, o, &ro));
                CHECK(!ro.blew_up && ro.t_final == bo.chaos.t_end, "lane %d: blew_up %d", o, ro.blew_up);
                if (variant || stop) continue; /* the comparison once is enough */
                /* unaffected: the same as a single-orbit run */
                fpl_chaos_options so;
                fpl_chaos_options_init(&so);
                so.t_end = bo.chaos.t_end;
                so.n_samples = NS;
                double sm[NS];
                fpl_chaos_result sr;
                CHECK_OK(fpl_chaos_run(l[o], "yoshida4", NULL, 0.0, y0 + 128 * o, NULL, &so, NULL,
                                       sm, NULL, NULL, &sr));
                CHECK(rel_diff(mle + NS * o, sm, sr.n_samples) < 1e-12, "lane %d disturbed", o);
            }
            fpl_chaos_batch_free(&b);
        }
    }
    free(y0);
    for (int r = 0; r < 3; r++) fpl_lattice_free(&l[r]);
}

/* Save at t = 700, restore into a fresh handle, continue: bit for bit the uninterrupted run. */
static void test_checkpoint(void)
{
    /* alpha = 0, beta = 1 (no escape): large random states turn chaotic within t ~ 100 */
    fpl_lattice *l[5];
    for (int r = 0; r < 5; r++) {
        double v[8];
        CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, (unsigned long)r + 1, 8, v));
        CHECK_OK(fpl_lattice_create(8, 0.0, 1.0, FPL_MODEL_NONLINEAR, v, &l[r]));
    }
    double y0[5 * 16];
    for (int i = 0; i < 5 * 16; i++) y0[i] = (i / 16 % 2 ? 1.5 : 0.05) * check_uniform();
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 3000.0;
    bo.chaos.n_samples = NS;
    bo.chaos.stop_when_chaotic = 1;
    double m1[5 * NS], m2[5 * NS];
    fpl_chaos_batch *a = NULL, *b = NULL;
    CHECK_OK(fpl_chaos_batch_create(l, 5, "srkn14a6", NULL, 0.0, y0, NULL, &bo, &a));
    CHECK_OK(fpl_chaos_batch_advance(a, bo.chaos.t_end, NULL, m1, NULL, NULL));
    CHECK_OK(fpl_chaos_batch_create(l, 5, "srkn14a6", NULL, 0.0, y0, NULL, &bo, &b));
    CHECK_OK(fpl_chaos_batch_advance(b, 700.0, NULL, m2, NULL, NULL));
    long len = fpl_chaos_batch_save_size(b);
    double *buf = malloc(sizeof(double) * (size_t)len);
    CHECK_OK(fpl_chaos_batch_save(b, buf));
    fpl_chaos_batch_free(&b);
    CHECK_OK(fpl_chaos_batch_create(l, 5, "srkn14a6", NULL, 0.0, y0, NULL, &bo, &b));
    CHECK(fpl_chaos_batch_restore(b, buf, len - 1) == FPL_ERR_ARG, "short buffer accepted");
    CHECK_OK(fpl_chaos_batch_restore(b, buf, len));
    CHECK(fpl_chaos_batch_time(b) == 700.0, "restored time %g", fpl_chaos_batch_time(b));
    CHECK_OK(fpl_chaos_batch_advance(b, bo.chaos.t_end, NULL, m2, NULL, NULL));
    int chaotic = 0;
    for (int r = 0; r < 5; r++) {
        fpl_chaos_batch_result ra, rb;
        CHECK_OK(fpl_chaos_batch_get_result(a, r, &ra));
        CHECK_OK(fpl_chaos_batch_get_result(b, r, &rb));
        chaotic += ra.chaotic;
        CHECK(ra.mle == rb.mle && ra.sali == rb.sali && ra.t_final == rb.t_final &&
              ra.megno == rb.megno && ra.megno == ra.megno &&
              ra.chaotic == rb.chaotic && ra.n_samples == rb.n_samples && ra.steps == rb.steps &&
              memcmp(m1 + r * NS, m2 + r * NS, sizeof(double) * (size_t)ra.n_samples) == 0,
              "lane %d: restored run differs (mle %.17g vs %.17g)", r, ra.mle, rb.mle);
    }
    CHECK(chaotic >= 1 && chaotic < 5, "%d lanes of 5 turned chaotic", chaotic);
    free(buf);
    fpl_chaos_batch_free(&a);
    fpl_chaos_batch_free(&b);
    for (int r = 0; r < 5; r++) fpl_lattice_free(&l[r]);
}

static void expect_error_events(fpl_lattice *const *l, int R, const char *method, double dt,
                                double t_end, double renorm, const fpl_event_set *events,
                                const char *needle)
{
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = t_end;
    bo.chaos.renorm_interval = renorm;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    io.dt = dt;
    io.events = events;
    double y0[4 * 16] = {0};
    fpl_chaos_batch *b = (fpl_chaos_batch *)&io; /* must be reset to NULL */
    int st = fpl_chaos_batch_create(l, R, method, &io, 0.0, y0, NULL, &bo, &b);
    CHECK(st < 0 && b == NULL && strstr(fpl_last_error(), needle) != NULL,
          "expected an error naming '%s', got %d: %s", needle, st, fpl_last_error());
}

static void expect_error(fpl_lattice *const *l, int R, const char *method, double dt, double t_end,
                         double renorm, const char *needle)
{
    expect_error_events(l, R, method, dt, t_end, renorm, NULL, needle);
}

static void test_bad_input(void)
{
    fpl_lattice *a = NULL, *b = NULL, *c = NULL, *d = NULL;
    CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, 1, NULL, &a));
    CHECK_OK(fpl_lattice_create(6, 0.25, 0.0, 1, NULL, &b));
    CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, 3, NULL, &c));
    CHECK_OK(fpl_lattice_create(8, 0.3, 0.0, 1, NULL, &d));
    fpl_lattice *ab[2] = {a, b}, *ac[2] = {a, c}, *ad[2] = {a, d}, *aa[2] = {a, a}, *an[2] = {a, NULL};
    expect_error(aa, 0, "yoshida4", 0.01, 10.0, 1.0, "n_orbits");
    expect_error(ab, 2, "yoshida4", 0.01, 10.0, 1.0, "lattices[1]: N = 6");
    expect_error(ac, 2, "yoshida4", 0.01, 10.0, 1.0, "lattices[1]: model");
    expect_error(ad, 2, "yoshida4", 0.01, 10.0, 1.0, "lattices[1]: alpha");
    expect_error(an, 2, "yoshida4", 0.01, 10.0, 1.0, "lattices[1]: NULL");
    expect_error(aa, 2, "yoshida4", 0.01, 1e300, 1.0, "t_end");
    expect_error(aa, 2, "yoshida4", 0.01, NAN, 1.0, "t_end");
    expect_error(aa, 2, "yoshida4", 0.01, 10.0, 0.0, "renorm_interval");
    expect_error(aa, 2, "yoshida4", 0.01, 10.0, -1.0, "renorm_interval");
    expect_error(aa, 2, "yoshida4", 0.01, 10.0, 0.005, "renorm_interval = 0.005 must be >= dt");
    expect_error(aa, 2, "yoshida4", -0.01, 10.0, 1.0, "dt");
    expect_error(aa, 2, "dop853", 0.01, 10.0, 1.0, "method 'dop853' is not supported");
    expect_error(aa, 2, "aba864-harmonic", 0.01, 10.0, 1.0, "not supported");
    expect_error(aa, 2, "rk99", 0.01, 10.0, 1.0, "unknown");
    fpl_event_set me = {1, {FPL_EVENT_MODE_ENERGY}, {4.0}, {1}};
    expect_error_events(aa, 2, "yoshida4", 0.01, 10.0, 1.0, &me, "mode energy");
    fpl_event_set bad = {1, {FPL_EVENT_MAX_STRETCH}, {-4.0}, {0}};
    expect_error_events(aa, 2, "yoshida4", 0.01, 10.0, 1.0, &bad, "events: threshold[0]");
    /* a non-finite y0, and queries on bad orbits */
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 10.0;
    double y0[2 * 16] = {0};
    y0[20] = NAN;
    fpl_chaos_batch *bb = NULL;
    CHECK(fpl_chaos_batch_create(aa, 2, "yoshida4", NULL, 0.0, y0, NULL, &bo, &bb) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "y0[1][4]"), "NaN y0: %s", fpl_last_error());
    y0[20] = 0.0;
    CHECK_OK(fpl_chaos_batch_create(aa, 2, "yoshida4", NULL, 0.0, y0, NULL, &bo, &bb));
    fpl_chaos_batch_result r;
    CHECK(fpl_chaos_batch_get_result(bb, 2, &r) == FPL_ERR_ARG && strstr(fpl_last_error(), "orbit"),
          "orbit 2 of 2: %s", fpl_last_error());
    CHECK(fpl_chaos_batch_advance(bb, NAN, NULL, NULL, NULL, NULL) == FPL_ERR_ARG, "NaN t_until");
    fpl_chaos_batch_free(&bb);
    CHECK(bb == NULL, "free resets the handle");
    fpl_chaos_batch_free(NULL);
    fpl_lattice_free(&a);
    fpl_lattice_free(&b);
    fpl_lattice_free(&c);
    fpl_lattice_free(&d);
}

/* fpl_chaos_batch_get_orbit / set_orbits: at t = 700 every orbit leaves its lane in the
 * single-orbit format; set into a fresh batch, the run continues bit for bit as the
 * uninterrupted one, and each running orbit restored into its own fpl_chaos handle continues
 * bit for bit as fpl_chaos_run of that orbit alone. */
static void test_orbit_format(void)
{
    enum { R = 5, N = 8, K = 2, LANE = 2 * N * (K + 1), NA = FPL_CHAOS_N_ACCUMULATORS };
    fpl_lattice *l[R];
    for (int r = 0; r < R; r++) {
        double v[N];
        CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, (unsigned long)r + 1, N, v));
        CHECK_OK(fpl_lattice_create(N, 0.0, 1.0, FPL_MODEL_NONLINEAR, v, &l[r]));
    }
    double y0[R * 2 * N];
    for (int i = 0; i < R * 2 * N; i++) y0[i] = (i / (2 * N) % 2 ? 1.5 : 0.05) * check_uniform();
    fpl_chaos_batch_options bo;
    fpl_chaos_batch_options_init(&bo);
    bo.chaos.t_end = 3000.0;
    bo.chaos.n_samples = NS;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    io.dt = 0.1;
    double m1[R * NS], m2[R * NS];
    fpl_chaos_batch *a = NULL, *b = NULL;
    CHECK_OK(fpl_chaos_batch_create(l, R, "srkn14a6", &io, 0.0, y0, NULL, &bo, &a));
    CHECK_OK(fpl_chaos_batch_advance(a, bo.chaos.t_end, NULL, m1, NULL, NULL));
    CHECK_OK(fpl_chaos_batch_create(l, R, "srkn14a6", &io, 0.0, y0, NULL, &bo, &b));
    CHECK_OK(fpl_chaos_batch_advance(b, 700.0, NULL, m2, NULL, NULL));
    long steps[R];
    double t[R], y[R * LANE], acc[R * NA];
    for (int r = 0; r < R; r++)
        CHECK_OK(fpl_chaos_batch_get_orbit(b, r, &steps[r], &t[r], y + r * LANE, acc + r * NA));
    CHECK(fpl_chaos_batch_get_orbit(b, R, &steps[0], &t[0], y, acc) == FPL_ERR_ARG,
          "orbit index out of range accepted");
    fpl_chaos_batch_free(&b);

    /* the same orbits into a fresh batch */
    CHECK_OK(fpl_chaos_batch_create(l, R, "srkn14a6", &io, 0.0, y0, NULL, &bo, &b));
    long bad_steps[R];
    memcpy(bad_steps, steps, sizeof steps);
    bad_steps[R - 1] += 1;
    CHECK(acc[(R - 1) * NA + 10] != 0 ||
          fpl_chaos_batch_set_orbits(b, bad_steps, t, y, acc) == FPL_ERR_ARG,
          "running orbits at different steps accepted");
    CHECK_OK(fpl_chaos_batch_set_orbits(b, steps, t, y, acc));
    CHECK(fpl_chaos_batch_time(b) == 700.0, "time after set_orbits %g", fpl_chaos_batch_time(b));
    CHECK_OK(fpl_chaos_batch_advance(b, bo.chaos.t_end, NULL, m2, NULL, NULL));
    int running = 0;
    for (int r = 0; r < R; r++) {
        fpl_chaos_batch_result ra, rb;
        CHECK_OK(fpl_chaos_batch_get_result(a, r, &ra));
        CHECK_OK(fpl_chaos_batch_get_result(b, r, &rb));
        CHECK(ra.mle == rb.mle && ra.sali == rb.sali && ra.t_final == rb.t_final &&
              ra.megno == rb.megno && ra.megno == ra.megno &&
              ra.chaotic == rb.chaotic && ra.n_samples == rb.n_samples && ra.steps == rb.steps &&
              memcmp(m1 + r * NS, m2 + r * NS, sizeof(double) * (size_t)ra.n_samples) == 0,
              "orbit %d: continued batch differs (mle %.17g vs %.17g)", r, ra.mle, rb.mle);

        /* each running orbit in its own fpl_chaos handle, against fpl_chaos_run of it alone */
        if (acc[r * NA + 10] != 0) continue;
        running++;
        fpl_chaos_options so = bo.chaos;
        double sm[NS], cm[NS];
        fpl_chaos_result sres, cres;
        CHECK_OK(fpl_chaos_run(l[r], "srkn14a6", &io, 0.0, y0 + r * 2 * N, NULL, &so, NULL, sm,
                               NULL, NULL, &sres));
        fpl_chaos *c = NULL;
        CHECK_OK(fpl_chaos_create(l[r], "srkn14a6", &io, 0.0, y0 + r * 2 * N, NULL, &so, &c));
        if (!c) continue;
        CHECK_OK(fpl_integrator_restore(fpl_chaos_integrator(c), steps[r], t[r], y + r * LANE));
        CHECK_OK(fpl_chaos_restore(c, acc + r * NA));
        memcpy(cm, m1 + r * NS, sizeof cm);          /* the samples before t = 700 */
        CHECK_OK(fpl_chaos_advance(c, bo.chaos.t_end, NULL, cm, NULL, NULL));
        CHECK_OK(fpl_chaos_get_result(c, &cres));
        CHECK(cres.mle == sres.mle && cres.sali == sres.sali && cres.steps == sres.steps &&
              cres.n_samples == sres.n_samples &&
              memcmp(cm, sm, sizeof(double) * (size_t)sres.n_samples) == 0,
              "orbit %d: lane -> fpl_chaos differs from fpl_chaos_run (mle %.17g vs %.17g)", r,
              cres.mle, sres.mle);
        fpl_chaos_free(&c);
    }
    CHECK(running >= 1, "no orbit was still running at t = 700");
    fpl_chaos_batch_free(&a);
    fpl_chaos_batch_free(&b);
    for (int r = 0; r < R; r++) fpl_lattice_free(&l[r]);
}

/* The list of batch methods: every splitting scheme with the kinetic drift, in the registry's
 * order, each of which the batch kernel accepts; the refusal of another method names them. */
static void test_methods(void)
{
    static const char *const expected[] = {"leapfrog", "yoshida4", "aba864", "srkn14a6"};
    const int count = fpl_chaos_batch_method_count();
    CHECK(count == 4, "%d batch methods, expected 4", count);
    for (int i = 0; i < count && i < 4; i++) {
        const char *name = fpl_chaos_batch_method_name(i);
        CHECK(name && strcmp(name, expected[i]) == 0, "batch method %d: %s, expected %s", i,
              name ? name : "NULL", expected[i]);
    }
    CHECK(fpl_chaos_batch_method_name(count) == NULL && fpl_chaos_batch_method_name(-1) == NULL,
          "index out of range gives NULL");
    fpl_lattice *a = NULL;
    CHECK_OK(fpl_lattice_create(8, 0.25, 0.0, 1, NULL, &a));
    fpl_lattice *aa[2] = {a, a};
    for (int i = 0; i < count; i++) {
        fpl_chaos_batch_options bo;
        fpl_chaos_batch_options_init(&bo);
        bo.chaos.t_end = 1.0;
        double y0[2 * 16] = {0};
        y0[0] = 0.1;
        fpl_chaos_batch *bb = NULL;
        CHECK_OK(fpl_chaos_batch_create(aa, 2, fpl_chaos_batch_method_name(i), NULL, 0.0, y0, NULL,
                                        &bo, &bb));
        fpl_chaos_batch_free(&bb);
    }
    expect_error(aa, 2, "dprkn8", 0.01, 10.0, 1.0, "(leapfrog, yoshida4, aba864, srkn14a6)");
    fpl_lattice_free(&a);
}

int main(void)
{
    test_agreement();
    test_rings_and_toda();
    test_chaotic_orbit();
    test_early_exit();
    test_blowup();
    test_checkpoint();
    test_orbit_format();
    test_bad_input();
    test_methods();
    return check_report("chaos_batch");
}
