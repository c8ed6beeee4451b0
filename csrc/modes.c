/* Normal modes. Fixed ends: the orthogonal type-I sine transform, by a real FFT of the odd
 * extension (length 2(N+1)). Periodic: the orthonormal discrete Hartley transform, by a real FFT
 * of length N. Both in O(N log N) for every N (fft.c). */
#include <math.h>
#include <string.h>
#include "internal.h"

/* out_k = sqrt(2/(N+1)) sum_j in_j sin(pi j k/(N+1)), k = 1..N.  For the odd extension
 * y (length M = 2(N+1)), Y_k = sum y_j e^{-2 pi i jk/M} = -2i sum_j in_j sin(pi jk/(N+1)),
 * and the half-complex output stores Im Y_k at index 2k. */
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
    int st = fpl_rdft_forward(work->rdft, buf);
    if (st) return st;
    const double scale = -0.5 * sqrt(2.0 / (n + 1.0));
    for (int k = 1; k <= n; k++)
        out[k - 1] = scale * buf[2 * k];
    return FPL_OK;
}

/* out_k = N^{-1/2} sum_j in_j cas(2 pi jk/N), cas = cos + sin, k = 0..N-1: with X_k = sum_j in_j
 * e^{-2 pi i jk/N}, out_k = (Re X_k - Im X_k)/sqrt(N), and X_{N-k} = conj(X_k) for real input. */
static int hartley_transform(fpl_work *work, const double *in, double *out)
{
    const int n = work->n;
    double *buf = work->fft;
    memcpy(buf, in, sizeof(double) * (size_t)n);
    int st = fpl_rdft_forward(work->rdft, buf);
    if (st) return st;
    const double scale = 1.0 / sqrt((double)n);
    out[0] = scale * buf[0];
    for (int k = 1; 2 * k < n; k++) {
        const double re = buf[2 * k - 1], im = buf[2 * k];
        out[k] = scale * (re - im);
        out[n - k] = scale * (re + im);
    }
    if (n % 2 == 0) out[n / 2] = scale * buf[n - 1];
    return FPL_OK;
}

static int transform(const fpl_lattice *lattice, fpl_work *work, const double *in, double *out)
{
    return lattice->boundary == FPL_BOUNDARY_PERIODIC ? hartley_transform(work, in, out)
                                                      : sine_transform(work, in, out);
}

int fpl_modes_omega(int n, double *omega)
{
    if (n < 2) return fpl_error(NULL, FPL_ERR_ARG, "N must be >= 2 (got %d)", n);
    if (!omega) return fpl_error(NULL, FPL_ERR_ARG, "omega: NULL pointer");
    for (int k = 1; k <= n; k++)
        omega[k - 1] = 2.0 * sin(k * M_PI / (2.0 * (n + 1)));
    return FPL_OK;
}

/* omega of mode index i (0-based position in the arrays of this file) */
static double omega_at(const fpl_lattice *lattice, int i)
{
    const int n = lattice->n;
    if (lattice->boundary == FPL_BOUNDARY_PERIODIC) return 2.0 * sin(i * M_PI / n);
    return 2.0 * sin((i + 1) * M_PI / (2.0 * (n + 1)));
}

int fpl_modes_frequencies(const fpl_lattice *lattice, double *omega)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!omega) return fpl_error(NULL, FPL_ERR_ARG, "omega: NULL pointer");
    for (int i = 0; i < lattice->n; i++)
        omega[i] = omega_at(lattice, i);
    return FPL_OK;
}

/* One-shot: a temporary workspace per call. */
int fpl_modes_transform(const fpl_lattice *lattice, const double *x, double *q)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!x || !q) return fpl_error(NULL, FPL_ERR_ARG, "x/q: NULL pointer");
    fpl_work *w = NULL;
    int st = fpl_work_create(lattice->n, FPL_WORK_MODES_OF(lattice), &w);
    if (st) return st;
    st = transform(lattice, w, x, q);
    fpl_work_free(&w);
    return st;
}

int fpl_modes_energies(const fpl_lattice *lattice, const double *y, double *energies)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!y || !energies) return fpl_error(NULL, FPL_ERR_ARG, "y/energies: NULL pointer");
    fpl_work *w = NULL;
    int st = fpl_work_create(lattice->n, FPL_WORK_MODES_OF(lattice), &w);
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
    int st = transform(lattice, work, y, energies); /* Q_k */
    if (st) return st;
    st = transform(lattice, work, vel, vel); /* P_k */
    if (st) return st;
    for (int i = 0; i < n; i++) {
        const double w = omega_at(lattice, i);
        const double q = energies[i], p = vel[i];
        energies[i] = 0.5 * (p * p + w * w * q * q);
    }
    return FPL_OK;
}

int fpl_modes_initial_state(const fpl_lattice *lattice, int k, double amplitude, double *y)
{
    if (!lattice) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    const int n = lattice->n;
    const int ring = lattice->boundary == FPL_BOUNDARY_PERIODIC;
    if (ring && (k < 1 || k > n - 1))
        return fpl_error(NULL, FPL_ERR_ARG, "mode k must be in 1..N-1 = %d for a periodic chain "
                         "(k = 0 is the uniform translation) (got %d)", n - 1, k);
    if (!ring && (k < 1 || k > n))
        return fpl_error(NULL, FPL_ERR_ARG, "mode k must be in 1..N = %d (got %d)", n, k);
    if (!isfinite(amplitude))
        return fpl_error(NULL, FPL_ERR_ARG, "amplitude must be finite (got %g)", amplitude);
    if (!y) return fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer");
    for (int j = 1; j <= n; j++) {
        /* ring: particle j-1 at sin(2 pi k (j-1)/N + pi/4) = cas(2 pi k (j-1)/N)/sqrt(2); the
         * phase (k (j-1)) mod N is kept exact in integers */
        y[j - 1] = ring ? amplitude * sin(2.0 * M_PI * (double)(((long)k * (j - 1)) % n) / n
                                          + 0.25 * M_PI)
                        : amplitude * sin(M_PI * k * j / (n + 1.0));
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
