/* Bad input: every invalid parameter gives an error status and a message naming it. */
#include <limits.h>
#include <string.h>
#include "check.h"
#include "fputlab.h"

#define EXPECT_ERR(call, code, word)                                                           \
    do {                                                                                       \
        int st_ = (call);                                                                      \
        CHECK(st_ == (code), "%s returned %d, expected %d", #call, st_, (code));               \
        CHECK(strstr(fpl_last_error(), (word)) != NULL, "%s: message '%s' lacks '%s'", #call,  \
              fpl_last_error(), (word));                                                       \
    } while (0)

int main(void)
{
    fpl_lattice *lat = NULL;
    double v[4] = {1, 1, 1, 1}, y[8] = {0}, out[8];
    EXPECT_ERR(fpl_lattice_create(1, 0.25, 0.0, 1, NULL, &lat), FPL_ERR_ARG, "N");
    CHECK(lat == NULL, "no handle on failure");
    EXPECT_ERR(fpl_lattice_create(-5, 0.25, 0.0, 1, NULL, &lat), FPL_ERR_ARG, "N");
    EXPECT_ERR(fpl_lattice_create(4, NAN, 0.0, 1, NULL, &lat), FPL_ERR_ARG, "alpha");
    EXPECT_ERR(fpl_lattice_create(4, INFINITY, 0.0, 1, NULL, &lat), FPL_ERR_ARG, "alpha");
    EXPECT_ERR(fpl_lattice_create(4, 0.25, NAN, 1, NULL, &lat), FPL_ERR_ARG, "beta");
    EXPECT_ERR(fpl_lattice_create(4, 0.25, 0.0, 7, NULL, &lat), FPL_ERR_UNKNOWN, "model");
    v[2] = -0.1;
    EXPECT_ERR(fpl_lattice_create(4, 0.25, 0.0, 2, v, &lat), FPL_ERR_ARG, "v[2]");
    v[2] = NAN;
    EXPECT_ERR(fpl_lattice_create(4, 0.25, 0.0, 3, v, &lat), FPL_ERR_ARG, "v[2]");
    EXPECT_ERR(fpl_lattice_create(4, 0.25, 0.0, 1, NULL, NULL), FPL_ERR_ARG, "out");

    EXPECT_ERR(fpl_disorder_draw(0, -1.0, 1, 4, v), FPL_ERR_ARG, "tau");
    EXPECT_ERR(fpl_disorder_draw(0, NAN, 1, 4, v), FPL_ERR_ARG, "tau");
    EXPECT_ERR(fpl_disorder_draw(2, 100.0, 1, 4, v), FPL_ERR_ARG, "tau");
    EXPECT_ERR(fpl_disorder_draw(9, 10.0, 1, 4, v), FPL_ERR_UNKNOWN, "disorder kind");
    EXPECT_ERR(fpl_disorder_draw(0, 10.0, 1, 0, v), FPL_ERR_ARG, "N");
    EXPECT_ERR(fpl_modes_omega(1, out), FPL_ERR_ARG, "N");

    CHECK_OK(fpl_lattice_create(4, 0.25, 0.0, 1, NULL, &lat));
    y[1] = NAN;
    EXPECT_ERR(fpl_lattice_force(lat, y, out), FPL_ERR_ARG, "x[1]");
    /* a lattice is shared and read-only: its "handle message" is this thread's last error */
    CHECK(strstr(fpl_lattice_errmsg(lat), "x[1]") != NULL, "handle message: %s",
          fpl_lattice_errmsg(lat));
    CHECK(strcmp(fpl_lattice_errmsg(lat), fpl_last_error()) == 0, "lattice message = last error");
    EXPECT_ERR(fpl_lattice_energy(lat, y, out), FPL_ERR_ARG, "y[1]");
    y[1] = 0.0;
    EXPECT_ERR(fpl_lattice_rhs(lat, y, -1, out), FPL_ERR_ARG, "n_dev");
    CHECK_OK(fpl_lattice_force(lat, y, out));
    EXPECT_ERR(fpl_modes_initial_state(lat, 0, 1.0, y), FPL_ERR_ARG, "mode k");
    EXPECT_ERR(fpl_modes_initial_state(lat, 5, 1.0, y), FPL_ERR_ARG, "mode k");
    EXPECT_ERR(fpl_modes_initial_state(lat, 1, NAN, y), FPL_ERR_ARG, "amplitude");

    const fpl_splitting *s = NULL;
    EXPECT_ERR(fpl_splitting_lookup("rk4-magic", &s), FPL_ERR_UNKNOWN, "rk4-magic");
    CHECK(strstr(fpl_last_error(), "yoshida4") != NULL, "lists the known methods");
    CHECK_OK(fpl_splitting_lookup("yoshida4", &s));
    CHECK_OK(fpl_modes_initial_state(lat, 1, 1.0, y));
    EXPECT_ERR(fpl_splitting_advance(s, lat, y, 0, 0.0, 10), FPL_ERR_ARG, "dt");
    EXPECT_ERR(fpl_splitting_advance(s, lat, y, 0, -0.1, 10), FPL_ERR_ARG, "dt");
    EXPECT_ERR(fpl_splitting_advance(s, lat, y, 0, NAN, 10), FPL_ERR_ARG, "dt");
    EXPECT_ERR(fpl_splitting_advance(s, lat, y, 0, 0.01, -3), FPL_ERR_ARG, "nsteps");
    fpl_integrator *h = NULL;
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    EXPECT_ERR(fpl_integrator_create(lat, "rk4-magic", 0, &opt, 0.0, y, &h), FPL_ERR_UNKNOWN,
               "rk4-magic");
    CHECK(h == NULL, "no handle on failure");
    EXPECT_ERR(fpl_integrator_create(lat, "yoshida4", -1, &opt, 0.0, y, &h), FPL_ERR_ARG, "n_dev");
    EXPECT_ERR(fpl_integrator_create(lat, "yoshida4", 0, &opt, NAN, y, &h), FPL_ERR_ARG, "t0");
    opt.dt = 0.0;
    EXPECT_ERR(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y, &h), FPL_ERR_ARG, "dt");
    opt.dt = -1.0;
    EXPECT_ERR(fpl_integrator_create(lat, "leapfrog", 0, &opt, 0.0, y, &h), FPL_ERR_ARG, "dt");
    opt.dt = 0.01;
    y[3] = INFINITY;
    EXPECT_ERR(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y, &h), FPL_ERR_ARG, "y0[3]");
    y[3] = 0.0;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y, &h));
    double ts[3] = {1.0, 0.5, 2.0}, ek[12];
    int done = -1;
    EXPECT_ERR(fpl_integrator_sample(h, ts, 3, NULL, ek, NULL, &done), FPL_ERR_ARG, "t_samples[1]");
    CHECK(done == 0, "nothing done");
    CHECK(strstr(fpl_integrator_errmsg(h), "t_samples[1]") != NULL, "handle message");
    CHECK_OK(fpl_integrator_advance(h, 3.0, NULL));
    EXPECT_ERR(fpl_integrator_advance(h, 2.0, NULL), FPL_ERR_ARG, "t_target");
    EXPECT_ERR(fpl_integrator_advance(h, NAN, NULL), FPL_ERR_ARG, "t_target");
    fpl_integrator_free(&h);
    CHECK(h == NULL, "free clears the handle");

    /* a run that blows up ends cleanly, says when, keeps the last finite state, and leaves only
     * finite samples */
    double big[8];
    CHECK_OK(fpl_modes_initial_state(lat, 1, 30.0, big)); /* far beyond the cubic barrier */
    double tb[50], eb[50 * 4], en[50];
    for (int i = 0; i < 50; i++) tb[i] = 0.5 * (i + 1);
    for (int i = 0; i < 50 * 4; i++) eb[i] = -1.0;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, big, &h));
    int st = fpl_integrator_sample(h, tb, 50, NULL, eb, en, &done);
    CHECK(st == FPL_ERR_NONFINITE, "blow-up status %d", st);
    CHECK(strstr(fpl_integrator_errmsg(h), "between t =") != NULL, "blow-up message: %s",
          fpl_integrator_errmsg(h));
    CHECK(done < 50, "stopped early (%d samples)", done);
    for (int i = 0; i < done * 4; i++) CHECK(isfinite(eb[i]), "sample %d not finite", i);
    double last[8];
    CHECK_OK(fpl_integrator_get_state(h, last));
    for (int i = 0; i < 8; i++) CHECK(isfinite(last[i]), "last state not finite");
    fpl_integrator_free(&h);

    /* sizes: products that would overflow or cannot fit in memory are refused with a status,
     * before anything is read or allocated (INT_MAX sites stalled in calloc until the OOM
     * killer; n_dev = INT_MAX overflowed n_dev + 1 and dim^2 and crashed) */
    fpl_lattice *huge = NULL;
    EXPECT_ERR(fpl_lattice_create(INT_MAX, 0.25, 0.0, 1, NULL, &huge), FPL_ERR_NOMEM, "lattice");
    CHECK(huge == NULL, "no handle for a lattice that cannot fit");
    double jac[64];
    EXPECT_ERR(fpl_lattice_jacobian_dense(lat, y, INT_MAX, jac), FPL_ERR_NOMEM, "n_dev");
    EXPECT_ERR(fpl_lattice_jacobian_dense(lat, y, 1 << 16, jac), FPL_ERR_NOMEM, "Jacobian");
    EXPECT_ERR(fpl_lattice_rhs(lat, y, INT_MAX, out), FPL_ERR_NOMEM, "n_dev");
    EXPECT_ERR(fpl_lattice_tangent_force(lat, y, INT_MAX, y, out), FPL_ERR_NOMEM, "n_dev");
    EXPECT_ERR(fpl_integrator_create(lat, "yoshida4", INT_MAX, &opt, 0.0, y, &h), FPL_ERR_NOMEM,
               "n_dev");
    CHECK(h == NULL, "no integrator for an impossible state size");
    EXPECT_ERR(fpl_splitting_advance(s, lat, y, INT_MAX, 0.01, 1), FPL_ERR_NOMEM, "n_dev");
    fpl_run_info ri;
    fpl_run_info_init(&ri);
    ri.n_dev = INT_MAX;
    fpl_results *res = NULL;
    EXPECT_ERR(fpl_results_create("never-written.h5", lat, &ri, &res), FPL_ERR_NOMEM, "n_dev");
    CHECK(res == NULL, "no results handle");
    double w[8 * 4];
    EXPECT_ERR(fpl_chaos_gali(w, INT_MAX, 1L << 40, out), FPL_ERR_NOMEM, "GALI");
    fpl_lattice_free(&lat);
    fpl_lattice_free(&lat); /* double free of a cleared handle is harmless */
    fpl_lattice_free(NULL);
    return check_report("errors");
}
