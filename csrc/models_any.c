/* Generic kernels for every model and both boundary conditions: force, tangent force, the
 * Jacobian's entries and the energies, for the public evaluation API, the SUNDIALS and GSL back
 * ends (through fpl_kernel_*) and the events. Not the hot path (the splitting schemes use the
 * kicks of models.c, models_periodic.c and model_toda.c), so written for clarity: one bond at a
 * time through `stretch` and `bond_law`. Notation as internal.h: bond b joins particles b-1 and
 * b; fixed ends: bonds 0..N, walls beyond; periodic: bonds 0..N-1, particle -1 = N-1 and bond
 * N = bond 0, so F_i = s_i (phi_{i+1} - phi_i) holds for both. */
#include <math.h>
#include <string.h>
#include "models_extra.h"
#include "fpl_expm1.h"

/* R_b = c[b] x[b] - c[b-1] x[b-1] of bond b = 0..N. */
static double stretch(const fpl_lattice *lat, const double *c, const double *x, int b)
{
    const int n = lat->n;
    if (lat->boundary == FPL_BOUNDARY_PERIODIC) {
        const int right = b == n ? 0 : b, left = b == 0 ? n - 1 : b - 1;
        return c[right] * x[right] - c[left] * x[left];
    }
    const double right = b < n ? c[b] * x[b] : 0.0;
    const double left = b > 0 ? c[b - 1] * x[b - 1] : 0.0;
    return right - left;
}

/* The bond force is phi = L + phi_nl(R): L the linear stretch (cl), R the nonlinear one (cn).
 * Polynomial models: phi_nl = alpha R^2 + beta R^3. Toda (cl = cn = 1, so L = R):
 * phi_nl = V'(R) - R. kap_nl = d phi_nl / dR, dkap = d kap_nl / dR. */
typedef struct bond_law {
    int toda;
    double a, b, inv_2a;
} bond_law;

static bond_law law_of(const fpl_lattice *lat)
{
    bond_law law = {lat->ops->model == FPL_MODEL_TODA, lat->alpha, lat->beta, 0.0};
    if (law.toda) law.inv_2a = 0.5 / lat->alpha;
    return law;
}

static void law_eval(const bond_law *law, double R, double *phi_nl, double *kap_nl, double *dkap)
{
    const double a = law->a, b = law->b;
    if (law->toda) {
        const double m = fpl_expm1(2.0 * a * R);   /* the kicks' expm1 (model_terms.h) */
        *phi_nl = m * law->inv_2a - R;
        *kap_nl = m;
        *dkap = 2.0 * a * (1.0 + m);
    } else {
        *phi_nl = R * R * (a + b * R);
        *kap_nl = R * (2.0 * a + 3.0 * b * R);
        *dkap = 2.0 * a + 6.0 * b * R;
    }
}

static int bond_count(const fpl_lattice *lat)
{
    return lat->boundary == FPL_BOUNDARY_PERIODIC ? lat->n : lat->n + 1;
}

/* phi_b (and kappa_b = kap_nl(R_b) if kap) for b = 0..N, phi_N = phi_0 on a ring. */
static void bond_forces(const fpl_lattice *lat, const double *x, double *phi, double *kap)
{
    const bond_law law = law_of(lat);
    const int nb = bond_count(lat);
    for (int b = 0; b < nb; b++) {
        double pn, kn, dk;
        law_eval(&law, stretch(lat, lat->cn, x, b), &pn, &kn, &dk);
        phi[b] = stretch(lat, lat->cl, x, b) + pn;
        if (kap) kap[b] = kn;
    }
    if (nb == lat->n) {
        phi[lat->n] = phi[0];
        if (kap) kap[lat->n] = kap[0];
    }
}

void fpl_any_force(const fpl_lattice *lat, fpl_work *work, const double *x, double *f)
{
    double *phi = work->phi;
    bond_forces(lat, x, phi, NULL);
    for (int i = 0; i < lat->n; i++)
        f[i] = lat->s[i] * (phi[i + 1] - phi[i]);
}

