/* Each model's bond expressions, written once (private, not installed).
 *
 * The scalar kernels of models.c (kicks, fused steppers, the anharmonic force of the harmonic
 * split, energies) and the lane kernels of chaos_batch.c (GCC generic vectors of doubles) both
 * evaluate these macros, so a lane and a single orbit compute the same operations in the same
 * order and agree to the last bit. Macros rather than inline functions because the same
 * expression serves `double` and the lane vector type; every argument is a plain value (an
 * argument may be evaluated more than once). Notation as in internal.h: bond b joins particles
 * b-1 and b (the walls are particles -1 and N),
 *   L_b = cl[b] x[b] - cl[b-1] x[b-1],   R_b = cn[b] x[b] - cn[b-1] x[b-1],
 *   phi_b = L_b + alpha R_b^2 + beta R_b^3,   kappa_b = dphi_b/dR_b - dL_b/dR_b,
 *   F_i = s[i] (phi_{i+1} - phi_i),   x_i' = minv[i] p_i.
 * The operand order matters: it fixes the rounding, and with it the bits every test and the
 * chaos study's counts rely on. */
#ifndef FPUTLAB_MODEL_TERMS_H
#define FPUTLAB_MODEL_TERMS_H

#include "fpl_expm1.h"

/* ---- model 1, the homogeneous chain (cl = cn = s = minv = 1): d_b = x_b - x_{b-1} --------- */

/* phi_b and the full curvature V''(d_b) (the linear part's 1 included). */
#define FPL_HOM_PHI(d, a, b) ((d) + (d) * (d) * ((a) + (b) * (d)))
#define FPL_HOM_KAPPA(d, a, b) (1.0 + (d) * (2.0 * (a) + 3.0 * (b) * (d)))
/* beta = 0 (the kernels' `cubic` = 0 builds): with b = 0, a + b d == a and 2a + 3b d == 2a
 * exactly for finite d, so these give the bits of the two above with 4 flops fewer. */
#define FPL_HOM_PHI_QUAD(d, a) ((d) + (d) * (d) * (a))
#define FPL_HOM_KAPPA_QUAD(d, a) (1.0 + (d) * (2.0 * (a)))
/* The tangent bond force is kappa_b dd_b (dd_b the deviation vector's d_b; -kappa_N dx_{N-1}
 * at the right wall). */

/* ---- models 2 and 3: the general bond (linear stretch L, nonlinear stretch R) -------------- */

#define FPL_PHI(L, R, a, b) ((L) + (R) * (R) * ((a) + (b) * (R)))
#define FPL_KAPPA(R, a, b) ((R) * (2.0 * (a) + 3.0 * (b) * (R)))
/* beta = 0: the same bits as FPL_PHI / FPL_KAPPA with b = 0 (see above). */
#define FPL_PHI_QUAD(L, R, a) ((L) + (R) * (R) * (a))
#define FPL_KAPPA_QUAD(R, a) ((R) * (2.0 * (a)))
/* Tangent bond force dphi_b = dL_b + kappa_b dR_b of an interior bond (dL, dR: the deviation
 * vector's stretches). */
#define FPL_DPHI(dL, kap, dR) ((dL) + (kap) * (dR))
/* The wall bonds keep the form (kappa c) dx of the one particle they touch:
 * left (b = 0, particle 0): dL_0 + kappa_0 cn_0 dx_0, dL_0 = cl_0 dx_0;
 * right (b = N, particle N-1): dL_N - kappa_N cn_{N-1} dx_{N-1}, dL_N = -cl_{N-1} dx_{N-1}. */
#define FPL_DPHI_LEFT(dL, kap, c, dx) ((dL) + (kap) * (c) * (dx))
#define FPL_DPHI_RIGHT(dL, kap, c, dx) ((dL) - (kap) * (c) * (dx))

/* The anharmonic part alone (the harmonic split's kick, linear part = the homogeneous chain). */
#define FPL_ANH_PHI(R, a, b) ((R) * (R) * ((a) + (b) * (R)))

/* Potential energy of one bond of stretch r (every model: r = R_b with c = cn for models 1-2,
 * c = cl for model 3's Eq. (Hamilt)). */
#define FPL_BOND_ENERGY(r, a, b) ((r) * (r) * (0.5 + (r) * ((a) / 3.0 + 0.25 * (b) * (r))))

/* ---- model 4, the Toda lattice (cl = cn = s = minv = 1): d_b = x_b - x_{b-1} -------------- */

/* V(d) = (e^{2 alpha d} - 1 - 2 alpha d)/(4 alpha^2). From m = expm1(2 alpha d), one a bond
 * (expm1 rather than exp - 1: the harmonic limit lives in the digits exp - 1 would lose):
 * phi_b = V'(d_b) = m / (2 alpha) (inv_2a = 1/(2 alpha)) and the full curvature V''(d_b) = 1 + m.
 * expm1 is fpl_expm1.h's, branch-free, so the bond loops vectorise; a lane kernel calls its
 * four-lane form FPL_TODA_M_V4 (out = m), the same arithmetic (the same bits per lane). */
#define FPL_TODA_M(d, two_a) fpl_expm1((two_a) * (d))
#define FPL_TODA_M_V4(out, d, two_a)                                                               \
    do {                                                                                         \
        const fpl_v4d u_ = (two_a) * (d);                                                        \
        fpl_expm1_v4(&u_, &(out));                                                               \
    } while (0)
#define FPL_TODA_PHI(m, inv_2a) ((m) * (inv_2a))
#define FPL_TODA_KAPPA(m) (1.0 + (m))
/* The tangent bond force is kappa_b dd_b, as model 1's. */

/* ---- the kick's divergence and the kinetic drift ------------------------------------------ */

/* p_i += h s_i (phi_{i+1} - phi_i); the unit-s form (models 1, 3) drops the exact factor 1. */
#define FPL_KICK(p, h, s, f1, f0) ((p) += (h) * (s) * ((f1) - (f0)))
#define FPL_KICK_UNIT(p, h, f1, f0) ((p) += (h) * ((f1) - (f0)))
/* x_i += h minv_i p_i; the unit-mass form (models 1, 3) drops the exact factor 1. */
#define FPL_DRIFT(x, h, minv, p) ((x) += (h) * (minv) * (p))
#define FPL_DRIFT_UNIT(x, h, p) ((x) += (h) * (p))

#endif
