/* A real discrete Fourier transform of any length m in O(m log m), for the mode transforms.
 *
 * GSL's mixed-radix real FFT has fast kernels for the factors 2, 3, 4, 5 and a generic one that
 * costs O(p) per element for any other prime factor p: a length with a large prime factor costs
 * O(m p), O(m^2) for a prime length (the fixed chain's sine transform has length 2(N+1):
 * Lattice(65536).mode_energies took 58 s, N + 1 = 65537 being prime). For such lengths this file
 * uses Bluestein's algorithm: the DFT as a convolution with the chirp w_n = e^{i pi n^2/m},
 * done by FFTs of a 5-smooth length L >= 2m - 1 (two per transform, the kernel's precomputed).
 * Why Bluestein and not a zero-padded transform: zero-padding changes the transform (the sine
 * modes of N + 1 sites are not those of a padded chain), while Bluestein computes the same DFT
 * exactly (round-off O(eps log m)). Why not an FFT library with its own prime handling (FFTW):
 * one more dependency, GPL-compatible but not in the project's set; GSL has what is needed.
 * Lengths whose prime factors are all <= FPL_FFT_DIRECT_MAX_PRIME keep GSL's mixed-radix
 * transform, so those results are bit for bit what they were. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_complex.h>
#include <gsl/gsl_fft_real.h>
#include "internal.h"

/* Past this prime factor Bluestein is cheaper: GSL's generic factor costs ~p complex
 * multiply-adds an element, Bluestein 2 FFTs of length ~2m, ~30 log2(m) flops an
 * element, which p passes near 100 at the lengths of interest. */
#define FPL_FFT_DIRECT_MAX_PRIME 100

struct fpl_rdft {
    size_t m;
    /* direct: GSL mixed radix */
    gsl_fft_real_wavetable *wavetable;
    gsl_fft_real_workspace *workspace;
    /* Bluestein: chirp w_n (n < m, complex interleaved), FFT of the kernel (L complex), work */
    size_t L;
    double *chirp, *kernel_hat, *work;
    gsl_fft_complex_wavetable *cwavetable;  /* GSL's mixed radix: 10x its radix2 at L = 2^19 */
    gsl_fft_complex_workspace *cworkspace;
};

static size_t largest_prime_factor(size_t m)
{
    size_t largest = 1;
    for (size_t p = 2; p * p <= m; p++) {
        while (m % p == 0) {
            largest = p;
            m /= p;
        }
    }
    return m > 1 ? m : largest;
}

void fpl_rdft_free(fpl_rdft **plan)
{
    if (!plan || !*plan) return;
    fpl_rdft *f = *plan;
    if (f->wavetable) gsl_fft_real_wavetable_free(f->wavetable);
    if (f->workspace) gsl_fft_real_workspace_free(f->workspace);
    if (f->cwavetable) gsl_fft_complex_wavetable_free(f->cwavetable);
    if (f->cworkspace) gsl_fft_complex_workspace_free(f->cworkspace);
    free(f->chirp);
    free(f->kernel_hat);
    free(f->work);
    free(f);
    *plan = NULL;
}

