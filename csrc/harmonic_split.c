/* Near-integrable splitting of the lattice: H = H_harm + H_anh with
 *   H_harm = sum_i p_i^2/2 + sum_b (x_b - x_{b-1})^2/2 = p.p/2 + x.Kx/2,   K = tridiag(-1, 2, -1),
 *   H_anh  = sum_b (alpha R_b^3/3 + beta R_b^4/4).
 * A = exact flow of H_harm (every normal mode turns by the angle w_k h, w_k^2 the eigenvalues
 * of K, in (0, 4)); B = kick by the anharmonic force alone, p <- p + h F_anh(x).
 * For a lattice whose nonlinearity is eps-small this is the setting in which schemes such as
 * ABA(8,6,4) (Blanes et al. 2013; the SABA family of Laskar & Robutel 2001) reach their
 * eps-dependent orders: error O(eps h^8 + eps^2 h^6 + eps^3 h^4) instead of a generic h^4.
 *
 * The split applies when the linear part is exactly the homogeneous chain: cl = s = minv = 1,
 * i.e. model 1, and model 3 (disorder in the nonlinear couplings only; there B is not a
 * gradient but the composition is still a consistent order-p scheme for x'' = F(x)). Model 2's
 * linear couplings vary: refused by the run_setup hook.
 *
 * How A is computed: as three shears, all in real space,
 *   x += T(K) p,   p -= S(K) x,   x += T(K) p,
 *   T(lambda) = tan(h sqrt(lambda)/2)/sqrt(lambda),   S(lambda) = sqrt(lambda) sin(h sqrt(lambda)),
 * which is the rotation of every mode by h w_k (the half-angle shear factorisation). T and S are
 * entire in lambda on the spectrum and are applied as Chebyshev series in K (Clenshaw, one
 * tridiagonal product per degree), truncated where the coefficients fall below 1e-17: the flow is
 * exact to round-off, costs O(N) per degree (no sine transform: its FFT costs depend on the
 * factors of N+1 and are 10-1000x slower for the usual N = 2^k), and vectorises.
 * Why shears: a shear x += A p with A a polynomial in the symmetric K is symplectic whatever the
 * rounding of its coefficients; a rotation matrix with rounded cos/sin entries is not (its
 * determinant is 1 + O(1e-16) with a fixed sign, and the energy drifts linearly; measured
 * 5e-12 by t = 1e3 for N = 64 at dt = 0.05 in a first version, against 1e-14 now).
 * Deviation vectors: A is linear (its tangent map is itself); B's is dp += h J_anh(x) dx. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

#define NODES 64          /* Chebyshev interpolation nodes for the coefficients */
#define COEF_TOL 1e-17    /* truncate where |c_k| < COEF_TOL (relative to the series' scale) */
#define MAX_ANGLE 1.0     /* largest w h per sub-rotation (keeps the degrees ~ 10-20) */
#define MAX_DRIFTS 16
#define MAX_DEGREE 32

/* The scheme's state (fpl_split_run.state), owned by the run: the Chebyshev coefficients of
 * the drifts for one dt, and scratch. */
static void harmonic_drift(void *ctx, double *y, int stage, double h);
static void harmonic_kick(void *ctx, double *y, double h);
static void harmonic_begin_step(void *ctx, const fpl_splitting *scheme, double dt);

typedef struct fpl_harmonic_state {
    const fpl_splitting *scheme; /* coefficients are for this scheme and dt (scheme NULL: none) */
    double dt;
    int reps;                    /* sub-rotations per drift */
    int deg[MAX_DRIFTS][2];      /* degrees of T and S per drift */
    double coef[MAX_DRIFTS][2][MAX_DEGREE + 1];
    double *work;                /* 4N scratch */
} fpl_harmonic_state;

/* The scratch does not depend on the number of deviation vectors: they are processed one at a
 * time. */
