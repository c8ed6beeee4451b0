/* Every model's kernel against a hand-fused plain-C loop of the same model and against the
 * memory bandwidth (issue 15's roofline, extended for issue 22).
 *
 * One Yoshida 4 step (drifts w1/2, (w0+w1)/2, (w0+w1)/2, w1/2; kicks w1, w0, w1) of the FPUT-alpha
 * chain (alpha = 0.25, beta = 0, fixed ends), for model 1 (homogeneous), 2 (hamiltonian: cl = cn
 * = s = v, minv = 1/v) and 3 (nonlinear: cn = v) with v_j spread over [0.9, 1.1] (the paper's
 * tau = 10 %; model 3 is not conservative and runs away with much more), with k deviation
 * vectors (0, 1, 2, 6 and 2N where the state fits in 16 MB), timed three ways:
 *   fputlab   fpl_splitting_advance("yoshida4"): the model's fused stepper (target_clones
 *             AVX2/SSE2)
 *   plain C   a minimal hand-written step of the same model in the same layout: one loop per
 *             drift over all vectors; per kick one loop that forms each particle's two bonds
 *             (phi, kappa and the tangent bond forces) from the neighbours without temporaries,
 *             the orbit and up to two vectors together (k > 2: the orbit loop stores kappa, then
 *             one loop per vector), boundaries peeled; compiled here with the flags given on the
 *             command line (see roofline.sh)
 *   bound     the step's compulsory memory traffic (bytes counted below) at the bandwidth of a
 *             STREAM-like triad a = b + s c measured in the same run on 3 x 64 MB (24 bytes per
 *             element; out of cache this is the time the memory system needs, in cache it is no
 *             bound, only a scale)
 * Bytes per particle-step counted: a drift reads x, p and writes x of each vector (24 bytes; model
 * 2 also reads minv: + 8); a kick reads x, reads and writes p (24) and the same for each vector
 * (24 each), plus the coefficient arrays it streams (model 2: cn, s; model 3: cn). Yoshida 4 = 4
 * drifts + 3 kicks: model 1 with 2 vectors 504 bytes, model 3 528, model 2 576.
 * fputlab's own step with up to 2 vectors is fused further (each stage's drift and kick one pass
 * over the state, a step's last drift in the next step's first pass): 3 passes reading and
 * writing x, p of each vector (32 bytes each) and reading the coefficients (model 2: minv, cn, s;
 * model 3: cn), model 1 with 2 vectors 288 bytes, model 3 312, model 2 360 (column "fpl B",
 * "fpl/fbnd" = fputlab against that traffic at the triad bandwidth). Chains of N > 1024 with 3 or
 * more vectors (and with 1 or 2 where the state exceeds 10 MiB) take sweeps of 10 steps, the
 * chain block by block: one such pass per 10 steps.
 * Cost = process CPU time per particle-step (ns), best of the repeats (at least 10 steps each),
 * fputlab and plain C
 * interleaved in each repeat (the machine is shared). The plain step is checked against
 * fputlab's to round-off first. Also printed: fputlab against model 1 at the same N and k, and
 * the cost of one extra deviation vector in orbit steps, (t(k) - t(0)) / (k t(0)).
 * With "ring" the periodic chains instead (bond 0 joining particles N-1 and 0; the plain step's
 * two end particles take that bond, its interior is the fixed chain's), each timed against its
 * plain-C ring step and against fputlab's fixed chain of the same model, N and k, the three
 * interleaved ("ring/fix"; the bytes are the fixed chain's).
 * Model 4, the Toda lattice (V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2), fixed ends), is
 * timed the same way against its own plain loop (plain_toda_kick: per kick one loop forming each
 * bond's V' and V'' from one fpl_expm1, the library's e^x - 1, into two scratch arrays, then one
 * loop kicking the orbit and up to two vectors), its bytes counted as model 1's (the scratch
 * arrays, in cache at every N here, not counted).
 * Usage: roofline [repeats] [max_N] [min_N] [fixed|ring] [models, e.g. 14] (the last two in
 * either order; the rings: models 1-3). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "fputlab.h"
#include "../csrc/fpl_expm1.h"

#define ALPHA 0.25
#define CBRT2 1.2599210498948731647672106072782283505702514647015
#define W1 (1.0 / (2.0 - CBRT2))
#define W0 (-CBRT2 / (2.0 - CBRT2))

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The model's coefficients (as the library's model table sets them). */
typedef struct coef {
    double *cn, *s, *minv;
} coef;

