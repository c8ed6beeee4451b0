/* The Toda lattice: unit masses, bond potential V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2)
 * (FPUT-alpha to third order in r, FPUT-alpha-beta with beta = 2 alpha^2/3 to fourth), on the
 * plain stretches d_b = x_b - x_{b-1}, with fixed ends or on a ring. Homogeneous: the chain is
 * integrable only so (a disorder v would make it one more non-integrable chain, which models 2
 * and 3 already are), so lattice.c refuses a non-uniform v and beta != 0.
 * The kicks form V'(d_b) and V''(d_b) from one expm1 per bond (fpl_expm1.h, branch-free, so the
 * bond loops vectorise) into the scratch arrays; the fused stepper below does the same a block
 * of particles at a time, with the drift fused in. */
#include "models_extra.h"
#include "model_terms.h"

#define FPL_INLINE static inline __attribute__((always_inline))

void fpl_toda_coefficients(double v, double *cl, double *cn, double *s, double *minv)
{
    (void)v;
    *cl = *cn = *s = *minv = 1.0;
}

/* phi_b = V'(d_b) (and kappa_b = V''(d_b) if `tangent`) for b = 0..N; ring: d_0 = x_0 - x_{N-1}
 * and bond N = bond 0; fixed: d_0 = x_0, d_N = -x_{N-1}. */
FPL_INLINE void toda_bonds(int n, const double *restrict x, double alpha, double *restrict phi,
                           double *restrict kap, const int ring, const int tangent)
{
    const double two_a = 2.0 * alpha, inv_2a = 0.5 / alpha;
    const double d0 = ring ? x[0] - x[n - 1] : x[0];
    double m = FPL_TODA_M(d0, two_a);
    phi[0] = FPL_TODA_PHI(m, inv_2a);
    if (tangent) kap[0] = FPL_TODA_KAPPA(m);
    for (int k = 1; k < n; k++) {
        const double mk = FPL_TODA_M(x[k] - x[k - 1], two_a);
        phi[k] = FPL_TODA_PHI(mk, inv_2a);
        if (tangent) kap[k] = FPL_TODA_KAPPA(mk);
    }
    if (ring) {
        phi[n] = phi[0];
        if (tangent) kap[n] = kap[0];
    } else {
        m = FPL_TODA_M(-x[n - 1], two_a);
        phi[n] = FPL_TODA_PHI(m, inv_2a);
        if (tangent) kap[n] = FPL_TODA_KAPPA(m);
    }
}

/* dphi_b = kappa_b dd_b, the stretches of the deviation vector dx. */
FPL_INLINE void toda_bond_tangent(int n, const double *restrict dx, const double *restrict kap,
                                  double *restrict dphi, const int ring)
{
    dphi[0] = kap[0] * (ring ? dx[0] - dx[n - 1] : dx[0]);
    for (int k = 1; k < n; k++)
        dphi[k] = kap[k] * (dx[k] - dx[k - 1]);
    dphi[n] = ring ? dphi[0] : kap[n] * -dx[n - 1];
}

FPL_INLINE void add_divergence_unit(int n, double h, const double *restrict phi,
                                    double *restrict p)
{
    for (int i = 0; i < n; i++)
        FPL_KICK_UNIT(p[i], h, phi[i + 1], phi[i]);
}

FPL_INLINE void toda_kick_body(const fpl_lattice_ctx *c, double *y, double h, const int ring)
{
    const fpl_lattice *lat = c->lat;
    fpl_work *w = c->work;
    const int n = lat->n, n_dev = c->n_dev;
    if (n_dev == 0)
        toda_bonds(n, y, lat->alpha, w->phi, w->kappa, ring, 0);
    else
        toda_bonds(n, y, lat->alpha, w->phi, w->kappa, ring, 1);
    add_divergence_unit(n, h, w->phi, y + n);
    for (int m = 0; m < n_dev; m++) {
        double *dx = y + 2 * (size_t)n * (size_t)(m + 1);
        toda_bond_tangent(n, dx, w->kappa, w->dphi, ring);
        add_divergence_unit(n, h, w->dphi, dx + n);
    }
}

FPL_HOT void fpl_toda_kick_fixed(void *ctx, double *y, double h)
{
    toda_kick_body(ctx, y, h, 0);
}

FPL_HOT void fpl_toda_kick_periodic(void *ctx, double *y, double h)
{
    toda_kick_body(ctx, y, h, 1);
}

/* ---- the fused stepper ------------------------------------------------------------------- */

