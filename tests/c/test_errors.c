/* Bad input: every invalid parameter gives an error status and a message naming it. */
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
    CHECK(strstr(fpl_lattice_errmsg(lat), "x[1]") != NULL, "handle message: %s",
          fpl_lattice_errmsg(lat));
    EXPECT_ERR(fpl_lattice_energy(lat, y, out), FPL_ERR_ARG, "y[1]");
    y[1] = 0.0;
    EXPECT_ERR(fpl_lattice_rhs(lat, y, -1, out), FPL_ERR_ARG, "n_dev");
    CHECK_OK(fpl_lattice_force(lat, y, out));
    CHECK(fpl_lattice_errmsg(lat)[0] == '\0', "message cleared by a successful call");
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
    double ts[3] = {1.0, 0.5, 2.0}, ek[12];
    int done = -1;
    EXPECT_ERR(fpl_splitting_run(s, lat, y, 0.0, 0.01, ts, 3, ek, NULL, NULL, &done), FPL_ERR_ARG,
               "t_samples[1]");
    CHECK(done == 0, "nothing done");
    ts[1] = 1.5;
    EXPECT_ERR(fpl_splitting_run(s, lat, y, 2.0, 0.01, ts, 3, ek, NULL, NULL, &done), FPL_ERR_ARG,
               "t_samples[0]");
    EXPECT_ERR(fpl_splitting_run(s, lat, y, NAN, 0.01, ts, 3, ek, NULL, NULL, &done), FPL_ERR_ARG,
               "t0");

    /* a run that blows up ends cleanly, says when, and leaves only finite samples */
    double big[8];
    CHECK_OK(fpl_modes_initial_state(lat, 1, 30.0, big)); /* far beyond the cubic barrier */
    double tb[50], eb[50 * 4], en[50];
    for (int i = 0; i < 50; i++) tb[i] = 0.5 * (i + 1);
    for (int i = 0; i < 50 * 4; i++) eb[i] = -1.0;
    int st = fpl_splitting_run(s, lat, big, 0.0, 0.01, tb, 50, eb, en, NULL, &done);
    CHECK(st == FPL_ERR_NONFINITE, "blow-up status %d", st);
    CHECK(strstr(fpl_lattice_errmsg(lat), "between t =") != NULL, "blow-up message: %s",
          fpl_lattice_errmsg(lat));
    CHECK(done < 50, "stopped early (%d samples)", done);
    for (int i = 0; i < done * 4; i++) CHECK(isfinite(eb[i]), "sample %d not finite", i);
    fpl_lattice_free(&lat);
    fpl_lattice_free(&lat); /* double free of a cleared handle is harmless */
    fpl_lattice_free(NULL);
    return check_report("errors");
}