/* x += h minv p for the orbit and each deviation vector (layout [x p] per vector). */
static inline void plain_drift(int model, int n, int k, double *restrict y, const coef *c,
                               double h)
{
    for (int v = 0; v <= k; v++) {
        double *restrict x = y + 2 * (size_t)n * v;
        const double *restrict p = x + n;
        if (model == 2)
            for (int i = 0; i < n; i++) x[i] += h * c->minv[i] * p[i];
        else
            for (int i = 0; i < n; i++) x[i] += h * p[i];
    }
}

/* Bond j (particles j-1, j; 0 beyond the walls) of vector u: linear and nonlinear stretch. */
static inline void stretch(int model, const double *u, const double *cn, int n, int j,
                           double *L, double *R)
{
    const double ur = j < n ? u[j] : 0.0, ul = j > 0 ? u[j - 1] : 0.0;
    const double cr = j < n ? cn[j] : 0.0, cl = j > 0 ? cn[j - 1] : 0.0;
    if (model == 1) {
        *L = *R = ur - ul;
    } else {
        *R = cr * ur - cl * ul;
        *L = model == 2 ? *R : ur - ul;
    }
}

/* The ring's bond j (particles j-1 and j mod N: bonds 0 and N both the wrap-around bond). */
static inline void stretch_ring(int model, const double *u, const double *cn, int n, int j,
                                double *L, double *R)
{
    const int r = j % n, l = (j + n - 1) % n;
    if (model == 1) {
        *L = *R = u[r] - u[l];
    } else {
        *R = cn[r] * u[r] - cn[l] * u[l];
        *L = model == 2 ? *R : u[r] - u[l];
    }
}

/* One particle next to a wall (i = 0 or n-1; on the ring: next to the wrap-around bond), every
 * vector: written plainly. */
static void plain_kick_end(int model, int ring, int n, int k, double *y, const coef *c, double h,
                           int i)
{
    void (*const bond)(int, const double *, const double *, int, int, double *, double *) =
        ring ? stretch_ring : stretch;
    double Ll, Rl, Lr, Rr;
    bond(model, y, c->cn, n, i, &Ll, &Rl);
    bond(model, y, c->cn, n, i + 1, &Lr, &Rr);
    const double sc = model == 2 ? h * c->s[i] : h;
    y[n + i] += sc * ((Lr + ALPHA * Rr * Rr) - (Ll + ALPHA * Rl * Rl));
    /* model 1: kappa includes the linear 1 and L = R */
    const double kl = (model == 1) + 2.0 * ALPHA * Rl, kr = (model == 1) + 2.0 * ALPHA * Rr;
    for (int v = 1; v <= k; v++) {
        double *w = y + 2 * (size_t)n * v;
        double dLl, dRl, dLr, dRr;
        bond(model, w, c->cn, n, i, &dLl, &dRl);
        bond(model, w, c->cn, n, i + 1, &dLr, &dRr);
        if (model == 1)
            w[n + i] += sc * (kr * dRr - kl * dRl);
        else
            w[n + i] += sc * ((dLr + kr * dRr) - (dLl + kl * dRl));
    }
}

/* Particle i's tangent kick of vector d (into o) from the curvatures kl, kr of its bonds. */
#define TANGENT_AT(d, o)                                                                    \
    do {                                                                                    \
        if (model == 1) {                                                                   \
            (o)[i] += sc * (kr * ((d)[i + 1] - (d)[i]) - kl * ((d)[i] - (d)[i - 1]));       \
        } else {                                                                            \
            const double dRl = cn[i] * (d)[i] - cn[i - 1] * (d)[i - 1];                     \
            const double dRr = cn[i + 1] * (d)[i + 1] - cn[i] * (d)[i];                     \
            const double dLl = model == 2 ? dRl : (d)[i] - (d)[i - 1];                      \
            const double dLr = model == 2 ? dRr : (d)[i + 1] - (d)[i];                      \
            (o)[i] += sc * ((dLr + kr * dRr) - (dLl + kl * dRl));                           \
        }                                                                                   \
    } while (0)