/* n steps of a drift-kick scheme in one pass per stage, as models.c's stage_fused does for
 * models 1-3: the drift runs a block of particles ahead of the kick (particles [done, i1]
 * drifted just before the kick of particles [i0, i1), whose bonds i0..i1 reach x_{i0-1}..x_{i1}),
 * and the last drift of a step and the first of the next are applied to each element in one
 * pass (x += h_s p, then x += h_0 p). A block's bond terms (phi, kappa, the vectors' dphi: at
 * most TODA_BLOCK + 1 entries of the scratch arrays, which stay in L1) are formed once per bond
 * with toda_bonds' expressions, and the momenta kicked from them as add_divergence_unit does.
 * The blocks cover the interior particles 1..N-2 (interior bonds only); particles 0 and N-1
 * (whose bond 0, on a ring, needs x_{N-1} drifted) are kicked after the last block, their four
 * bonds' expm1 in one four-lane call (at N = 64 three scalar calls a kick cost ~20 %). Every element gets the operations of fpl_split_step on fpl_drift_unit_mass /
 * fpl_toda_kick_*, in that order: bit-identical (tests/c/test_splitting.c). Any N >= 2 and any
 * number of deviation vectors. */
#define TODA_BLOCK 256

/* x += h0 p (if `pre`), then x += h p, particles [lo, hi). */
FPL_INLINE void toda_drift_range(int lo, int hi, double *restrict x, const double *restrict p,
                                 double h0, double h, const int pre)
{
    for (int i = lo; i < hi; i++) {
        if (pre) FPL_DRIFT_UNIT(x[i], h0, p[i]);
        FPL_DRIFT_UNIT(x[i], h, p[i]);
    }
}

/* phi and (if `tangent`) kappa of the cnt interior bonds whose right particles are xb[0..cnt-1]:
 * a multiple of four in the vectorised loop, the last 1-3 with the bonds before them (recomputed,
 * the same values; lanes past the bonds hold d = 0) in one four-lane call, not in the loop's
 * scalar remainder (at N = 16 a fifth of the bonds). */
#define TODA_LANE_D(l) (j0 + (l) < cnt ? xb[j0 + (l)] - xb[j0 + (l) - 1] : 0.0)
#define TODA_LANE_STORE(l)                                                                       \
    do {                                                                                         \
        if (j0 + (l) < cnt) {                                                                    \
            phi[j0 + (l)] = FPL_TODA_PHI(mv[l], inv_2a);                                         \
            if (tangent) kap[j0 + (l)] = FPL_TODA_KAPPA(mv[l]);                                  \
        }                                                                                        \
    } while (0)

FPL_INLINE void toda_block_bonds(int cnt, const double *restrict xb, double two_a, double inv_2a,
                                 double *restrict phi, double *restrict kap, const int tangent)
{
    const int body = cnt & ~3;
    for (int j = 0; j < body; j++) {
        const double m = FPL_TODA_M(xb[j] - xb[j - 1], two_a);
        phi[j] = FPL_TODA_PHI(m, inv_2a);
        if (tangent) kap[j] = FPL_TODA_KAPPA(m);
    }
    if (body < cnt) {
        const int j0 = cnt >= 4 ? cnt - 4 : 0;
        const fpl_v4d d = {TODA_LANE_D(0), TODA_LANE_D(1), TODA_LANE_D(2), TODA_LANE_D(3)};
        fpl_v4d mv;
        FPL_TODA_M_V4(mv, d, two_a);
        TODA_LANE_STORE(0);
        TODA_LANE_STORE(1);
        TODA_LANE_STORE(2);
        TODA_LANE_STORE(3);
    }
}

/* dphi of the same bonds for a deviation vector (ub: its coordinates from the block's first). */
FPL_INLINE void toda_block_tangent(int cnt, const double *restrict ub, const double *restrict kap,
                                   double *restrict dphi)
{
    for (int j = 0; j < cnt; j++)
        dphi[j] = kap[j] * (ub[j] - ub[j - 1]);
}

FPL_INLINE void toda_block_kick(int cnt, double *restrict pb, const double *restrict f, double h)
{
    for (int j = 0; j < cnt; j++)
        FPL_KICK_UNIT(pb[j], h, f[j + 1], f[j]);
}

