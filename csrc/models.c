/* The three lattice models as data: how their coefficient arrays follow from v, and kernels.
 * Hot kernels are branch-free loops over contiguous arrays; the boundary bonds (to the fixed
 * ends) are peeled off so the interior loops vectorise. See internal.h for the notation. */
#include <stdio.h>
#include <string.h>
#include "models_extra.h"
#include "model_terms.h"

/* Inlined into the kicks so that their AVX2 clones (FPL_HOT) vectorise these loops 4-wide too. */
#define FPL_INLINE static inline __attribute__((always_inline))

/* ---- bond quantities ------------------------------------------------------------------- */

/* phi_b = L_b + alpha R_b^2 + beta R_b^3 and, if kap != NULL, kappa_b = 2 alpha R_b + 3 beta R_b^2. */
FPL_INLINE void bond_forces_generic(int n, const double *restrict x, const double *restrict cl,
                                const double *restrict cn, double a, double b,
                                double *restrict phi, double *restrict kap)
{
    double L = cl[0] * x[0], R = cn[0] * x[0];
    phi[0] = FPL_PHI(L, R, a, b);
    if (kap) kap[0] = FPL_KAPPA(R, a, b);
    if (kap) {
        for (int k = 1; k < n; k++) {
            double Lk = cl[k] * x[k] - cl[k - 1] * x[k - 1];
            double Rk = cn[k] * x[k] - cn[k - 1] * x[k - 1];
            phi[k] = FPL_PHI(Lk, Rk, a, b);
            kap[k] = FPL_KAPPA(Rk, a, b);
        }
    } else {
        for (int k = 1; k < n; k++) {
            double Lk = cl[k] * x[k] - cl[k - 1] * x[k - 1];
            double Rk = cn[k] * x[k] - cn[k - 1] * x[k - 1];
            phi[k] = FPL_PHI(Lk, Rk, a, b);
        }
    }
    L = -cl[n - 1] * x[n - 1];
    R = -cn[n - 1] * x[n - 1];
    phi[n] = FPL_PHI(L, R, a, b);
    if (kap) kap[n] = FPL_KAPPA(R, a, b);
}

FPL_INLINE void bond_forces_homogeneous(int n, const double *restrict x, double a, double b,
                                    double *restrict phi, double *restrict kap)
{
    double d = x[0];
    phi[0] = FPL_HOM_PHI(d, a, b);
    if (kap) kap[0] = FPL_HOM_KAPPA(d, a, b);
    if (kap) {
        for (int k = 1; k < n; k++) {
            double dk = x[k] - x[k - 1];
            phi[k] = FPL_HOM_PHI(dk, a, b);
            kap[k] = FPL_HOM_KAPPA(dk, a, b);
        }
    } else {
        for (int k = 1; k < n; k++) {
            double dk = x[k] - x[k - 1];
            phi[k] = FPL_HOM_PHI(dk, a, b);
        }
    }
    d = -x[n - 1];
    phi[n] = FPL_HOM_PHI(d, a, b);
    if (kap) kap[n] = FPL_HOM_KAPPA(d, a, b);
}

/* Tangent bond forces dphi_b = dL_b + kappa_b dR_b. */
FPL_INLINE void bond_tangent_generic(int n, const double *restrict dx, const double *restrict cl,
                                 const double *restrict cn, const double *restrict kap,
                                 double *restrict dphi)
{
    dphi[0] = FPL_DPHI_LEFT(cl[0] * dx[0], kap[0], cn[0], dx[0]);
    for (int k = 1; k < n; k++)
        dphi[k] = FPL_DPHI(cl[k] * dx[k] - cl[k - 1] * dx[k - 1], kap[k],
                           cn[k] * dx[k] - cn[k - 1] * dx[k - 1]);
    dphi[n] = FPL_DPHI_RIGHT(-cl[n - 1] * dx[n - 1], kap[n], cn[n - 1], dx[n - 1]);
}

/* Homogeneous: kap already holds the full curvature V''(d_b). */
FPL_INLINE void bond_tangent_homogeneous(int n, const double *restrict dx, const double *restrict kap,
                                     double *restrict dphi)
{
    dphi[0] = kap[0] * dx[0];
    for (int k = 1; k < n; k++)
        dphi[k] = kap[k] * (dx[k] - dx[k - 1]);
    dphi[n] = -kap[n] * dx[n - 1];
}

FPL_INLINE void add_divergence(int n, double h, const double *restrict s, const double *restrict phi,
                           double *restrict p)
{
    for (int i = 0; i < n; i++)
        FPL_KICK(p[i], h, s[i], phi[i + 1], phi[i]);
}

FPL_INLINE void add_divergence_unit(int n, double h, const double *restrict phi, double *restrict p)
{
    for (int i = 0; i < n; i++)
        FPL_KICK_UNIT(p[i], h, phi[i + 1], phi[i]);
}

/* ---- kicks (the hot path of the splitting schemes) ------------------------------------- */

FPL_HOT static void kick_generic(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    const fpl_lattice *lat = c->lat;
    fpl_work *w = c->work;
    const int n = lat->n, n_dev = c->n_dev;
    bond_forces_generic(n, y, lat->cl, lat->cn, lat->alpha, lat->beta, w->phi,
                        n_dev > 0 ? w->kappa : NULL);
    add_divergence(n, h, lat->s, w->phi, y + n);
    for (int m = 0; m < n_dev; m++) {
        double *dx = y + 2 * (size_t)n * (size_t)(m + 1);
        bond_tangent_generic(n, dx, lat->cl, lat->cn, w->kappa, w->dphi);
        add_divergence(n, h, lat->s, w->dphi, dx + n);
    }
}

/* The homogeneous kick with the bond forces formed where they are used: each particle computes
 * its two bonds' phi (every interior bond twice, two flops cheaper than a store and a load) and
 * the deviation vectors' tangent bond forces likewise from kappa, so the only scratch array
 * streamed is kappa (the phi/dphi passes of bond_forces_homogeneous / bond_tangent_homogeneous
 * cost ~2x at large N, benchmarks/roofline.c). Same expressions in the same order as those:
 * bit-identical results. */
#define PHI_H(d) FPL_HOM_PHI(d, a, b)
#define KAP_H(d) FPL_HOM_KAPPA(d, a, b)
/* The loops take `cubic` as a constant (their callers are inlined with 0 or 1): with beta = 0 the
 * cubic terms are dropped, 4 of ~20 flops a particle, with the same bits (model_terms.h). */
#define PHI_C(d) (cubic ? PHI_H(d) : FPL_HOM_PHI_QUAD(d, a))
#define KAP_C(d) (cubic ? KAP_H(d) : FPL_HOM_KAPPA_QUAD(d, a))

FPL_INLINE void kick_orbit_homogeneous(int lo, int hi, const double *restrict x,
                                       double *restrict p,
                                       double a, double b, double h, double *restrict kap,
                                       const int cubic)
{
    for (int i = lo; i < hi; i++) {
        const double dl = x[i] - x[i - 1], dr = x[i + 1] - x[i];
        FPL_KICK_UNIT(p[i], h, PHI_C(dr), PHI_C(dl));
        if (kap) kap[i] = KAP_C(dl);
    }
}

FPL_INLINE void kick_tangent_homogeneous(int n, const double *restrict dx, double *restrict dp,
                                         const double *restrict kap, double h)
{
    for (int i = 1; i < n - 1; i++)
        FPL_KICK_UNIT(dp[i], h, kap[i + 1] * (dx[i + 1] - dx[i]), kap[i] * (dx[i] - dx[i - 1]));
}

/* Chains without an interior particle (N < 3): the bond-array form. Kept out of line (noipa) so
 * that the compiler does not specialise its loops for N < 3, where they cannot vectorise (the
 * benchmark's vectorisation check reads every loop of the hot path). */
__attribute__((noipa)) static void kick_homogeneous_short(const fpl_lattice *lat, fpl_work *w,
                                                         double *y, int n_dev, double h)
{
    const int n = lat->n;
    bond_forces_homogeneous(n, y, lat->alpha, lat->beta, w->phi, n_dev > 0 ? w->kappa : NULL);
    add_divergence_unit(n, h, w->phi, y + n);
    for (int m = 0; m < n_dev; m++) {
        double *dx = y + 2 * (size_t)n * (size_t)(m + 1);
        bond_tangent_homogeneous(n, dx, w->kappa, w->dphi);
        add_divergence_unit(n, h, w->dphi, dx + n);
    }
}

/* The orbit and one or two deviation vectors in one pass: the curvatures kappa are formed where
 * they are used (KAP_H of the same two bonds, the same values the kappa array would hold), so
 * nothing but the state is streamed and kappa is not re-read once per vector (out of cache that
 * pass cost ~1.6x the plain-C roofline, benchmarks/roofline.c). Same expressions in the same
 * order as the vector-by-vector form below: bit-identical results. */
FPL_INLINE void kick_orbit_tangent_homogeneous(int lo, int hi, const double *restrict x,
                                               double *restrict p, const double *restrict u,
                                               double *restrict q, const double *restrict w,
                                               double *restrict r, double a, double b, double h,
                                               const int cubic, const int two)
{
    /* `two` is a constant at every (inlined) call: the second vector's line is there or not */
    for (int i = lo; i < hi; i++) {
        const double dl = x[i] - x[i - 1], dr = x[i + 1] - x[i];
        FPL_KICK_UNIT(p[i], h, PHI_C(dr), PHI_C(dl));
        const double kl = KAP_C(dl), kr = KAP_C(dr);
        FPL_KICK_UNIT(q[i], h, kr * (u[i + 1] - u[i]), kl * (u[i] - u[i - 1]));
        if (two) FPL_KICK_UNIT(r[i], h, kr * (w[i + 1] - w[i]), kl * (w[i] - w[i - 1]));
    }
}

/* dp^(m)_0 and dp^(m)_{n-1}: the particles next to the walls (bonds 0, 1, n-1, n). */
FPL_INLINE void kick_tangent_ends(int n, const double *dx, double *dp, double k0, double k1,
                                  double km, double kn, double h)
{
    const double t0 = k0 * dx[0], t1 = k1 * (dx[1] - dx[0]);
    const double tm = km * (dx[n - 1] - dx[n - 2]), tn = -kn * dx[n - 1];
    FPL_KICK_UNIT(dp[0], h, t1, t0);
    FPL_KICK_UNIT(dp[n - 1], h, tn, tm);
}

FPL_INLINE void kick_homogeneous_body(const fpl_lattice_ctx *c, double *y, double h,
                                      const int cubic)
{
    const fpl_lattice *lat = c->lat;
    fpl_work *w = c->work;
    const int n = lat->n, n_dev = c->n_dev;
    const double a = lat->alpha, b = lat->beta;
    if (n < 3) {
        kick_homogeneous_short(lat, w, y, n_dev, h);
        return;
    }
    const size_t stride = 2 * (size_t)n;   /* one vector [x p] */
    const double *x = y;
    double *p = y + n, *kap = w->kappa;
    /* boundary bonds 0 (wall to particle 0) and n (particle n-1 to wall), and bonds 1, n-1 */
    const double d0 = x[0], d1 = x[1] - x[0];
    const double dm = x[n - 1] - x[n - 2], dn = -x[n - 1];
    const double phi0 = PHI_H(d0), phi1 = PHI_H(d1), phim = PHI_H(dm), phin = PHI_H(dn);
    const double k0 = KAP_H(d0), k1 = KAP_H(d1), km = KAP_H(dm), kn = KAP_H(dn);
    if (n_dev == 0) {
        kick_orbit_homogeneous(1, n - 1, x, p, a, b, h, NULL, cubic);
    } else if (n_dev == 1) {
        kick_orbit_tangent_homogeneous(1, n - 1, x, p, y + stride, y + stride + n, NULL, NULL, a,
                                       b, h, cubic, 0);
    } else if (n_dev == 2) {
        kick_orbit_tangent_homogeneous(1, n - 1, x, p, y + stride, y + stride + n, y + 2 * stride,
                                       y + 2 * stride + n, a, b, h, cubic, 1);
    } else {
        /* more vectors (GALI_k, k > 2): kappa once into the scratch array, then one pass each */
        kick_orbit_homogeneous(1, n - 1, x, p, a, b, h, kap, cubic);
        kap[0] = k0;
        kap[n - 1] = km;
        kap[n] = kn;
        for (int m = 0; m < n_dev; m++) {
            const double *dx = y + stride * (size_t)(m + 1);
            kick_tangent_homogeneous(n, dx, (double *)dx + n, kap, h);
        }
    }
    FPL_KICK_UNIT(p[0], h, phi1, phi0);
    FPL_KICK_UNIT(p[n - 1], h, phin, phim);
    for (int m = 0; m < n_dev; m++) {
        const double *dx = y + stride * (size_t)(m + 1);
        kick_tangent_ends(n, dx, (double *)dx + n, k0, k1, km, kn, h);
    }
}

