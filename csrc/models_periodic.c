/* The periodic chains: N particles on a ring, N bonds, bond 0 joining particle N-1 and 0
 * (x_N = x_0; the disorder coefficients indexed mod N). Hot kernels as in models.c: branch-free
 * loops over contiguous arrays with the wrap-around bond peeled off, so the interior loops
 * vectorise. The generic (non-hot) kernels and the energies are models_any.c's; the Toda kick
 * is model_toda.c's. */
#include <string.h>
#include "models_extra.h"
#include "model_terms.h"

#define FPL_INLINE static inline __attribute__((always_inline))

/* ---- drifts (the same for both boundaries; shared with the Toda entries) ------------------ */

FPL_HOT void fpl_drift_unit_mass(void *ctx, double *y, int stage, double h)
{
    (void)stage;
    const fpl_lattice_ctx *c = ctx;
    const int n = c->lat->n, n_dev = c->n_dev;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict x = y + 2 * (size_t)n * m;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++)
            FPL_DRIFT_UNIT(x[i], h, p[i]);
    }
}

FPL_HOT void fpl_drift_masses(void *ctx, double *y, int stage, double h)
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

/* ---- models 2 and 3: bond arrays, the wrap-around bond 0 first ----------------------------- */

/* phi_b = L_b + alpha R_b^2 + beta R_b^3 and kappa_b = 2 alpha R_b + 3 beta R_b^2 for b = 0..N-1,
 * with phi_N = phi_0 (and kappa_N = kappa_0) so that F_i = s_i (phi_{i+1} - phi_i) for every i. */
FPL_INLINE void bond_forces_periodic(int n, const double *restrict x, const double *restrict cl,
                                     const double *restrict cn, double a, double b,
                                     double *restrict phi, double *restrict kap, const int tangent)
{
    const double L = cl[0] * x[0] - cl[n - 1] * x[n - 1];
    const double R = cn[0] * x[0] - cn[n - 1] * x[n - 1];
    phi[0] = phi[n] = FPL_PHI(L, R, a, b);
    if (tangent) kap[0] = kap[n] = FPL_KAPPA(R, a, b);
    for (int k = 1; k < n; k++) {
        const double Lk = cl[k] * x[k] - cl[k - 1] * x[k - 1];
        const double Rk = cn[k] * x[k] - cn[k - 1] * x[k - 1];
        phi[k] = FPL_PHI(Lk, Rk, a, b);
        if (tangent) kap[k] = FPL_KAPPA(Rk, a, b);
    }
}

FPL_INLINE void bond_tangent_periodic(int n, const double *restrict dx, const double *restrict cl,
                                      const double *restrict cn, const double *restrict kap,
                                      double *restrict dphi)
{
    dphi[0] = dphi[n] = FPL_DPHI(cl[0] * dx[0] - cl[n - 1] * dx[n - 1], kap[0],
                                 cn[0] * dx[0] - cn[n - 1] * dx[n - 1]);
    for (int k = 1; k < n; k++)
        dphi[k] = FPL_DPHI(cl[k] * dx[k] - cl[k - 1] * dx[k - 1], kap[k],
                           cn[k] * dx[k] - cn[k - 1] * dx[k - 1]);
}

FPL_INLINE void add_divergence(int n, double h, const double *restrict s,
                               const double *restrict phi, double *restrict p)
{
    for (int i = 0; i < n; i++)
        FPL_KICK(p[i], h, s[i], phi[i + 1], phi[i]);
}

FPL_HOT void fpl_kick_generic_periodic(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    const fpl_lattice *lat = c->lat;
    fpl_work *w = c->work;
    const int n = lat->n, n_dev = c->n_dev;
    if (n_dev == 0) {
        bond_forces_periodic(n, y, lat->cl, lat->cn, lat->alpha, lat->beta, w->phi, w->kappa, 0);
    } else {
        bond_forces_periodic(n, y, lat->cl, lat->cn, lat->alpha, lat->beta, w->phi, w->kappa, 1);
    }
    add_divergence(n, h, lat->s, w->phi, y + n);
    for (int m = 0; m < n_dev; m++) {
        double *dx = y + 2 * (size_t)n * (size_t)(m + 1);
        bond_tangent_periodic(n, dx, lat->cl, lat->cn, w->kappa, w->dphi);
        add_divergence(n, h, lat->s, w->dphi, dx + n);
    }
}