/* Interior particles: the orbit and nv = 0, 1 or 2 vectors (u, q), (w, r) in one loop (nv a
 * constant at each call); with kap (k > 2) the orbit only, kappa of the left bond stored. */
static inline void plain_kick_interior(int model, int n, int nv, const double *restrict x,
                                       double *restrict p, const double *restrict u,
                                       double *restrict q, const double *restrict w,
                                       double *restrict r, const double *restrict cn,
                                       const double *restrict s, double *restrict kap, double h)
{
    for (int i = 1; i < n - 1; i++) {
        double Rl, Rr, Ll, Lr;
        if (model == 1) {
            Rl = Ll = x[i] - x[i - 1];
            Rr = Lr = x[i + 1] - x[i];
        } else {
            Rl = cn[i] * x[i] - cn[i - 1] * x[i - 1];
            Rr = cn[i + 1] * x[i + 1] - cn[i] * x[i];
            Ll = model == 2 ? Rl : x[i] - x[i - 1];
            Lr = model == 2 ? Rr : x[i + 1] - x[i];
        }
        const double sc = model == 2 ? h * s[i] : h;
        p[i] += sc * ((Lr + ALPHA * Rr * Rr) - (Ll + ALPHA * Rl * Rl));
        const double kl = (model == 1) + 2.0 * ALPHA * Rl, kr = (model == 1) + 2.0 * ALPHA * Rr;
        if (kap) kap[i] = kl;
        if (nv >= 1) TANGENT_AT(u, q);
        if (nv == 2) TANGENT_AT(w, r);
    }
}

/* One vector's interior tangent kick from stored kappa (kap[i]: bond i). */
static inline void plain_tangent_interior(int model, int n, const double *restrict d,
                                          double *restrict o, const double *restrict cn,
                                          const double *restrict s, const double *restrict kap,
                                          double h)
{
    for (int i = 1; i < n - 1; i++) {
        const double sc = model == 2 ? h * s[i] : h;
        const double kl = kap[i], kr = kap[i + 1];
        if (model == 1) {
            o[i] += sc * (kr * (d[i + 1] - d[i]) - kl * (d[i] - d[i - 1]));
        } else {
            const double dRl = cn[i] * d[i] - cn[i - 1] * d[i - 1];
            const double dRr = cn[i + 1] * d[i + 1] - cn[i] * d[i];
            const double dLl = model == 2 ? dRl : d[i] - d[i - 1];
            const double dLr = model == 2 ? dRr : d[i + 1] - d[i];
            o[i] += sc * ((dLr + kr * dRr) - (dLl + kl * dRl));
        }
    }
}

/* The kick; `ring`: the periodic chain (the interior particles are the fixed chain's). */
static inline void plain_kick(int model, int ring, int n, int k, double *y, const coef *c,
                              double *kap, double h)
{
    /* the ends first: they read the interior's old x only (the kick changes p alone) */
    plain_kick_end(model, ring, n, k, y, c, h, 0);
    plain_kick_end(model, ring, n, k, y, c, h, n - 1);
    const size_t st = 2 * (size_t)n;
    if (k == 0) {
        plain_kick_interior(model, n, 0, y, y + n, NULL, NULL, NULL, NULL, c->cn, c->s, NULL, h);
        return;
    }
    if (k == 1) {
        plain_kick_interior(model, n, 1, y, y + n, y + st, y + st + n, NULL, NULL, c->cn, c->s,
                            NULL, h);
        return;
    }
    if (k == 2) {
        plain_kick_interior(model, n, 2, y, y + n, y + st, y + st + n, y + 2 * st,
                            y + 2 * st + n, c->cn, c->s, NULL, h);
        return;
    }
    plain_kick_interior(model, n, 0, y, y + n, NULL, NULL, NULL, NULL, c->cn, c->s, kap, h);
    {   /* kappa of bond n-1 */
        double L, R;
        stretch(model, y, c->cn, n, n - 1, &L, &R);
        kap[n - 1] = (model == 1) + 2.0 * ALPHA * R;
    }
    for (int v = 1; v <= k; v++)
        plain_tangent_interior(model, n, y + st * v, y + st * v + n, c->cn, c->s, kap, h);
}