int fpl_harmonic_run_setup(const fpl_splitting *scheme, fpl_split_run *run)
{
    const fpl_lattice *lat = run->lc.lat;
    const int n = lat->n;
    if (lat->boundary != FPL_BOUNDARY_FIXED)
        return fpl_error(NULL, FPL_ERR_ARG, "boundary: method '%s' integrates the fixed-end harmonic "
                         "chain exactly (its sine modes); a periodic chain needs 'aba864' instead",
                         scheme->name);
    if (lat->ops->model == FPL_MODEL_TODA)
        return fpl_error(NULL, FPL_ERR_ARG, "model: method '%s' splits off the harmonic chain and "
                         "kicks with the polynomial anharmonic force; the Toda lattice needs "
                         "'aba864' instead", scheme->name);
    for (int j = 0; j < n; j++) {
        if (lat->cl[j] != 1.0 || lat->s[j] != 1.0 || lat->minv[j] != 1.0)
            return fpl_error(NULL, FPL_ERR_ARG,
                             "method '%s' integrates the harmonic chain exactly, which needs "
                             "uniform linear couplings and masses (models 'homogeneous' and "
                             "'nonlinear'); this '%s' lattice has v[%d] = %g in its linear part: "
                             "use 'aba864' instead",
                             scheme->name, lat->ops->name, j, lat->v[j]);
    }
    if (scheme->n_kicks + 1 > MAX_DRIFTS)
        return fpl_error(NULL, FPL_ERR_ARG, "method '%s': %d drifts, at most %d supported",
                         scheme->name, scheme->n_kicks + 1, MAX_DRIFTS);
    fpl_harmonic_state *hs = calloc(1, sizeof *hs);
    double *work = malloc(sizeof(double) * 4 * (size_t)n);
    if (!hs || !work) {
        free(hs);
        free(work);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (harmonic split, N = %d)", n);
    }
    hs->work = work;
    run->state = hs;
    run->sys.drift = harmonic_drift;
    run->sys.kick = harmonic_kick;
    run->sys.begin_step = harmonic_begin_step;
    run->sys.steps = NULL;   /* the model's fused stepper is the kinetic split's */
    return FPL_OK;
}

void fpl_harmonic_state_free(void *state)
{
    fpl_harmonic_state *hs = state;
    if (!hs) return;
    free(hs->work);
    free(hs);
}

/* Chebyshev coefficients on lambda in [0, 4] (x = lambda/2 - 1) of T (which = 0) or S (1) for
 * angle parameter h, in long double so that the round-off of the sums (~1e-19) lies below the
 * truncation level; returns the degree after truncation, or -1 if it exceeds the maximum. */
static int chebyshev(int which, double h, double *coef)
{
    long double f[NODES], c[NODES], cs[4 * NODES];
    const long double pi = 3.141592653589793238462643383279502884L;
    /* cos(pi k (2j+1) / (2 NODES)) = cs[k (2j+1) mod 4 NODES]: 256 cosines, not 4096 */
    for (int m = 0; m < 4 * NODES; m++) cs[m] = cosl(pi * m / (2 * NODES));
    for (int j = 0; j < NODES; j++) {
        const long double x = cosl(pi * (j + 0.5L) / NODES), lam = 2.0L + 2.0L * x,
                          w = sqrtl(lam);
        f[j] = which == 0 ? tanl(0.5L * h * w) / w : w * sinl(h * w);
    }
    long double scale = 0.0L;
    for (int k = 0; k < NODES; k++) {
        long double sum = 0.0L;
        for (int j = 0; j < NODES; j++) sum += f[j] * cs[(k * (2 * j + 1)) % (4 * NODES)];
        c[k] = (k == 0 ? 1.0L : 2.0L) * sum / NODES;
        scale += fabsl(c[k]);
    }
    int deg = NODES - 1;
    while (deg > 0 && fabsl(c[deg]) < COEF_TOL * scale) deg--;
    if (deg > MAX_DEGREE || deg > NODES / 2) return -1; /* aliasing would show */
    for (int k = 0; k <= deg; k++) coef[k] = (double)c[k];
    return deg;
}

/* Coefficients for every drift of the scheme at step dt, recomputed only when dt or the scheme
 * changes (a run keeps one dt; an event search or an off-grid sample pays ~1e3 cosines). */
static void prepare_step(const fpl_splitting *scheme, fpl_harmonic_state *hc, double dt)
{
    if (hc->scheme == scheme && hc->dt == dt) return;
    double a_max = 0.0;
    for (int i = 0; i <= scheme->n_kicks; i++) a_max = fmax(a_max, fabs(scheme->drift[i]));
    int reps = (int)fmax(1.0, ceil(2.0 * a_max * dt / MAX_ANGLE)); /* w <= 2 */
    for (;;) {
        int ok = 1;
        for (int i = 0; i <= scheme->n_kicks && ok; i++) {
            const double h = scheme->drift[i] * dt / reps;
            for (int which = 0; which < 2 && ok; which++) {
                hc->deg[i][which] = chebyshev(which, h, hc->coef[i][which]);
                ok = hc->deg[i][which] >= 0;
            }
        }
        /* the degree falls with the angle; the cap only guards against a broken libm */
        if (ok || reps > (1 << 20)) break;
        reps *= 2;
    }
    hc->reps = reps;
    hc->scheme = scheme;
    hc->dt = dt;
}