/* ---- drifts ------------------------------------------------------------------------------ */

/* Kinetic drift x^(m) += h minv p^(m) for the orbit and every deviation vector (the drift is
 * linear, so its tangent map is itself). Unit masses skip minv: (h * 1) * p == h * p exactly,
 * so both forms give the same bits where minv = 1, and the unit form streams one array less. */
FPL_INLINE void drift_vector_unit(int n, double *restrict x, double h)
{
    const double *restrict p = x + n;
    for (int i = 0; i < n; i++)
        FPL_DRIFT_UNIT(x[i], h, p[i]);
}

FPL_INLINE void drift_vector_masses(int n, double *restrict x, const double *restrict minv,
                                    double h)
{
    const double *restrict p = x + n;
    for (int i = 0; i < n; i++)
        FPL_DRIFT(x[i], h, minv[i], p[i]);
}

FPL_INLINE void drift_unit_mass_body(const fpl_lattice_ctx *c, double *y, double h)
{
    const int n = c->lat->n, n_dev = c->n_dev;
    for (int m = 0; m <= n_dev; m++)
        drift_vector_unit(n, y + 2 * (size_t)n * m, h);
}

FPL_HOT static void drift_unit_mass(void *ctx, double *y, int stage, double h)
{
    (void)stage;
    drift_unit_mass_body(ctx, y, h);
}

FPL_INLINE void drift_masses_body(const fpl_lattice_ctx *c, double *y, double h)
{
    const int n = c->lat->n, n_dev = c->n_dev;
    for (int m = 0; m <= n_dev; m++)
        drift_vector_masses(n, y + 2 * (size_t)n * m, c->lat->minv, h);
}

FPL_HOT static void drift_masses(void *ctx, double *y, int stage, double h)
{
    (void)stage;
    drift_masses_body(ctx, y, h);
}

/* ---- the homogeneous chain's kick ---------------------------------------------------------- */

FPL_HOT static void kick_homogeneous(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_homogeneous_body(c, y, h, 0);
    else
        kick_homogeneous_body(c, y, h, 1);
}

/* ---- models 2 and 3: fused kicks ---------------------------------------------------------- */

/* The disordered models' kick with the bond terms formed where they are used, as the homogeneous
 * kick above: each particle computes its two bonds' phi (and kappa, and the deviation vectors'
 * dphi), so nothing but the state and cn (model 2: also s) is streamed; kick_generic's phi, kappa
 * and dphi arrays cost a store and a re-read per bond and vector (~1,030 against ~530 bytes per
 * particle-step, issue 22). `ham` is a constant at every (inlined) call: model 2 (cl = cn, so
 * L_b = R_b; s and minv) or model 3 (cl = s = minv = 1: the multiplications by 1 of the generic
 * kernels are exact and left out, L_b = x_b - x_{b-1}). The expressions are those of
 * bond_forces_generic / bond_tangent_generic / add_divergence in the same order (model_terms.h),
 * so the results are bit-identical to kick_generic's. Valid for N >= 3 (the wall bonds are
 * peeled off); shorter chains take kick_generic. */
#define R_IN(u, k) (cn[k] * (u)[k] - cn[(k) - 1] * (u)[(k) - 1])
#define L_IN(u, k) (ham ? R_IN(u, k) : (u)[k] - (u)[(k) - 1])
#define PHI_G(L, R) (cubic ? FPL_PHI(L, R, a, b) : FPL_PHI_QUAD(L, R, a))
#define KAP_G(R) (cubic ? FPL_KAPPA(R, a, b) : FPL_KAPPA_QUAD(R, a))
#define DPHI_IN(u, k, kap) FPL_DPHI(L_IN(u, k), kap, R_IN(u, k))
#define KICK_G(target, i, f1, f0) \
    do { if (ham) FPL_KICK(target, h, s[i], f1, f0); else FPL_KICK_UNIT(target, h, f1, f0); } while (0)

/* Particles in one block of the many-vector kick: kappa of a block's bonds (4 kB) stays in L1
 * while every deviation vector's tangent kick reads it. */
#define KICK_BLOCK 512

/* Interior particles [lo, hi) of the orbit; with kap, also kappa_b of bonds lo..hi into kap. */
FPL_INLINE void kick_orbit_general(int lo, int hi, const double *restrict x, double *restrict p,
                                   const double *restrict cn, const double *restrict s, double a,
                                   double b, double h, double *restrict kap, const int ham,
                                   const int cubic)
{
    for (int i = lo; i < hi; i++) {
        const double Rl = R_IN(x, i), Rr = R_IN(x, i + 1);
        KICK_G(p[i], i, PHI_G(L_IN(x, i + 1), Rr), PHI_G(L_IN(x, i), Rl));
        if (kap) kap[i] = KAP_G(Rl);
    }
    if (kap && hi > lo) kap[hi] = KAP_G(R_IN(x, hi));
}

/* Interior particles [lo, hi) of one deviation vector (u, q), kappa_b of bonds lo..hi in kap. */
FPL_INLINE void kick_tangent_general(int lo, int hi, const double *restrict u, double *restrict q,
                                     const double *restrict cn, const double *restrict s,
                                     const double *restrict kap, double h, const int ham)
{
    for (int i = lo; i < hi; i++)
        KICK_G(q[i], i, DPHI_IN(u, i + 1, kap[i + 1]), DPHI_IN(u, i, kap[i]));
}

/* The interior of the orbit and one or two deviation vectors in one pass (kappa of both bonds
 * formed in registers; `two` a constant). */
FPL_INLINE void kick_orbit_tangent_general(int lo, int hi, const double *restrict x,
                                           double *restrict p,
                                           const double *restrict u, double *restrict q,
                                           const double *restrict w, double *restrict r,
                                           const double *restrict cn, const double *restrict s,
                                           double a, double b, double h, const int ham,
                                           const int cubic, const int two)
{
    for (int i = lo; i < hi; i++) {
        const double Rl = R_IN(x, i), Rr = R_IN(x, i + 1);
        KICK_G(p[i], i, PHI_G(L_IN(x, i + 1), Rr), PHI_G(L_IN(x, i), Rl));
        const double kl = KAP_G(Rl), kr = KAP_G(Rr);
        KICK_G(q[i], i, DPHI_IN(u, i + 1, kr), DPHI_IN(u, i, kl));
        if (two) KICK_G(r[i], i, DPHI_IN(w, i + 1, kr), DPHI_IN(w, i, kl));
    }
}

/* Particles 0 and n-1 of one deviation vector (bonds 0, 1, n-1, n with their kappas). */
FPL_INLINE void kick_tangent_ends_general(int n, const double *dx, double *dp,
                                          const double *cn, const double *s, double k0,
                                          double k1, double km, double kn, double h,
                                          const int ham)
{
    const double t0 = FPL_DPHI_LEFT(ham ? cn[0] * dx[0] : dx[0], k0, cn[0], dx[0]);
    const double t1 = DPHI_IN(dx, 1, k1), tm = DPHI_IN(dx, n - 1, km);
    const double tn = FPL_DPHI_RIGHT(ham ? -cn[n - 1] * dx[n - 1] : -dx[n - 1], kn, cn[n - 1],
                                     dx[n - 1]);
    KICK_G(dp[0], 0, t1, t0);
    KICK_G(dp[n - 1], n - 1, tn, tm);
}

/* The kick of particles 1 .. n-2 (both bonds interior) for the orbit and the n_dev vectors, the
 * same on fixed ends and rings (the callers add the end particles). */
FPL_INLINE void kick_interior_general(const fpl_lattice_ctx *c, double *y, double h, const int ham,
                                      const int cubic)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    const double a = lat->alpha, b = lat->beta;
    const double *restrict cn = lat->cn, *restrict s = lat->s;
    const size_t stride = 2 * (size_t)n;   /* one vector [x p] */
    const double *x = y;
    double *p = y + n;
    if (n_dev == 0) {
        kick_orbit_general(1, n - 1, x, p, cn, s, a, b, h, NULL, ham, cubic);
    } else if (n_dev == 1) {
        kick_orbit_tangent_general(1, n - 1, x, p, y + stride, y + stride + n, NULL, NULL, cn, s,
                                   a, b, h, ham, cubic, 0);
    } else if (n_dev == 2) {
        kick_orbit_tangent_general(1, n - 1, x, p, y + stride, y + stride + n, y + 2 * stride,
                                   y + 2 * stride + n, cn, s, a, b, h, ham, cubic, 1);
    } else {
        /* many vectors (GALI_k, the Lyapunov spectrum): block by block, kappa of the block's
         * bonds once, then each vector's tangent kick on the block */
        double *kap = c->work->kappa;
        for (int i0 = 1; i0 < n - 1; i0 += KICK_BLOCK) {
            const int i1 = i0 + KICK_BLOCK < n - 1 ? i0 + KICK_BLOCK : n - 1;
            kick_orbit_general(i0, i1, x, p, cn, s, a, b, h, kap, ham, cubic);
            for (int m = 1; m <= n_dev; m++) {
                const double *dx = y + stride * (size_t)m;
                kick_tangent_general(i0, i1, dx, (double *)dx + n, cn, s, kap, h, ham);
            }
        }
    }
}

FPL_INLINE void kick_general_body(const fpl_lattice_ctx *c, double *y, double h, const int ham,
                                  const int cubic)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    if (n < 3) {
        kick_generic((void *)c, y, h);
        return;
    }
    const double a = lat->alpha, b = lat->beta;
    const double *restrict cn = lat->cn, *restrict s = lat->s;
    const size_t stride = 2 * (size_t)n;   /* one vector [x p] */
    const double *x = y;
    double *p = y + n;
    /* the wall bonds 0 and n, and bonds 1 and n-1 */
    const double L0 = ham ? cn[0] * x[0] : x[0], R0 = cn[0] * x[0];
    const double Ln = ham ? -cn[n - 1] * x[n - 1] : -x[n - 1], Rn = -cn[n - 1] * x[n - 1];
    const double R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
    const double phi0 = PHI_G(L0, R0), phi1 = PHI_G(L_IN(x, 1), R1);
    const double phim = PHI_G(L_IN(x, n - 1), Rm), phin = PHI_G(Ln, Rn);
    const double k0 = KAP_G(R0), k1 = KAP_G(R1), km = KAP_G(Rm), kn = KAP_G(Rn);
    kick_interior_general(c, y, h, ham, cubic);
    KICK_G(p[0], 0, phi1, phi0);
    KICK_G(p[n - 1], n - 1, phin, phim);
    for (int m = 1; m <= n_dev; m++) {
        const double *dx = y + stride * (size_t)m;
        kick_tangent_ends_general(n, dx, (double *)dx + n, cn, s, k0, k1, km, kn, h, ham);
    }
}

FPL_HOT static void kick_hamiltonian(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_general_body(c, y, h, 1, 0);
    else
        kick_general_body(c, y, h, 1, 1);
}

FPL_HOT static void kick_nonlinear(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_general_body(c, y, h, 0, 0);
    else
        kick_general_body(c, y, h, 0, 1);
}

/* ---- the periodic models 2 and 3: fused kicks and steppers -------------------------------- */

/* On the ring bond 0 joins particle N-1 and 0 (x_N = x_0): kick_general_body's interior loops
 * serve particles 1..N-2 unchanged, and only the two end particles see the wrap-around bond.
 * The expressions are kick_generic_periodic's (models_periodic.c) with the exact factors 1 of
 * model 3 (cl, s) left out and model 2's L_b = R_b formed as R_b (cl = cn): bit-identical to it.
 * N >= 3; shorter rings take fpl_kick_generic_periodic. */
#define R_WRAP(u) (cn[0] * (u)[0] - cn[n - 1] * (u)[n - 1])
#define L_WRAP(u) (ham ? R_WRAP(u) : (u)[0] - (u)[n - 1])

/* The ring's end particles 0 and N-1 of one deviation vector from the curvatures kw (the
 * wrap-around bond), k1 and km (bonds 1 and N-1), for every model (`model` a constant): the
 * expressions of kick_ring_body (models_periodic.c) and kick_general_ring_body below. */
FPL_INLINE void kick_tangent_ends_ring(int n, const double *dx, double *dp, const double *cn,
                                       const double *s, double kw, double k1, double km, double h,
                                       const int model)
{
    if (model == FPL_MODEL_HOMOGENEOUS) {
        const double tw = kw * (dx[0] - dx[n - 1]);
        FPL_KICK_UNIT(dp[0], h, k1 * (dx[1] - dx[0]), tw);
        FPL_KICK_UNIT(dp[n - 1], h, tw, km * (dx[n - 1] - dx[n - 2]));
        return;
    }
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double tw = FPL_DPHI(L_WRAP(dx), kw, R_WRAP(dx));
    const double t1 = DPHI_IN(dx, 1, k1), tm = DPHI_IN(dx, n - 1, km);
    KICK_G(dp[0], 0, t1, tw);
    KICK_G(dp[n - 1], n - 1, tw, tm);
}

