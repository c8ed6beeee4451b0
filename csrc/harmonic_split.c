/* Near-integrable splitting of the lattice: H = H_harm + H_anh with
 *   H_harm = sum_i p_i^2/2 + sum_b (x_b - x_{b-1})^2/2 = sum_k (P_k^2 + w_k^2 Q_k^2)/2,
 *   H_anh  = sum_b (alpha R_b^3/3 + beta R_b^4/4),     w_k = 2 sin(k pi / (2(N+1))),
 * (Q, P) the normal-mode coordinates of the fixed-end chain (orthogonal sine transform).
 * A = exact flow of H_harm: every mode turns by the angle w_k h,
 *   Q <- cos(w h) Q + sin(w h)/w P,   P <- -w sin(w h) Q + cos(w h) P;
 * B = kick by the anharmonic force alone, p <- p + h F_anh(x).
 * For a lattice whose nonlinearity is eps-small this is the setting in which schemes such as
 * ABA(8,6,4) (Blanes et al. 2013; the SABA family of Laskar & Robutel 2001) reach their
 * eps-dependent orders: error O(eps h^8 + eps^2 h^6 + eps^3 h^4) instead of a generic h^4.
 *
 * The split applies when the linear part is exactly the homogeneous chain: cl = s = minv = 1,
 * i.e. model 1, and model 3 (disorder in the nonlinear couplings only; then B is not a gradient
 * but the composition is still a consistent order-p scheme for x'' = F(x)). Model 2's linear
 * couplings vary, its normal modes are not a sine transform: refused by the prepare hook.
 *
 * Cost: the step stays in mode space between stages, so a step of s kicks takes 2s + 4 sine
 * transforms (FFT, O(N log N)) per vector instead of O(N) kicks; worth it when the accuracy
 * gained at small nonlinearity pays for the transforms. Deviation vectors: A is linear (its
 * tangent map is itself); B's tangent map is dp += h J_anh(x) dx. */
#include <math.h>
#include <stdlib.h>
#include "internal.h"

int fpl_harmonic_prepare(const fpl_splitting *scheme, fpl_lattice *lat, int n_dev)
{
    const int n = lat->n;
    for (int j = 0; j < n; j++) {
        if (lat->cl[j] != 1.0 || lat->s[j] != 1.0 || lat->minv[j] != 1.0)
            return fpl_error(lat, FPL_ERR_ARG,
                             "method '%s' integrates the harmonic chain exactly in normal modes, "
                             "which needs uniform linear couplings and masses (models "
                             "'homogeneous' and 'nonlinear'); this '%s' lattice has v[%d] = %g "
                             "in its linear part: use 'aba864' instead",
                             scheme->name, lat->ops->name, j, lat->v[j]);
    }
    const size_t dim = 2 * (size_t)n * ((size_t)n_dev + 1);
    const size_t work = 2 * (size_t)n + 2 * dim;
    if (lat->modework_cap < work) {
        double *w = realloc(lat->modework, sizeof(double) * work);
        if (!w)
            return fpl_error(lat, FPL_ERR_NOMEM, "out of memory (mode-space scratch, N = %d)", n);
        lat->modework = w;
        lat->modework_cap = work;
    }
    const size_t need = 2 * (size_t)n * (size_t)(scheme->n_kicks + 1);
    if (lat->rot_cap < need) {
        double *rot = realloc(lat->rot, sizeof(double) * need);
        if (!rot)
            return fpl_error(lat, FPL_ERR_NOMEM, "out of memory (mode rotations, N = %d)", n);
        lat->rot = rot;
        lat->rot_cap = need;
        lat->rot_scheme = NULL; /* contents no longer match any step */
    }
    return FPL_OK;
}

/* The A-flow turns each mode (w Q, P) by theta = w h. As a matrix [[c, s/w], [-w s, c]] the
 * rounded entries give a determinant 1 + O(1e-16) with a fixed sign per mode, applied every
 * drift: the harmonic energy then drifts linearly in time (measured 5e-12 by t = 1e3, N = 64,
 * dt = 0.05, against 6e-14 with shears). The same rotation as three shears,
 *   Q += tan(theta/2)/w P,   P -= w sin(theta) Q,   Q += tan(theta/2)/w P,
 * is exactly area-preserving whatever the rounding of its two coefficients (a shear has
 * determinant 1), so only the phase carries round-off. tan(theta/2) is well conditioned for
 * |theta| <= pi/2; a larger angle (huge steps only) is done as r equal sub-rotations.
 * Coefficients per drift i: tq = tan(theta/2)/w, sp = w sin(theta), theta = w a_i dt / r;
 * recomputed only when dt or the scheme changes (a run keeps one dt; an event search or an
 * off-grid sample pays O(N s) trigonometric calls once). */