/* Model 4, the Toda lattice: phi_b = V'(d_b) = expm1(2 alpha d_b)/(2 alpha) and kappa_b =
 * V''(d_b) = 1 + expm1(2 alpha d_b) of bonds b = 0..n into phi, kap (one fpl_expm1 a bond, the
 * loop vectorised), then p_i += h (phi_{i+1} - phi_i) and each vector's dp_i += h (kappa_{i+1}
 * (u_{i+1} - u_i) - kappa_i (u_i - u_{i-1})), the orbit and up to two vectors in one loop. */
static inline void plain_toda_kick(int n, int k, double *restrict y, double *restrict phi,
                                   double *restrict kap, double h)
{
    const double two_a = 2.0 * ALPHA, inv_2a = 0.5 / ALPHA;
    const size_t st = 2 * (size_t)n;
    const double *restrict x = y;
    {
        const double m0 = fpl_expm1(two_a * x[0]), mn = fpl_expm1(two_a * -x[n - 1]);
        phi[0] = m0 * inv_2a;
        kap[0] = 1.0 + m0;
        phi[n] = mn * inv_2a;
        kap[n] = 1.0 + mn;
    }
    for (int b = 1; b < n; b++) {
        const double m = fpl_expm1(two_a * (x[b] - x[b - 1]));
        phi[b] = m * inv_2a;
        kap[b] = 1.0 + m;
    }
    double *restrict p = y + n;
    for (int v = 1; v <= k; v++) {   /* the vectors' end particles (walls: u_{-1} = u_n = 0) */
        const double *u = y + st * v;
        double *q = y + st * v + n;
        q[0] += h * (kap[1] * (u[1] - u[0]) - kap[0] * u[0]);
        q[n - 1] += h * (kap[n] * -u[n - 1] - kap[n - 1] * (u[n - 1] - u[n - 2]));
    }
    if (k <= 2) {
        const double *restrict u = k >= 1 ? y + st : NULL, *restrict w = k == 2 ? y + 2 * st : NULL;
        double *restrict q = k >= 1 ? y + st + n : NULL, *restrict r = k == 2 ? y + 2 * st + n : NULL;
        if (k == 0)
            for (int i = 0; i < n; i++) p[i] += h * (phi[i + 1] - phi[i]);
        else if (k == 1)
            for (int i = 1; i < n - 1; i++) {
                p[i] += h * (phi[i + 1] - phi[i]);
                q[i] += h * (kap[i + 1] * (u[i + 1] - u[i]) - kap[i] * (u[i] - u[i - 1]));
            }
        else
            for (int i = 1; i < n - 1; i++) {
                p[i] += h * (phi[i + 1] - phi[i]);
                q[i] += h * (kap[i + 1] * (u[i + 1] - u[i]) - kap[i] * (u[i] - u[i - 1]));
                r[i] += h * (kap[i + 1] * (w[i + 1] - w[i]) - kap[i] * (w[i] - w[i - 1]));
            }
        if (k >= 1) {
            p[0] += h * (phi[1] - phi[0]);
            p[n - 1] += h * (phi[n] - phi[n - 1]);
        }
        return;
    }
    for (int i = 0; i < n; i++) p[i] += h * (phi[i + 1] - phi[i]);
    for (int v = 1; v <= k; v++) {
        const double *restrict u = y + st * v;
        double *restrict q = y + st * v + n;
        for (int i = 1; i < n - 1; i++)
            q[i] += h * (kap[i + 1] * (u[i + 1] - u[i]) - kap[i] * (u[i] - u[i - 1]));
    }
}

static void plain_toda_yoshida4(int n, int k, double *y, const coef *c, double *phi,
                                double *kap, double dt, long steps)
{
    for (long s = 0; s < steps; s++) {
        plain_drift(1, n, k, y, c, 0.5 * W1 * dt);
        plain_toda_kick(n, k, y, phi, kap, W1 * dt);
        plain_drift(1, n, k, y, c, 0.5 * (W0 + W1) * dt);
        plain_toda_kick(n, k, y, phi, kap, W0 * dt);
        plain_drift(1, n, k, y, c, 0.5 * (W0 + W1) * dt);
        plain_toda_kick(n, k, y, phi, kap, W1 * dt);
        plain_drift(1, n, k, y, c, 0.5 * W1 * dt);
    }
}

