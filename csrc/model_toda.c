/* The Toda lattice: unit masses, bond potential V(r) = (e^{2 alpha r} - 1 - 2 alpha r)/(4 alpha^2)
 * (FPUT-alpha to third order in r, FPUT-alpha-beta with beta = 2 alpha^2/3 to fourth), on the
 * plain stretches d_b = x_b - x_{b-1}, with fixed ends or on a ring. Homogeneous: the chain is
 * integrable only so (a disorder v would make it one more non-integrable chain, which models 2
 * and 3 already are), so lattice.c refuses a non-uniform v and beta != 0.
 * The kicks form V'(d_b) and V''(d_b) from one expm1 per bond into the scratch arrays; the loops
 * stay branch-free, but expm1 is a libm call, so they do not vectorise as the polynomial ones. */
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