/* The ring's end particles of the orbit and of nv = 0, 1 or 2 deviation vectors (u, q), (w, r)
 * (the fused stage's ends); with kap, also kappa of bonds 0 = N and N-1 into it (the
 * many-vector step's). The expressions of kick_ring_body / kick_general_ring_body. */
FPL_INLINE void kick_ring_ends(int n, const double *x, double *p, const double *u, double *q,
                               const double *w, double *r, const double *cn, const double *s,
                               double a, double b, double h, double *kap, const int model,
                               const int cubic, const int nv)
{
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    double kw, k1, km;
    if (model == FPL_MODEL_HOMOGENEOUS) {
        const double dw = x[0] - x[n - 1], d1 = x[1] - x[0], dm = x[n - 1] - x[n - 2];
        const double phiw = PHI_C(dw), phi1 = PHI_C(d1), phim = PHI_C(dm);
        kw = KAP_C(dw), k1 = KAP_C(d1), km = KAP_C(dm);
        FPL_KICK_UNIT(p[0], h, phi1, phiw);
        FPL_KICK_UNIT(p[n - 1], h, phiw, phim);
    } else {
        const double Rw = R_WRAP(x), R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
        const double phiw = PHI_G(L_WRAP(x), Rw), phi1 = PHI_G(L_IN(x, 1), R1);
        const double phim = PHI_G(L_IN(x, n - 1), Rm);
        kw = KAP_G(Rw), k1 = KAP_G(R1), km = KAP_G(Rm);
        KICK_G(p[0], 0, phi1, phiw);
        KICK_G(p[n - 1], n - 1, phiw, phim);
    }
    if (kap) {
        kap[0] = kap[n] = kw;
        kap[n - 1] = km;
    }
    if (nv >= 1) kick_tangent_ends_ring(n, u, q, cn, s, kw, k1, km, h, model);
    if (nv == 2) kick_tangent_ends_ring(n, w, r, cn, s, kw, k1, km, h, model);
}

FPL_INLINE void kick_general_ring_body(const fpl_lattice_ctx *c, double *y, double h,
                                       const int ham, const int cubic)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    if (n < 3) {
        fpl_kick_generic_periodic((void *)c, y, h);
        return;
    }
    const double a = lat->alpha, b = lat->beta;
    const double *restrict cn = lat->cn, *restrict s = lat->s;
    const size_t stride = 2 * (size_t)n;
    const double *x = y;
    double *p = y + n;
    /* the wrap-around bond 0 (= bond N), and bonds 1 and N-1 */
    const double Rw = R_WRAP(x), R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
    const double phiw = PHI_G(L_WRAP(x), Rw), phi1 = PHI_G(L_IN(x, 1), R1);
    const double phim = PHI_G(L_IN(x, n - 1), Rm);
    const double kw = KAP_G(Rw), k1 = KAP_G(R1), km = KAP_G(Rm);
    kick_interior_general(c, y, h, ham, cubic);
    KICK_G(p[0], 0, phi1, phiw);
    KICK_G(p[n - 1], n - 1, phiw, phim);
    for (int m = 1; m <= n_dev; m++) {
        const double *dx = y + stride * (size_t)m;
        double *dp = (double *)dx + n;
        const double tw = FPL_DPHI(L_WRAP(dx), kw, R_WRAP(dx));
        const double t1 = DPHI_IN(dx, 1, k1), tm = DPHI_IN(dx, n - 1, km);
        KICK_G(dp[0], 0, t1, tw);
        KICK_G(dp[n - 1], n - 1, tw, tm);
    }
}

FPL_HOT void fpl_kick_ring_hamiltonian(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_general_ring_body(c, y, h, 1, 0);
    else
        kick_general_ring_body(c, y, h, 1, 1);
}

FPL_HOT void fpl_kick_ring_nonlinear(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_general_ring_body(c, y, h, 0, 0);
    else
        kick_general_ring_body(c, y, h, 0, 1);
}

/* n steps with drift and kick inlined: fpl_split_step on fpl_drift_masses (model 2) or
 * fpl_drift_unit_mass (model 3) and the ring kick above, the same operations in the same order
 * (the rings' steppers, after the fixed chains' below, take it where neither the fused stages
 * nor the many-vector steps apply). */
FPL_INLINE void steps_general_ring_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                        double *y, double dt, long nsteps, const int ham,
                                        const int cubic)
{
    const int st = scheme->n_kicks;
    const double *da = scheme->drift, *kb = scheme->kick;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            if (ham) drift_masses_body(c, y, da[i] * dt);
            else drift_unit_mass_body(c, y, da[i] * dt);
            kick_general_ring_body(c, y, kb[i] * dt, ham, cubic);
        }
        if (ham) drift_masses_body(c, y, da[st] * dt);
        else drift_unit_mass_body(c, y, da[st] * dt);
    }
}

/* ---- many deviation vectors: the step vector by vector ------------------------------------ */

/* With many deviation vectors (GALI_k, the Lyapunov spectrum with k up to 2N) the kick-by-kick
 * order streams every vector through the cache once per stage, 2s+1 passes a step. The tangent
 * map needs nothing from the orbit but the bond curvatures of each kick, so the step is taken in
 * two parts: the orbit through all stages, its kick writing kappa of every bond into row i of
 * work->kappa_stages (formed once per bond and kick); then the vectors, a block of them at a
 * time, through all stages with those rows, the block staying in L1 for the whole step. Every element gets exactly the
 * operations of the stage-by-stage order (the vectors do not interact): bit-identical. */

/* The orbit's kick (all particles) with kappa_b of every bond 0..N into kap (`ring`: the
 * periodic chain, a constant). */
FPL_INLINE void kick_orbit_kappa(const fpl_lattice *lat, double *y, double h, double *kap,
                                 const int model, const int cubic, const int ring)
{
    const int n = lat->n;
    const double a = lat->alpha, b = lat->beta;
    const double *x = y;
    double *p = y + n;
    if (ring) {   /* bond 0 = bond N: the wrap-around bond (its kappa in both rows) */
        if (model == FPL_MODEL_HOMOGENEOUS)
            kick_orbit_homogeneous(1, n - 1, x, p, a, b, h, kap, cubic);
        else
            kick_orbit_general(1, n - 1, x, p, lat->cn, lat->s, a, b, h, kap,
                               model == FPL_MODEL_HAMILTONIAN, cubic);
        kick_ring_ends(n, x, p, NULL, NULL, NULL, NULL, lat->cn, lat->s, a, b, h, kap, model,
                       cubic, 0);
        return;
    }
    if (model == FPL_MODEL_HOMOGENEOUS) {
        const double d0 = x[0], d1 = x[1] - x[0];
        const double dm = x[n - 1] - x[n - 2], dn = -x[n - 1];
        const double phi0 = PHI_H(d0), phi1 = PHI_H(d1), phim = PHI_H(dm), phin = PHI_H(dn);
        kick_orbit_homogeneous(1, n - 1, x, p, a, b, h, kap, cubic);
        kap[0] = KAP_H(d0);
        kap[n - 1] = KAP_H(dm);
        kap[n] = KAP_H(dn);
        FPL_KICK_UNIT(p[0], h, phi1, phi0);
        FPL_KICK_UNIT(p[n - 1], h, phin, phim);
        return;
    }
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double *restrict cn = lat->cn, *restrict s = lat->s;
    const double L0 = ham ? cn[0] * x[0] : x[0], R0 = cn[0] * x[0];
    const double Ln = ham ? -cn[n - 1] * x[n - 1] : -x[n - 1], Rn = -cn[n - 1] * x[n - 1];
    const double R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
    const double phi0 = PHI_G(L0, R0), phi1 = PHI_G(L_IN(x, 1), R1);
    const double phim = PHI_G(L_IN(x, n - 1), Rm), phin = PHI_G(Ln, Rn);
    kick_orbit_general(1, n - 1, x, p, cn, s, a, b, h, kap, ham, cubic);
    kap[0] = KAP_G(R0);
    kap[n] = KAP_G(Rn);
    KICK_G(p[0], 0, phi1, phi0);
    KICK_G(p[n - 1], n - 1, phin, phim);
}

/* One deviation vector's tangent kick (all particles) from the curvatures kap of bonds 0..N. */
FPL_INLINE void kick_tangent_vector(const fpl_lattice *lat, double *v, double h,
                                    const double *kap, const int model, const int ring)
{
    const int n = lat->n;
    const double *dx = v;
    double *dp = v + n;
    if (ring) {
        if (model == FPL_MODEL_HOMOGENEOUS)
            kick_tangent_homogeneous(n, dx, dp, kap, h);
        else
            kick_tangent_general(1, n - 1, dx, dp, lat->cn, lat->s, kap, h,
                                 model == FPL_MODEL_HAMILTONIAN);
        kick_tangent_ends_ring(n, dx, dp, lat->cn, lat->s, kap[0], kap[1], kap[n - 1], h, model);
        return;
    }
    if (model == FPL_MODEL_HOMOGENEOUS) {
        kick_tangent_homogeneous(n, dx, dp, kap, h);
        kick_tangent_ends(n, dx, dp, kap[0], kap[1], kap[n - 1], kap[n], h);
        return;
    }
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    kick_tangent_general(1, n - 1, dx, dp, lat->cn, lat->s, kap, h, ham);
    kick_tangent_ends_general(n, dx, dp, lat->cn, lat->s, kap[0], kap[1], kap[n - 1], kap[n], h,
                              ham);
}

FPL_INLINE void drift_vector(const fpl_lattice *lat, double *v, double h, const int model)
{
    if (model == FPL_MODEL_HAMILTONIAN) drift_vector_masses(lat->n, v, lat->minv, h);
    else drift_vector_unit(lat->n, v, h);
}

/* n steps, the orbit first and then each vector (N >= 3, scheme->n_kicks <= FPL_KAPPA_STAGES,
 * work->kappa_stages present). */
FPL_INLINE void steps_by_vector_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                     double *y, double dt, long nsteps, const int model,
                                     const int cubic, const int ring)
{
    const fpl_lattice *lat = c->lat;
    const int st = scheme->n_kicks, n = lat->n, n_dev = c->n_dev;
    const double *da = scheme->drift, *kb = scheme->kick;
    double *K = c->work->kappa_stages;
    const size_t stride = 2 * (size_t)n, rows = (size_t)n + 1;
    /* vectors in blocks of ~16 kB (half of L1): a vector's tangent kick reads dx_{i-1}, dx_i,
     * dx_{i+1} just stored by its drift, and unaligned loads over fresh stores stall (no store
     * forwarding) unless the block's other drifts come in between (3x slower at N = 16) */
    const int vb = n <= 512 ? 1024 / n : 1;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            drift_vector(lat, y, da[i] * dt, model);
            kick_orbit_kappa(lat, y, kb[i] * dt, K + rows * (size_t)i, model, cubic, ring);
        }
        drift_vector(lat, y, da[st] * dt, model);
        for (int m0 = 1; m0 <= n_dev; m0 += vb) {
            const int m1 = m0 + vb <= n_dev + 1 ? m0 + vb : n_dev + 1;
            for (int i = 0; i < st; i++) {
                for (int m = m0; m < m1; m++)
                    drift_vector(lat, y + stride * (size_t)m, da[i] * dt, model);
                for (int m = m0; m < m1; m++)
                    kick_tangent_vector(lat, y + stride * (size_t)m, kb[i] * dt,
                                        K + rows * (size_t)i, model, ring);
            }
            for (int m = m0; m < m1; m++)
                drift_vector(lat, y + stride * (size_t)m, da[st] * dt, model);
        }
    }
}

/* Whether the vector-by-vector step applies (else the stage-by-stage one): from 8 vectors and
 * N = 32 on it was 5-15 % faster (N = 32-512, k = 8-2N, all three models); with fewer vectors or
 * shorter chains the stage-by-stage kick with kappa in registers or one array is as fast or
 * faster (benchmarks/roofline.c, measured under load). Longer chains take the sweeps below
 * (steps_sweep_body: 11-23 % faster than this at N = 4096, k = 8, 16 and 2N). */
static int steps_by_vector(const fpl_splitting *scheme, const fpl_lattice_ctx *c)
{
    return c->n_dev >= 8 && c->lat->n >= 32 && c->lat->n <= FPL_VEC_INNER_MAX_N &&
           c->work->kappa_stages && scheme->n_kicks <= FPL_KAPPA_STAGES;
}

/* ---- many deviation vectors: vector-inner tiles ------------------------------------------ */

