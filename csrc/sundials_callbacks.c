/* The lattice models in SUNDIALS callback form (N_Vector / SUNMatrix): fpl_sun_rhs, the SPRKStep
 * split fpl_sun_force / fpl_sun_velocity, Jacobians and roots. The integrator back ends that use
 * them live in files of their own (backend_arkode.c, backend_cvode.c, backend_sprk.c). */
#include <sunmatrix/sunmatrix_band.h>
#include <stdio.h>
#include <sunmatrix/sunmatrix_dense.h>
#include "fputlab/sundials.h"
#include <float.h>
#include <string.h>
#include "internal.h"

/* user_data of every callback: an fpl_system (fputlab/events.h), which brings the lattice, the
 * criteria and the kernels' scratch. */

/* n_dev from the vector length 2N(1+n_dev), or -1 (message on the handle) if it does not fit. */
static int n_dev_of(fpl_system *sys, N_Vector y)
{
    sunindextype len = N_VGetLength(y), two_n = 2 * (sunindextype)sys->lat->n;
    if (len < two_n || len % two_n != 0) {
        fpl_error(sys->errmsg, FPL_ERR_ARG, "N_Vector length %ld is not a multiple 2N(1+n_dev) of 2N = %ld",
                  (long)len, (long)two_n);
        return -1;
    }
    return (int)(len / two_n) - 1;
}

/* What the right-hand sides check first: the deviation-vector count from the length of y (-1:
 * unrecoverable), and a finite y (1: recoverable, the integrator retries with a smaller step).
 * 0 and n_dev on success. */
static int checked_state(fpl_system *sys, N_Vector y, sunrealtype t, const char *what,
                         int *n_dev)
{
    if ((*n_dev = n_dev_of(sys, y)) < 0) return -1;
    long bad;
    if (!fpl_is_finite_array(N_VGetArrayPointer(y), N_VGetLength(y), &bad)) {
        fpl_error(sys->errmsg, FPL_ERR_NONFINITE, "%s called with non-finite y[%ld] at t = %g", what, bad,
                  t);
        return 1;
    }
    return 0;
}

int fpl_sun_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    fpl_system *sys = user_data;
    int n_dev, st = checked_state(sys, y, t, "rhs", &n_dev);
    if (st) return st;
    const double *yd = N_VGetArrayPointer(y);
    fpl_kernel_rhs(sys->lat, sys->work, yd, n_dev, N_VGetArrayPointer(ydot));
    return 0;
}

/* SPRKStep form: the momenta part p' = F(x), dp' = J(x) dx (f1), zeros in the position blocks. */
int fpl_sun_force(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    fpl_system *sys = user_data;
    int n_dev, st = checked_state(sys, y, t, "force", &n_dev);
    if (st) return st;
    const double *yd = N_VGetArrayPointer(y);
    const size_t n = (size_t)sys->lat->n;
    double *f = N_VGetArrayPointer(ydot);
    for (int m = 0; m <= n_dev; m++) memset(f + 2 * n * (size_t)m, 0, sizeof(double) * n);
    fpl_kernel_force(sys->lat, sys->work, yd, f + n);
    for (int m = 1; m <= n_dev; m++)
        fpl_kernel_tangent(sys->lat, sys->work, yd, 1, yd + 2 * n * (size_t)m,
                           f + 2 * n * (size_t)m + n);
    return 0;
}

/* SPRKStep form: the positions part x' = p/m, dx' = dp/m (f2), zeros in the momentum blocks. */
int fpl_sun_velocity(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    (void)t;
    fpl_system *sys = user_data;
    const fpl_lattice *lat = sys->lat;
    int n_dev = n_dev_of(sys, y);
    if (n_dev < 0) return -1;
    const size_t n = (size_t)lat->n;
    const double *yd = N_VGetArrayPointer(y);
    double *f = N_VGetArrayPointer(ydot);
    for (int m = 0; m <= n_dev; m++) {
        const double *p = yd + 2 * n * (size_t)m + n;
        double *xd = f + 2 * n * (size_t)m;
        for (size_t i = 0; i < n; i++) xd[i] = lat->minv[i] * p[i];
        memset(xd + n, 0, sizeof(double) * n);
    }
    return 0;
}

