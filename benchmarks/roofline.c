/* The force kernel against a plain-C roofline (issue 15, "On the old target of the integrator
 * issue": the kernel within 1.5x of the plain-C roofline).
 *
 * One Yoshida 4 step (drifts w1/2, (w0+w1)/2, (w0+w1)/2, w1/2; kicks w1, w0, w1) of the
 * homogeneous FPUT-alpha chain (alpha = 0.25, fixed ends) with 2 deviation vectors, three ways:
 *   fputlab   fpl_splitting_advance("yoshida4") (the library's kernel, target_clones AVX2/SSE2)
 *   plain C   a minimal hand-written step in the same layout: one loop per drift over all
 *             vectors, one fused loop per kick computing the orbit force and both tangent forces
 *             from the neighbours (no temporaries), boundaries peeled; compiled here
 *             with the flags given on the command line (see roofline.sh)
 *   bandwidth at large N, the time the memory system needs for the step's compulsory traffic:
 *             every drift and every kick streams each vector's x and p once (read x, read p,
 *             write one of them: 24 bytes per particle and vector), 7 passes per step, at the
 *             bandwidth of the drift loop itself measured on arrays of the same size (so the
 *             bound is what a streaming pass achieves here, not a data-sheet number)
 * Cost = process CPU time per particle-step (ns), best of --repeats repeats, all variants
 * interleaved in each repeat (the machine is shared). The plain step is checked against
 * fputlab's to round-off first. Usage: roofline [repeats]. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "fputlab.h"

#define ALPHA 0.25
#define NDEV 2
#define CBRT2 1.2599210498948731647672106072782283505702514647015
#define W1 (1.0 / (2.0 - CBRT2))
#define W0 (-CBRT2 / (2.0 - CBRT2))

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* x += h p for the orbit and each deviation vector (layout [x p] per vector). */
static void plain_drift(int n, double *restrict y, double h)
{
    for (int v = 0; v <= NDEV; v++) {
        double *restrict x = y + 2 * (size_t)n * v;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++) x[i] += h * p[i];
    }
}

/* p_i += h (phi(d_{i+1}) - phi(d_i)), phi(d) = d + a d^2, d_i = x_i - x_{i-1} (x_0 = x_{n+1} = 0);
 * dp_i += h (k_{i+1} dd_{i+1} - k_i dd_i), k = 1 + 2 a d: all three vectors in one loop. */
static inline void kick_at(int i, double xl, double xc, double xr, const double *y, int n,
                           double *y_out, double h)
{
    const double dl = xc - xl, dr = xr - xc;
    y_out[n + i] += h * ((dr + ALPHA * dr * dr) - (dl + ALPHA * dl * dl));
    const double kl = 1.0 + 2.0 * ALPHA * dl, kr = 1.0 + 2.0 * ALPHA * dr;
    for (int v = 1; v <= NDEV; v++) {
        const double *w = y + 2 * (size_t)n * v;
        const double wl = i > 0 ? w[i - 1] : 0.0, wr = i < n - 1 ? w[i + 1] : 0.0;
        y_out[2 * (size_t)n * v + n + i] += h * (kr * (wr - w[i]) - kl * (w[i] - wl));
    }
}

/* The interior particles, written out for the orbit and both vectors (what one writes by hand). */
static void kick_interior(int n, const double *restrict x, double *restrict p,
                          const double *restrict w1, double *restrict q1,
                          const double *restrict w2, double *restrict q2, double h)
{
    for (int i = 1; i < n - 1; i++) {
        const double dl = x[i] - x[i - 1], dr = x[i + 1] - x[i];
        p[i] += h * ((dr + ALPHA * dr * dr) - (dl + ALPHA * dl * dl));
        const double kl = 1.0 + 2.0 * ALPHA * dl, kr = 1.0 + 2.0 * ALPHA * dr;
        q1[i] += h * (kr * (w1[i + 1] - w1[i]) - kl * (w1[i] - w1[i - 1]));
        q2[i] += h * (kr * (w2[i + 1] - w2[i]) - kl * (w2[i] - w2[i - 1]));
    }
}

static void plain_kick(int n, double *y, double h)
{
    kick_at(0, 0.0, y[0], y[1], y, n, y, h);
    kick_interior(n, y, y + n, y + 2 * (size_t)n, y + 3 * (size_t)n, y + 4 * (size_t)n,
                  y + 5 * (size_t)n, h);
    kick_at(n - 1, y[n - 2], y[n - 1], 0.0, y, n, y, h);
}

