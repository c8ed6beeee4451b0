/* A run written to an HDF5 results file as it goes (samples of time, mode energies and energy;
 * schema in docs/hdf5.md): the FPUT recurrence of the homogeneous chain, mode 1 excited,
 * yoshida4 at dt = 0.01, a sample every 10 time units. Usage: results_hdf5 [FILE]
 * (default fpl_example_results.h5). Read it with h5dump, h5py or fputlab.io. */
#include <stdio.h>
#include <fputlab.h>

enum { N = 32 };

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "fpl_example_results.h5";
    double y[2 * N];
    fpl_lattice *lat = NULL;
    fpl_integrator *integ = NULL;
    fpl_results *res = NULL;
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);          /* dt = 0.01 */
    fpl_run_info info;
    fpl_run_info_init(&info);
    info.method = "yoshida4";
    info.dt = opt.dt;
    if (fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat) != 0 ||
        fpl_modes_initial_state(lat, 1, 1.0, y) != 0 ||
        fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y, &integ) != 0 ||
        fpl_results_create(path, lat, &info, &res) != 0) {
        fprintf(stderr, "fputlab: %s\n", fpl_last_error());
        return 1;
    }
    int st = fpl_results_append(res, 0.0, y);
    for (int k = 1; k <= 100 && st == 0; k++) {
        st = fpl_integrator_advance(integ, 10.0 * k, y);
        if (st == 0) st = fpl_results_append(res, 10.0 * k, y);
    }
    if (st != 0) fprintf(stderr, "fputlab: %s\n", fpl_last_error());
    fpl_results_set_status(res, st == 0 ? "completed" : "failed", st == 0 ? "" : fpl_last_error());
    long rows = fpl_results_count(res);
    int closed = fpl_results_close(&res);
    printf("%s: %ld samples to t = %g, status %d, close %d\n", path, rows,
           fpl_integrator_time(integ), st, closed);
    fpl_integrator_free(&integ);
    fpl_lattice_free(&lat);
    return st != 0 || closed != 0 || rows != 101;
}