static inline void plain_yoshida4_model(int model, int ring, int n, int k, double *y,
                                        const coef *c, double *kap, double dt, long steps)
{
    for (long s = 0; s < steps; s++) {
        plain_drift(model, n, k, y, c, 0.5 * W1 * dt);
        plain_kick(model, ring, n, k, y, c, kap, W1 * dt);
        plain_drift(model, n, k, y, c, 0.5 * (W0 + W1) * dt);
        plain_kick(model, ring, n, k, y, c, kap, W0 * dt);
        plain_drift(model, n, k, y, c, 0.5 * (W0 + W1) * dt);
        plain_kick(model, ring, n, k, y, c, kap, W1 * dt);
        plain_drift(model, n, k, y, c, 0.5 * W1 * dt);
    }
}

/* One build per model and boundary (constants in each). */
static void plain_yoshida4(int model, int ring, int n, int k, double *y, const coef *c,
                           double *kap, double dt, long steps)
{
    if (model == 4) {   /* fixed ends only */
        plain_toda_yoshida4(n, k, y, c, kap + n + 1, kap, dt, steps);
        return;
    }
    if (ring) {
        if (model == 1) plain_yoshida4_model(1, 1, n, k, y, c, kap, dt, steps);
        else if (model == 2) plain_yoshida4_model(2, 1, n, k, y, c, kap, dt, steps);
        else plain_yoshida4_model(3, 1, n, k, y, c, kap, dt, steps);
        return;
    }
    if (model == 1) plain_yoshida4_model(1, 0, n, k, y, c, kap, dt, steps);
    else if (model == 2) plain_yoshida4_model(2, 0, n, k, y, c, kap, dt, steps);
    else plain_yoshida4_model(3, 0, n, k, y, c, kap, dt, steps);
}

static void initial(int n, int k, double *y)
{
    for (int j = 0; j < n; j++) {
        y[j] = 0.3 * sin(3.14159265358979323846 * (j + 1) / (n + 1));
        y[n + j] = 0.0;
    }
    for (long i = 2L * n; i < 2L * n * (k + 1); i++) y[i] = 0.1 * sin(0.37 * (double)i);
}

/* Bytes per particle-step of Yoshida 4 (see the top). */
static double step_bytes(int model, int k)
{
    const double drift = 24.0 * (k + 1) + (model == 2 ? 8.0 : 0.0);
    const double kick = 24.0 * (k + 1) + (model == 2 ? 16.0 : model == 3 ? 8.0 : 0.0);
    return 4.0 * drift + 3.0 * kick;
}

/* Bytes per particle-step of fputlab's own step: the stage-fused one (k <= 2: three passes a
 * step); on chains of N > 1024 with k >= 3, or k = 1, 2 and a state over 10 MiB, the sweeps (one
 * pass per 10 Yoshida 4 steps, the chain block by block); else (k >= 3, N <= 1024) the two-pass
 * step's bytes. */
static double fused_step_bytes(int model, int n, int k)
{
    const double pass = 32.0 * (k + 1) + (model == 2 ? 24.0 : model == 3 ? 8.0 : 0.0);
    const int sweep = model != 4 && n > 1024 && (k >= 3 || (k >= 1 && 16.0 * n * (k + 1) > 10.0 * 1048576.0));
    if (sweep) return pass / 10.0;
    if (k > 2) return step_bytes(model, k);
    return 3.0 * pass;
}

/* Triad a = b + s c on 3 arrays of m doubles: bytes/s, best of `repeats`. */
static double triad_bandwidth(int repeats)
{
    const size_t m = (size_t)8 << 20; /* 64 MB each */
    double *a = malloc(m * sizeof *a), *b = malloc(m * sizeof *b), *c = malloc(m * sizeof *c);
    if (!a || !b || !c) return NAN;
    for (size_t i = 0; i < m; i++) { a[i] = 0.0; b[i] = 1.0; c[i] = 2.0; }
    double best = INFINITY;
    for (int r = 0; r < repeats; r++) {
        const double t0 = cpu_now();
        for (size_t i = 0; i < m; i++) a[i] = b[i] + 0.5 * c[i];
        best = fmin(best, cpu_now() - t0);
        b[r % m] = a[(r * 7919) % m]; /* keep the loop */
    }
    free(a);
    free(b);
    free(c);
    return 24.0 * (double)m / best;
}