/* The vector-by-vector step above streams each vector along the chain, one vector at a time: a
 * bond's kappa is re-read once per vector and each tangent kick forms every bond term twice
 * (once for each of its particles). Here the vectors go in tiles of W (W = 4 or 8, a constant
 * at every inlined call) copied into the vector-inner layout of work->tile, row j = [dx_j of
 * the W vectors | dp_j of them], so that each bond's kappa multiplies W contiguous entries (SIMD
 * along the vectors) and each bond term is formed once and kept for the next row. The drift and
 * the kick of a stage are one pass over the rows (row j+1 is drifted just before row j's kick,
 * which needs it: a one-row lag). The orbit runs a group of steps first, keeping kappa of every
 * kick (work->kappa_rows rows); each tile is then copied in, taken through the whole group and
 * copied back (the O(N W) copies are paid once per group, up to 168 Yoshida steps at N = 64).
 * Every element gets the operations of the stage-by-stage kernels in the same order (the same
 * model_terms.h expressions; a bond term formed once has the value it had formed twice):
 * bit-identical. Padding lanes of the last tile hold zeros and are not copied back. */

/* Vectors m0..m0+cnt-1 (cnt <= W) of y into the tile, the other lanes zero. */
FPL_INLINE void tile_load(int n, const double *y, size_t stride, int m0, int cnt,
                          double *restrict t, const int W)
{
    for (int l = 0; l < W; l++) {
        if (l < cnt) {
            const double *v = y + stride * (size_t)(m0 + l);
            for (int j = 0; j < n; j++) {
                t[2 * W * (size_t)j + l] = v[j];
                t[2 * W * (size_t)j + W + l] = v[n + j];
            }
        } else {
            for (int j = 0; j < n; j++)
                t[2 * W * (size_t)j + l] = t[2 * W * (size_t)j + W + l] = 0.0;
        }
    }
}

FPL_INLINE void tile_store(int n, double *y, size_t stride, int m0, int cnt,
                           const double *restrict t, const int W)
{
    for (int l = 0; l < cnt; l++) {
        double *v = y + stride * (size_t)(m0 + l);
        for (int j = 0; j < n; j++) {
            v[j] = t[2 * W * (size_t)j + l];
            v[n + j] = t[2 * W * (size_t)j + W + l];
        }
    }
}

/* Four vectors' entries of a row as one value: GCC's generic vectors (one AVX2 register in the
 * x86-64-v3 clone, two SSE2 registers in the baseline one), element-wise IEEE operations, so each
 * lane computes exactly what the scalar code computes (as chaos_batch.c's lanes). A row of a
 * tile of W = 4 nv vectors is nv such values of x, then nv of p; the tile is 32-byte aligned. */
typedef double vec4 __attribute__((vector_size(4 * sizeof(double))));
#define TILE_ROW(t, j, nv) ((vec4 *)(void *)(t) + 2 * (size_t)(nv) * (size_t)(j))

/* x += h minv p of row j (drift_vector_unit / drift_vector_masses element-wise). */
FPL_INLINE void tile_drift_row(vec4 *restrict r, double h, const double *restrict minv, int j,
                               const int model, const int nv)
{
    for (int v = 0; v < nv; v++) {
        if (model == FPL_MODEL_HAMILTONIAN) FPL_DRIFT(r[v], h, minv[j], r[nv + v]);
        else FPL_DRIFT_UNIT(r[v], h, r[nv + v]);
    }
}

FPL_INLINE void tile_drift(int n, double *restrict t, double h, const double *restrict minv,
                           const int model, const int nv)
{
    for (int j = 0; j < n; j++) tile_drift_row(TILE_ROW(t, j, nv), h, minv, j, model, nv);
}

/* Row j's tangent kick from its right bond (rows j, j+1 = a, b; curvature k): the bond's term
 * f1, the kick with the left bond's f0, f0 = f1 for the next row. */
FPL_INLINE void tile_bond(vec4 *restrict a, const vec4 *restrict b, vec4 *restrict f0, double k,
                          const fpl_lattice *lat, int j, double hk, const int model, const int nv)
{
    const double *restrict cn = lat->cn, *restrict s = lat->s;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    for (int v = 0; v < nv; v++) {
        vec4 f1;
        if (model == FPL_MODEL_HOMOGENEOUS) {
            f1 = k * (b[v] - a[v]);
        } else {
            const vec4 R = cn[j + 1] * b[v] - cn[j] * a[v];
            f1 = FPL_DPHI(ham ? R : b[v] - a[v], k, R);
        }
        if (ham) FPL_KICK(a[nv + v], hk, s[j], f1, f0[v]);
        else FPL_KICK_UNIT(a[nv + v], hk, f1, f0[v]);
        f0[v] = f1;
    }
}

/* One stage on the tile: drift by hd, then the tangent kick by hk with the curvatures kap of
 * bonds 0..N. f0 carries the tangent bond force of row j's left bond (kick_tangent_ends /
 * kick_tangent_ends_general's wall terms at the ends, the interior bonds' terms of
 * kick_tangent_homogeneous / kick_tangent_general in between). On the ring (`ring` a constant)
 * both ends take the wrap-around bond's term (kick_tangent_ends_ring's), row N-1 drifted first. */
FPL_INLINE void tile_stage(int n, double *restrict t, const double *restrict kap,
                           const fpl_lattice *lat, double hd, double hk, const int model,
                           const int nv, const int ring)
{
    const double *restrict cn = lat->cn, *restrict s = lat->s, *restrict minv = lat->minv;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    vec4 f0[2], fw[2];
    vec4 *restrict r0 = TILE_ROW(t, 0, nv);
    vec4 *rn = TILE_ROW(t, n - 1, nv);
    if (ring) tile_drift_row(rn, hd, minv, n - 1, model, nv);
    tile_drift_row(r0, hd, minv, 0, model, nv);
    for (int v = 0; v < nv; v++) {
        const vec4 u = r0[v];
        if (ring) {
            const vec4 un = rn[v];
            if (model == FPL_MODEL_HOMOGENEOUS) {
                f0[v] = kap[0] * (u - un);
            } else {
                const vec4 R = cn[0] * u - cn[n - 1] * un;
                f0[v] = FPL_DPHI(ham ? R : u - un, kap[0], R);
            }
            fw[v] = f0[v];
        } else if (model == FPL_MODEL_HOMOGENEOUS) {
            f0[v] = kap[0] * u;
        } else {
            f0[v] = FPL_DPHI_LEFT(ham ? cn[0] * u : u, kap[0], cn[0], u);
        }
    }
    /* rows 1..N-1 drifted one ahead of the kick (the ring's row N-1 already is) */
    for (int j = 0; j + 1 < n - ring; j++) {
        vec4 *restrict a = TILE_ROW(t, j, nv), *restrict b = TILE_ROW(t, j + 1, nv);
        tile_drift_row(b, hd, minv, j + 1, model, nv);
        tile_bond(a, b, f0, kap[j + 1], lat, j, hk, model, nv);
    }
    if (ring) tile_bond(TILE_ROW(t, n - 2, nv), rn, f0, kap[n - 1], lat, n - 2, hk, model, nv);
    vec4 *restrict r = TILE_ROW(t, n - 1, nv);
    for (int v = 0; v < nv; v++) {
        const vec4 u = r[v];
        vec4 fn;
        if (ring) fn = fw[v];
        else if (model == FPL_MODEL_HOMOGENEOUS) fn = -kap[n] * u;
        else fn = FPL_DPHI_RIGHT(ham ? -cn[n - 1] * u : -u, kap[n], cn[n - 1], u);
        if (ham) FPL_KICK(r[nv + v], hk, s[n - 1], fn, f0[v]);
        else FPL_KICK_UNIT(r[nv + v], hk, fn, f0[v]);
    }
}

/* n steps, a group of steps of the orbit at a time, then each tile through the group (N >= 3,
 * work->tile present, work->kappa_rows >= scheme->n_kicks). */
FPL_INLINE void steps_vector_inner_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                        double *y, double dt, long nsteps, const int model,
                                        const int cubic, const int nv, const int ring)
{
    const int W = 4 * nv;
    const fpl_lattice *lat = c->lat;
    const int st = scheme->n_kicks, n = lat->n, n_dev = c->n_dev;
    const double *da = scheme->drift, *kb = scheme->kick;
    double *K = c->work->kappa_stages, *t = c->work->tile;
    const size_t stride = 2 * (size_t)n, rows = (size_t)n + 1;
    const long group = c->work->kappa_rows / st;
    for (long k0 = 0; k0 < nsteps; k0 += group) {
        const long g = nsteps - k0 < group ? nsteps - k0 : group;
        for (long k = 0; k < g; k++) {
            for (int i = 0; i < st; i++) {
                drift_vector(lat, y, da[i] * dt, model);
                kick_orbit_kappa(lat, y, kb[i] * dt, K + rows * (size_t)(k * st + i), model,
                                 cubic, ring);
            }
            drift_vector(lat, y, da[st] * dt, model);
        }
        for (int m0 = 1; m0 <= n_dev; m0 += W) {
            const int cnt = n_dev + 1 - m0 < W ? n_dev + 1 - m0 : W;
            tile_load(n, y, stride, m0, cnt, t, W);
            for (long k = 0; k < g; k++) {
                for (int i = 0; i < st; i++)
                    tile_stage(n, t, K + rows * (size_t)(k * st + i), lat, da[i] * dt,
                               kb[i] * dt, model, nv, ring);
                tile_drift(n, t, da[st] * dt, lat->minv, model, nv);
            }
            tile_store(n, y, stride, m0, cnt, t, W);
        }
    }
}

/* Whether the vector-inner step applies: from FPL_VEC_INNER_MIN_DEV vectors, N = 3 to
 * FPL_VEC_INNER_MAX_N, with the scratch fpl_work_reserve_vectors sized. */
static int steps_vector_inner(const fpl_splitting *scheme, const fpl_lattice_ctx *c)
{
    return c->n_dev >= FPL_VEC_INNER_MIN_DEV && c->lat->n >= 3 &&
           c->lat->n <= FPL_VEC_INNER_MAX_N && c->work->tile &&
           scheme->n_kicks <= c->work->kappa_rows;
}

/* The many-vector steppers of one model, instantiated for beta = 0 or not and tiles of 4 (up to
 * 4 vectors: no padding lanes) or 8; `ring` (a constant): the periodic chain. Returns 0 (nothing
 * done) where neither many-vector step applies. */
FPL_INLINE int steps_many_vectors(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                  double *y, double dt, long nsteps, const int model,
                                  const int ring)
{
    const int cubic = c->lat->beta != 0.0;
    if (steps_vector_inner(scheme, c)) {
        if (c->n_dev <= 4) {
            if (cubic) steps_vector_inner_body(scheme, c, y, dt, nsteps, model, 1, 1, ring);
            else steps_vector_inner_body(scheme, c, y, dt, nsteps, model, 0, 1, ring);
        } else {
            if (cubic) steps_vector_inner_body(scheme, c, y, dt, nsteps, model, 1, 2, ring);
            else steps_vector_inner_body(scheme, c, y, dt, nsteps, model, 0, 2, ring);
        }
        return 1;
    }
    if (steps_by_vector(scheme, c)) {
        if (cubic) steps_by_vector_body(scheme, c, y, dt, nsteps, model, 1, ring);
        else steps_by_vector_body(scheme, c, y, dt, nsteps, model, 0, ring);
        return 1;
    }
    return 0;
}

/* ---- the fused steppers ---------------------------------------------------------------- */

/* n steps of the scheme, drift and kick inlined (fpl_split_system.steps): the same operations in
 * the same order as fpl_split_step on drift_unit_mass / kick_homogeneous. */
FPL_INLINE void steps_homogeneous_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                       double *y, double dt, long nsteps, const int cubic)
{
    const int s = scheme->n_kicks;
    const double *a = scheme->drift, *b = scheme->kick;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < s; i++) {
            drift_unit_mass_body(c, y, a[i] * dt);
            kick_homogeneous_body(c, y, b[i] * dt, cubic);
        }
        drift_unit_mass_body(c, y, a[s] * dt);
    }
}

/* n steps of the scheme with drift and kick inlined (fpl_split_system.steps): the operations of
 * fpl_split_step on the model's drift / kick in the same order, so bit-identical to it. */
FPL_INLINE void steps_general_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                   double *y, double dt, long nsteps, const int ham,
                                   const int cubic)
{
    const int st = scheme->n_kicks;
    const double *da = scheme->drift, *kb = scheme->kick;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            if (ham) drift_masses_body(c, y, da[i] * dt);
            else drift_unit_mass_body(c, y, da[i] * dt);
            kick_general_body(c, y, kb[i] * dt, ham, cubic);
        }
        if (ham) drift_masses_body(c, y, da[st] * dt);
        else drift_unit_mass_body(c, y, da[st] * dt);
    }
}

/* ---- the stage fused: drift and kick in one pass (up to 2 deviation vectors) -------------- */

