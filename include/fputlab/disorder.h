/* fputlab — disorder (variability) draws, reproducible from an explicit seed.
 *
 * The generator is GSL's mt19937 seeded with `seed`; draws are made for j = 1..N in order, so
 * the same seed gives the same v on every machine and from C or Python.
 *   FPL_DISORDER_GAUSSIAN            v_j = 1 + sigma z_j, z_j ~ N(0,1), sigma = tau/300 (paper:
 *                                    "within +-tau%" is a 3-sigma statement)
 *   FPL_DISORDER_TRUNCATED_GAUSSIAN  as above with z_j redrawn until |z_j| <= 3, so |v_j - 1| <= tau/100
 *   FPL_DISORDER_UNIFORM             v_j = 1 + (tau/100) u_j, u_j ~ U(-1, 1)
 * tau is in percent. */
#ifndef FPUTLAB_DISORDER_H
#define FPUTLAB_DISORDER_H

#include "fputlab/common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum fpl_disorder {
    FPL_DISORDER_GAUSSIAN = 0,
    FPL_DISORDER_TRUNCATED_GAUSSIAN = 1,
    FPL_DISORDER_UNIFORM = 2
} fpl_disorder;

/* Draw v (length n) for tolerance tau (percent, tau >= 0). Errors: n < 1, tau < 0 or NaN,
 * tau >= 100 for uniform/truncated (v would reach 0), unknown kind. Gaussian draws with v_j <= 0
 * are reported as an error rather than silently clipped. */
FPL_API int fpl_disorder_draw(int kind, double tau, unsigned long seed, int n, double *v);

/* The underlying standardised draws (z for the Gaussian kinds, u for uniform), so that
 * v = 1 + sigma z can be formed for any tau with the same realisation. */
FPL_API int fpl_disorder_standard(int kind, unsigned long seed, int n, double *z);

FPL_API const char *fpl_disorder_name(int kind);

#ifdef __cplusplus
}
#endif
#endif
