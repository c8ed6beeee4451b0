/* The bond potential's barrier: where a bond stretch leaves the potential well around r = 0. */
#include <math.h>
#include "internal.h"

/* FPUT-alpha-beta: V'(r) = r (1 + alpha r + beta r^2); its non-zero roots are the tops of the
 * barriers (V' changes sign there: past them the bond is pushed further out). A double root
 * (alpha^2 = 4 beta) is an inflection, no barrier. Toda: V'(r) = 0 only at r = 0, no barrier.
 * The roots by the stable form of the quadratic formula (no cancellation when 4 beta << alpha^2,
 * where the nearer root tends to -1/alpha). */
int fpl_lattice_barrier(const fpl_lattice *lattice, double *lower, double *upper)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!lower || !upper) return fpl_error(NULL, FPL_ERR_ARG, "lower/upper: NULL pointer");
    *lower = -INFINITY;
    *upper = INFINITY;
    if (lattice->ops->model == FPL_MODEL_TODA) return FPL_OK;
    const double a = lattice->alpha, b = lattice->beta;
    double roots[2] = {0.0, 0.0};
    if (b == 0.0) {
        if (a != 0.0) roots[0] = -1.0 / a;
    } else {
        const double disc = a * a - 4.0 * b;
        if (!(disc > 0.0)) return FPL_OK;
        const double q = -0.5 * (a + copysign(sqrt(disc), a));
        roots[0] = q / b;
        roots[1] = 1.0 / q;
    }
    for (int i = 0; i < 2; i++) {
        const double r = roots[i];
        if (r < 0.0 && r > *lower) *lower = r;
        if (r > 0.0 && r < *upper) *upper = r;
    }
    return FPL_OK;
}

double fpl_barrier_stretch(const fpl_lattice *lattice)
{
    double lower, upper;
    if (fpl_lattice_barrier(lattice, &lower, &upper)) return INFINITY;
    return fmin(-lower, upper);
}
