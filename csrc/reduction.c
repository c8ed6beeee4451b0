/* Reduction to a few normal modes (paper Sec. 4): two-mode coefficients as closed sums, their exact
 * moments over the disorder, the two-mode ODE and the Galerkin truncation, both integrated as split
 * systems by the one splitting step and grid driver of splitting.c. The formulas are in include/fputlab/reduction.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

#define N_COEF 6

struct fpl_galerkin {
    int n, m;
    fpl_lattice *lat;  /* own copy: the handle does not depend on the caller's lattice's lifetime */
    fpl_work *work;    /* the force kernel's scratch */
    double *basis;     /* m x n, basis[k n + j] = A_{j+1,k+1} */
    double *omega;     /* m */
    double *x, *f;     /* n scratch */
    double *acc;       /* m scratch for the kicks */
    char errmsg[FPL_ERRMSG_LEN];
};

/* Record an error (thread-local, and on the Galerkin handle if there is one). */
static int red_error(fpl_galerkin *g, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int red_error(fpl_galerkin *g, int status, const char *fmt, ...)
{
    char buf[FPL_ERRMSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fpl_error(NULL, status, "%s", buf);
    if (g) memcpy(g->errmsg, buf, sizeof buf);
    return status;
}

/* A_{jk} with the fixed ends A_{0k} = A_{N+1,k} = 0 (1-based j, k). */
static double mode_shape(int n, int j, int k)
{
    if (j <= 0 || j >= n + 1) return 0.0;
    return sqrt(2.0 / (n + 1.0)) * sin(M_PI * (double)j * (double)k / (n + 1.0));
}

static int check_finite_array(fpl_galerkin *g, const char *name, const double *a, long len)
{
    long bad = -1;
    if (!fpl_is_finite_array(a, len, &bad))
        return red_error(g, FPL_ERR_ARG, "%s[%ld] is not finite (%g)", name, bad, a[bad]);
    return FPL_OK;
}

/* ---- two-mode coefficients ------------------------------------------------------------ */

static int check_chain(int n, double alpha)
{
    if (n < 2) return red_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!isfinite(alpha))
        return red_error(NULL, FPL_ERR_ARG, "alpha must be finite (got %g)", alpha);
    return FPL_OK;
}

int fpl_reduction_coefficients(int n, double alpha, int model, const double *v, double *a,
                               double *b)
{
    int st = check_chain(n, alpha);
    if (st) return st;
    if (!fpl_model_ops_for(model)) return fpl_model_unknown(model);
    if (model == FPL_MODEL_TODA)
        return red_error(NULL, FPL_ERR_ARG, "model: the two-mode reduction is derived for the "
                         "FPUT-alpha chains (models 1-3), not the Toda lattice");
    if (!a || !b) return red_error(NULL, FPL_ERR_ARG, "a/b: NULL pointer");
    const int weighted = model != FPL_MODEL_HOMOGENEOUS && v != NULL;
    if (weighted) {
        for (int j = 0; j < n; j++)
            if (!isfinite(v[j]) || v[j] <= 0.0)
                return red_error(NULL, FPL_ERR_ARG,
                                 "v[%d] = %g: variability must be finite and > 0", j, v[j]);
    }
    /* One pass over the bonds j = 0..N: D_j1, D_j2 and the weighted stretches rho_j1, rho_j2. */
    double s[N_COEF] = {0};
    for (int j = 0; j <= n; j++) {
        double vl = weighted && j >= 1 ? v[j - 1] : 1.0;
        double vr = weighted && j + 1 <= n ? v[j] : 1.0;
        double l1 = mode_shape(n, j, 1), r1 = mode_shape(n, j + 1, 1);
        double l2 = mode_shape(n, j, 2), r2 = mode_shape(n, j + 1, 2);
        double d1 = r1 - l1, d2 = r2 - l2;
        double rho1 = vr * r1 - vl * l1, rho2 = vr * r2 - vl * l2;
        s[0] += d1 * rho1 * rho1;
        s[1] += d1 * rho2 * rho2;
        s[2] += d1 * rho1 * rho2;
        s[3] += d2 * rho1 * rho1;
        s[4] += d2 * rho2 * rho2;
        s[5] += d2 * rho1 * rho2;
    }
    a[0] = -alpha * s[0];
    a[1] = -alpha * s[1];
    a[2] = -2.0 * alpha * s[2];  /* r^2 holds 2 Q_1 Q_2 rho_1 rho_2 */
    b[0] = -alpha * s[3];
    b[1] = -alpha * s[4];
    b[2] = -2.0 * alpha * s[5];
    return FPL_OK;
}

int fpl_reduction_normalise(int n, const double *a, const double *b, double *a_paper,
                            double *b_paper, double *a_tilde, double *b_tilde)
{
    if (n < 2) return red_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!a || !b) return red_error(NULL, FPL_ERR_ARG, "a/b: NULL pointer");
    const double w1 = 2.0 * sin(M_PI / (2.0 * (n + 1))), w2 = 2.0 * sin(M_PI / (n + 1.0));
    const double eps = w2 - 2.0 * w1;
    for (int i = 0; i < 3; i++) {
        if (a_paper) a_paper[i] = a[i] / eps;
        if (b_paper) b_paper[i] = b[i] / eps;
    }
    if (a_tilde) *a_tilde = a[2] / eps / (2.0 * w1);
    if (b_tilde) *b_tilde = b[0] / eps / (2.0 * w2);
    return FPL_OK;
}