static void rotations(const fpl_splitting *scheme, fpl_lattice *lat, double dt)
{
    if (lat->rot_scheme == scheme && lat->rot_dt == dt) return;
    const int n = lat->n, s = scheme->n_kicks;
    const double w_max = 2.0 * sin(n * M_PI / (2.0 * (n + 1)));
    double a_max = 0.0;
    for (int i = 0; i <= s; i++) a_max = fmax(a_max, fabs(scheme->drift[i]));
    const double r = fmax(1.0, ceil(w_max * a_max * dt / (0.5 * M_PI)));
    lat->rot_reps = (int)r;
    for (int i = 0; i <= s; i++) {
        double *tq = lat->rot + 2 * (size_t)n * i, *sp = tq + n;
        const double h = scheme->drift[i] * dt / r;
        for (int k = 1; k <= n; k++) {
            const double w = 2.0 * sin(k * M_PI / (2.0 * (n + 1)));
            tq[k - 1] = tan(0.5 * w * h) / w;
            sp[k - 1] = w * sin(w * h);
        }
    }
    lat->rot_scheme = scheme;
    lat->rot_dt = dt;
}

/* A-flow of drift i on the orbit and every deviation vector, all held in mode space. */
static void rotate(const fpl_lattice *lat, double *z, int n_dev, int i)
{
    const int n = lat->n;
    const double *restrict tq = lat->rot + 2 * (size_t)n * i, *restrict sp = tq + n;
    for (int m = 0; m <= n_dev; m++) {
        double *restrict q = z + 2 * (size_t)n * m, *restrict p = q + n;
        for (int r = 0; r < lat->rot_reps; r++) {
            for (int k = 0; k < n; k++) {
                double qk = q[k] + tq[k] * p[k];
                const double pk = p[k] - sp[k] * qk;
                q[k] = qk + tq[k] * pk;
                p[k] = pk;
            }
        }
    }
}

/* B-kick in mode space: x = S Q, f = F_anh(x), P += h S f (S the sine transform, S = S^-1 = S^T);
 * deviation vectors: dx = S dQ, dP += h S J_anh(x) dx. */
static void kick(fpl_lattice *lat, double *z, int n_dev, double h)
{
    const int n = lat->n;
    double *x = lat->modework, *f = lat->modework + n;
    fpl_modes_sine(lat, z, x);
    fpl_kernel_anharmonic_force(lat, x, f);
    fpl_modes_sine(lat, f, f);
    for (int k = 0; k < n; k++) z[n + k] += h * f[k];
    for (int m = 1; m <= n_dev; m++) {
        double *dq = z + 2 * (size_t)n * m, *dp = dq + n;
        fpl_modes_sine(lat, dq, x);
        fpl_kernel_anharmonic_tangent(lat, x, f);
        fpl_modes_sine(lat, f, f);
        for (int k = 0; k < n; k++) dp[k] += h * f[k];
    }
}

/* All vectors of y (real space) into z (mode space) by the sine transform. */
static void to_modes(fpl_lattice *lat, const double *y, double *z, int n_dev)
{
    const int n = lat->n;
    for (int m = 0; m <= n_dev; m++) {
        const size_t o = 2 * (size_t)n * m;
        fpl_modes_sine(lat, y + o, z + o);
        fpl_modes_sine(lat, y + o + n, z + o + n);
    }
}

/* The step moves to mode space and back. In floating point the pair S S is the identity only
 * up to a systematic ~1e-16 scaling (the rounded normalisation), and taking the whole state
 * through it every step made the energy drift linearly (measured with the shear rotations:
 * 6e-12 by t = 1e3 at dt = 0.05, N = 64). So only the step's change crosses back:
 * y += S (z_end - z_start) with z_start = S y; the bias then scales the change, not the state
 * (measured 6e-14, round-off level). */
void fpl_step_harmonic(const fpl_splitting *scheme, fpl_lattice *lat, double *y, int n_dev,
                       double dt)
{
    const int n = lat->n, s = scheme->n_kicks;
    const size_t dim = 2 * (size_t)n * ((size_t)n_dev + 1);
    double *z = lat->modework + 2 * (size_t)n, *z0 = z + dim;
    rotations(scheme, lat, dt);
    to_modes(lat, y, z0, n_dev);
    for (size_t i = 0; i < dim; i++) z[i] = z0[i];
    for (int i = 0; i < s; i++) {
        rotate(lat, z, n_dev, i);
        kick(lat, z, n_dev, scheme->kick[i] * dt);
    }
    rotate(lat, z, n_dev, s);
    for (size_t i = 0; i < dim; i++) z[i] -= z0[i];
    to_modes(lat, z, z, n_dev);
    for (size_t i = 0; i < dim; i++) y[i] += z[i];
}