static void emit_dense(void *ctx, long row, long col, double value)
{
    SUNMatrix m = ctx;
    SM_ELEMENT_D(m, row, col) += value;
}

static void emit_band(void *ctx, long row, long col, double value)
{
    SUNMatrix m = ctx;
    SM_ELEMENT_B(m, row, col) += value;
}

int fpl_sun_band_widths(const fpl_lattice *lattice, int n_dev, sunindextype *upper,
                        sunindextype *lower)
{
    if (!lattice || !upper || !lower || n_dev < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "lattice/upper/lower NULL or n_dev < 0");
    if (lattice->boundary == FPL_BOUNDARY_PERIODIC)
        return fpl_error(NULL, FPL_ERR_ARG, "boundary: the Jacobian of a periodic chain is not "
                         "banded (the wrap-around bond couples x_0 and x_{N-1}); use a dense "
                         "matrix");
    sunindextype n = lattice->n;
    *upper = n;                               /* x'_i depends on p_i */
    *lower = n + 1 + 2 * n * (sunindextype)n_dev; /* p'-rows on x; last block's dp' on the orbit x */
    return FPL_OK;
}

int fpl_sun_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void *user_data,
                N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    (void)t; (void)fy; (void)tmp1; (void)tmp2; (void)tmp3;
    fpl_system *sys = user_data;
    const fpl_lattice *lat = sys->lat;
    int n_dev = n_dev_of(sys, y);
    if (n_dev < 0) return -1;
    SUNMatZero(jac);
    switch (SUNMatGetID(jac)) {
    case SUNMATRIX_DENSE:
        fpl_kernel_jacobian_entries(lat, N_VGetArrayPointer(y), n_dev, emit_dense, jac);
        return 0;
    case SUNMATRIX_BAND: {
        sunindextype mu, ml;
        if (fpl_sun_band_widths(lat, n_dev, &mu, &ml)) {
            char why[FPL_ERRMSG_LEN];   /* a copy: fpl_error writes the buffer it would read */
            snprintf(why, sizeof why, "%s", fpl_last_error());
            fpl_error(sys->errmsg, FPL_ERR_ARG, "%s", why);
            return -1;
        }
        if (SM_UBAND_B(jac) < mu || SM_LBAND_B(jac) < ml) {
            fpl_error(sys->errmsg, FPL_ERR_ARG,
                      "band matrix has bandwidths (mu %ld, ml %ld); need (%ld, %ld)",
                      (long)SM_UBAND_B(jac), (long)SM_LBAND_B(jac), (long)mu, (long)ml);
            return -1;
        }
        fpl_kernel_jacobian_entries(lat, N_VGetArrayPointer(y), n_dev, emit_band, jac);
        return 0;
    }
    default:
        fpl_error(sys->errmsg, FPL_ERR_ARG, "fpl_sun_jac supports dense and band SUNMatrix only");
        return -1;
    }
}

int fpl_sun_roots(sunrealtype t, N_Vector y, sunrealtype *gout, void *user_data)
{
    (void)t;
    fpl_system *sys = user_data;
    const double *yd = N_VGetArrayPointer(y);
    if (!fpl_is_finite_array(yd, 2L * sys->lat->n, NULL)) {
        for (int i = 0; i < sys->events.n; i++) gout[i] = -DBL_MAX;
        return 0;
    }
    fpl_events_eval(sys->lat, sys->work, &sys->events, yd, gout);
    return 0;
}

struct jtimes_ctx { const double *v; double *jv; };

static void emit_jtimes(void *ctx, long row, long col, double value)
{
    struct jtimes_ctx *c = ctx;
    c->jv[row] += value * c->v[col];
}

int fpl_sun_jtimes(N_Vector v, N_Vector jv, sunrealtype t, N_Vector y, N_Vector fy,
                   void *user_data, N_Vector tmp)
{
    (void)t; (void)fy; (void)tmp;
    fpl_system *sys = user_data;
    int n_dev = n_dev_of(sys, y);
    if (n_dev < 0) return -1;
    N_VConst(0.0, jv);
    struct jtimes_ctx c = {N_VGetArrayPointer(v), N_VGetArrayPointer(jv)};
    fpl_kernel_jacobian_entries(sys->lat, N_VGetArrayPointer(y), n_dev, emit_jtimes, &c);
    return 0;
}