/* Out of cache a stage's drift and kick were two passes over the state (the drift streams x, p
 * and writes x of each vector, then the kick streams x and p again): the drift is done a block
 * of particles ahead of the kick instead, particles [done, i1] drifted just before the kick of
 * interior particles [i0, i1), whose bonds reach x_{i0-1} .. x_{i1}; the two end particles are
 * kicked after the last block. The last drift of a step and the first of the next are applied
 * to each element in the same pass (x += h_s p, then x += h_0 p: p does not change between
 * them). Every element gets the operations of the stage-by-stage order, in that order:
 * bit-identical. The block (FUSE_BLOCK particles, 9 arrays at most: 18 kB) is still in L1 when
 * the kick reads it. Drifts in [lo, hi) of one vector: `pre` a constant (the previous step's
 * last drift, h0, first). */
#define FUSE_BLOCK 256

FPL_INLINE void drift_range(int lo, int hi, double *restrict x, const double *restrict p,
                            const double *restrict minv, double h0, double h, const int ham,
                            const int pre)
{
    for (int i = lo; i < hi; i++) {
        if (ham) {
            if (pre) FPL_DRIFT(x[i], h0, minv[i], p[i]);
            FPL_DRIFT(x[i], h, minv[i], p[i]);
        } else {
            if (pre) FPL_DRIFT_UNIT(x[i], h0, p[i]);
            FPL_DRIFT_UNIT(x[i], h, p[i]);
        }
    }
}

/* One stage (drift hd, after hd0 if `pre`; kick hk) of model `model` with nv = n_dev = 0, 1 or 2
 * (constants), N >= 3; `ring` (a constant): the periodic chain, whose interior particles are the
 * fixed chain's and whose end particles see the wrap-around bond instead of the walls. */
FPL_INLINE void stage_fused(const fpl_lattice_ctx *c, double *y, double hd0, double hd,
                            double hk, const int model, const int cubic, const int nv,
                            const int pre, const int ring)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double a = lat->alpha, b = lat->beta, h = hk;
    const double *restrict cn = lat->cn, *restrict s = lat->s, *restrict minv = lat->minv;
    const size_t stride = 2 * (size_t)n;
    double *x = y, *p = y + n;
    double *u = nv >= 1 ? y + stride : NULL, *q = nv >= 1 ? u + n : NULL;
    double *w = nv == 2 ? y + 2 * stride : NULL, *r = nv == 2 ? w + n : NULL;
    int done = 0;   /* particles [0, done) drifted */
    for (int i0 = 1; i0 < n - 1; i0 += FUSE_BLOCK) {
        const int i1 = i0 + FUSE_BLOCK < n - 1 ? i0 + FUSE_BLOCK : n - 1;
        const int d1 = i1 == n - 1 ? n : i1 + 1;
        drift_range(done, d1, x, p, minv, hd0, hd, ham, pre);
        if (nv >= 1) drift_range(done, d1, u, q, minv, hd0, hd, ham, pre);
        if (nv == 2) drift_range(done, d1, w, r, minv, hd0, hd, ham, pre);
        done = d1;
        if (model == FPL_MODEL_HOMOGENEOUS) {
            if (nv == 0) kick_orbit_homogeneous(i0, i1, x, p, a, b, h, NULL, cubic);
            else kick_orbit_tangent_homogeneous(i0, i1, x, p, u, q, w, r, a, b, h, cubic, nv == 2);
        } else {
            if (nv == 0)
                kick_orbit_general(i0, i1, x, p, cn, s, a, b, h, NULL, ham, cubic);
            else
                kick_orbit_tangent_general(i0, i1, x, p, u, q, w, r, cn, s, a, b, h, ham, cubic,
                                           nv == 2);
        }
    }
    /* the end particles, as kick_homogeneous_body / kick_general_body (the ring's: as
     * kick_ring_body / kick_general_ring_body) */
    if (ring) {
        kick_ring_ends(n, x, p, u, q, w, r, cn, s, a, b, h, NULL, model, cubic, nv);
    } else if (model == FPL_MODEL_HOMOGENEOUS) {
        const double d0 = x[0], d1 = x[1] - x[0];
        const double dm = x[n - 1] - x[n - 2], dn = -x[n - 1];
        const double phi0 = PHI_H(d0), phi1 = PHI_H(d1), phim = PHI_H(dm), phin = PHI_H(dn);
        const double k0 = KAP_H(d0), k1 = KAP_H(d1), km = KAP_H(dm), kn = KAP_H(dn);
        FPL_KICK_UNIT(p[0], h, phi1, phi0);
        FPL_KICK_UNIT(p[n - 1], h, phin, phim);
        if (nv >= 1) kick_tangent_ends(n, u, q, k0, k1, km, kn, h);
        if (nv == 2) kick_tangent_ends(n, w, r, k0, k1, km, kn, h);
    } else {
        const double L0 = ham ? cn[0] * x[0] : x[0], R0 = cn[0] * x[0];
        const double Ln = ham ? -cn[n - 1] * x[n - 1] : -x[n - 1], Rn = -cn[n - 1] * x[n - 1];
        const double R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
        const double phi0 = PHI_G(L0, R0), phi1 = PHI_G(L_IN(x, 1), R1);
        const double phim = PHI_G(L_IN(x, n - 1), Rm), phin = PHI_G(Ln, Rn);
        const double k0 = KAP_G(R0), k1 = KAP_G(R1), km = KAP_G(Rm), kn = KAP_G(Rn);
        KICK_G(p[0], 0, phi1, phi0);
        KICK_G(p[n - 1], n - 1, phin, phim);
        if (nv >= 1) kick_tangent_ends_general(n, u, q, cn, s, k0, k1, km, kn, h, ham);
        if (nv == 2) kick_tangent_ends_general(n, w, r, cn, s, k0, k1, km, kn, h, ham);
    }
}

/* n steps with fused stages (N >= 3, nv = n_dev <= 2 and ring constants). */
FPL_INLINE void steps_fused_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c, double *y,
                                 double dt, long nsteps, const int model, const int cubic,
                                 const int nv, const int ring)
{
    const int st = scheme->n_kicks, n = c->lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double *da = scheme->drift, *kb = scheme->kick;
    const size_t stride = 2 * (size_t)n;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            if (i == 0 && k > 0)
                stage_fused(c, y, da[st] * dt, da[0] * dt, kb[0] * dt, model, cubic, nv, 1,
                            ring);
            else
                stage_fused(c, y, 0.0, da[i] * dt, kb[i] * dt, model, cubic, nv, 0, ring);
        }
    }
    if (nsteps > 0)
        for (int m = 0; m <= nv; m++)
            drift_range(0, n, y + stride * (size_t)m, y + stride * (size_t)m + n, c->lat->minv,
                        0.0, da[st] * dt, ham, 0);
}

/* The fused steps where they apply (returns 0 otherwise: N < 3, more than 2 vectors). */
FPL_INLINE int steps_fused(const fpl_splitting *scheme, const fpl_lattice_ctx *c, double *y,
                           double dt, long nsteps, const int model, const int cubic,
                           const int ring)
{
    if (c->lat->n < 3 || c->n_dev > 2) return 0;
    if (c->n_dev == 0) steps_fused_body(scheme, c, y, dt, nsteps, model, cubic, 0, ring);
    else if (c->n_dev == 1) steps_fused_body(scheme, c, y, dt, nsteps, model, cubic, 1, ring);
    else steps_fused_body(scheme, c, y, dt, nsteps, model, cubic, 2, ring);
    return 1;
}

/* ---- many deviation vectors on long chains: the stage fused, kappa once a block ----------- */

/* With 3 or more vectors on chains beyond the vector-inner tiles (N > FPL_VEC_INNER_MAX_N, where
 * a tile of 8 vectors leaves L2) the stage-by-stage step made two passes over the whole state
 * per stage: every vector's drift, then the kick (kappa of a block of bonds once, each vector's
 * tangent kick on the block). Here a stage is one pass, as stage_fused's for up to 2 vectors:
 * block by block, the orbit is drifted and kicked (kappa of the block's bonds into
 * work->kappa, 4 kB, in L1), then each vector in turn is drifted on the block and kicked with
 * those kappas while its block (8 kB) is still in L1. The last drift of a step and the first of
 * the next are one pass (x += h_s p, then x += h_0 p). Every element gets the operations of the
 * stage-by-stage order (kick_homogeneous_body / kick_general_body with n_dev > 2), in that order:
 * bit-identical. */
#define FUSE_MANY_BLOCK 512
/* Rings whose state exceeds FPL_SWEEP_FEW_MIN_BYTES (the fixed chains take the sweep there) go in
 * blocks of 4096 particles (a vector's block, 64 kB, stays in L2 between its drift and kick):
 * with 512-particle blocks (one 4 kB page of each array a block: likely the hardware prefetch
 * restarting on every page, not verified) rings were up to 1.4x slower than the stage-by-stage
 * step out of cache (model 1, N = 262 144, k = 6);
 * there 4096 was 1.3-1.5x faster than 512 at k = 6 and 8 (0.9-1.3x at k = 3), and in cache
 * (N = 4096-32 768, k = 3-8) 512 was 3-35 % faster than 4096 (models 1-3, branch ring2's
 * measurements; benchmarks/README.md). The block changes no element's operations. */
#define FUSE_MANY_RING_BLOCK_BIG 4096

/* dp_i += h (kappa_{i+1} ddx_{i+1} - kappa_i ddx_i) for i in [lo, hi) (kick_tangent_homogeneous
 * on a range). */
FPL_INLINE void kick_tangent_homogeneous_range(int lo, int hi, const double *restrict dx,
                                               double *restrict dp, const double *restrict kap,
                                               double h)
{
    for (int i = lo; i < hi; i++)
        FPL_KICK_UNIT(dp[i], h, kap[i + 1] * (dx[i + 1] - dx[i]), kap[i] * (dx[i] - dx[i - 1]));
}

/* One stage (drift hd, after hd0 if `pre`; kick hk) with c->n_dev >= 3 vectors, N >= 3; `ring`
 * (a constant): the periodic chain, as stage_fused's (the interior blocks are the fixed chain's,
 * whose kick of particle 1 needs only x_0, drifted in the first block; the end particles, kicked
 * after the last block when every particle is drifted, see the wrap-around bond). */
FPL_INLINE void stage_fused_many(const fpl_lattice_ctx *c, double *y, double hd0, double hd,
                                 double hk, const int model, const int cubic, const int pre,
                                 const int ring)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double a = lat->alpha, b = lat->beta, h = hk;
    const double *restrict cn = lat->cn, *restrict s = lat->s, *restrict minv = lat->minv;
    double *restrict kap = c->work->kappa;
    const size_t stride = 2 * (size_t)n;
    double *x = y, *p = y + n;
    int done = 0;   /* particles [0, done) drifted */
    const int blk = ring && 16.0 * n * (n_dev + 1) > FPL_SWEEP_FEW_MIN_BYTES
                        ? FUSE_MANY_RING_BLOCK_BIG : FUSE_MANY_BLOCK;
    for (int i0 = 1; i0 < n - 1; i0 += blk) {
        const int i1 = i0 + blk < n - 1 ? i0 + blk : n - 1;
        const int d1 = i1 == n - 1 ? n : i1 + 1;
        drift_range(done, d1, x, p, minv, hd0, hd, ham, pre);
        if (model == FPL_MODEL_HOMOGENEOUS) {
            kick_orbit_homogeneous(i0, i1, x, p, a, b, h, kap, cubic);
            kap[i1] = KAP_C(x[i1] - x[i1 - 1]);
        } else {
            kick_orbit_general(i0, i1, x, p, cn, s, a, b, h, kap, ham, cubic);
        }
        for (int m = 1; m <= n_dev; m++) {
            double *u = y + stride * (size_t)m, *q = u + n;
            drift_range(done, d1, u, q, minv, hd0, hd, ham, pre);
            if (model == FPL_MODEL_HOMOGENEOUS)
                kick_tangent_homogeneous_range(i0, i1, u, q, kap, h);
            else
                kick_tangent_general(i0, i1, u, q, cn, s, kap, h, ham);
        }
        done = d1;
    }
    /* the end particles, as kick_homogeneous_body / kick_general_body (the ring's: as
     * kick_ring_body / kick_general_ring_body; kappa of the wrap-around bond and of bond N-1
     * into kap[0] and kap[n - 1], bond 1's is in kap[1] from the first block, the bits of
     * kick_ring_ends' k1: the same expression on the same x) */
    if (ring) {
        kick_ring_ends(n, x, p, NULL, NULL, NULL, NULL, cn, s, a, b, h, kap, model, cubic, 0);
        for (int m = 1; m <= n_dev; m++) {
            double *u = y + stride * (size_t)m;
            kick_tangent_ends_ring(n, u, u + n, cn, s, kap[0], kap[1], kap[n - 1], h, model);
        }
    } else if (model == FPL_MODEL_HOMOGENEOUS) {
        const double d0 = x[0], d1 = x[1] - x[0];
        const double dm = x[n - 1] - x[n - 2], dn = -x[n - 1];
        const double phi0 = PHI_H(d0), phi1 = PHI_H(d1), phim = PHI_H(dm), phin = PHI_H(dn);
        const double k0 = KAP_H(d0), k1 = KAP_H(d1), km = KAP_H(dm), kn = KAP_H(dn);
        FPL_KICK_UNIT(p[0], h, phi1, phi0);
        FPL_KICK_UNIT(p[n - 1], h, phin, phim);
        for (int m = 1; m <= n_dev; m++) {
            double *u = y + stride * (size_t)m;
            kick_tangent_ends(n, u, u + n, k0, k1, km, kn, h);
        }
    } else {
        const double L0 = ham ? cn[0] * x[0] : x[0], R0 = cn[0] * x[0];
        const double Ln = ham ? -cn[n - 1] * x[n - 1] : -x[n - 1], Rn = -cn[n - 1] * x[n - 1];
        const double R1 = R_IN(x, 1), Rm = R_IN(x, n - 1);
        const double phi0 = PHI_G(L0, R0), phi1 = PHI_G(L_IN(x, 1), R1);
        const double phim = PHI_G(L_IN(x, n - 1), Rm), phin = PHI_G(Ln, Rn);
        const double k0 = KAP_G(R0), k1 = KAP_G(R1), km = KAP_G(Rm), kn = KAP_G(Rn);
        KICK_G(p[0], 0, phi1, phi0);
        KICK_G(p[n - 1], n - 1, phin, phim);
        for (int m = 1; m <= n_dev; m++) {
            double *u = y + stride * (size_t)m;
            kick_tangent_ends_general(n, u, u + n, cn, s, k0, k1, km, kn, h, ham);
        }
    }
}

