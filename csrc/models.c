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

FPL_INLINE void kick_orbit_homogeneous(int n, const double *restrict x, double *restrict p,
                                       double a, double b, double h, double *restrict kap,
                                       const int cubic)
{
    for (int i = 1; i < n - 1; i++) {
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
FPL_INLINE void kick_orbit_tangent_homogeneous(int n, const double *restrict x,
                                               double *restrict p, const double *restrict u,
                                               double *restrict q, const double *restrict w,
                                               double *restrict r, double a, double b, double h,
                                               const int cubic, const int two)
{
    /* `two` is a constant at every (inlined) call: the second vector's line is there or not */
    for (int i = 1; i < n - 1; i++) {
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
        kick_orbit_homogeneous(n, x, p, a, b, h, NULL, cubic);
    } else if (n_dev == 1) {
        kick_orbit_tangent_homogeneous(n, x, p, y + stride, y + stride + n, NULL, NULL, a, b, h,
                                       cubic, 0);
    } else if (n_dev == 2) {
        kick_orbit_tangent_homogeneous(n, x, p, y + stride, y + stride + n, y + 2 * stride,
                                       y + 2 * stride + n, a, b, h, cubic, 1);
    } else {
        /* more vectors (GALI_k, k > 2): kappa once into the scratch array, then one pass each */
        kick_orbit_homogeneous(n, x, p, a, b, h, kap, cubic);
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
FPL_INLINE void drift_unit_mass_body(const fpl_lattice_ctx *c, double *y, double h)
{
    const int n = c->lat->n, n_dev = c->n_dev;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict x = y + 2 * (size_t)n * m;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++)
            FPL_DRIFT_UNIT(x[i], h, p[i]);
    }
}

FPL_HOT static void drift_unit_mass(void *ctx, double *y, int stage, double h)
{
    (void)stage;
    drift_unit_mass_body(ctx, y, h);
}

FPL_HOT static void drift_masses(void *ctx, double *y, int stage, double h)
{
    (void)stage;
    const fpl_lattice_ctx *c = ctx;
    const int n = c->lat->n, n_dev = c->n_dev;
    const double *restrict minv = c->lat->minv;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict x = y + 2 * (size_t)n * m;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++)
            FPL_DRIFT(x[i], h, minv[i], p[i]);
    }
}

/* ---- the homogeneous chain's fused stepper ---------------------------------------------- */

FPL_HOT static void kick_homogeneous(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_homogeneous_body(c, y, h, 0);
    else
        kick_homogeneous_body(c, y, h, 1);
}

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

FPL_HOT static void steps_homogeneous(const fpl_splitting *scheme, void *ctx, double *y,
                                      double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        steps_homogeneous_body(scheme, c, y, dt, nsteps, 0);
    else
        steps_homogeneous_body(scheme, c, y, dt, nsteps, 1);
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
    {FPL_MODEL_HAMILTONIAN, "hamiltonian", coefficients_hamiltonian, drift_masses, kick_generic,
     NULL, energy_hamiltonian, FPL_BOUNDARY_FIXED, NULL, NULL, NULL},
    {FPL_MODEL_NONLINEAR, "nonlinear", coefficients_nonlinear, drift_unit_mass, kick_generic,
     NULL, energy_plain, FPL_BOUNDARY_FIXED, NULL, NULL, NULL},
    /* model_toda.c; periodic chains: models_periodic.c */
    {FPL_MODEL_TODA, "toda", fpl_toda_coefficients, drift_unit_mass, fpl_toda_kick_fixed, NULL,
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