static void plain_yoshida4(int n, double *y, double dt, long steps)
{
    for (long s = 0; s < steps; s++) {
        plain_drift(n, y, 0.5 * W1 * dt);
        plain_kick(n, y, W1 * dt);
        plain_drift(n, y, 0.5 * (W0 + W1) * dt);
        plain_kick(n, y, W0 * dt);
        plain_drift(n, y, 0.5 * (W0 + W1) * dt);
        plain_kick(n, y, W1 * dt);
        plain_drift(n, y, 0.5 * W1 * dt);
    }
}

static void initial(int n, double *y)
{
    for (int j = 0; j < n; j++) {
        y[j] = sin(3.14159265358979323846 * (j + 1) / (n + 1));
        y[n + j] = 0.0;
    }
    for (long i = 2L * n; i < 2L * n * (NDEV + 1); i++) y[i] = 0.1 * sin(0.37 * (double)i);
}

/* Bandwidth of the drift loop (24 bytes per element: read x, p; write x), bytes/s. */
static double drift_seconds(int n, double *y, long reps)
{
    const double t0 = cpu_now();
    for (long r = 0; r < reps; r++) plain_drift(n, y, 1e-12);
    return cpu_now() - t0;
}

int main(int argc, char **argv)
{
    const int repeats = argc > 1 ? atoi(argv[1]) : 7;
    const int sizes[] = {64, 512, 4096, 32768, 1 << 22};
    const fpl_splitting *yo = NULL;
    if (fpl_splitting_lookup("yoshida4", &yo)) return 1;
    printf("%8s %10s %14s %14s %14s %9s %9s\n", "N", "steps", "fputlab", "plain C",
           "bandwidth", "fpl/plain", "fpl/bw");
    printf("%8s %10s %14s %14s %14s\n", "", "", "[ns/(p*step)]", "[ns/(p*step)]",
           "[ns/(p*step)]");
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        const int n = sizes[k];
        const long len = 2L * n * (NDEV + 1);
        /* ~0.05 s of work per timing at ~2 ns per particle-step */
        long steps = (long)(2.5e7 / n);
        if (steps < 2) steps = 2;
        double *a = malloc(sizeof(double) * (size_t)len), *b = malloc(sizeof(double) * (size_t)len);
        fpl_lattice *lat = NULL;
        if (!a || !b || fpl_lattice_create(n, ALPHA, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &lat)) {
            fprintf(stderr, "set-up failed at N = %d\n", n);
            return 1;
        }
        /* same step, same result (round-off apart): the plain loop is the same computation */
        initial(n, a);
        initial(n, b);
        if (fpl_splitting_advance(yo, lat, a, NDEV, 0.01, 3)) return 1;
        plain_yoshida4(n, b, 0.01, 3);
        double diff = 0.0;
        for (long i = 0; i < len; i++) diff = fmax(diff, fabs(a[i] - b[i]));
        if (diff > 1e-12) {
            fprintf(stderr, "N = %d: plain step differs from fputlab's by %.2e\n", n, diff);
            return 1;
        }
        double best_f = INFINITY, best_p = INFINITY, best_bw = INFINITY;
        for (int r = 0; r < repeats; r++) {
            double t0 = cpu_now();
            fpl_splitting_advance(yo, lat, a, NDEV, 0.01, steps);
            best_f = fmin(best_f, (cpu_now() - t0) / ((double)steps * n));
            t0 = cpu_now();
            plain_yoshida4(n, b, 0.01, steps);
            best_p = fmin(best_p, (cpu_now() - t0) / ((double)steps * n));
            /* 7 streaming passes per step over 3 vectors at the drift loop's bandwidth */
            const double t = drift_seconds(n, b, 7 * steps) / (7.0 * (double)steps);
            best_bw = fmin(best_bw, 7.0 * t / n);
        }
        const double bw = 24.0 * (NDEV + 1) * 7.0 / best_bw; /* bytes/s of the drift loop */
        printf("%8d %10ld %14.3f %14.3f %14.3f %9.2f %9.2f   (drift loop %.1f GB/s)\n", n, steps,
               best_f * 1e9, best_p * 1e9, best_bw * 1e9, best_f / best_p, best_f / best_bw,
               bw / 1e9);
        fflush(stdout);
        fpl_lattice_free(&lat);
        free(a);
        free(b);
    }
    return 0;
}
