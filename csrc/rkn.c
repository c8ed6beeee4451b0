/* Explicit Runge-Kutta-Nystrom methods as fixed-step schemes (tables in integrators/dprkn*.c).
 *
 * Why: at tight accuracy a high-order RKN needs far fewer force evaluations than any symplectic
 * composition: on the homogeneous chain (N = 64, mode 1, 2 deviation vectors, T = 100) DPRKN12
 * reaches a state error of 1e-9 with ~1700 evaluations, srkn14a6 needs ~8000. It is not
 * symplectic (the energy error grows with time), so it is for short, precise runs and reference
 * solutions; long runs and the chaos study stay with the compositions.
 *
 * The method runs on the lattice's own kinetic split, using its drift and kick as black boxes,
 * so it works for every model and carries the deviation vectors with the method's own tangent
 * map (an RK method commutes with linearisation: applied to (x, dx) with forces (F(x), J(x) dx)
 * it yields the derivative of its numerical map). With v = M^-1 p and one full-state buffer Z_i
 * per stage (x-halves: the stage positions X_i; p-halves: the stage forces K_i):
 *   Z_i.p = c_i p + h sum_{j<i} a_ij K_j,  Z_i.x = x,  drift(Z_i, h)  =>  Z_i.x = X_i,
 *   Z_i.p = 0,  kick(Z_i, 1)  =>  Z_i.p = F(X_i) = K_i (and J(X_i) dX_i for the vectors);
 *   W.p = p + h sum_i b_i K_i,  W.x = x,  drift(W, h)  =>  x' = W.x;  p' = p + h sum_i bp_i K_i.
 * The buffers are allocated once per run (run_setup); a step allocates nothing. */
#include <stdlib.h>
#include <string.h>
#include "internal.h"

/* Terms of one linear combination: at most one per stage. */
#define RKN_MAX_STAGES 32

typedef struct rkn_state {
    const fpl_rkn_table *tab;
    fpl_split_system inner;   /* the lattice's kinetic split (drift, kick; ctx = the run) */
    int n;                    /* particles: each vector is [x (n), p (n)] */
    int nvec;                 /* orbit + deviation vectors */
    long dim;
    double *z;                /* stages x dim */
    double *w;                /* dim */
} rkn_state;

/* out = c0 base + sum_t coef[t] src[t] on the p-halves of every vector (base NULL: c0 = 0;
 * base == out: out += ..., c0 must be 1). Up to four terms per pass, the base folded into the
 * first (a quarter of the loads and stores of one pass per term); zero coefficients are already
 * dropped by the caller. */
FPL_HOT static void combine_p(const rkn_state *st, double *out, double c0, const double *base,
                              int nterm, const double *coef, double *const *src)
{
    const int n = st->n;
    for (int m = 0; m < st->nvec; m++) {
        const size_t off = 2 * (size_t)n * (size_t)m + (size_t)n;
        double *restrict o = out + off;
        int t = 0;
        if (base != out) {          /* first pass: o = c0 base + (up to) four terms */
            const int g = nterm < 4 ? nterm : 4;
            if (g == 0) {
                if (base) {
                    const double *b0 = base + off;
                    for (int i = 0; i < n; i++) o[i] = c0 * b0[i];
                } else {
                    memset(o, 0, sizeof(double) * (size_t)n);
                }
                continue;
            }
            /* missing terms: coefficient 0 on the first source (a computed stage, never the
             * uninitialised output) */
            const double *s0 = src[0] + off, *s1 = g > 1 ? src[1] + off : s0;
            const double *s2 = g > 2 ? src[2] + off : s0, *s3 = g > 3 ? src[3] + off : s0;
            const double k0 = coef[0], k1 = g > 1 ? coef[1] : 0.0, k2 = g > 2 ? coef[2] : 0.0,
                         k3 = g > 3 ? coef[3] : 0.0;
            if (base) {
                const double *b0 = base + off;
                for (int i = 0; i < n; i++)
                    o[i] = c0 * b0[i] + k0 * s0[i] + k1 * s1[i] + k2 * s2[i] + k3 * s3[i];
            } else {
                for (int i = 0; i < n; i++)
                    o[i] = k0 * s0[i] + k1 * s1[i] + k2 * s2[i] + k3 * s3[i];
            }
            t = g;
        }
        for (; t < nterm; t += 4) {
            const int g = nterm - t < 4 ? nterm - t : 4;
            const double *s0 = src[t] + off, *s1 = g > 1 ? src[t + 1] + off : s0;
            const double *s2 = g > 2 ? src[t + 2] + off : s0, *s3 = g > 3 ? src[t + 3] + off : s0;
            const double k0 = coef[t], k1 = g > 1 ? coef[t + 1] : 0.0,
                         k2 = g > 2 ? coef[t + 2] : 0.0, k3 = g > 3 ? coef[t + 3] : 0.0;
            for (int i = 0; i < n; i++)
                o[i] += k0 * s0[i] + k1 * s1[i] + k2 * s2[i] + k3 * s3[i];
        }
    }
}