/* n steps with fused stages and n_dev >= 3 vectors (N >= 3; `ring` a constant). */
FPL_INLINE void steps_fused_many_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                      double *y, double dt, long nsteps, const int model,
                                      const int cubic, const int ring)
{
    const int st = scheme->n_kicks, n = c->lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double *da = scheme->drift, *kb = scheme->kick;
    const size_t stride = 2 * (size_t)n;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < st; i++) {
            if (i == 0 && k > 0)
                stage_fused_many(c, y, da[st] * dt, da[0] * dt, kb[0] * dt, model, cubic, 1,
                                 ring);
            else
                stage_fused_many(c, y, 0.0, da[i] * dt, kb[i] * dt, model, cubic, 0, ring);
        }
    }
    if (nsteps > 0)
        for (int m = 0; m <= c->n_dev; m++)
            drift_range(0, n, y + stride * (size_t)m, y + stride * (size_t)m + n, c->lat->minv,
                        0.0, da[st] * dt, ham, 0);
}

/* ---- many deviation vectors on long chains: sweeps of many stages, chain block by block ---- */

/* stage_fused_many still streams the whole state (the orbit and every vector, 29 MB at
 * N = 262 144 with 6 vectors) through the cache once per stage. A sweep takes up to
 * FPL_SWEEP_STAGES stages (several steps) in one pass: the chain in blocks of FPL_SWEEP_BLOCK
 * particles [lo, hi), and in block b stage s drifts [lo - s, hi - s) and kicks [lo - s - 1,
 * hi - s - 1) (clipped to the chain; the last block reaches the right wall at every stage).
 * The drift runs one particle ahead of the kick on the right (the kick of hi - s - 2 reads
 * x_{hi-s-1}), and each stage one particle further left, so that a particle's stage-s drift
 * follows its stage-(s-1) kick. Only the first particle kicked, lo - s - 1, needs a neighbour
 * the previous block has already moved on: its left bond's term at stage s, formed by the
 * previous block as the right bond of its last kicked particle, is carried over (work->
 * sweep_carry; the wall bond at the left end). The orbit runs the block's stages first, keeping
 * the kappa of every bond of every stage (work->sweep_rows, FPL_SWEEP_STAGES x 546 doubles,
 * in L1/L2); then each vector runs them on its block (8 kB, in L1 throughout) with those
 * kappas: each bond's kappa is formed once per stage and reused by every vector, and the state
 * is streamed once per sweep. Every element gets the operations of the stage-by-stage order in
 * that order, and a bond term formed once (carried) has the bits it has formed twice:
 * bit-identical. The interior of a block's kick is the stage-by-stage kernels' loops on the
 * block's arrays (shifted so that index 0 is the first particle kicked). */

typedef struct {
    double hd0, hd, hk;   /* the previous step's last drift (if pre), this stage's drift, kick */
    int pre;
} sweep_stage;

/* The drift range and kick range of block [lo, hi) at stage s (n: the chain). */
FPL_INLINE void sweep_ranges(int n, int lo, int hi, int s, int *dlo, int *dhi, int *klo, int *khi)
{
    *dlo = lo - s > 0 ? lo - s : 0;
    *dhi = hi == n ? n : hi - s;
    *klo = lo - s - 1 > 0 ? lo - s - 1 : 0;
    *khi = hi == n ? n : hi - s - 1;
}

FPL_INLINE void sweep_drift(int lo, int hi, double *x, const double *p, const double *minv,
                            const sweep_stage *g, const int ham)
{
    if (g->pre) drift_range(lo, hi, x, p, minv, g->hd0, g->hd, ham, 1);
    else drift_range(lo, hi, x, p, minv, 0.0, g->hd, ham, 0);
}

/* The orbit's stages on block [lo, hi): kicks, kappa of bonds klo..khi into row s (kr[j - klo]),
 * the right bond's phi and kappa of the last particle kicked into carry[2s], carry[2s+1]. */
FPL_INLINE void sweep_orbit_block(const fpl_lattice *lat, double *y, const sweep_stage *stg,
                                  int S, int lo, int hi, double *rows, double *carry,
                                  const int model, const int cubic)
{
    const int n = lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double a = lat->alpha, b = lat->beta;
    const double *restrict cn = lat->cn, *restrict s = lat->s, *restrict minv = lat->minv;
    double *x = y, *p = y + n;
    for (int q = 0; q < S; q++) {
        int dlo, dhi, klo, khi;
        sweep_ranges(n, lo, hi, q, &dlo, &dhi, &klo, &khi);
        const double h = stg[q].hk;
        double *kr = rows + (size_t)FPL_SWEEP_ROW * q;
        sweep_drift(dlo, dhi, x, p, minv, &stg[q], ham);
        /* the first particle: its left bond from the wall or carried, its right bond formed */
        double phiL, kapL, phiR, kapR;
        if (model == FPL_MODEL_HOMOGENEOUS) {
            if (klo == 0) {
                phiL = PHI_H(x[0]);
                kapL = KAP_H(x[0]);
            } else {
                phiL = carry[2 * q];
                kapL = carry[2 * q + 1];
            }
            const double dr = x[klo + 1] - x[klo];
            phiR = PHI_C(dr);
            kapR = KAP_C(dr);
            FPL_KICK_UNIT(p[klo], h, phiR, phiL);
        } else {
            if (klo == 0) {
                const double L0 = ham ? cn[0] * x[0] : x[0], R0 = cn[0] * x[0];
                phiL = PHI_G(L0, R0);
                kapL = KAP_G(R0);
            } else {
                phiL = carry[2 * q];
                kapL = carry[2 * q + 1];
            }
            const double Rr = R_IN(x, klo + 1);
            phiR = PHI_G(L_IN(x, klo + 1), Rr);
            kapR = KAP_G(Rr);
            KICK_G(p[klo], klo, phiR, phiL);
        }
        kr[0] = kapL;
        kr[1] = kapR;
        /* the interior particles klo+1 .. ihi-1, on arrays shifted by klo */
        const int ihi = khi == n ? n - 1 : khi, m = ihi - klo;
        if (model == FPL_MODEL_HOMOGENEOUS) {
            kick_orbit_homogeneous(1, m, x + klo, p + klo, a, b, h, kr, cubic);
            kr[m] = KAP_C(x[ihi] - x[ihi - 1]);
        } else {
            kick_orbit_general(1, m, x + klo, p + klo, cn + klo, s + klo, a, b, h, kr, ham,
                               cubic);
        }
        if (khi == n) {
            /* particle n-1 and the right wall (as kick_homogeneous_body / kick_general_body) */
            if (model == FPL_MODEL_HOMOGENEOUS) {
                const double dm = x[n - 1] - x[n - 2], dn = -x[n - 1];
                FPL_KICK_UNIT(p[n - 1], h, PHI_H(dn), PHI_H(dm));
                kr[n - klo] = KAP_H(dn);
            } else {
                const double Ln = ham ? -cn[n - 1] * x[n - 1] : -x[n - 1];
                const double Rn = -cn[n - 1] * x[n - 1], Rm = R_IN(x, n - 1);
                KICK_G(p[n - 1], n - 1, PHI_G(Ln, Rn), PHI_G(L_IN(x, n - 1), Rm));
                kr[n - klo] = KAP_G(Rn);
            }
        } else if (model == FPL_MODEL_HOMOGENEOUS) {
            const double d = x[khi] - x[khi - 1];
            carry[2 * q] = PHI_C(d);
            carry[2 * q + 1] = KAP_C(d);
        } else {
            const double R = R_IN(x, khi);
            carry[2 * q] = PHI_G(L_IN(x, khi), R);
            carry[2 * q + 1] = KAP_G(R);
        }
    }
}

/* One deviation vector v's stages on block [lo, hi) with the orbit's kappa rows; carry[s]: the
 * tangent term of the left bond of the first particle kicked at stage s. */
FPL_INLINE void sweep_vector_block(const fpl_lattice *lat, double *v, const sweep_stage *stg,
                                   int S, int lo, int hi, const double *rows, double *carry,
                                   const int model)
{
    const int n = lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double *restrict cn = lat->cn, *restrict s = lat->s, *restrict minv = lat->minv;
    double *u = v, *q = v + n;
    for (int g = 0; g < S; g++) {
        int dlo, dhi, klo, khi;
        sweep_ranges(n, lo, hi, g, &dlo, &dhi, &klo, &khi);
        const double h = stg[g].hk;
        const double *kr = rows + (size_t)FPL_SWEEP_ROW * g;
        sweep_drift(dlo, dhi, u, q, minv, &stg[g], ham);
        double tL, tR;
        if (model == FPL_MODEL_HOMOGENEOUS) {
            tL = klo == 0 ? kr[0] * u[0] : carry[g];
            tR = kr[1] * (u[klo + 1] - u[klo]);
            FPL_KICK_UNIT(q[klo], h, tR, tL);
        } else {
            tL = klo == 0 ? FPL_DPHI_LEFT(ham ? cn[0] * u[0] : u[0], kr[0], cn[0], u[0])
                          : carry[g];
            tR = DPHI_IN(u, klo + 1, kr[1]);
            KICK_G(q[klo], klo, tR, tL);
        }
        const int ihi = khi == n ? n - 1 : khi, m = ihi - klo;
        if (model == FPL_MODEL_HOMOGENEOUS)
            kick_tangent_homogeneous_range(1, m, u + klo, q + klo, kr, h);
        else
            kick_tangent_general(1, m, u + klo, q + klo, cn + klo, s + klo, kr, h, ham);
        if (khi == n) {
            const double km = kr[n - 1 - klo], kn = kr[n - klo];
            if (model == FPL_MODEL_HOMOGENEOUS) {
                const double tm = km * (u[n - 1] - u[n - 2]), tn = -kn * u[n - 1];
                FPL_KICK_UNIT(q[n - 1], h, tn, tm);
            } else {
                const double tm = DPHI_IN(u, n - 1, km);
                const double tn = FPL_DPHI_RIGHT(ham ? -cn[n - 1] * u[n - 1] : -u[n - 1], kn,
                                                 cn[n - 1], u[n - 1]);
                KICK_G(q[n - 1], n - 1, tn, tm);
            }
        } else if (model == FPL_MODEL_HOMOGENEOUS) {
            carry[g] = kr[khi - klo] * (u[khi] - u[khi - 1]);
        } else {
            carry[g] = DPHI_IN(u, khi, kr[khi - klo]);
        }
    }
}

/* S stages of the orbit and every vector in one sweep over the chain. */
FPL_INLINE void sweep_stages(const fpl_lattice_ctx *c, double *y, const sweep_stage *stg, int S,
                             const int model, const int cubic)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    const size_t stride = 2 * (size_t)n;
    double *rows = c->work->sweep_rows, *carry = c->work->sweep_carry;
    for (int lo = 0; lo < n; lo += FPL_SWEEP_BLOCK) {
        const int hi = n - lo <= FPL_SWEEP_BLOCK ? n : lo + FPL_SWEEP_BLOCK;
        sweep_orbit_block(lat, y, stg, S, lo, hi, rows, carry, model, cubic);
        for (int m = 1; m <= n_dev; m++)
            sweep_vector_block(lat, y + stride * (size_t)m, stg, S, lo, hi, rows,
                               carry + (size_t)FPL_SWEEP_STAGES * (size_t)(m + 1), model);
        if (hi == n) break;
    }
}

