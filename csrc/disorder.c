/* Disorder draws from GSL's mt19937 with an explicit seed (reproducible everywhere). */
#include <math.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include "internal.h"

const char *fpl_disorder_name(int kind)
{
    switch (kind) {
    case FPL_DISORDER_GAUSSIAN: return "gaussian";
    case FPL_DISORDER_TRUNCATED_GAUSSIAN: return "truncated";
    case FPL_DISORDER_UNIFORM: return "uniform";
    default: return "unknown";
    }
}

int fpl_disorder_standard(int kind, unsigned long seed, int n, double *z)
{
    if (n < 1) return fpl_error(NULL, FPL_ERR_ARG, "N must be >= 1 (got %d)", n);
    if (!z) return fpl_error(NULL, FPL_ERR_ARG, "z: NULL pointer");
    if (kind < FPL_DISORDER_GAUSSIAN || kind > FPL_DISORDER_UNIFORM)
        return fpl_error(NULL, FPL_ERR_UNKNOWN,
                         "disorder kind %d is unknown (0 gaussian, 1 truncated, 2 uniform)", kind);
    gsl_set_error_handler_off();
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (!rng) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating the RNG");
    gsl_rng_set(rng, seed);
    for (int j = 0; j < n; j++) {
        double draw;
        switch (kind) {
        case FPL_DISORDER_GAUSSIAN:
            draw = gsl_ran_gaussian(rng, 1.0);
            break;
        case FPL_DISORDER_TRUNCATED_GAUSSIAN:
            do draw = gsl_ran_gaussian(rng, 1.0);
            while (fabs(draw) > 3.0);
            break;
        default:
            draw = gsl_ran_flat(rng, -1.0, 1.0);
            break;
        }
        z[j] = draw;
    }
    gsl_rng_free(rng);
    return FPL_OK;
}

int fpl_disorder_draw(int kind, double tau, unsigned long seed, int n, double *v)
{
    if (!(tau >= 0.0) || !isfinite(tau))
        return fpl_error(NULL, FPL_ERR_ARG, "tau must be finite and >= 0 (got %g)", tau);
    if (kind != FPL_DISORDER_GAUSSIAN && tau >= 100.0)
        return fpl_error(NULL, FPL_ERR_ARG,
                         "tau must be < 100 percent for %s disorder (got %g): v would reach 0",
                         fpl_disorder_name(kind), tau);
    int st = fpl_disorder_standard(kind, seed, n, v);
    if (st) return st;
    /* Gaussian kinds: tau is a 3-sigma tolerance; uniform: the half-width. */
    double scale = kind == FPL_DISORDER_UNIFORM ? tau / 100.0 : tau / 300.0;
    for (int j = 0; j < n; j++) {
        v[j] = 1.0 + scale * v[j];
        if (!(v[j] > 0.0))
            return fpl_error(NULL, FPL_ERR_ARG,
                             "tau = %g gives v[%d] = %g <= 0 (seed %lu); use a smaller tau or "
                             "truncated disorder", tau, j, v[j], seed);
    }
    return FPL_OK;
}