/* dst.x-halves = src.x-halves (dst.p-halves untouched). */
static void copy_x(const rkn_state *st, double *dst, const double *src)
{
    const size_t n = (size_t)st->n;
    for (int m = 0; m < st->nvec; m++)
        memcpy(dst + 2 * n * (size_t)m, src + 2 * n * (size_t)m, sizeof(double) * n);
}

static void zero_p(const rkn_state *st, double *y)
{
    const size_t n = (size_t)st->n;
    for (int m = 0; m < st->nvec; m++)
        memset(y + 2 * n * (size_t)m + n, 0, sizeof(double) * n);
}

/* The terms h * w[j] K_j with w[j] != 0 (j < count) into coef/src; returns their number. */
static int gather(const rkn_state *st, const double *w, int count, double h, double *coef,
                  double **src)
{
    int k = 0;
    for (int j = 0; j < count; j++)
        if (w[j] != 0.0) {
            coef[k] = h * w[j];
            src[k++] = st->z + (size_t)j * (size_t)st->dim;
        }
    return k;
}

static void rkn_steps(const fpl_splitting *scheme, void *ctx, double *y, double dt, long nsteps)
{
    (void)scheme;
    const fpl_split_run *run = ctx;
    const rkn_state *st = run->state;
    const fpl_rkn_table *T = st->tab;
    const int s = T->stages;
    const fpl_split_system *sys = &st->inner;
    double coef[RKN_MAX_STAGES], *src[RKN_MAX_STAGES];
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < s; i++) {
            double *zi = st->z + (size_t)i * (size_t)st->dim;
            int nt = gather(st, T->a + (size_t)i * (size_t)s, i, dt, coef, src);
            combine_p(st, zi, T->c[i], y, nt, coef, src);
            copy_x(st, zi, y);
            sys->drift(sys->ctx, zi, 0, dt);
            zero_p(st, zi);
            sys->kick(sys->ctx, zi, 1.0);
        }
        int nt = gather(st, T->b, s, dt, coef, src);
        combine_p(st, st->w, 1.0, y, nt, coef, src);
        copy_x(st, st->w, y);
        sys->drift(sys->ctx, st->w, 0, dt);
        copy_x(st, y, st->w);
        nt = gather(st, T->bp, s, dt, coef, src);
        combine_p(st, y, 1.0, y, nt, coef, src);
    }
}

int fpl_rkn_run_setup(const fpl_splitting *scheme, fpl_split_run *run)
{
    const fpl_rkn_table *T = scheme->rkn;
    if (!T || T->stages < 1 || T->stages > RKN_MAX_STAGES)
        return fpl_error(NULL, FPL_ERR_ARG, "method '%s': not an RKN table of 1..%d stages",
                         scheme->name, RKN_MAX_STAGES);
    int mst = fpl_check_alloc((size_t)run->sys.dim, (size_t)T->stages * sizeof(double),
                              "the RKN stage vectors");
    if (mst) return mst;
    rkn_state *st = calloc(1, sizeof *st);
    if (!st) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (%s)", scheme->name);
    st->tab = T;
    st->inner = run->sys;          /* the kinetic split fpl_split_run_init set up */
    st->inner.steps = NULL;
    st->n = run->lc.lat->n;
    st->nvec = run->lc.n_dev + 1;
    st->dim = run->sys.dim;
    st->z = malloc(sizeof(double) * (size_t)st->dim * (size_t)T->stages);
    st->w = malloc(sizeof(double) * (size_t)st->dim);
    if (!st->z || !st->w) {
        const long dim = st->dim;
        fpl_rkn_state_free(st);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (%s, %d stages of %ld doubles)",
                         scheme->name, T->stages, dim);
    }
    run->state = st;
    run->sys.steps = rkn_steps;
    run->sys.begin_step = NULL;
    return FPL_OK;
}

void fpl_rkn_state_free(void *state)
{
    rkn_state *st = state;
    if (!st) return;
    free(st->z);
    free(st->w);
    free(st);
}
