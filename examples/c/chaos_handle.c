/* Chaos indicators with the piecewise chaos handle: the disordered Hamiltonian lattice (model 2)
 * with yoshida4, mLE, SALI and GALI_2 at up to 40 log-spaced times (fewer when two fall on one
 * renormalisation), advanced in pieces (as a program that checkpoints or reports progress would). A regular orbit (small energy): the mLE decays
 * like ln(t)/t and SALI stays away from 0. */
#include <math.h>
#include <stdio.h>
#include <fputlab.h>

enum { N = 16, SAMPLES = 40 };

int main(void)
{
    double v[N], y0[2 * N], t[SAMPLES], mle[SAMPLES], sali[SAMPLES], gali[SAMPLES];
    fpl_lattice *lat = NULL;
    fpl_chaos *chaos = NULL;
    fpl_chaos_options opt;
    fpl_chaos_options_init(&opt);
    opt.t_end = 2000.0;
    opt.n_samples = SAMPLES;
    opt.n_dev = 2;                               /* two deviation vectors: SALI and GALI_2 */
    fpl_integrator_options iopt;
    fpl_integrator_options_init(&iopt);
    iopt.dt = 0.05;
    if (fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 7, N, v) != 0 ||
        fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_HAMILTONIAN, v, &lat) != 0 ||
        fpl_modes_initial_state(lat, 1, 0.5, y0) != 0 ||
        fpl_chaos_create(lat, "yoshida4", &iopt, 0.0, y0, NULL, &opt, &chaos) != 0) {
        fprintf(stderr, "fputlab: %s\n", fpl_last_error());
        return 1;
    }
    int st = 0;
    for (double t_next = 500.0; !fpl_chaos_done(chaos) && st >= 0; t_next += 500.0)
        st = fpl_chaos_advance(chaos, t_next, t, mle, sali, gali);
    fpl_chaos_result res;
    fpl_chaos_get_result(chaos, &res);
    for (int i = 0; i < res.n_samples; i += 8)
        printf("t = %8.1f  mLE = %.3e  SALI = %.3f  GALI_2 = %.3f\n", t[i], mle[i], sali[i],
               gali[i]);
    printf("final: t = %g, %d samples, mLE = %.3e (ln(t)/t = %.3e), SALI = %.3f, chaotic %d, "
           "status %d\n", res.t_final, res.n_samples, res.mle, log(res.t_final) / res.t_final,
           res.sali, res.chaotic, st);
    fpl_chaos_free(&chaos);
    fpl_lattice_free(&lat);
    return st < 0 || res.n_samples < SAMPLES / 2 || res.chaotic || !(res.mle < 0.05) ||
           !(res.sali > 1e-3);
}