/* One stage: drift by hd (after hd0 if `pre`), kick by hk. */
FPL_INLINE void toda_stage(const fpl_lattice_ctx *c, double *y, double hd0, double hd, double hk,
                           const int ring, const int tangent, const int pre)
{
    const int n = c->lat->n, n_dev = c->n_dev;
    const double two_a = 2.0 * c->lat->alpha, inv_2a = 0.5 / c->lat->alpha;
    const size_t stride = 2 * (size_t)n;
    double *restrict phi = c->work->phi, *restrict kap = c->work->kappa;
    double *restrict dphi = c->work->dphi;
    double *x = y, *p = y + n;
    int done = 0;   /* particles [0, done) drifted */
    for (int i0 = 1; i0 < n - 1; i0 += TODA_BLOCK) {
        const int i1 = i0 + TODA_BLOCK < n - 1 ? i0 + TODA_BLOCK : n - 1;
        const int d1 = i1 == n - 1 ? n : i1 + 1;
        for (int m = 0; m <= n_dev; m++)
            toda_drift_range(done, d1, y + stride * (size_t)m, y + stride * (size_t)m + n, hd0,
                             hd, pre);
        done = d1;
        /* bonds i0..i1 (all interior) at phi[0..i1-i0] */
        const int cnt = i1 - i0;
        toda_block_bonds(cnt + 1, x + i0, two_a, inv_2a, phi, kap, tangent);
        toda_block_kick(cnt, p + i0, phi, hk);
        for (int m = 1; m <= n_dev; m++) {
            const double *u = y + stride * (size_t)m;
            toda_block_tangent(cnt + 1, u + i0, kap, dphi);
            toda_block_kick(cnt, (double *)u + n + i0, dphi, hk);
        }
    }
    for (int m = 0; m <= n_dev && done < n; m++)   /* N = 2: no interior particle */
        toda_drift_range(done, n, y + stride * (size_t)m, y + stride * (size_t)m + n, hd0, hd,
                         pre);
    /* particles 0 and N-1: bonds 0, 1, N-1 and N (on a ring bond N is bond 0; N = 2: bond N-1
     * is bond 1), their expm1 four lanes at once (the scalar function's bits) */
    const fpl_v4d d = {ring ? x[0] - x[n - 1] : x[0], x[1] - x[0], x[n - 1] - x[n - 2],
                       ring ? x[0] - x[n - 1] : -x[n - 1]};
    fpl_v4d mv;
    FPL_TODA_M_V4(mv, d, two_a);
    FPL_KICK_UNIT(p[0], hk, FPL_TODA_PHI(mv[1], inv_2a), FPL_TODA_PHI(mv[0], inv_2a));
    FPL_KICK_UNIT(p[n - 1], hk, FPL_TODA_PHI(mv[3], inv_2a), FPL_TODA_PHI(mv[2], inv_2a));
    for (int m = 1; m <= n_dev; m++) {
        const double *u = y + stride * (size_t)m;
        double *q = (double *)u + n;
        const double t0 = FPL_TODA_KAPPA(mv[0]) * (ring ? u[0] - u[n - 1] : u[0]);
        const double t1 = FPL_TODA_KAPPA(mv[1]) * (u[1] - u[0]);
        const double tm = FPL_TODA_KAPPA(mv[2]) * (u[n - 1] - u[n - 2]);
        const double tn = FPL_TODA_KAPPA(mv[3]) * (ring ? u[0] - u[n - 1] : -u[n - 1]);
        FPL_KICK_UNIT(q[0], hk, t1, t0);
        FPL_KICK_UNIT(q[n - 1], hk, tn, tm);
    }
}

FPL_INLINE void toda_steps_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c, double *y,
                                double dt, long nsteps, const int ring, const int tangent)
{
    const int st = scheme->n_kicks, n = c->lat->n;
    const double *da = scheme->drift, *kb = scheme->kick;
    const size_t stride = 2 * (size_t)n;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            if (i == 0 && k > 0)
                toda_stage(c, y, da[st] * dt, da[0] * dt, kb[0] * dt, ring, tangent, 1);
            else
                toda_stage(c, y, 0.0, da[i] * dt, kb[i] * dt, ring, tangent, 0);
        }
    }
    if (nsteps > 0)
        for (int m = 0; m <= c->n_dev; m++)
            toda_drift_range(0, n, y + stride * (size_t)m, y + stride * (size_t)m + n, 0.0,
                             da[st] * dt, 0);
}

FPL_HOT void fpl_toda_steps_fixed(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                                  long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->n_dev == 0) toda_steps_body(scheme, c, y, dt, nsteps, 0, 0);
    else toda_steps_body(scheme, c, y, dt, nsteps, 0, 1);
}

FPL_HOT void fpl_toda_steps_periodic(const fpl_splitting *scheme, void *ctx, double *y, double dt,
                                     long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->n_dev == 0) toda_steps_body(scheme, c, y, dt, nsteps, 1, 0);
    else toda_steps_body(scheme, c, y, dt, nsteps, 1, 1);
}