int fpl_rdft_create(size_t m, fpl_rdft **out)
{
    *out = NULL;
    fpl_rdft *f = calloc(1, sizeof *f);
    if (!f) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating an FFT plan");
    f->m = m;
    if (largest_prime_factor(m) <= FPL_FFT_DIRECT_MAX_PRIME) {
        f->wavetable = gsl_fft_real_wavetable_alloc(m);
        f->workspace = gsl_fft_real_workspace_alloc(m);
        if (!f->wavetable || !f->workspace) goto nomem;
        *out = f;
        return FPL_OK;
    }
    /* the smallest 5-smooth L >= 2m - 1: GSL's fast radices, up to ~2x shorter than a power of 2
     * (the gaps between 5-smooth numbers are a few per cent at these sizes) */
    size_t L = 2 * m - 1;
    while (largest_prime_factor(L) > 5) L++;
    f->L = L;
    f->chirp = malloc(sizeof(double) * 2 * m);
    f->kernel_hat = calloc(2 * L, sizeof(double));
    f->work = malloc(sizeof(double) * 2 * L);
    f->cwavetable = gsl_fft_complex_wavetable_alloc(L);
    f->cworkspace = gsl_fft_complex_workspace_alloc(L);
    if (!f->chirp || !f->kernel_hat || !f->work || !f->cwavetable || !f->cworkspace) goto nomem;
    /* w_n = e^{i pi n^2/m}: n^2 mod 2m kept exactly in integers (n^2 itself would lose the
     * phase's digits for large n), updated as (n+1)^2 = n^2 + 2n + 1. */
    size_t sq = 0;
    for (size_t n = 0; n < m; n++) {
        const double phase = M_PI * (double)sq / (double)m;
        f->chirp[2 * n] = cos(phase);
        f->chirp[2 * n + 1] = sin(phase);
        sq = (sq + 2 * n + 1) % (2 * m);
    }
    /* kernel b_n = w_n for |n| < m, wrapped around the length L */
    double *b = f->kernel_hat;
    for (size_t n = 0; n < m; n++) {
        b[2 * n] = f->chirp[2 * n];
        b[2 * n + 1] = f->chirp[2 * n + 1];
        if (n > 0) {
            b[2 * (L - n)] = f->chirp[2 * n];
            b[2 * (L - n) + 1] = f->chirp[2 * n + 1];
        }
    }
    if (gsl_fft_complex_forward(b, 1, L, f->cwavetable, f->cworkspace)) {
        fpl_rdft_free(&f);
        return fpl_error(NULL, FPL_ERR_BACKEND, "GSL FFT failed setting up a transform of %zu", m);
    }
    *out = f;
    return FPL_OK;
nomem:
    fpl_rdft_free(&f);
    return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating an FFT of length %zu", m);
}

/* X_k = sum_j x_j e^{-2 pi i jk/m} = conj(w_k) sum_j (x_j conj(w_j)) w_{k-j}, since
 * jk = (j^2 + k^2 - (k-j)^2)/2. */
static int bluestein(fpl_rdft *f, double *data)
{
    const size_t m = f->m, L = f->L;
    double *a = f->work;
    const double *w = f->chirp, *bh = f->kernel_hat;
    for (size_t j = 0; j < m; j++) {
        a[2 * j] = data[j] * w[2 * j];
        a[2 * j + 1] = -data[j] * w[2 * j + 1];
    }
    memset(a + 2 * m, 0, sizeof(double) * 2 * (L - m));
    if (gsl_fft_complex_forward(a, 1, L, f->cwavetable, f->cworkspace))
        return fpl_error(NULL, FPL_ERR_BACKEND, "GSL FFT failed (length %zu)", L);
    for (size_t k = 0; k < L; k++) {
        const double re = a[2 * k] * bh[2 * k] - a[2 * k + 1] * bh[2 * k + 1];
        const double im = a[2 * k] * bh[2 * k + 1] + a[2 * k + 1] * bh[2 * k];
        a[2 * k] = re;
        a[2 * k + 1] = im;
    }
    if (gsl_fft_complex_inverse(a, 1, L, f->cwavetable, f->cworkspace))
        return fpl_error(NULL, FPL_ERR_BACKEND, "GSL FFT failed (length %zu)", L);
    /* GSL's half-complex layout: X_0, then (Re X_k, Im X_k) for 0 < k < m/2, then X_{m/2} */
    for (size_t k = 0; 2 * k <= m; k++) {
        const double re = a[2 * k] * w[2 * k] + a[2 * k + 1] * w[2 * k + 1];
        const double im = a[2 * k + 1] * w[2 * k] - a[2 * k] * w[2 * k + 1];
        if (k == 0) {
            data[0] = re;
        } else if (2 * k == m) {
            data[m - 1] = re;
        } else {
            data[2 * k - 1] = re;
            data[2 * k] = im;
        }
    }
    return FPL_OK;
}

int fpl_rdft_forward(fpl_rdft *plan, double *data)
{
    if (plan->wavetable) {
        int st = gsl_fft_real_transform(data, 1, plan->m, plan->wavetable, plan->workspace);
        if (st)
            return fpl_error(NULL, FPL_ERR_BACKEND, "GSL FFT failed: %s", gsl_strerror(st));
        return FPL_OK;
    }
    return bluestein(plan, data);
}
