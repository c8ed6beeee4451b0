/* Count heap allocations inside fpl_integrator_advance (the hot loop) and, for information,
 * inside fpl_integrator_sample, for every method fpl_method_name() lists and every model, with
 * 2 deviation vectors. Needs the malloc-counting shim (malloc_count.c) preloaded:
 *
 *   LD_PRELOAD=./libmalloc_count.so ./alloc_check [N]
 *
 * Output, one line per (phase, method, model), for benchmarks/run.py to parse (phase "create" is
 * the positive control: creating an integrator must show allocations, proving the shim counts):
 *   alloc <phase> <method> <model> adaptive=<0|1> status=<int> allocs=<n> frees=<n> bytes=<n> steps=<n>
 * The integrator is created and advanced once (t = 0 -> 1) before counting, so one-time set-up
 * (work arrays, SUNDIALS/GSL memory) is not counted; only the steady-state loop is. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <fputlab.h>

typedef void (*start_fn)(void);
typedef void (*stop_fn)(long *, long *, long *);

int main(int argc, char **argv)
{
    start_fn count_start = (start_fn)dlsym(RTLD_DEFAULT, "malloc_count_start");
    stop_fn count_stop = (stop_fn)dlsym(RTLD_DEFAULT, "malloc_count_stop");
    if (!count_start || !count_stop) {
        fprintf(stderr, "alloc_check: the malloc-counting shim is not loaded (LD_PRELOAD)\n");
        return 2;
    }
    const int n = argc > 1 ? atoi(argv[1]) : 64;
    const int n_dev = 2;
    if (n < 2) return 2;
    const long dim = 2L * n * (1 + n_dev);
    double *y0 = malloc(sizeof(double) * (size_t)dim);
    double *y = malloc(sizeof(double) * (size_t)dim);
    double *v = malloc(sizeof(double) * (size_t)n);
    double *ek = malloc(sizeof(double) * 10 * (size_t)n);
    double en[10], ts[10];
    if (!y0 || !y || !v || !ek) return 2;

    /* orbit: x_j = sin(pi j/(N+1)), p = 0; deviation vectors: fixed pseudo-random unit vectors */
    unsigned long long s = 12345;
    for (int j = 0; j < n; j++) {
        y0[j] = sin(M_PI * (j + 1) / (n + 1));
        y0[n + j] = 0.0;
    }
    for (int m = 1; m <= n_dev; m++) {
        double *w = y0 + 2L * n * m, norm = 0.0;
        for (long i = 0; i < 2L * n; i++) {
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            w[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
            norm += w[i] * w[i];
        }
        for (long i = 0; i < 2L * n; i++) w[i] /= sqrt(norm);
    }

    static const int models[] = {FPL_MODEL_HOMOGENEOUS, FPL_MODEL_HAMILTONIAN, FPL_MODEL_NONLINEAR};
    int failures = 0;
    for (int k = 0; k < fpl_method_count(); k++) {
        const char *method = fpl_method_name(k);
        int order = 0, adaptive = 0;
        fpl_method_info(method, &order, &adaptive);
        for (int im = 0; im < 3; im++) {
            const int model = models[im];
            fpl_lattice *lat = NULL;
            if (model != FPL_MODEL_HOMOGENEOUS) fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 1, n, v);
            if (fpl_lattice_create(n, 0.25, 0.0, model, model == FPL_MODEL_HOMOGENEOUS ? NULL : v,
                                   &lat) != 0) {
                fprintf(stderr, "lattice: %s\n", fpl_last_error());
                failures++;
                continue;
            }
            fpl_integrator_options opt;
            fpl_integrator_options_init(&opt);
            if (adaptive) {
                opt.dt = 0.0;
                opt.rtol = opt.atol = 1e-8;
            } else {
                opt.dt = 0.01;
            }
            fpl_integrator *h = NULL;
            long a = 0, f = 0, b = 0, steps0 = 0, steps1 = 0, fe = 0;
            /* positive control: creating the integrator does allocate, so the shim must see it */
            count_start();
            int st = fpl_integrator_create(lat, method, n_dev, &opt, 0.0, y0, &h);
            count_stop(&a, &f, &b);
            printf("alloc create %s %s adaptive=%d status=%d allocs=%ld frees=%ld bytes=%ld "
                   "steps=0\n", method, fpl_model_name(model), adaptive, st, a, f, b);
            if (st == FPL_ERR_ARG) {
                /* the method does not apply to this model (aba864-harmonic on model 2) */
                printf("alloc refused %s %s adaptive=%d status=%d allocs=0 frees=0 bytes=0 "
                       "steps=0\n", method, fpl_model_name(model), adaptive, st);
                fpl_lattice_free(&lat);
                continue;
            }
            if (st == 0) st = fpl_integrator_advance(h, 1.0, y); /* warm-up, not counted */
            if (st != 0) {
                printf("alloc advance %s %s adaptive=%d status=%d allocs=-1 frees=-1 bytes=-1 "
                       "steps=0 error=%s\n", method, fpl_model_name(model), adaptive, st,
                       fpl_last_error());
                fpl_integrator_free(&h);
                fpl_lattice_free(&lat);
                continue;
            }
            fpl_integrator_counters(h, &steps0, &fe);
            count_start();
            st = fpl_integrator_advance(h, 51.0, y);
            count_stop(&a, &f, &b);
            fpl_integrator_counters(h, &steps1, &fe);
            printf("alloc advance %s %s adaptive=%d status=%d allocs=%ld frees=%ld bytes=%ld "
                   "steps=%ld\n", method, fpl_model_name(model), adaptive, st, a, f, b,
                   steps1 - steps0);
            for (int i = 0; i < 10; i++) ts[i] = 52.0 + 1.5 * i;
            int done = 0;
            count_start();
            st = fpl_integrator_sample(h, ts, 10, NULL, ek, en, &done);
            count_stop(&a, &f, &b);
            printf("alloc sample %s %s adaptive=%d status=%d allocs=%ld frees=%ld bytes=%ld "
                   "steps=%d\n", method, fpl_model_name(model), adaptive, st, a, f, b, done);
            fflush(stdout);
            fpl_integrator_free(&h);
            fpl_lattice_free(&lat);
        }
    }
    free(y0);
    free(y);
    free(v);
    free(ek);
    return failures ? 1 : 0;
}