void fpl_any_tangent(const fpl_lattice *lat, fpl_work *work, const double *x, int n_dev,
                     const double *dx, double *df)
{
    const int n = lat->n, nb = bond_count(lat);
    double *kap = work->kappa, *dphi = work->dphi;
    bond_forces(lat, x, work->phi, kap);
    for (int m = 0; m < n_dev; m++) {
        const double *u = dx + (size_t)m * n;
        double *out = df + (size_t)m * n;
        for (int b = 0; b < nb; b++)
            dphi[b] = stretch(lat, lat->cl, u, b) + kap[b] * stretch(lat, lat->cn, u, b);
        if (nb == n) dphi[n] = dphi[0];
        for (int i = 0; i < n; i++)
            out[i] = lat->s[i] * (dphi[i + 1] - dphi[i]);
    }
}

void fpl_any_jacobian_entries(const fpl_lattice *lat, const double *y, int n_dev,
                              void (*emit)(void *ctx, long row, long col, double value), void *ctx)
{
    const int n = lat->n, ring = lat->boundary == FPL_BOUNDARY_PERIODIC;
    const bond_law law = law_of(lat);
    const double *cl = lat->cl, *cn = lat->cn, *s = lat->s, *x = y;
    for (int blk = 0; blk <= n_dev; blk++) {
        const long o = 2L * n * blk;
        for (int i = 0; i < n; i++)
            emit(ctx, o + i, o + n + i, lat->minv[i]);
        for (int i = 0; i < n; i++) {
            /* neighbours (-1: a wall); on a ring of two both are the other particle, and the
             * emitted values add up */
            const int l = i > 0 ? i - 1 : ring ? n - 1 : -1;
            const int r = i + 1 < n ? i + 1 : ring ? 0 : -1;
            const double Rl = stretch(lat, cn, x, i), Rr = stretch(lat, cn, x, i + 1);
            double pl, kl, dkl, pr, kr, dkr;
            law_eval(&law, Rl, &pl, &kl, &dkl);
            law_eval(&law, Rr, &pr, &kr, &dkr);
            const long row = o + n + i;
            emit(ctx, row, o + i, -s[i] * (2 * cl[i] + (kl + kr) * cn[i]));
            if (r >= 0) emit(ctx, row, o + r, s[i] * (cl[r] + kr * cn[r]));
            if (l >= 0) emit(ctx, row, o + l, s[i] * (cl[l] + kl * cn[l]));
            if (blk > 0) {
                /* d/dx of J(x) dx: the curvature kappa depends on x */
                const double *dx = y + o;
                const double gl = dkl * stretch(lat, cn, dx, i);
                const double gr = dkr * stretch(lat, cn, dx, i + 1);
                emit(ctx, row, i, -s[i] * (gr + gl) * cn[i]);
                if (r >= 0) emit(ctx, row, r, s[i] * gr * cn[r]);
                if (l >= 0) emit(ctx, row, l, s[i] * gl * cn[l]);
            }
        }
    }
}

double fpl_toda_bond_energy(double r, double alpha)
{
    const double u = 2.0 * alpha * r;
    if (fabs(u) < 0.1) {
        /* (e^u - 1 - u) = sum_{k>=2} u^k/k!; to u^13 the remainder is < 0.1^14/14! relative */
        double term = 1.0 / 6227020800.0, sum = term; /* 1/13! */
        for (int k = 12; k >= 2; k--) {
            term *= k + 1;  /* 1/k! from 1/(k+1)! */
            sum = sum * u + term;
        }
        return sum * u * u / (4.0 * alpha * alpha);
    }
    return (fpl_expm1(u) - u) / (4.0 * alpha * alpha);
}

static double energy_with(const fpl_lattice *lat, const double *y, const double *c)
{
    const int n = lat->n, nb = bond_count(lat);
    const int toda = lat->ops->model == FPL_MODEL_TODA;
    const double a = lat->alpha, b = lat->beta;
    const double *x = y, *p = y + n;
    double kin = 0.0, pot = 0.0;
    for (int i = 0; i < n; i++)
        kin += 0.5 * lat->minv[i] * p[i] * p[i];
    for (int k = 0; k < nb; k++) {
        const double r = stretch(lat, c, x, k);
        pot += toda ? fpl_toda_bond_energy(r, a) : r * r * (0.5 + r * (a / 3.0 + 0.25 * b * r));
    }
    return kin + pot;
}

double fpl_any_energy_hamiltonian(const fpl_lattice *lat, const double *y)
{
    return energy_with(lat, y, lat->cn);
}

double fpl_any_energy_plain(const fpl_lattice *lat, const double *y)
{
    return energy_with(lat, y, lat->cl);
}
