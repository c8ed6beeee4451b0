/* fpl_expm1 (csrc/fpl_expm1.h, the Toda bond's e^x - 1) against long-double expm1l, an
 * independent computation with 11 more bits: the error in units of the last place of the
 * correctly rounded double, over the whole range. Random values (uniform on [-50, 720] and
 * log-uniform magnitudes from 1e-320 to 710, both signs), the reduction's boundaries
 * (k ln2 +- ln2/2, where k changes, dense around +-ln2/2), tiny and subnormal x (exact),
 * large negative x (-> -1), the overflow edge log(DBL_MAX) = 709.78..., +-inf and NaN. The
 * four-lane form fpl_expm1_v4 (chaos_batch.c's lanes) must give the scalar's bits. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "check.h"
#include "fpl_expm1.h"

static double worst_ulp = 0.0, worst_x = 0.0;
static long n_values = 0, n_lane_mismatch = 0;

/* |y - e| in ulps of the double nearest e (for |e| below the normal range, 2^-1074). */
static double ulp_error(double y, long double e)
{
    if (isnan(e)) return isnan(y) ? 0.0 : INFINITY;
    const double er = (double)e;
    if (isinf(er)) return isinf(y) && (y > 0) == (er > 0) ? 0.0 : INFINITY;
    int ex;
    frexp(er, &ex);
    const double ulp = er == 0.0 || ex - 53 < -1074 ? 0x1p-1074 : ldexp(1.0, ex - 53);
    return (double)(fabsl((long double)y - e) / (long double)ulp);
}

static double lane_values[4];
static int lane_fill = 0;

static void flush_lanes(void)
{
    fpl_v4d xv = {lane_values[0], lane_values[1], lane_values[2], lane_values[3]};
    fpl_v4d yv;
    fpl_expm1_v4(&xv, &yv);
    for (int w = 0; w < lane_fill; w++) {
        const double y = fpl_expm1(lane_values[w]), yl = yv[w];
        if (memcmp(&y, &yl, sizeof y) != 0) n_lane_mismatch++;
    }
    lane_fill = 0;
}

static void probe(double x)
{
    const double y = fpl_expm1(x);
    const double err = ulp_error(y, expm1l((long double)x));
    if (!(err <= worst_ulp)) {
        worst_ulp = err;
        worst_x = x;
    }
    n_values++;
    lane_values[lane_fill++] = x;
    if (lane_fill == 4) flush_lanes();
}

/* A double in [0, 1) from the harness's generator. */
static double unit(void)
{
    return 0.5 * (check_uniform() + 1.0);
}

int main(void)
{
    const double ln2 = 0.69314718055994530942, xmax = log(DBL_MAX);
    for (int i = 0; i < 400000; i++)
        probe(-50.0 + 770.0 * unit());
    for (int i = 0; i < 400000; i++) {
        const double mag = exp(log(1e-320) + (log(710.0) - log(1e-320)) * unit());
        probe(i % 2 ? mag : -mag);
    }
    /* the reduction's boundaries (k changes at (k + 1/2) ln2) and values close to them */
    for (int k = -70; k <= 1025; k++) {
        const double b = (k + 0.5) * ln2;
        double x = b;
        for (int j = 0; j < 40; j++) x = nextafter(x, -INFINITY);
        for (int j = 0; j < 80; j++, x = nextafter(x, INFINITY)) probe(x);
        for (int j = 0; j < 20; j++) probe(b + 1e-3 * check_uniform());
    }
    for (int i = 0; i < 200000; i++)   /* densely around the small-result boundaries +-ln2/2 */
        probe((i % 2 ? 0.5 : -0.5) * ln2 + 0.05 * check_uniform());
    for (int i = 0; i < 200000; i++)   /* k = 1, 2 and -1, -2: results of either sign near 0.3-3 */
        probe(3.0 * check_uniform());
    /* tiny and subnormal: e^x - 1 rounds to x */
    const double tiny[] = {0x1p-1074, 0x1p-1060, 0x1.fffffffffffffp-1023, 0x1p-1022, 1e-300,
                           1e-100, 0x1p-54, 0x1p-53, 0x1p-30, 1e-9};
    for (size_t i = 0; i < sizeof tiny / sizeof *tiny; i++) {
        CHECK(fpl_expm1(tiny[i]) == tiny[i] || tiny[i] > 0x1p-54, "expm1(%a) = %a, not exact",
              tiny[i], fpl_expm1(tiny[i]));
        CHECK(fpl_expm1(-tiny[i]) == -tiny[i] || tiny[i] > 0x1p-54, "expm1(%a) = %a, not exact",
              -tiny[i], fpl_expm1(-tiny[i]));
        probe(tiny[i]);
        probe(-tiny[i]);
    }
    CHECK(fpl_expm1(0.0) == 0.0 && !signbit(fpl_expm1(0.0)) && signbit(fpl_expm1(-0.0)),
          "expm1(+-0) = %a, %a", fpl_expm1(0.0), fpl_expm1(-0.0));
    /* large negative: -> -1 (exactly -1 once e^x < 2^-54) */
    for (double x = -30.0; x >= -800.0; x -= 0.37) probe(x);
    CHECK(fpl_expm1(-40.0) == -1.0 && fpl_expm1(-1e300) == -1.0 && fpl_expm1(-INFINITY) == -1.0,
          "expm1(-40) = %a, expm1(-1e300) = %a, expm1(-inf) = %a", fpl_expm1(-40.0),
          fpl_expm1(-1e300), fpl_expm1(-INFINITY));
    /* the overflow edge: finite up to log(DBL_MAX), inf beyond */
    double x = xmax;
    for (int j = 0; j < 200; j++) x = nextafter(x, -INFINITY);
    for (int j = 0; j < 400; j++, x = nextafter(x, INFINITY)) probe(x);
    for (double z = 700.0; z < 720.0; z += 0.013) probe(z);
    CHECK(isinf(fpl_expm1(710.0)) && isinf(fpl_expm1(1e300)) && isinf(fpl_expm1(INFINITY)),
          "expm1(710) = %a, expm1(inf) = %a", fpl_expm1(710.0), fpl_expm1(INFINITY));
    CHECK(isfinite(fpl_expm1(709.78)), "expm1(709.78) = %a", fpl_expm1(709.78));
    /* NaN propagates (blow-up detection relies on non-finite values) */
    CHECK(isnan(fpl_expm1(NAN)) && isnan(fpl_expm1(-NAN)), "expm1(NaN) = %a", fpl_expm1(NAN));
    probe(INFINITY);
    probe(-INFINITY);
    probe(NAN);
    flush_lanes();
    CHECK(worst_ulp <= 1.0, "max error %.3f ulp at x = %.17g", worst_ulp, worst_x);
    CHECK(n_lane_mismatch == 0, "%ld values: the four-lane form differs from the scalar one",
          n_lane_mismatch);
    printf("fpl_expm1 vs expm1l: %ld values, max error %.3f ulp (x = %.17g); lanes = scalar\n",
           n_values, worst_ulp, worst_x);
    return check_report("expm1");
}
