/* e^x - 1 without libm, branch-free, so that the loops calling it vectorise (private, not
 * installed). The Toda kicks call it once per bond: libm's expm1 is a scalar call, which kept
 * those loops scalar (issue 22). One arithmetic, written once (FPL_EXPM1_BODY), serves `double`
 * (fpl_expm1, vectorised by the compiler where it is inlined into a loop) and the four-lane
 * vectors of chaos_batch.c (fpl_expm1_v4, GCC generic vectors), so a lane and a single orbit
 * agree to the last bit. Max error < 1 ulp against long-double expm1l (tests/c/test_expm1.c).
 *
 * Algorithm. Clamp x to [-45, 710] (below -45, e^x - 1 rounds to -1; above 710 it overflows,
 * log DBL_MAX = 709.78). k = round(x / ln 2) by the shifter trick (x / ln2 + 1.5 2^52 rounds to
 * an integer whose low mantissa bits are k), r = x - k ln2 by Cody-Waite (ln2_hi has 21 trailing
 * zero bits, so k ln2_hi and x - k ln2_hi are exact), c the rounding error of r.
 * e^(r + c) - 1 = r + t, t = r^2/2 + r^3 q(r) + c (1 + r), q the Taylor series of
 * (e^r - 1 - r - r^2/2)/r^3 to r^10 (its truncation < 0.1 ulp of the result on |r| <= ln2/2),
 * r^2/2 formed as rh^2/2 (exact: Veltkamp's split r = rh + rl, rh of 26 bits) plus the rest.
 * Then e^x - 1 = 2 (s (1 + r + t) - 1/2) with s = 2^(k-1) built from k's bits (the factor 2 is
 * exact and keeps 2^1024 out at the overflow edge), the leading sum (s - 1/2) + s r formed with
 * its rounding errors (TwoSum), so that where the result is small next to s (k = 1, x just above
 * ln2/2) only the final rounding and t's small error remain: measured max 0.80 ulp. For
 * |x| < 2^-54 (where the halved scale would round subnormals) and NaN the result is x itself:
 * e^x - 1 rounds to x there, -0 stays -0, and NaN propagates (blow-up detection relies on
 * non-finite values). Branch-free: the clamps compile to min/max, the last select to a blend.
 * The exact steps (Veltkamp, TwoSum) need a product and a sum rounded separately: compile
 * without FMA contraction (-ffp-contract=off, ISO C's default, as the library is built). */
#ifndef FPUTLAB_FPL_EXPM1_H
#define FPUTLAB_FPL_EXPM1_H

#include <stdint.h>
#include <string.h>

#define FPL_EXPM1_SHIFTER 0x1.8p52
#define FPL_EXPM1_INV_LN2 0x1.71547652b82fep0
#define FPL_EXPM1_LN2_HI 0x1.62e42feep-1         /* 6.93147180369123816490e-01 (fdlibm) */
#define FPL_EXPM1_LN2_LO 0x1.a39ef35793c76p-33   /* 1.90821492927058770002e-10 */

/* The arithmetic, for a type T with the helpers SEL(c, u, v) = c ? u : v (elementwise) and
 * HALF_SCALE(kd) = 2^(k-1) from the shifted k's bits ((bits(kd) + 1022) << 52: the shifter's
 * low 12 bits are 0, the shift drops its high ones; k + 1022 is in [957, 2046], a normal
 * exponent). `out` receives the result. */