/* Modes (k; l, m) and the factor -alpha (2 - delta_lm) of each coefficient, in (a, b) order. */
static const int coef_modes[N_COEF][3] = {{1, 1, 1}, {1, 2, 2}, {1, 1, 2},
                                          {2, 1, 1}, {2, 2, 2}, {2, 1, 2}};

static void quadratic_forms(int n, double alpha, double *diag, double *off)
{
    for (int c = 0; c < N_COEF; c++) {
        const int k = coef_modes[c][0], l = coef_modes[c][1], m = coef_modes[c][2];
        const double kappa = -alpha * (l == m ? 1.0 : 2.0);
        double *d = diag + (size_t)c * n, *o = off + (size_t)c * (n - 1);
        /* w_j = kappa D_jk for bonds j = 0..N; particle i (1-based) touches bonds i-1 and i. */
        double w_prev = kappa * (mode_shape(n, 1, k) - mode_shape(n, 0, k));
        for (int i = 1; i <= n; i++) {
            double w = kappa * (mode_shape(n, i + 1, k) - mode_shape(n, i, k));
            d[i - 1] = (w_prev + w) * mode_shape(n, i, l) * mode_shape(n, i, m);
            if (i < n)
                o[i - 1] = -0.5 * w * (mode_shape(n, i + 1, l) * mode_shape(n, i, m) +
                                       mode_shape(n, i, l) * mode_shape(n, i + 1, m));
            w_prev = w;
        }
    }
}

int fpl_reduction_quadratic_forms(int n, double alpha, double *diag, double *off)
{
    int st = check_chain(n, alpha);
    if (st) return st;
    if (!diag || !off) return red_error(NULL, FPL_ERR_ARG, "diag/off: NULL pointer");
    quadratic_forms(n, alpha, diag, off);
    return FPL_OK;
}

/* Scale s of v = 1 + s z and the moments m2 = E z^2, m4 = E z^4 of one standardised draw. */
static int disorder_moments(int kind, double tau, double *s, double *m2, double *m4)
{
    switch (kind) {
    case FPL_DISORDER_GAUSSIAN:
        *s = tau / 300.0, *m2 = 1.0, *m4 = 3.0;
        return FPL_OK;
    case FPL_DISORDER_TRUNCATED_GAUSSIAN: {
        /* N(0,1) conditioned on |z| <= c: integrate z^2 phi and z^4 phi by parts. */
        const double c = 3.0, phi = exp(-0.5 * c * c) / sqrt(2.0 * M_PI);
        const double mass = erf(c / sqrt(2.0));
        const double int2 = mass - 2.0 * c * phi;
        *s = tau / 300.0, *m2 = int2 / mass, *m4 = (3.0 * int2 - 2.0 * c * c * c * phi) / mass;
        return FPL_OK;
    }
    case FPL_DISORDER_UNIFORM:
        *s = tau / 100.0, *m2 = 1.0 / 3.0, *m4 = 1.0 / 5.0;
        return FPL_OK;
    default:
        return red_error(NULL, FPL_ERR_UNKNOWN,
                         "disorder kind %d is unknown (0 gaussian, 1 truncated, 2 uniform)", kind);
    }
}