/* out = sum_k c_k T_k(X) v with X = K/2 - I, (X u)_i = -(u_{i-1} + u_{i+1})/2 (fixed ends), by
 * Clenshaw's recurrence b_k = c_k v + 2 X b_{k+1} - b_{k+2}; out = c_0 v + X b_1 - b_2.
 * work: 3N scratch. */
FPL_HOT static void chebyshev_apply(int n, const double *restrict c, int deg,
                                    const double *restrict v, double *restrict out,
                                    double *restrict work)
{
    double *b0 = work, *b1 = work + n, *b2 = work + 2 * (size_t)n;
    memset(b1, 0, sizeof(double) * (size_t)n);
    memset(b2, 0, sizeof(double) * (size_t)n);
    for (int k = deg; k >= 1; k--) {
        const double ck = c[k];
        double *restrict nb = b0;
        const double *restrict p1 = b1, *restrict p2 = b2;
        nb[0] = ck * v[0] - p1[1] - p2[0];
        for (int i = 1; i < n - 1; i++)
            nb[i] = ck * v[i] - (p1[i - 1] + p1[i + 1]) - p2[i];
        nb[n - 1] = ck * v[n - 1] - p1[n - 2] - p2[n - 1];
        double *t = b2; /* rotate: b2 <- b1, b1 <- b0, b0 <- old b2 */
        b2 = b1;
        b1 = b0;
        b0 = t;
    }
    out[0] = c[0] * v[0] - 0.5 * b1[1] - b2[0];
    for (int i = 1; i < n - 1; i++)
        out[i] = c[0] * v[i] - 0.5 * (b1[i - 1] + b1[i + 1]) - b2[i];
    out[n - 1] = c[0] * v[n - 1] - 0.5 * b1[n - 2] - b2[n - 1];
}

FPL_HOT static void axpy(int n, double a, const double *restrict x, double *restrict y)
{
    for (int i = 0; i < n; i++) y[i] += a * x[i];
}

/* A-flow of drift i on the orbit and every deviation vector. */
static void rotate(const fpl_harmonic_state *hc, int n, double *y, int n_dev, int i)
{
    double *tmp = hc->work, *work = tmp + n;
    const double *ct = hc->coef[i][0], *cs = hc->coef[i][1];
    const int dt_ = hc->deg[i][0], ds = hc->deg[i][1];
    for (int m = 0; m <= n_dev; m++) {
        double *x = y + 2 * (size_t)n * m, *p = x + n;
        for (int r = 0; r < hc->reps; r++) {
            chebyshev_apply(n, ct, dt_, p, tmp, work);
            axpy(n, 1.0, tmp, x);
            chebyshev_apply(n, cs, ds, x, tmp, work);
            axpy(n, -1.0, tmp, p);
            chebyshev_apply(n, ct, dt_, p, tmp, work);
            axpy(n, 1.0, tmp, x);
        }
    }
}

/* The drift of stage i (h is drift[i] dt of the step that begin_step prepared). */
static void harmonic_drift(void *ctx, double *y, int stage, double h)
{
    (void)h;
    const fpl_split_run *run = ctx;
    rotate(run->state, run->lc.lat->n, y, run->lc.n_dev, stage);
}

static void harmonic_begin_step(void *ctx, const fpl_splitting *scheme, double dt)
{
    const fpl_split_run *run = ctx;
    prepare_step(scheme, run->state, dt);
}

/* B-kick: p += h F_anh(x); deviation vectors dp += h J_anh(x) dx. */
static void harmonic_kick(void *ctx, double *y, double h)
{
    const fpl_split_run *run = ctx;
    const fpl_lattice *lat = run->lc.lat;
    fpl_work *work = run->lc.work;
    double *f = ((fpl_harmonic_state *)run->state)->work;
    const int n = lat->n, n_dev = run->lc.n_dev;
    fpl_kernel_anharmonic_force(lat, work, y, f);
    axpy(n, h, f, y + n);
    for (int m = 1; m <= n_dev; m++) {
        double *dx = y + 2 * (size_t)n * m;
        fpl_kernel_anharmonic_tangent(lat, work, dx, f);
        axpy(n, h, f, dx + n);
    }
}
