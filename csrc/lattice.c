/* Lattice handle: validation, coefficient arrays per model, public evaluation API. */
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
    if (!out)
        return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (n < 2)
        return fpl_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!isfinite(alpha))
        return fpl_error(NULL, FPL_ERR_ARG, "alpha must be finite (got %g)", alpha);
    if (!isfinite(beta))
        return fpl_error(NULL, FPL_ERR_ARG, "beta must be finite (got %g)", beta);
    const fpl_model_ops *ops = fpl_model_ops_for(model);
    if (!ops)
        return fpl_error(NULL, FPL_ERR_UNKNOWN,
                         "model %d is unknown (1 homogeneous, 2 hamiltonian, 3 nonlinear)", model);
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
    lat->alpha = alpha;
    lat->beta = beta;
    lat->ops = ops;
    size_t nn = (size_t)n;
    lat->v = xcalloc(nn);
    lat->cl = xcalloc(nn);
    lat->cn = xcalloc(nn);
    lat->s = xcalloc(nn);
    lat->minv = xcalloc(nn);
    lat->phi = xcalloc(nn + 1);
    lat->kappa = xcalloc(nn + 1);
    lat->dphi = xcalloc(nn + 1);
    lat->fft = xcalloc(2 * (nn + 1));
    lat->ek = xcalloc(nn);
    if (!lat->v || !lat->cl || !lat->cn || !lat->s || !lat->minv || !lat->phi || !lat->kappa ||
        !lat->dphi || !lat->fft || !lat->ek || fpl_modes_alloc(lat) != 0) {
        fpl_lattice_free(&lat);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating a lattice of N = %d", n);
    }
    for (int j = 0; j < n; j++) {
        double vj = v ? v[j] : 1.0;
        lat->v[j] = vj;
        lat->cl[j] = model == FPL_MODEL_HAMILTONIAN ? vj : 1.0;
        lat->cn[j] = model == FPL_MODEL_HOMOGENEOUS ? 1.0 : vj;
        lat->s[j] = model == FPL_MODEL_HAMILTONIAN ? vj : 1.0;
        lat->minv[j] = model == FPL_MODEL_HAMILTONIAN ? 1.0 / vj : 1.0;
    }
    *out = lat;
    return FPL_OK;
}

void fpl_lattice_free(fpl_lattice **lattice)
{
    if (!lattice || !*lattice)
        return;
    fpl_lattice *lat = *lattice;
    fpl_modes_release(lat);
    free(lat->v);
    free(lat->cl);
    free(lat->cn);
    free(lat->s);
    free(lat->minv);
    free(lat->phi);
    free(lat->kappa);
    free(lat->dphi);
    free(lat->fft);
    free(lat->ek);
    free(lat->harm);
    free(lat->harmwork);
    free(lat);
    *lattice = NULL;
}

const char *fpl_lattice_errmsg(const fpl_lattice *lattice)
{
    return lattice ? lattice->errmsg : "lattice: NULL handle";
}

int fpl_lattice_size(const fpl_lattice *lattice) { return lattice ? lattice->n : 0; }
double fpl_lattice_alpha(const fpl_lattice *lattice) { return lattice ? lattice->alpha : NAN; }
double fpl_lattice_beta(const fpl_lattice *lattice) { return lattice ? lattice->beta : NAN; }
int fpl_lattice_model(const fpl_lattice *lattice) { return lattice ? lattice->ops->model : 0; }

/* Common argument checks; returns 0 or an error status already recorded. */
#define CHECK_LATTICE(lat)                                                                     \
    do {                                                                                       \
        if (!(lat)) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");                \
        fpl_error_clear(lat);                                                                  \
    } while (0)
#define CHECK_PTR(lat, ptr)                                                                    \
    do {                                                                                       \
        if (!(ptr)) return fpl_error((lat), FPL_ERR_ARG, #ptr ": NULL pointer");               \
    } while (0)
#define CHECK_NDEV(lat, n_dev)                                                                 \
    do {                                                                                       \
        if ((n_dev) < 0)                                                                       \
            return fpl_error((lat), FPL_ERR_ARG, "n_dev must be >= 0 (got %d)", (n_dev));      \
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

static int check_finite_input(fpl_lattice *lat, const char *name, const double *a, long len)
{
    long bad = -1;
    if (!fpl_is_finite_array(a, len, &bad))
        return fpl_error(lat, FPL_ERR_ARG, "%s[%ld] is not finite (%g)", name, bad, a[bad]);
    return FPL_OK;
}

int fpl_lattice_force(fpl_lattice *lattice, const double *x, double *force)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, x);
    CHECK_PTR(lattice, force);
    int st = check_finite_input(lattice, "x", x, lattice->n);
    if (st) return st;
    fpl_kernel_force(lattice, x, force);
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

int fpl_lattice_force_jacobian(fpl_lattice *lattice, const double *x, double *lower, double *diag,
                               double *upper)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, x);
    CHECK_PTR(lattice, lower);
    CHECK_PTR(lattice, diag);
    CHECK_PTR(lattice, upper);
    int st = check_finite_input(lattice, "x", x, lattice->n);
    if (st) return st;
    /* Read the tridiagonal off the p-rows of the first-order Jacobian (orbit block only). */
    struct tridiag_ctx c = {lattice->n, lower, diag, upper};
    fpl_kernel_jacobian_entries(lattice, x, 0, emit_tridiag, &c);
    return FPL_OK;
}

int fpl_lattice_tangent_force(fpl_lattice *lattice, const double *x, int n_dev, const double *dx,
                              double *dforce)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, x);
    CHECK_NDEV(lattice, n_dev);
    if (n_dev == 0) return FPL_OK;
    CHECK_PTR(lattice, dx);
    CHECK_PTR(lattice, dforce);
    int st = check_finite_input(lattice, "x", x, lattice->n);
    if (!st) st = check_finite_input(lattice, "dx", dx, (long)lattice->n * n_dev);
    if (st) return st;
    fpl_kernel_tangent(lattice, x, n_dev, dx, dforce);
    return FPL_OK;
}

int fpl_lattice_rhs(fpl_lattice *lattice, const double *y, int n_dev, double *ydot)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, y);
    CHECK_PTR(lattice, ydot);
    CHECK_NDEV(lattice, n_dev);
    int st = check_finite_input(lattice, "y", y, 2L * lattice->n * (n_dev + 1));
    if (st) return st;
    fpl_kernel_rhs(lattice, y, n_dev, ydot);
    return FPL_OK;
}

struct dense_ctx { double *a; long dim; };

static void emit_row_major(void *ctx, long row, long col, double value)
{
    struct dense_ctx *c = ctx;
    c->a[row * c->dim + col] += value;
}

int fpl_lattice_jacobian_dense(fpl_lattice *lattice, const double *y, int n_dev, double *jac)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, y);
    CHECK_PTR(lattice, jac);
    CHECK_NDEV(lattice, n_dev);
    long dim = 2L * lattice->n * (n_dev + 1);
    int st = check_finite_input(lattice, "y", y, dim);
    if (st) return st;
    memset(jac, 0, sizeof(double) * (size_t)(dim * dim));
    struct dense_ctx c = {jac, dim};
    fpl_kernel_jacobian_entries(lattice, y, n_dev, emit_row_major, &c);
    return FPL_OK;
}

int fpl_lattice_energy(fpl_lattice *lattice, const double *y, double *energy)
{
    CHECK_LATTICE(lattice);
    CHECK_PTR(lattice, y);
    CHECK_PTR(lattice, energy);
    int st = check_finite_input(lattice, "y", y, 2L * lattice->n);
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