int fpl_reduction_moments(int n, double alpha, int model, int kind, double tau, double *mean,
                          double *cov)
{
    int st = check_chain(n, alpha);
    if (st) return st;
    if (!fpl_model_ops_for(model)) return fpl_model_unknown(model);
    if (model == FPL_MODEL_TODA)
        return red_error(NULL, FPL_ERR_ARG, "model: the two-mode reduction is derived for the "
                         "FPUT-alpha chains (models 1-3), not the Toda lattice");
    if (!(tau >= 0.0) || !isfinite(tau))
        return red_error(NULL, FPL_ERR_ARG, "tau must be finite and >= 0 (got %g)", tau);
    if (kind != FPL_DISORDER_GAUSSIAN && tau >= 100.0)
        return red_error(NULL, FPL_ERR_ARG,
                         "tau must be < 100 percent for %s disorder (got %g): v would reach 0",
                         fpl_disorder_name(kind), tau);
    if (!mean) return red_error(NULL, FPL_ERR_ARG, "mean: NULL pointer");
    double s = 0.0, m2 = 0.0, m4 = 0.0;
    st = disorder_moments(kind, tau, &s, &m2, &m4);
    if (st) return st;
    if (model == FPL_MODEL_HOMOGENEOUS) s = 0.0;

    double *diag = malloc(sizeof(double) * (size_t)N_COEF * (3 * (size_t)n));
    if (!diag) return red_error(NULL, FPL_ERR_NOMEM, "out of memory (N = %d)", n);
    double *off = diag + (size_t)N_COEF * n;       /* 6 x (n-1), room for 6 x n */
    double *g = off + (size_t)N_COEF * n;          /* 6 x n: M 1 */
    quadratic_forms(n, alpha, diag, off);
    for (int c = 0; c < N_COEF; c++) {
        const double *d = diag + (size_t)c * n, *o = off + (size_t)c * (n - 1);
        double *gc = g + (size_t)c * n, total = 0.0, trace = 0.0;
        for (int i = 0; i < n; i++) {
            gc[i] = d[i] + (i > 0 ? o[i - 1] : 0.0) + (i < n - 1 ? o[i] : 0.0);
            total += gc[i];
            trace += d[i];
        }
        mean[c] = total + s * s * m2 * trace;
    }
    if (cov) {
        const double s2 = s * s, s4 = s2 * s2;
        for (int c = 0; c < N_COEF; c++) {
            for (int e = c; e < N_COEF; e++) {
                const double *dc = diag + (size_t)c * n, *de = diag + (size_t)e * n;
                const double *oc = off + (size_t)c * (n - 1), *oe = off + (size_t)e * (n - 1);
                const double *gc = g + (size_t)c * n, *ge = g + (size_t)e * n;
                double gg = 0.0, dd = 0.0, oo = 0.0;
                for (int i = 0; i < n; i++) {
                    gg += gc[i] * ge[i];
                    dd += dc[i] * de[i];
                }
                for (int i = 0; i < n - 1; i++) oo += oc[i] * oe[i];
                /* tr(M M') of two symmetric tridiagonals = sum d d' + 2 sum o o'; the third
                 * moments vanish, so the linear and quadratic parts in z are uncorrelated. */
                double value = 4.0 * s2 * m2 * gg +
                               s4 * (2.0 * m2 * m2 * (dd + 2.0 * oo) + (m4 - 3.0 * m2 * m2) * dd);
                cov[c * N_COEF + e] = cov[e * N_COEF + c] = value;
            }
        }
    }
    free(diag);
    return FPL_OK;
}

/* ---- second-order systems Q'' = acc(Q) under the splitting tables ---------------------- */

typedef void (*accel_fn)(void *ctx, const double *q, double *acc);

typedef struct second_order {
    int m;            /* degrees of freedom; z = (Q_1..Q_m, P_1..P_m) */
    accel_fn accel;
    void *ctx;
    double *acc;      /* m scratch */
} second_order;

/* As a split system (splitting.c: fpl_split_step, fpl_split_grid_advance): drift Q += h P (unit
 * masses), kick P += h acc(Q). */
static void modal_drift(void *ctx, double *z, int stage, double h)
{
    (void)stage;
    const second_order *so = ctx;
    const int m = so->m;
    double *q = z;
    const double *p = z + m;
    for (int k = 0; k < m; k++) q[k] += h * p[k];
}

static void modal_kick(void *ctx, double *z, double h)
{
    const second_order *so = ctx;
    const int m = so->m;
    double *p = z + m, *acc = so->acc;
    so->accel(so->ctx, z, acc);
    for (int k = 0; k < m; k++) p[k] += h * acc[k];
}

static fpl_split_system modal_system(second_order *so)
{
    return (fpl_split_system){2L * so->m, modal_drift, modal_kick, NULL, so, NULL};
}

