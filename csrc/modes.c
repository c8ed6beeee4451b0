/* Normal modes: the orthogonal type-I sine transform by FFT of the odd extension. */
#include <math.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_real.h>
#include "internal.h"

/* out_k = sqrt(2/(N+1)) sum_j in_j sin(pi j k/(N+1)), k = 1..N.  For the odd extension
 * y (length M = 2(N+1)), Y_k = sum y_j e^{-2 pi i jk/M} = -2i sum_j in_j sin(pi jk/(N+1)),
 * and GSL's half-complex output stores Im Y_k at index 2k. */
static int sine_transform(fpl_work *work, const double *in, double *out)
{
    const int n = work->n;
    const size_t m = 2 * ((size_t)n + 1);
    double *buf = work->fft;
    buf[0] = 0.0;
    buf[n + 1] = 0.0;
    for (int j = 1; j <= n; j++) {
        buf[j] = in[j - 1];
        buf[m - (size_t)j] = -in[j - 1];
    }
    int st = gsl_fft_real_transform(buf, 1, m, work->fft_wavetable, work->fft_workspace);
    if (st)
        return fpl_error(NULL, FPL_ERR_BACKEND, "GSL FFT failed: %s", gsl_strerror(st));
    const double scale = -0.5 * sqrt(2.0 / (n + 1.0));
    for (int k = 1; k <= n; k++)
        out[k - 1] = scale * buf[2 * k];
    return FPL_OK;
}

int fpl_modes_omega(int n, double *omega)
{
    if (n < 2) return fpl_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!omega) return fpl_error(NULL, FPL_ERR_ARG, "omega: NULL pointer");
    for (int k = 1; k <= n; k++)
        omega[k - 1] = 2.0 * sin(k * M_PI / (2.0 * (n + 1)));
    return FPL_OK;
}

/* One-shot: a temporary workspace per call. */
int fpl_modes_transform(const fpl_lattice *lattice, const double *x, double *q)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (lattice->boundary != FPL_BOUNDARY_FIXED)
        return fpl_error(NULL, FPL_ERR_ARG, "boundary: periodic normal modes are not implemented yet");
    if (!x || !q) return fpl_error(NULL, FPL_ERR_ARG, "x/q: NULL pointer");
    fpl_work *w = NULL;
    int st = fpl_work_create(lattice->n, 1, &w);
    if (st) return st;
    st = sine_transform(w, x, q);
    fpl_work_free(&w);
    return st;
}

int fpl_modes_energies(const fpl_lattice *lattice, const double *y, double *energies)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (lattice->boundary != FPL_BOUNDARY_FIXED)
        return fpl_error(NULL, FPL_ERR_ARG, "boundary: periodic normal modes are not implemented yet");
    if (!y || !energies) return fpl_error(NULL, FPL_ERR_ARG, "y/energies: NULL pointer");
    fpl_work *w = NULL;
    int st = fpl_work_create(lattice->n, 1, &w);
    if (st) return st;
    st = fpl_modes_energies_work(lattice, w, y, energies);
    fpl_work_free(&w);
    return st;
}

int fpl_modes_energies_work(const fpl_lattice *lattice, fpl_work *work, const double *y,
                            double *energies)
{
    const int n = lattice->n;
    double *vel = work->dphi; /* N+1 scratch, free outside the kicks */
    fpl_lattice_velocity(lattice, y, vel);
    int st = sine_transform(work, y, energies); /* Q_k */
    if (st) return st;
    st = sine_transform(work, vel, vel); /* P_k */
    if (st) return st;
    for (int k = 1; k <= n; k++) {
        double w = 2.0 * sin(k * M_PI / (2.0 * (n + 1)));
        double q = energies[k - 1], p = vel[k - 1];
        energies[k - 1] = 0.5 * (p * p + w * w * q * q);
    }
    return FPL_OK;
}

int fpl_modes_initial_state(const fpl_lattice *lattice, int k, double amplitude, double *y)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    const int n = lattice->n;
    if (k < 1 || k > n)
        return fpl_error(NULL, FPL_ERR_ARG, "mode k must be in 1..N = %d (got %d)", n, k);
    if (!isfinite(amplitude))
        return fpl_error(NULL, FPL_ERR_ARG, "amplitude must be finite (got %g)", amplitude);
    if (!y) return fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer");
    for (int j = 1; j <= n; j++) {
        y[j - 1] = amplitude * sin(M_PI * k * j / (n + 1.0));
        y[n + j - 1] = 0.0;
    }
    return FPL_OK;
}

int fpl_modes_initial_state_coupled(const fpl_lattice *lattice, int k, double amplitude, double *y)
{
    int st = fpl_modes_initial_state(lattice, k, amplitude, y);
    if (st) return st;
    for (int j = 0; j < lattice->n; j++)
        y[j] /= lattice->cl[j];
    return FPL_OK;
}