/* ---- the homogeneous ring: fused kick and stepper ---------------------------------------- */

/* V'(d) and V''(d) of the FPUT-alpha-beta bond; `cubic` is a constant at every inlined call
 * (beta = 0 drops the cubic terms, as models.c does). */
#define PHI_P(d) (cubic ? FPL_HOM_PHI(d, a, b) : FPL_HOM_PHI_QUAD(d, a))
#define KAP_P(d) (cubic ? FPL_HOM_KAPPA(d, a, b) : FPL_HOM_KAPPA_QUAD(d, a))

/* Particles 1..N-2 form both their bonds' forces where they are used (no phi array); with
 * `store`, kappa_i = V''(d_i) of their left bond goes to kap for the deviation vectors. */
FPL_INLINE void kick_orbit_ring(int n, const double *restrict x, double *restrict p, double a,
                                double b, double h, double *restrict kap, const int cubic,
                                const int store)
{
    for (int i = 1; i < n - 1; i++) {
        const double dl = x[i] - x[i - 1], dr = x[i + 1] - x[i];
        p[i] += h * (PHI_P(dr) - PHI_P(dl));
        if (store) kap[i] = KAP_P(dl);
    }
}

FPL_INLINE void kick_tangent_ring(int n, const double *restrict dx, double *restrict dp,
                                  const double *restrict kap, double h)
{
    for (int i = 1; i < n - 1; i++)
        dp[i] += h * (kap[i + 1] * (dx[i + 1] - dx[i]) - kap[i] * (dx[i] - dx[i - 1]));
}

/* The ring's kick: the interior particles in one branch-free loop, particles 0 and N-1 (the
 * two ends of the wrap-around bond d_0 = x_0 - x_{N-1}) peeled off. Valid for N >= 2 (N = 2: no
 * interior particle; bonds 0 and 1 both join the two particles). */
FPL_INLINE void kick_ring_body(const fpl_lattice_ctx *c, double *y, double h, const int cubic)
{
    const fpl_lattice *lat = c->lat;
    const int n = lat->n, n_dev = c->n_dev;
    const double a = lat->alpha, b = lat->beta;
    const size_t stride = 2 * (size_t)n;
    const double *x = y;
    double *p = y + n, *kap = c->work->kappa;
    const double dw = x[0] - x[n - 1], d1 = x[1] - x[0], dm = x[n - 1] - x[n - 2];
    const double phiw = PHI_P(dw), phi1 = PHI_P(d1), phim = PHI_P(dm);
    if (n_dev == 0) {
        kick_orbit_ring(n, x, p, a, b, h, kap, cubic, 0);
    } else {
        kick_orbit_ring(n, x, p, a, b, h, kap, cubic, 1);
        const double kw = KAP_P(dw), k1 = KAP_P(d1), km = KAP_P(dm);
        kap[n - 1] = km;
        for (int m = 0; m < n_dev; m++) {
            const double *dx = y + stride * (size_t)(m + 1);
            double *dp = (double *)dx + n;
            kick_tangent_ring(n, dx, dp, kap, h);
            const double tw = kw * (dx[0] - dx[n - 1]);
            dp[0] += h * (k1 * (dx[1] - dx[0]) - tw);
            dp[n - 1] += h * (tw - km * (dx[n - 1] - dx[n - 2]));
        }
    }
    p[0] += h * (phi1 - phiw);
    p[n - 1] += h * (phiw - phim);
}