/* The schemes' tables are applied here to the kinetic drift-kick split: refuse a scheme with a
 * split of its own (the harmonic split of the lattice). */
static int check_scheme(fpl_galerkin *g, const fpl_splitting *scheme)
{
    if (!scheme) return red_error(g, FPL_ERR_ARG, "method: NULL scheme");
    if (scheme->run_setup)
        return red_error(g, FPL_ERR_ARG, "method '%s' is not a drift-kick composition",
                         scheme->name);
    return FPL_OK;
}

static int check_run_args(fpl_galerkin *g, const fpl_splitting *scheme, const double *z0, int m,
                          double t0, double dt, const double *t_samples, int n_samples)
{
    int st = check_scheme(g, scheme);
    if (st) return st;
    if (!z0) return red_error(g, FPL_ERR_ARG, "z0: NULL pointer");
    if (!isfinite(t0)) return red_error(g, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    if (!(dt > 0.0) || !isfinite(dt))
        return red_error(g, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", dt);
    if (n_samples < 0)
        return red_error(g, FPL_ERR_ARG, "n_samples must be >= 0 (got %d)", n_samples);
    if (n_samples > 0 && !t_samples) return red_error(g, FPL_ERR_ARG, "t_samples: NULL pointer");
    for (int i = 0; i < n_samples; i++) {
        double prev = i ? t_samples[i - 1] : t0;
        if (!isfinite(t_samples[i]) || t_samples[i] < prev)
            return red_error(g, FPL_ERR_ARG,
                             "t_samples[%d] = %g: sample times must be finite, >= t0 and "
                             "non-decreasing", i, t_samples[i]);
        if ((t_samples[i] - t0) / dt > 1e17)
            return red_error(g, FPL_ERR_ARG, "t_samples[%d] = %g needs more than 1e17 steps of "
                             "dt = %g", i, t_samples[i], dt);
    }
    return check_finite_array(g, "z0", z0, 2L * m);
}

/* Fixed-step run on the grid t0 + n dt with exact off-grid samples (one partial step from a
 * copy). omega (length m) is needed only for mode_energies. */
static int run_system(fpl_galerkin *g, const fpl_splitting *scheme, second_order *so,
                      const double *z0, double t0, double dt, const double *t_samples,
                      int n_samples, const double *omega, double *mode_energies, double *states,
                      int *n_done)
{
    const int m = so->m;
    const fpl_split_system sys = modal_system(so);
    const size_t len = 2 * (size_t)m;
    double *z = malloc(sizeof(double) * 3 * len);
    if (!z) return red_error(g, FPL_ERR_NOMEM, "out of memory (state of %d modes)", m);
    double *partial = z + len, *backup = z + 2 * len;
    memcpy(z, z0, sizeof(double) * len);
    long step = 0, bad = 0;
    int done = 0, st = FPL_OK;
    for (int i = 0; i < n_samples; i++) {
        double target = (t_samples[i] - t0) / dt;
        long n_target = (long)floor(target + 1e-9);
        if (fpl_split_grid_advance(scheme, &sys, z, backup, &step, n_target, dt, &bad)) {
            st = red_error(g, FPL_ERR_NONFINITE,
                           "state became non-finite between t = %.10g and t = %.10g "
                           "(blow-up or dt = %g too large)", t0 + step * dt, t0 + bad * dt, dt);
            break;
        }
        const double *sample = z;
        double rest = (target - (double)n_target) * dt;
        if (rest > 1e-9 * dt) {
            memcpy(partial, z, sizeof(double) * len);
            fpl_split_step(scheme, &sys, partial, rest);
            sample = partial;
            if (!fpl_is_finite_array(partial, (long)len, NULL)) {
                st = red_error(g, FPL_ERR_NONFINITE,
                               "state became non-finite between t = %.10g and t = %.10g "
                               "(blow-up or dt = %g too large)", t0 + step * dt, t_samples[i], dt);
                break;
            }
        }
        if (mode_energies) {
            double *e = mode_energies + (size_t)i * m;
            for (int k = 0; k < m; k++) {
                const double q = sample[k], p = sample[m + k];
                e[k] = 0.5 * (p * p + omega[k] * omega[k] * q * q);
            }
            /* a finite but huge state can still overflow its energies */
            if (!fpl_is_finite_array(e, m, NULL)) {
                st = red_error(g, FPL_ERR_NONFINITE, "energies overflowed at t = %.10g (blow-up)",
                               t_samples[i]);
                break;
            }
        }
        if (states) memcpy(states + (size_t)i * len, sample, sizeof(double) * len);
        done = i + 1;
    }
    free(z);
    if (n_done) *n_done = done;
    return st;
}

/* ---- the two-mode ODE (Eq. msvar) -------------------------------------------------------- */

typedef struct two_mode {
    double w1sq, w2sq, a[3], b[3];
} two_mode;

static void two_mode_accel(void *ctx, const double *q, double *acc)
{
    const two_mode *c = ctx;
    const double q1 = q[0], q2 = q[1];
    acc[0] = -c->w1sq * q1 + c->a[0] * q1 * q1 + c->a[1] * q2 * q2 + c->a[2] * q1 * q2;
    acc[1] = -c->w2sq * q2 + c->b[0] * q1 * q1 + c->b[1] * q2 * q2 + c->b[2] * q1 * q2;
}

int fpl_reduction_two_mode_run(const fpl_splitting *scheme, const double *omega, const double *a,
                               const double *b, const double *z0, double t0, double dt,
                               const double *t_samples, int n_samples, double *states,
                               int *n_done)
{
    if (n_done) *n_done = 0;
    if (!omega || !a || !b) return red_error(NULL, FPL_ERR_ARG, "omega/a/b: NULL pointer");
    int st = check_finite_array(NULL, "omega", omega, 2);
    if (!st) st = check_finite_array(NULL, "a", a, 3);
    if (!st) st = check_finite_array(NULL, "b", b, 3);
    if (!st) st = check_run_args(NULL, scheme, z0, 2, t0, dt, t_samples, n_samples);
    if (st) return st;
    two_mode c = {omega[0] * omega[0], omega[1] * omega[1], {a[0], a[1], a[2]}, {b[0], b[1], b[2]}};
    double acc[2];
    second_order so = {2, two_mode_accel, &c, acc};
    return run_system(NULL, scheme, &so, z0, t0, dt, t_samples, n_samples, NULL, NULL, states,
                      n_done);
}

/* ---- Galerkin truncation ------------------------------------------------------------------ */

/* Q'' = A_M^T minv F(A_M Q): x'' = minv F(x) is the acceleration of every model (Eq. dis1 for
 * model 2, where F = p' = v x''). */
static void galerkin_accel(void *ctx, const double *q, double *acc)
{
    fpl_galerkin *g = ctx;
    const int n = g->n, m = g->m;
    double *restrict x = g->x, *restrict f = g->f;
    const double *restrict minv = g->lat->minv;
    memset(x, 0, sizeof(double) * (size_t)n);
    for (int k = 0; k < m; k++) {
        const double *restrict col = g->basis + (size_t)k * n;
        const double qk = q[k];
        for (int j = 0; j < n; j++) x[j] += qk * col[j];
    }
    fpl_kernel_force(g->lat, g->work, x, f);
    for (int j = 0; j < n; j++) f[j] *= minv[j];
    for (int k = 0; k < m; k++) {
        const double *restrict col = g->basis + (size_t)k * n;
        double sum = 0.0;
        for (int j = 0; j < n; j++) sum += col[j] * f[j];
        acc[k] = sum;
    }
}

int fpl_galerkin_create(const fpl_lattice *lattice, int m, fpl_galerkin **out)
{
    if (!out) return red_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!lattice) return red_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    const int n = lattice->n;
    if (lattice->boundary != FPL_BOUNDARY_FIXED)
        return red_error(NULL, FPL_ERR_ARG, "boundary: the Galerkin truncation uses the fixed-end "
                         "chain's sine modes; a periodic chain is not supported");
    if (lattice->ops->model == FPL_MODEL_TODA)
        return red_error(NULL, FPL_ERR_ARG, "model: the Galerkin truncation projects the "
                         "polynomial FPUT force; the Toda lattice is not supported");
    if (m < 1 || m > n)
        return red_error(NULL, FPL_ERR_ARG, "M (number of modes) must be in 1..N = %d (got %d)", n,
                         m);
    fpl_galerkin *g = calloc(1, sizeof *g);
    if (!g) return red_error(NULL, FPL_ERR_NOMEM, "out of memory allocating the Galerkin handle");
    g->n = n;
    g->m = m;
    int st = fpl_lattice_create(n, lattice->alpha, lattice->beta, lattice->ops->model, lattice->v,
                                &g->lat);
    if (!st) st = fpl_work_create(n, 0, &g->work);
    if (st) {
        fpl_galerkin_free(&g);
        return st;
    }
    g->basis = malloc(sizeof(double) * (size_t)m * n);
    g->omega = malloc(sizeof(double) * (size_t)m);
    g->x = malloc(sizeof(double) * (size_t)n);
    g->f = malloc(sizeof(double) * (size_t)n);
    g->acc = malloc(sizeof(double) * (size_t)m);
    if (!g->basis || !g->omega || !g->x || !g->f || !g->acc) {
        fpl_galerkin_free(&g);
        return red_error(NULL, FPL_ERR_NOMEM, "out of memory (N = %d, M = %d)", n, m);
    }
    for (int k = 0; k < m; k++) {
        g->omega[k] = 2.0 * sin((k + 1) * M_PI / (2.0 * (n + 1)));
        for (int j = 0; j < n; j++) g->basis[(size_t)k * n + j] = mode_shape(n, j + 1, k + 1);
    }
    *out = g;
    return FPL_OK;
}

void fpl_galerkin_free(fpl_galerkin **galerkin)
{
    if (!galerkin || !*galerkin) return;
    fpl_galerkin *g = *galerkin;
    fpl_lattice_free(&g->lat);
    fpl_work_free(&g->work);
    free(g->basis);
    free(g->omega);
    free(g->x);
    free(g->f);
    free(g->acc);
    free(g);
    *galerkin = NULL;
}

const char *fpl_galerkin_errmsg(const fpl_galerkin *galerkin)
{
    return galerkin ? galerkin->errmsg : "galerkin: NULL handle";
}

int fpl_galerkin_modes(const fpl_galerkin *galerkin) { return galerkin ? galerkin->m : 0; }
int fpl_galerkin_size(const fpl_galerkin *galerkin) { return galerkin ? galerkin->n : 0; }

#define CHECK_GALERKIN(g)                                                                      \
    do {                                                                                       \
        if (!(g)) return red_error(NULL, FPL_ERR_ARG, "galerkin: NULL handle");                \
        (g)->errmsg[0] = '\0';                                                                 \
    } while (0)

int fpl_galerkin_acceleration(fpl_galerkin *galerkin, const double *q, double *qddot)
{
    CHECK_GALERKIN(galerkin);
    if (!q || !qddot) return red_error(galerkin, FPL_ERR_ARG, "q/qddot: NULL pointer");
    int st = check_finite_array(galerkin, "q", q, galerkin->m);
    if (st) return st;
    galerkin_accel(galerkin, q, qddot);
    return FPL_OK;
}

int fpl_galerkin_advance(const fpl_splitting *scheme, fpl_galerkin *galerkin, double *z,
                         double dt, long nsteps)
{
    CHECK_GALERKIN(galerkin);
    int st = check_scheme(galerkin, scheme);
    if (st) return st;
    if (!z) return red_error(galerkin, FPL_ERR_ARG, "z: NULL pointer");
    if (!(dt > 0.0) || !isfinite(dt))
        return red_error(galerkin, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", dt);
    if (nsteps < 0)
        return red_error(galerkin, FPL_ERR_ARG, "nsteps must be >= 0 (got %ld)", nsteps);
    const long len = 2L * galerkin->m;
    st = check_finite_array(galerkin, "z", z, len);
    if (st) return st;
    second_order so = {galerkin->m, galerkin_accel, galerkin, galerkin->acc};
    const fpl_split_system sys = modal_system(&so);
    fpl_split_steps(scheme, &sys, z, dt, nsteps);
    long bad = -1;
    if (!fpl_is_finite_array(z, len, &bad))
        return red_error(galerkin, FPL_ERR_NONFINITE,
                         "state became non-finite (z[%ld] = %g) within %ld steps of dt = %g", bad,
                         z[bad], nsteps, dt);
    return FPL_OK;
}

int fpl_galerkin_run(const fpl_splitting *scheme, fpl_galerkin *galerkin, const double *z0,
                     double t0, double dt, const double *t_samples, int n_samples,
                     double *mode_energies, double *states, int *n_done)
{
    if (n_done) *n_done = 0;
    CHECK_GALERKIN(galerkin);
    int st = check_run_args(galerkin, scheme, z0, galerkin->m, t0, dt, t_samples, n_samples);
    if (st) return st;
    second_order so = {galerkin->m, galerkin_accel, galerkin, galerkin->acc};
    return run_system(galerkin, scheme, &so, z0, t0, dt, t_samples, n_samples, galerkin->omega,
                      mode_energies, states, n_done);
}