#define FPL_EXPM1_BODY(T, x, out, SEL, HALF_SCALE)                                               \
    do {                                                                                         \
        /* x < 710 ? x : 710 (NaN -> 710: the last line restores it), then x > -45 ? x : -45 */   \
        T xc_ = SEL((x) < 710.0, x, 710.0);                                                      \
        xc_ = SEL(xc_ > -45.0, xc_, -45.0);                                                      \
        const T kd_ = xc_ * FPL_EXPM1_INV_LN2 + FPL_EXPM1_SHIFTER;                               \
        const T kf_ = kd_ - FPL_EXPM1_SHIFTER;                                                   \
        const T hi_ = xc_ - kf_ * FPL_EXPM1_LN2_HI, lo_ = kf_ * FPL_EXPM1_LN2_LO;                \
        const T r_ = hi_ - lo_, c_ = (hi_ - r_) - lo_;                                           \
        /* q = (e^r - 1 - r - r^2/2) / r^3 to r^10 (Taylor, 1/3! ... 1/13!) by Estrin's scheme: \
         * a short dependency chain, so that the out-of-order window overlaps iterations */      \
        const T r2_ = r_ * r_, r4_ = r2_ * r2_;                                                  \
        const T q01_ = 1.0 / 6.0 + 1.0 / 24.0 * r_, q23_ = 1.0 / 120.0 + 1.0 / 720.0 * r_;       \
        const T q45_ = 1.0 / 5040.0 + 1.0 / 40320.0 * r_;                                        \
        const T q67_ = 1.0 / 362880.0 + 1.0 / 3628800.0 * r_;                                    \
        const T q89_ = 1.0 / 39916800.0 + 1.0 / 479001600.0 * r_;                                \
        const T q03_ = q01_ + q23_ * r2_, q47_ = q45_ + q67_ * r2_;                              \
        const T q8a_ = q89_ + 1.0 / 6227020800.0 * r2_;                                          \
        const T q_ = (q03_ + q47_ * r4_) + q8a_ * (r4_ * r4_);                                   \
        /* t = e^(r + c) - 1 - r = r^2/2 + r^3 q + c (1 + r) as th + tl, th = rh^2/2 exact       \
         * (Veltkamp: r = rh + rl, rh of 26 bits) */                                             \
        const T sp_ = r_ * 134217729.0, rh_ = sp_ - (sp_ - r_), rl_ = r_ - rh_;                  \
        const T th_ = 0.5 * rh_ * rh_;                                                           \
        const T tl_ = (rl_ * (rh_ + 0.5 * rl_) + r2_ * (r_ * q_)) + c_ * (1.0 + r_);       \
        /* e^x - 1 = 2 (s (1 + r + t) - 1/2), s = 2^(k-1); the sum (s - 1/2) + s r with its    \
         * rounding errors */                                                                    \
        const T s_ = HALF_SCALE(kd_);                                                            \
        const T a_ = s_ - 0.5, ea_ = (s_ - a_) - 0.5;                                            \
        const T b_ = s_ * r_;                                                                    \
        const T sum_ = a_ + b_, bb_ = sum_ - a_;                                                 \
        const T err_ = (a_ - (sum_ - bb_)) + (b_ - bb_);                                         \
        const T y_ = 2.0 * (sum_ + (((err_ + ea_) + s_ * tl_) + s_ * th_));                      \
        /* |x| < 2^-54 (x^2 < 2^-108): e^x - 1 rounds to x (also -0 and subnormals, which the    \
         * halved scale would round); NaN: x */                                                  \
        (out) = SEL((x) * (x) >= 0x1p-108, y_, x);                                               \
    } while (0)

/* Scalar form: the selects are conditional expressions (compiled to compare-and-blend, the
 * clamps to min/max). */
#define FPL_EXPM1_SEL_D(c, u, v) ((c) ? (u) : (v))

static inline double fpl_expm1_half_scale(double kd)
{
    uint64_t u;
    memcpy(&u, &kd, sizeof u);
    u = (u + 1022u) << 52;
    double s;
    memcpy(&s, &u, sizeof s);
    return s;
}

static inline __attribute__((always_inline)) double fpl_expm1(double x)
{
    double y;
    FPL_EXPM1_BODY(double, x, y, FPL_EXPM1_SEL_D, fpl_expm1_half_scale);
    return y;
}

/* Four lanes: GCC generic vectors (one AVX2 register, or two SSE2 ones). A comparison gives a
 * lane mask of all ones or zeros; a cast between vector types of one size reinterprets the bits. */
typedef double fpl_v4d __attribute__((vector_size(4 * sizeof(double))));
typedef uint64_t fpl_v4u __attribute__((vector_size(4 * sizeof(uint64_t))));

/* Macros rather than functions: no vector is passed or returned by value (GCC's ABI note on
 * AVX vectors). FPL_V4 puts a constant in all four lanes and leaves a vector as it is (z * 1 is
 * exact: -0, inf and NaN stay). */
#define FPL_V4(z) ((z) * (fpl_v4d){1.0, 1.0, 1.0, 1.0})
#define FPL_EXPM1_SEL_V4(c, u, v)                                                                \
    ((fpl_v4d)(((fpl_v4u)FPL_V4(u) & (fpl_v4u)(c)) | ((fpl_v4u)FPL_V4(v) & ~(fpl_v4u)(c))))
#define FPL_EXPM1_HALF_SCALE_V4(kd) ((fpl_v4d)(((fpl_v4u)(kd) + 1022u) << 52))

/* *y = e^x - 1 lane by lane (through pointers: no vector crosses a function boundary). */
static inline __attribute__((always_inline)) void fpl_expm1_v4(const fpl_v4d *x, fpl_v4d *y)
{
    const fpl_v4d xv = *x;
    FPL_EXPM1_BODY(fpl_v4d, xv, *y, FPL_EXPM1_SEL_V4, FPL_EXPM1_HALF_SCALE_V4);
}

#endif