FPL_HOT static void kick_homogeneous_periodic(void *ctx, double *y, double h)
{
    const fpl_lattice_ctx *c = ctx;
    if (c->lat->beta == 0.0)
        kick_ring_body(c, y, h, 0);
    else
        kick_ring_body(c, y, h, 1);
}

FPL_INLINE void drift_unit_body(const fpl_lattice_ctx *c, double *y, double h)
{
    const int n = c->lat->n, n_dev = c->n_dev;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict x = y + 2 * (size_t)n * m;
        const double *restrict p = x + n;
        for (int i = 0; i < n; i++)
            FPL_DRIFT_UNIT(x[i], h, p[i]);
    }
}

/* n steps of a kinetic drift-kick scheme with drift and kick inlined: the same operations in the
 * same order as fpl_split_step on fpl_drift_unit_mass / kick_homogeneous_periodic. */
FPL_INLINE void steps_ring_body(const fpl_splitting *scheme, const fpl_lattice_ctx *c, double *y,
                                double dt, long nsteps, const int cubic)
{
    const int s = scheme->n_kicks;
    const double *a = scheme->drift, *b = scheme->kick;
    for (long k = 0; k < nsteps; k++) {
        for (int i = 0; i < s; i++) {
            drift_unit_body(c, y, a[i] * dt);
            kick_ring_body(c, y, b[i] * dt, cubic);
        }
        drift_unit_body(c, y, a[s] * dt);
    }
}

FPL_HOT static void steps_homogeneous_periodic(const fpl_splitting *scheme, void *ctx, double *y,
                                               double dt, long nsteps)
{
    const fpl_lattice_ctx *c = ctx;
    if (fpl_steps_ring_homogeneous_fused(scheme, ctx, y, dt, nsteps))
        return;
    if (c->lat->beta == 0.0)
        steps_ring_body(scheme, c, y, dt, nsteps, 0);
    else
        steps_ring_body(scheme, c, y, dt, nsteps, 1);
}

/* ---- the periodic model table ------------------------------------------------------------ */

/* coefficients NULL: they follow from the model alone, the fixed-end entry's (lattice.c). */
static const fpl_model_ops periodic_table[] = {
    {FPL_MODEL_HOMOGENEOUS, "homogeneous", NULL, fpl_drift_unit_mass, kick_homogeneous_periodic,
     steps_homogeneous_periodic, fpl_any_energy_hamiltonian, FPL_BOUNDARY_PERIODIC,
     fpl_any_force, fpl_any_tangent, fpl_any_jacobian_entries},
    /* models 2 and 3: the fused ring kicks and steppers of models.c (bit-identical to
     * fpl_kick_generic_periodic, which serves rings of N < 3) */
    {FPL_MODEL_HAMILTONIAN, "hamiltonian", NULL, fpl_drift_masses, fpl_kick_ring_hamiltonian,
     fpl_steps_ring_hamiltonian, fpl_any_energy_hamiltonian, FPL_BOUNDARY_PERIODIC,
     fpl_any_force, fpl_any_tangent, fpl_any_jacobian_entries},
    {FPL_MODEL_NONLINEAR, "nonlinear", NULL, fpl_drift_unit_mass, fpl_kick_ring_nonlinear,
     fpl_steps_ring_nonlinear, fpl_any_energy_plain, FPL_BOUNDARY_PERIODIC, fpl_any_force, fpl_any_tangent,
     fpl_any_jacobian_entries},
    {FPL_MODEL_TODA, "toda", NULL, fpl_drift_unit_mass, fpl_toda_kick_periodic,
     fpl_toda_steps_periodic,
     fpl_any_energy_hamiltonian, FPL_BOUNDARY_PERIODIC, fpl_any_force, fpl_any_tangent,
     fpl_any_jacobian_entries},
};

const fpl_model_ops *fpl_model_ops_periodic(int model)
{
    for (size_t i = 0; i < sizeof periodic_table / sizeof periodic_table[0]; i++)
        if (periodic_table[i].model == model)
            return &periodic_table[i];
    return NULL;
}