int main(int argc, char **argv)
{
    const int repeats = argc > 1 ? atoi(argv[1]) : 5;
    const long max_n = argc > 2 ? atol(argv[2]) : 1L << 22;
    const long min_n = argc > 3 ? atol(argv[3]) : 0;
    int ring = 0;
    const char *models = "1234";
    for (int i = 4; i < argc; i++) {
        if (strcmp(argv[i], "ring") == 0) ring = 1;
        else if (strcmp(argv[i], "fixed") == 0) ring = 0;
        else models = argv[i];
    }
    static const int sizes[] = {16, 64, 512, 4096, 32768, 262144, 1 << 22};
    const fpl_splitting *yo = NULL;
    if (fpl_splitting_lookup("yoshida4", &yo)) return 1;
    const double bw = triad_bandwidth(repeats + 2);
    printf("triad bandwidth %.2f GB/s (3 x 64 MB, best of %d)\n", bw / 1e9, repeats + 2);
    if (ring) {
        printf("rings: %5s %8s %5s %12s %12s %12s %9s %9s %9s\n%12s %8s %5s %12s %12s %12s\n",
               "model", "N", "k", "fputlab", "plain C", "fpl fixed", "fpl/plain", "ring/fix",
               "per-vec", "", "", "", "[ns/p-st]", "[ns/p-st]", "[ns/p-st]");
    } else {
        printf("%5s %8s %5s %9s %12s %12s %12s %9s %9s %9s %9s %6s %8s\n", "model", "N", "k",
               "bytes", "fputlab", "plain C", "bound", "fpl/plain", "fpl/bound", "fpl/mod1",
               "per-vec", "fpl B", "fpl/fbnd");
        printf("%5s %8s %5s %9s %12s %12s %12s\n", "", "", "", "[B/p-st]", "[ns/p-st]",
               "[ns/p-st]", "[ns/p-st]");
    }
    double t_model1[8][8] = {{0}}, t_orbit[8] = {0};
    for (int model = 1; model <= 4; model++) {
        if (!strchr(models, '0' + model) || (ring && model == 4)) continue;   /* no plain Toda ring */
        for (size_t in = 0; in < sizeof sizes / sizeof *sizes; in++) {
            const int n = sizes[in];
            if (n > max_n) break;
            if (n < min_n) continue;
            int devs[5] = {0, 1, 2, 6, 2 * n}, nd = 5;
            if ((2.0 * n + 1) * 2.0 * n * 8.0 > 16e6) nd = 4;   /* k = 2N: state <= 16 MB */
            if (n >= (1 << 22)) nd = 3;                        /* 200 MB at k = 2 */
            double *v = malloc(sizeof(double) * (size_t)n);
            coef c = {malloc(sizeof(double) * (size_t)n), malloc(sizeof(double) * (size_t)n),
                      malloc(sizeof(double) * (size_t)n)};
            double *kap = malloc(sizeof(double) * 2 * ((size_t)n + 1));   /* Toda: + phi */
            if (!v || !c.cn || !c.s || !c.minv || !kap) return 1;
            for (int j = 0; j < n; j++) {
                v[j] = 0.9 + 0.2 * (0.5 + 0.5 * sin(12.9898 * j + 78.233 * (j % 17)));
                c.cn[j] = model == 1 || model == 4 ? 1.0 : v[j];
                c.s[j] = model == 2 ? v[j] : 1.0;
                c.minv[j] = model == 2 ? 1.0 / v[j] : 1.0;
            }
            fpl_lattice *lat = NULL, *fixed = NULL;   /* fixed: the ring's fixed chain */
            if (fpl_lattice_create_ex(n, ALPHA, 0.0, model, model == 1 || model == 4 ? NULL : v,
                                      ring ? FPL_BOUNDARY_PERIODIC : FPL_BOUNDARY_FIXED, &lat) ||
                (ring && fpl_lattice_create(n, ALPHA, 0.0, model, model == 1 || model == 4 ? NULL : v, &fixed))) {
                fprintf(stderr, "lattice N = %d: %s\n", n, fpl_last_error());
                return 1;
            }
            for (int id = 0; id < nd; id++) {
                const int k = devs[id];
                const long len = 2L * n * (k + 1);
                /* ~0.03 s of work per timing at ~2 ns per particle-step and vector */
                long steps = (long)(1.5e7 / ((double)n * (k + 1)));
                /* fpl_splitting_advance checks the state for NaN/Inf before and after (two
                 * passes): at least 10 steps, so that they weigh < 3 % out of cache */
                if (steps < 10) steps = 10;
                if (steps > 200000) steps = 200000;   /* t <= 2000: model 3 stays bounded */
                const int reps = n >= (1 << 22) ? (repeats < 3 ? repeats : 3) : repeats;
                double *a = malloc(sizeof(double) * (size_t)len);
                double *b = malloc(sizeof(double) * (size_t)len);
                if (!a || !b) { fprintf(stderr, "out of memory at N = %d, k = %d\n", n, k); return 1; }
                initial(n, k, a);
                initial(n, k, b);
                if (fpl_splitting_advance(yo, lat, a, k, 0.01, 3)) return 1;
                plain_yoshida4(model, ring, n, k, b, &c, kap, 0.01, 3);
                double diff = 0.0;
                for (long i = 0; i < len; i++) diff = fmax(diff, fabs(a[i] - b[i]) / (1 + fabs(a[i])));
                if (diff > 1e-12) {
                    fprintf(stderr, "model %d N = %d k = %d: plain step differs from fputlab's by "
                            "%.2e\n", model, n, k, diff);
                    return 1;
                }
                double best_f = INFINITY, best_p = INFINITY, best_x = INFINITY;
                for (int r = 0; r < reps; r++) {
                    initial(n, k, a);   /* the same orbit every repeat (model 3 can run away) */
                    initial(n, k, b);
                    double t0 = cpu_now();
                    const int st = fpl_splitting_advance(yo, lat, a, k, 0.01, steps);
                    best_f = fmin(best_f, (cpu_now() - t0) / ((double)steps * n));
                    if (st) {
                        fprintf(stderr, "model %d N = %d k = %d: %s\n", model, n, k, fpl_last_error());
                        return 1;
                    }
                    t0 = cpu_now();
                    plain_yoshida4(model, ring, n, k, b, &c, kap, 0.01, steps);
                    best_p = fmin(best_p, (cpu_now() - t0) / ((double)steps * n));
                    if (!ring) continue;
                    initial(n, k, a);
                    t0 = cpu_now();
                    if (fpl_splitting_advance(yo, fixed, a, k, 0.01, steps)) return 1;
                    best_x = fmin(best_x, (cpu_now() - t0) / ((double)steps * n));
                }
                const double bound = step_bytes(model, k) / bw;
                if (model == 1) t_model1[in][id] = best_f;
                if (k == 0) t_orbit[in] = best_f;
                char per_vec[16] = "";
                if (k > 0) snprintf(per_vec, sizeof per_vec, "%.2f",
                                    (best_f - t_orbit[in]) / (k * t_orbit[in]));
                if (ring) {
                    printf("rings: %5d %8d %5d %12.3f %12.3f %12.3f %9.2f %9.2f %9s\n", model, n,
                           k, best_f * 1e9, best_p * 1e9, best_x * 1e9, best_f / best_p,
                           best_f / best_x, per_vec);
                    fflush(stdout);
                    free(a);
                    free(b);
                    continue;
                }
                printf("%5d %8d %5d %9.0f %12.3f %12.3f %12.3f %9.2f %9.2f %9.2f %9s %6.0f %8.2f\n",
                       model, n, k, step_bytes(model, k), best_f * 1e9, best_p * 1e9, bound * 1e9,
                       best_f / best_p, best_f / bound, best_f / t_model1[in][id], per_vec,
                       fused_step_bytes(model, n, k), best_f * bw / fused_step_bytes(model, n, k));
                fflush(stdout);
                free(a);
                free(b);
            }
            fpl_lattice_free(&lat);
            fpl_lattice_free(&fixed);
            free(v);
            free(c.cn);
            free(c.s);
            free(c.minv);
            free(kap);
        }
    }
    return 0;
}
