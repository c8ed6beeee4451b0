/* Lattice handle: validation, coefficient arrays (from the model table), public evaluation API. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include "internal.h"

int fpl_is_finite_array(const double *a, long len, long *first_bad)
{
    for (long i = 0; i < len; i++) {
        if (!isfinite(a[i])) {
            if (first_bad) *first_bad = i;
            return 0;
        }
    }
    return 1;
}

int fpl_state_check_finite(const double *y, long len)
{
    long bad = -1;
    if (!y || len < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer or negative length");
    if (!fpl_is_finite_array(y, len, &bad))
        return fpl_error(NULL, FPL_ERR_NONFINITE, "y[%ld] is not finite (%g)", bad, y[bad]);
    return FPL_OK;
}

static void *xcalloc(size_t n) { return calloc(n ? n : 1, sizeof(double)); }

int fpl_lattice_create(int n, double alpha, double beta, int model, const double *v,
                       fpl_lattice **out)
{
    return fpl_lattice_create_ex(n, alpha, beta, model, v, FPL_BOUNDARY_FIXED, out);
}

int fpl_lattice_create_ex(int n, double alpha, double beta, int model, const double *v,
                          int boundary, fpl_lattice **out)
{
    if (!out)
        return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (n < 2)
        return fpl_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!isfinite(alpha))
        return fpl_error(NULL, FPL_ERR_ARG, "alpha must be finite (got %g)", alpha);
    if (!isfinite(beta))
        return fpl_error(NULL, FPL_ERR_ARG, "beta must be finite (got %g)", beta);
    if (boundary != FPL_BOUNDARY_FIXED && boundary != FPL_BOUNDARY_PERIODIC)
        return fpl_error(NULL, FPL_ERR_ARG,
                         "boundary must be %d (fixed) or %d (periodic) (got %d)",
                         FPL_BOUNDARY_FIXED, FPL_BOUNDARY_PERIODIC, boundary);
    const fpl_model_ops *ops = fpl_model_ops_lookup(model, boundary);
    /* the coefficients follow from the model alone: the fixed-end entry's */
    const fpl_model_ops *fixed = fpl_model_ops_for(model);
    if (!ops || !fixed)
        return fpl_model_unknown(model);
    if (model == FPL_MODEL_TODA) {
        if (beta != 0.0)
            return fpl_error(NULL, FPL_ERR_ARG, "beta must be 0 for the Toda model (got %g): its "
                             "potential is fixed by alpha", beta);
        if (alpha == 0.0)
            return fpl_error(NULL, FPL_ERR_ARG, "alpha must be non-zero for the Toda model (alpha "
                             "= 0 is the harmonic chain: model homogeneous)");
        for (int j = 0; v && j < n; j++)
            if (v[j] != 1.0)
                return fpl_error(NULL, FPL_ERR_ARG, "v[%d] = %g: the Toda model is homogeneous "
                                 "(v = 1; disorder breaks its integrability)", j, v[j]);
    }
    if (v) {
        for (int j = 0; j < n; j++) {
            if (!isfinite(v[j]) || v[j] <= 0.0)
                return fpl_error(NULL, FPL_ERR_ARG,
                                 "v[%d] = %g: variability must be finite and > 0", j, v[j]);
        }
    }
    /* The library must never abort: GSL's default handler would. */
    gsl_set_error_handler_off();

    fpl_lattice *lat = calloc(1, sizeof *lat);
    if (!lat)
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating the lattice");
    lat->n = n;
    lat->boundary = boundary;
    lat->alpha = alpha;
    lat->beta = beta;
    lat->ops = ops;
    size_t nn = (size_t)n;
    lat->v = xcalloc(nn);
    lat->cl = xcalloc(nn);
    lat->cn = xcalloc(nn);
    lat->s = xcalloc(nn);
    lat->minv = xcalloc(nn);
    if (!lat->v || !lat->cl || !lat->cn || !lat->s || !lat->minv) {
        fpl_lattice_free(&lat);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating a lattice of N = %d", n);
    }
    for (int j = 0; j < n; j++) {
        lat->v[j] = v ? v[j] : 1.0;
        fixed->coefficients(lat->v[j], &lat->cl[j], &lat->cn[j], &lat->s[j], &lat->minv[j]);
    }
    *out = lat;
    return FPL_OK;
}

void fpl_lattice_free(fpl_lattice **lattice)
{
    if (!lattice || !*lattice)
        return;
    fpl_lattice *lat = *lattice;
    free(lat->v);
    free(lat->cl);
    free(lat->cn);
    free(lat->s);
    free(lat->minv);
    free(lat);
    *lattice = NULL;
}

const char *fpl_lattice_errmsg(const fpl_lattice *lattice)
{
    (void)lattice; /* shared and read-only: no message of its own */
    return fpl_last_error();
}

int fpl_lattice_size(const fpl_lattice *lattice) { return lattice ? lattice->n : 0; }
double fpl_lattice_alpha(const fpl_lattice *lattice) { return lattice ? lattice->alpha : NAN; }
double fpl_lattice_beta(const fpl_lattice *lattice) { return lattice ? lattice->beta : NAN; }
int fpl_lattice_model(const fpl_lattice *lattice) { return lattice ? lattice->ops->model : 0; }
int fpl_lattice_boundary(const fpl_lattice *lattice) { return lattice ? lattice->boundary : -1; }