/* n steps in sweeps of whole steps (N > 2 FPL_SWEEP_BLOCK, scheme->n_kicks <= FPL_SWEEP_STAGES,
 * the sweep scratch reserved for c->n_dev vectors). */
FPL_INLINE void steps_sweep_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                 double *y, double dt, long nsteps, const int model,
                                 const int cubic)
{
    const int st = scheme->n_kicks, n = c->lat->n;
    const int ham = model == FPL_MODEL_HAMILTONIAN;
    const double *da = scheme->drift, *kb = scheme->kick;
    const size_t stride = 2 * (size_t)n;
    const long group = FPL_SWEEP_STAGES / st;
    sweep_stage stg[FPL_SWEEP_STAGES];
    for (long k0 = 0; k0 < nsteps; k0 += group) {
        const long g = nsteps - k0 < group ? nsteps - k0 : group;
        for (long k = 0; k < g; k++)
            for (int i = 0; i < st; i++)
                stg[k * st + i] = (sweep_stage){da[st] * dt, da[i] * dt, kb[i] * dt,
                                                i == 0 && k0 + k > 0};
        sweep_stages(c, y, stg, (int)g * st, model, cubic);
    }
    if (nsteps > 0)
        for (int m = 0; m <= c->n_dev; m++)
            drift_range(0, n, y + stride * (size_t)m, y + stride * (size_t)m + n, c->lat->minv,
                        0.0, da[st] * dt, ham, 0);
}

static int steps_sweep_applies(const fpl_splitting *scheme, const fpl_lattice_ctx *c)
{
    return c->lat->n > 2 * FPL_SWEEP_BLOCK && c->n_dev >= 1 &&
           scheme->n_kicks <= FPL_SWEEP_STAGES && c->work->sweep_rows && c->work->sweep_carry &&
           c->work->sweep_dev >= c->n_dev;
}

/* One out-of-line function per model, beta and boundary (see FPL_HOT_APART below). The rings
 * take the stage-fused pass only: the sweep's left-to-right carry of a bond term cannot close
 * the ring (bond 0 = bond N would be needed at the left end before the right end is drifted). */
#define FPL_HOT_APART_MANY FPL_HOT __attribute__((noinline))
#define STEPS_FUSED_MANY(name, model, cubic)                                                     \
    FPL_HOT_APART_MANY static void name(const fpl_splitting *scheme, const fpl_lattice_ctx *c,  \
                                        double *y, double dt, long nsteps)                      \
    {                                                                                            \
        if (steps_sweep_applies(scheme, c))                                                      \
            steps_sweep_body(scheme, c, y, dt, nsteps, model, cubic);                            \
        else                                                                                     \
            steps_fused_many_body(scheme, c, y, dt, nsteps, model, cubic, 0);                    \
    }
#define STEPS_FUSED_MANY_RING(name, model, cubic)                                                \
    FPL_HOT_APART_MANY static void name(const fpl_splitting *scheme, const fpl_lattice_ctx *c,  \
                                        double *y, double dt, long nsteps)                      \
    {                                                                                            \
        steps_fused_many_body(scheme, c, y, dt, nsteps, model, cubic, 1);                        \
    }
STEPS_FUSED_MANY(steps_fused_many_homogeneous_quad, FPL_MODEL_HOMOGENEOUS, 0)
STEPS_FUSED_MANY(steps_fused_many_homogeneous_cubic, FPL_MODEL_HOMOGENEOUS, 1)
STEPS_FUSED_MANY(steps_fused_many_hamiltonian_quad, FPL_MODEL_HAMILTONIAN, 0)
STEPS_FUSED_MANY(steps_fused_many_hamiltonian_cubic, FPL_MODEL_HAMILTONIAN, 1)
STEPS_FUSED_MANY(steps_fused_many_nonlinear_quad, FPL_MODEL_NONLINEAR, 0)
STEPS_FUSED_MANY(steps_fused_many_nonlinear_cubic, FPL_MODEL_NONLINEAR, 1)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_homogeneous_quad, FPL_MODEL_HOMOGENEOUS, 0)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_homogeneous_cubic, FPL_MODEL_HOMOGENEOUS, 1)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_hamiltonian_quad, FPL_MODEL_HAMILTONIAN, 0)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_hamiltonian_cubic, FPL_MODEL_HAMILTONIAN, 1)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_nonlinear_quad, FPL_MODEL_NONLINEAR, 0)
STEPS_FUSED_MANY_RING(steps_fused_many_ring_nonlinear_cubic, FPL_MODEL_NONLINEAR, 1)

/* Whether the long-chain steps apply: 3 or more vectors on a chain the vector-inner tiles do not
 * serve (those and the vector-by-vector step are tried first), the sweep if its scratch is there,
 * else the stage-fused pass; 1 or 2 vectors only where the sweep serves them (fpl_sweep_serves),
 * else the stage_fused pass of steps_fused. Rings (`ring` a constant): 3 or more vectors only
 * (1 or 2 take steps_fused's stage_fused; no sweep). */
static int steps_fused_many_applies(const fpl_splitting *scheme, const fpl_lattice_ctx *c,
                                    const int ring)
{
    if (c->lat->n <= FPL_VEC_INNER_MAX_N) return 0;
    if (c->n_dev >= FPL_VEC_INNER_MIN_DEV) return 1;
    if (ring) return 0;
    return fpl_sweep_serves(c->lat->n, c->n_dev) && steps_sweep_applies(scheme, c);
}

/* The long-chain many-vector steps where they apply (returns 0 otherwise; `ring` a constant). */
FPL_INLINE int steps_fused_many(const fpl_splitting *scheme, const fpl_lattice_ctx *c, double *y,
                                double dt, long nsteps, const int model, const int ring)
{
    if (!steps_fused_many_applies(scheme, c, ring)) return 0;
    const int cubic = c->lat->beta != 0.0;
    if (ring) {
        if (model == FPL_MODEL_HOMOGENEOUS)
            (cubic ? steps_fused_many_ring_homogeneous_cubic
                   : steps_fused_many_ring_homogeneous_quad)(scheme, c, y, dt, nsteps);
        else if (model == FPL_MODEL_HAMILTONIAN)
            (cubic ? steps_fused_many_ring_hamiltonian_cubic
                   : steps_fused_many_ring_hamiltonian_quad)(scheme, c, y, dt, nsteps);
        else
            (cubic ? steps_fused_many_ring_nonlinear_cubic
                   : steps_fused_many_ring_nonlinear_quad)(scheme, c, y, dt, nsteps);
    } else if (model == FPL_MODEL_HOMOGENEOUS) {
        (cubic ? steps_fused_many_homogeneous_cubic : steps_fused_many_homogeneous_quad)(
            scheme, c, y, dt, nsteps);
    } else if (model == FPL_MODEL_HAMILTONIAN) {
        (cubic ? steps_fused_many_hamiltonian_cubic : steps_fused_many_hamiltonian_quad)(
            scheme, c, y, dt, nsteps);
    } else {
        (cubic ? steps_fused_many_nonlinear_cubic : steps_fused_many_nonlinear_quad)(
            scheme, c, y, dt, nsteps);
    }
    return 1;
}

/* The steppers with 0, 1 or 2 deviation vectors (stages fused) or too many or too long a chain
 * for the many-vector steps (stage by stage), one out-of-line function per model and beta. noinline: inlined into
 * steps_<model> beside the many-vector steppers, the kick loop lost its registers to that
 * function's other live values (model 3 with one vector reloaded five pointers and spilled two
 * vectors per iteration; 1.3-1.7x the hand-fused loop out of cache, benchmarks/roofline.c). The
 * same code, so bit-identical. */
#define FPL_HOT_APART FPL_HOT __attribute__((noinline))
FPL_HOT_APART static void steps_few_homogeneous_quad(const fpl_splitting *scheme,
                                                     const fpl_lattice_ctx *c, double *y,
                                                     double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 0, 0))
        steps_homogeneous_body(scheme, c, y, dt, nsteps, 0);
}

FPL_HOT_APART static void steps_few_homogeneous_cubic(const fpl_splitting *scheme,
                                                      const fpl_lattice_ctx *c, double *y,
                                                      double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 1, 0))
        steps_homogeneous_body(scheme, c, y, dt, nsteps, 1);
}

FPL_HOT_APART static void steps_few_hamiltonian_quad(const fpl_splitting *scheme,
                                                     const fpl_lattice_ctx *c, double *y,
                                                     double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 0, 0))
        steps_general_body(scheme, c, y, dt, nsteps, 1, 0);
}

FPL_HOT_APART static void steps_few_hamiltonian_cubic(const fpl_splitting *scheme,
                                                      const fpl_lattice_ctx *c, double *y,
                                                      double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 1, 0))
        steps_general_body(scheme, c, y, dt, nsteps, 1, 1);
}

FPL_HOT_APART static void steps_few_nonlinear_quad(const fpl_splitting *scheme,
                                                   const fpl_lattice_ctx *c, double *y,
                                                   double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 0, 0))
        steps_general_body(scheme, c, y, dt, nsteps, 0, 0);
}

FPL_HOT_APART static void steps_few_nonlinear_cubic(const fpl_splitting *scheme,
                                                    const fpl_lattice_ctx *c, double *y,
                                                    double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 1, 0))
        steps_general_body(scheme, c, y, dt, nsteps, 0, 1);
}

FPL_HOT static void steps_homogeneous(const fpl_splitting *scheme, void *ctx, double *y,
                                      double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 0))
        return;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 0))
        return;
    if (c->lat->beta == 0.0)
        steps_few_homogeneous_quad(scheme, c, y, dt, nsteps);
    else
        steps_few_homogeneous_cubic(scheme, c, y, dt, nsteps);
}

FPL_HOT static void steps_hamiltonian(const fpl_splitting *scheme, void *ctx, double *y,
                                      double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 0))
        return;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 0))
        return;
    if (c->lat->beta == 0.0)
        steps_few_hamiltonian_quad(scheme, c, y, dt, nsteps);
    else
        steps_few_hamiltonian_cubic(scheme, c, y, dt, nsteps);
}

FPL_HOT static void steps_nonlinear(const fpl_splitting *scheme, void *ctx, double *y,
                                    double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 0))
        return;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 0))
        return;
    if (c->lat->beta == 0.0)
        steps_few_nonlinear_quad(scheme, c, y, dt, nsteps);
    else
        steps_few_nonlinear_cubic(scheme, c, y, dt, nsteps);
}

/* ---- the rings' steppers: the fixed chains' fused stages and many-vector steps ------------ */

/* The same code with `ring` = 1 (the interior particles are the fixed chain's; the end
 * particles and the tiles' end rows see the wrap-around bond): the rings' kicks' operations in
 * the same order, so bit-identical to steps_ring_body (models_periodic.c) and
 * steps_general_ring_body, which remain for N < 3 and where neither applies. Out of line as the
 * fixed chains' steps_few_ ones. */
FPL_HOT_APART static int steps_few_ring_homogeneous_quad(const fpl_splitting *scheme,
                                                         const fpl_lattice_ctx *c, double *y,
                                                         double dt, long nsteps)
{
    return steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 0, 1);
}

FPL_HOT_APART static int steps_few_ring_homogeneous_cubic(const fpl_splitting *scheme,
                                                          const fpl_lattice_ctx *c, double *y,
                                                          double dt, long nsteps)
{
    return steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 1, 1);
}

FPL_HOT_APART static void steps_few_ring_hamiltonian_quad(const fpl_splitting *scheme,
                                                          const fpl_lattice_ctx *c, double *y,
                                                          double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 0, 1))
        steps_general_ring_body(scheme, c, y, dt, nsteps, 1, 0);
}

FPL_HOT_APART static void steps_few_ring_hamiltonian_cubic(const fpl_splitting *scheme,
                                                           const fpl_lattice_ctx *c, double *y,
                                                           double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 1, 1))
        steps_general_ring_body(scheme, c, y, dt, nsteps, 1, 1);
}

FPL_HOT_APART static void steps_few_ring_nonlinear_quad(const fpl_splitting *scheme,
                                                        const fpl_lattice_ctx *c, double *y,
                                                        double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 0, 1))
        steps_general_ring_body(scheme, c, y, dt, nsteps, 0, 0);
}

FPL_HOT_APART static void steps_few_ring_nonlinear_cubic(const fpl_splitting *scheme,
                                                         const fpl_lattice_ctx *c, double *y,
                                                         double dt, long nsteps)
{
    if (!steps_fused(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 1, 1))
        steps_general_ring_body(scheme, c, y, dt, nsteps, 0, 1);
}