/* Common argument checks; return 0 or an error status already recorded. */
#define CHECK_LATTICE(lat)                                                                     \
    do {                                                                                       \
        if (!(lat)) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");                \
    } while (0)
#define CHECK_PTR(ptr)                                                                         \
    do {                                                                                       \
        if (!(ptr)) return fpl_error(NULL, FPL_ERR_ARG, #ptr ": NULL pointer");                \
    } while (0)
#define CHECK_NDEV(n_dev)                                                                      \
    do {                                                                                       \
        if ((n_dev) < 0)                                                                       \
            return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 0 (got %d)", (n_dev));       \
    } while (0)

int fpl_lattice_get_v(const fpl_lattice *lattice, double *v, int n)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!v) return fpl_error(NULL, FPL_ERR_ARG, "v: NULL pointer");
    if (n != lattice->n)
        return fpl_error(NULL, FPL_ERR_ARG, "v has length %d, expected N = %d", n, lattice->n);
    memcpy(v, lattice->v, sizeof(double) * (size_t)n);
    return FPL_OK;
}

static int check_finite_input(const char *name, const double *a, long len)
{
    long bad = -1;
    if (!fpl_is_finite_array(a, len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "%s[%ld] is not finite (%g)", name, bad, a[bad]);
    return FPL_OK;
}

/* The one-shot evaluations below allocate a temporary workspace per call (not for hot loops). */

int fpl_lattice_force(const fpl_lattice *lattice, const double *x, double *force)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(x);
    CHECK_PTR(force);
    int st = check_finite_input("x", x, lattice->n);
    fpl_work *w = NULL;
    if (!st) st = fpl_work_create(lattice->n, 0, &w);
    if (st) return st;
    fpl_kernel_force(lattice, w, x, force);
    fpl_work_free(&w);
    return FPL_OK;
}

struct tridiag_ctx { long n; double *lower, *diag, *upper; };

static void emit_tridiag(void *ctx, long row, long col, double value)
{
    struct tridiag_ctx *c = ctx;
    long i = row - c->n; /* p-row i holds dF_i/dx_col */
    if (i < 0 || col >= c->n) return;
    if (col == i) c->diag[i] = value;
    else if (col == i + 1) c->upper[i] = value;
    else if (col == i - 1) c->lower[col] = value;
}

int fpl_lattice_force_jacobian(const fpl_lattice *lattice, const double *x, double *lower,
                               double *diag, double *upper)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(x);
    CHECK_PTR(lower);
    CHECK_PTR(diag);
    CHECK_PTR(upper);
    if (lattice->boundary == FPL_BOUNDARY_PERIODIC)
        return fpl_error(NULL, FPL_ERR_ARG, "boundary: the force Jacobian of a periodic chain is not "
                         "tridiagonal (the wrap-around bond couples x_0 and x_{N-1}); use "
                         "fpl_lattice_jacobian_dense");
    int st = check_finite_input("x", x, lattice->n);
    if (st) return st;
    /* Read the tridiagonal off the p-rows of the first-order Jacobian (orbit block only). */
    struct tridiag_ctx c = {lattice->n, lower, diag, upper};
    fpl_kernel_jacobian_entries(lattice, x, 0, emit_tridiag, &c);
    return FPL_OK;
}

int fpl_lattice_tangent_force(const fpl_lattice *lattice, const double *x, int n_dev,
                              const double *dx, double *dforce)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(x);
    CHECK_NDEV(n_dev);
    if (n_dev == 0) return FPL_OK;
    CHECK_PTR(dx);
    CHECK_PTR(dforce);
    int st = check_finite_input("x", x, lattice->n);
    if (!st) st = check_finite_input("dx", dx, (long)lattice->n * n_dev);
    fpl_work *w = NULL;
    if (!st) st = fpl_work_create(lattice->n, 0, &w);
    if (st) return st;
    fpl_kernel_tangent(lattice, w, x, n_dev, dx, dforce);
    fpl_work_free(&w);
    return FPL_OK;
}

int fpl_lattice_rhs(const fpl_lattice *lattice, const double *y, int n_dev, double *ydot)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(y);
    CHECK_PTR(ydot);
    CHECK_NDEV(n_dev);
    int st = check_finite_input("y", y, 2L * lattice->n * (n_dev + 1));
    fpl_work *w = NULL;
    if (!st) st = fpl_work_create(lattice->n, 0, &w);
    if (st) return st;
    fpl_kernel_rhs(lattice, w, y, n_dev, ydot);
    fpl_work_free(&w);
    return FPL_OK;
}

struct dense_ctx { double *a; long dim; };

static void emit_row_major(void *ctx, long row, long col, double value)
{
    struct dense_ctx *c = ctx;
    c->a[row * c->dim + col] += value;
}

int fpl_lattice_jacobian_dense(const fpl_lattice *lattice, const double *y, int n_dev,
                               double *jac)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(y);
    CHECK_PTR(jac);
    CHECK_NDEV(n_dev);
    long dim = 2L * lattice->n * (n_dev + 1);
    int st = check_finite_input("y", y, dim);
    if (st) return st;
    memset(jac, 0, sizeof(double) * (size_t)(dim * dim));
    struct dense_ctx c = {jac, dim};
    fpl_kernel_jacobian_entries(lattice, y, n_dev, emit_row_major, &c);
    return FPL_OK;
}

int fpl_lattice_energy(const fpl_lattice *lattice, const double *y, double *energy)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(y);
    CHECK_PTR(energy);
    int st = check_finite_input("y", y, 2L * lattice->n);
    if (st) return st;
    *energy = lattice->ops->energy(lattice, y);
    return FPL_OK;
}

int fpl_lattice_velocity(const fpl_lattice *lattice, const double *y, double *xdot)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!y || !xdot) return fpl_error(NULL, FPL_ERR_ARG, "y/xdot: NULL pointer");
    for (int i = 0; i < lattice->n; i++)
        xdot[i] = lattice->minv[i] * y[lattice->n + i];
    return FPL_OK;
}