FPL_HOT int fpl_steps_ring_homogeneous_fused(const fpl_splitting *scheme, void *ctx, double *y,
                                             double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 1))
        return 1;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_HOMOGENEOUS, 1))
        return 1;
    if (c->lat->beta == 0.0)
        return steps_few_ring_homogeneous_quad(scheme, c, y, dt, nsteps);
    return steps_few_ring_homogeneous_cubic(scheme, c, y, dt, nsteps);
}

FPL_HOT void fpl_steps_ring_hamiltonian(const fpl_splitting *scheme, void *ctx, double *y,
                                        double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 1))
        return;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_HAMILTONIAN, 1))
        return;
    if (c->lat->beta == 0.0)
        steps_few_ring_hamiltonian_quad(scheme, c, y, dt, nsteps);
    else
        steps_few_ring_hamiltonian_cubic(scheme, c, y, dt, nsteps);
}

FPL_HOT void fpl_steps_ring_nonlinear(const fpl_splitting *scheme, void *ctx, double *y,
                                      double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (steps_many_vectors(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 1))
        return;
    if (steps_fused_many(scheme, c, y, dt, nsteps, FPL_MODEL_NONLINEAR, 1))
        return;
    if (c->lat->beta == 0.0)
        steps_few_ring_nonlinear_quad(scheme, c, y, dt, nsteps);
    else
        steps_few_ring_nonlinear_cubic(scheme, c, y, dt, nsteps);
}

/* ---- anharmonic force (for the harmonic-split schemes, harmonic_split.c) ---------------- */

/* Valid when cl = s = minv = 1 (the linear part is the homogeneous chain, split off exactly):
 * phi_b = alpha R_b^2 + beta R_b^3, R_b = cn[b] x[b] - cn[b-1] x[b-1], f_i = phi_{i+1} - phi_i.
 * The curvatures kappa_b = 2 alpha R_b + 3 beta R_b^2 (for the tangent) are always kept in
 * work->kappa: two flops a bond buy a branch-free loop (the tangent needs them whenever n_dev > 0). */
FPL_HOT void fpl_kernel_anharmonic_force(const fpl_lattice *lat, fpl_work *work, const double *x,
                                         double *f)
{
    const int n = lat->n;
    const double a = lat->alpha, b = lat->beta;
    const double *restrict cn = lat->cn;
    double *restrict phi = work->phi, *restrict kap = work->kappa;
    double R = cn[0] * x[0];
    phi[0] = FPL_ANH_PHI(R, a, b);
    kap[0] = FPL_KAPPA(R, a, b);
    for (int k = 1; k < n; k++) {
        double Rk = cn[k] * x[k] - cn[k - 1] * x[k - 1];
        phi[k] = FPL_ANH_PHI(Rk, a, b);
        kap[k] = FPL_KAPPA(Rk, a, b);
    }
    R = -cn[n - 1] * x[n - 1];
    phi[n] = FPL_ANH_PHI(R, a, b);
    kap[n] = FPL_KAPPA(R, a, b);
    for (int i = 0; i < n; i++)
        f[i] = phi[i + 1] - phi[i];
}

FPL_HOT void fpl_kernel_anharmonic_tangent(const fpl_lattice *lat, fpl_work *work,
                                           const double *dx, double *df)
{
    const int n = lat->n;
    const double *restrict cn = lat->cn, *restrict kap = work->kappa;
    double *restrict dphi = work->dphi;
    dphi[0] = kap[0] * cn[0] * dx[0];
    for (int k = 1; k < n; k++)
        dphi[k] = kap[k] * (cn[k] * dx[k] - cn[k - 1] * dx[k - 1]);
    dphi[n] = -kap[n] * cn[n - 1] * dx[n - 1];
    for (int i = 0; i < n; i++)
        df[i] = dphi[i + 1] - dphi[i];
}

/* ---- energies --------------------------------------------------------------------------- */

static double bond_energy(double r, double a, double b)
{
    return FPL_BOND_ENERGY(r, a, b);
}

/* 1/2 sum minv p^2 + sum_b V(c[b] x[b] - c[b-1] x[b-1]). */
static double energy_with(const fpl_lattice *lat, const double *y, const double *c)
{
    const int n = lat->n;
    const double *x = y, *p = y + n;
    double kin = 0.0, pot = 0.0;
    for (int i = 0; i < n; i++)
        kin += 0.5 * lat->minv[i] * p[i] * p[i];
    pot += bond_energy(c[0] * x[0], lat->alpha, lat->beta);
    for (int k = 1; k < n; k++)
        pot += bond_energy(c[k] * x[k] - c[k - 1] * x[k - 1], lat->alpha, lat->beta);
    pot += bond_energy(-c[n - 1] * x[n - 1], lat->alpha, lat->beta);
    return kin + pot;
}

/* Models 1-2: the Hamiltonian (cl = cn). */
static double energy_hamiltonian(const fpl_lattice *lat, const double *y)
{
    return energy_with(lat, y, lat->cn);
}

/* Model 3: energy of Eq. (Hamilt) on the state (cl = 1, minv = 1). */
static double energy_plain(const fpl_lattice *lat, const double *y)
{
    return energy_with(lat, y, lat->cl);
}

/* ---- the models: coefficients from v, kernels -------------------------------------------- */

/* Model 1: v plays no part (cl = cn = s = minv = 1). */
static void coefficients_homogeneous(double v, double *cl, double *cn, double *s, double *minv)
{
    (void)v;
    *cl = *cn = *s = *minv = 1.0;
}

/* Model 2: v in the linear and nonlinear couplings and as the mass (cl = cn = s = v, minv = 1/v). */
static void coefficients_hamiltonian(double v, double *cl, double *cn, double *s, double *minv)
{
    *cl = *cn = *s = v;
    *minv = 1.0 / v;
}

/* Model 3: v in the nonlinear couplings only (cl = s = minv = 1, cn = v). */
static void coefficients_nonlinear(double v, double *cl, double *cn, double *s, double *minv)
{
    *cl = *s = *minv = 1.0;
    *cn = v;
}

/* Adding a model = adding one entry (and its FPL_MODEL_ constant in fputlab/lattice.h). */
static const fpl_model_ops ops_table[] = {
    {FPL_MODEL_HOMOGENEOUS, "homogeneous", coefficients_homogeneous, drift_unit_mass,
     kick_homogeneous, steps_homogeneous, energy_hamiltonian, FPL_BOUNDARY_FIXED, NULL, NULL, NULL},
    {FPL_MODEL_HAMILTONIAN, "hamiltonian", coefficients_hamiltonian, drift_masses,
     kick_hamiltonian, steps_hamiltonian, energy_hamiltonian, FPL_BOUNDARY_FIXED, NULL, NULL,
     NULL},
    {FPL_MODEL_NONLINEAR, "nonlinear", coefficients_nonlinear, drift_unit_mass, kick_nonlinear,
     steps_nonlinear, energy_plain, FPL_BOUNDARY_FIXED, NULL, NULL, NULL},
    /* model_toda.c; periodic chains: models_periodic.c */
    {FPL_MODEL_TODA, "toda", fpl_toda_coefficients, drift_unit_mass, fpl_toda_kick_fixed,
     fpl_toda_steps_fixed,
     fpl_any_energy_hamiltonian, FPL_BOUNDARY_FIXED, fpl_any_force, fpl_any_tangent,
     fpl_any_jacobian_entries},
};
#define N_MODELS (sizeof ops_table / sizeof ops_table[0])

const fpl_model_ops *fpl_model_ops_for(int model)
{
    for (size_t i = 0; i < N_MODELS; i++)
        if (ops_table[i].model == model)
            return &ops_table[i];
    return NULL;
}

const fpl_model_ops *fpl_model_ops_lookup(int model, int boundary)
{
    return boundary == FPL_BOUNDARY_PERIODIC ? fpl_model_ops_periodic(model)
                                             : fpl_model_ops_for(model);
}

int fpl_model_unknown(int model)
{
    char known[160] = "";
    for (size_t i = 0; i < N_MODELS; i++) {
        size_t used = strlen(known);
        snprintf(known + used, sizeof known - used, "%s%d %s", i ? ", " : "", ops_table[i].model,
                 ops_table[i].name);
    }
    return fpl_error(NULL, FPL_ERR_UNKNOWN, "model %d is unknown (%s)", model, known);
}

const char *fpl_model_name(int model)
{
    const fpl_model_ops *ops = fpl_model_ops_for(model);
    return ops ? ops->name : "unknown";
}

/* ---- generic (non-hot) kernels for the public evaluation API ---------------------------- */

void fpl_kernel_force(const fpl_lattice *lat, fpl_work *w, const double *x, double *f)
{
    if (lat->ops->force) {
        lat->ops->force(lat, w, x, f);
        return;
    }
    memset(f, 0, sizeof(double) * (size_t)lat->n);
    bond_forces_generic(lat->n, x, lat->cl, lat->cn, lat->alpha, lat->beta, w->phi, NULL);
    add_divergence(lat->n, 1.0, lat->s, w->phi, f);
}

void fpl_kernel_tangent(const fpl_lattice *lat, fpl_work *w, const double *x, int n_dev,
                        const double *dx, double *df)
{
    if (lat->ops->tangent) {
        lat->ops->tangent(lat, w, x, n_dev, dx, df);
        return;
    }
    const int n = lat->n;
    bond_forces_generic(n, x, lat->cl, lat->cn, lat->alpha, lat->beta, w->phi, w->kappa);
    for (int m = 0; m < n_dev; m++) {
        double *out = df + (size_t)m * n;
        memset(out, 0, sizeof(double) * (size_t)n);
        bond_tangent_generic(n, dx + (size_t)m * n, lat->cl, lat->cn, w->kappa, w->dphi);
        add_divergence(n, 1.0, lat->s, w->dphi, out);
    }
}

void fpl_kernel_rhs(const fpl_lattice *lat, fpl_work *work, const double *y, int n_dev,
                    double *ydot)
{
    const int n = lat->n;
    for (int m = 0; m <= n_dev; m++) {
        const double *p = y + 2 * (size_t)n * m + n;
        double *xd = ydot + 2 * (size_t)n * m;
        for (int i = 0; i < n; i++)
            xd[i] = lat->minv[i] * p[i];
    }
    fpl_kernel_force(lat, work, y, ydot + n);
    for (int m = 1; m <= n_dev; m++) {
        /* fpl_kernel_tangent recomputes kappa; cheap next to what a caller does with f */
        fpl_kernel_tangent(lat, work, y, 1, y + 2 * (size_t)n * m, ydot + 2 * (size_t)n * m + n);
    }
}

/* R_b of bond b (0..N) for coefficients c. */
static double stretch(const fpl_lattice *lat, const double *c, const double *x, int b)
{
    const int n = lat->n;
    double right = b < n ? c[b] * x[b] : 0.0;
    double left = b > 0 ? c[b - 1] * x[b - 1] : 0.0;
    return right - left;
}

void fpl_kernel_jacobian_entries(const fpl_lattice *lat, const double *y, int n_dev,
                                 fpl_emit_fn emit, void *ctx)
{
    if (lat->ops->jacobian_entries) {
        lat->ops->jacobian_entries(lat, y, n_dev, emit, ctx);
        return;
    }
    const int n = lat->n;
    const double a = lat->alpha, b = lat->beta;
    const double *cl = lat->cl, *cn = lat->cn, *s = lat->s, *x = y;
    for (int blk = 0; blk <= n_dev; blk++) {
        long o = 2L * n * blk;
        for (int i = 0; i < n; i++)
            emit(ctx, o + i, o + n + i, lat->minv[i]);
        for (int i = 0; i < n; i++) {
            double Rl = stretch(lat, cn, x, i), Rr = stretch(lat, cn, x, i + 1);
            double kl = Rl * (2 * a + 3 * b * Rl), kr = Rr * (2 * a + 3 * b * Rr);
            long row = o + n + i;
            emit(ctx, row, o + i, -s[i] * (2 * cl[i] + (kl + kr) * cn[i]));
            if (i + 1 < n) emit(ctx, row, o + i + 1, s[i] * (cl[i + 1] + kr * cn[i + 1]));
            if (i > 0) emit(ctx, row, o + i - 1, s[i] * (cl[i - 1] + kl * cn[i - 1]));
            if (blk > 0) {
                /* d/dx of J(x) dx: the curvature kappa depends on x */
                const double *dx = y + o;
                double dRl = stretch(lat, cn, dx, i), dRr = stretch(lat, cn, dx, i + 1);
                double gl = (2 * a + 6 * b * Rl) * dRl, gr = (2 * a + 6 * b * Rr) * dRr;
                emit(ctx, row, i, -s[i] * (gr + gl) * cn[i]);
                if (i + 1 < n) emit(ctx, row, i + 1, s[i] * gr * cn[i + 1]);
                if (i > 0) emit(ctx, row, i - 1, s[i] * gl * cn[i - 1]);
            }
        }
    }
}
