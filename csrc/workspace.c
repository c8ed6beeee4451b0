/* The kernels' scratch for one lattice size: owned by the runs, never by the (read-only) lattice. */
#include <stdlib.h>
#include "internal.h"

static void *xcalloc(size_t n) { return calloc(n ? n : 1, sizeof(double)); }

int fpl_work_create(int n, int modes, fpl_work **out)
{
    *out = NULL;
    fpl_work *w = calloc(1, sizeof *w);
    if (!w) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating a workspace");
    const size_t nn = (size_t)n, m = 2 * (nn + 1);
    w->n = n;
    w->phi = xcalloc(nn + 1);
    w->kappa = xcalloc(nn + 1);
    w->dphi = xcalloc(nn + 1);
    w->fft = xcalloc(m);
    w->ek = xcalloc(nn);
    if (n <= FPL_KAPPA_STAGES_MAX_N)   /* scratch, written before it is read: not zeroed */
        w->kappa_stages = malloc(sizeof(double) * FPL_KAPPA_STAGES * (nn + 1));
    w->kappa_rows = w->kappa_stages ? FPL_KAPPA_STAGES : 0;
    if (!w->phi || !w->kappa || !w->dphi || !w->fft || !w->ek ||
        (n <= FPL_KAPPA_STAGES_MAX_N && !w->kappa_stages)) {
        fpl_work_free(&w);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory allocating a workspace for N = %d", n);
    }
    if (modes != FPL_WORK_NO_MODES) {
        int st = fpl_rdft_create(modes == FPL_WORK_FOURIER_MODES ? nn : m, &w->rdft);
        if (st) {
            fpl_work_free(&w);
            return st;
        }
    }
    *out = w;
    return FPL_OK;
}

int fpl_work_reserve_vectors(fpl_work *w, int n_dev)
{
    const int n = w->n;
    if (fpl_sweep_serves(n, n_dev)) {
        /* the long-chain sweep: its kappa rows and the carried bond terms of n_dev vectors */
        if (!w->sweep_rows)
            w->sweep_rows = malloc(sizeof(double) * FPL_SWEEP_STAGES * FPL_SWEEP_ROW);
        if (w->sweep_rows && w->sweep_dev < n_dev) {
            double *c = realloc(w->sweep_carry,
                                sizeof(double) * FPL_SWEEP_STAGES * (2 + (size_t)n_dev));
            if (c) {
                w->sweep_carry = c;
                w->sweep_dev = n_dev;
            }
        }
        if (!w->sweep_rows || w->sweep_dev < n_dev)
            return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory sizing a workspace for %d "
                             "deviation vectors", n_dev);
        return FPL_OK;
    }
    if (n < 3 || n > FPL_VEC_INNER_MAX_N || n_dev < FPL_VEC_INNER_MIN_DEV) return FPL_OK;
    const size_t rows_n = (size_t)n + 1;
    /* as many kicks' kappa as fit in FPL_KAPPA_GROUP_DOUBLES: the tiles' transposes are paid
     * once per group of steps */
    size_t rows = FPL_KAPPA_GROUP_DOUBLES / rows_n;
    if (rows < FPL_KAPPA_STAGES) rows = FPL_KAPPA_STAGES;
    if (rows > FPL_KAPPA_ROWS_MAX) rows = FPL_KAPPA_ROWS_MAX;
    if (!w->tile) {
        /* 32-byte aligned: its rows are read as AVX2 vectors (the size, 128 N bytes, is a
         * multiple of the alignment as aligned_alloc asks) */
        w->tile = aligned_alloc(32, sizeof(double) * 2 * FPL_VEC_TILE * (size_t)n);
        if (!w->tile)
            return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory sizing a workspace for %d "
                             "deviation vectors", n_dev);
    }
    if ((size_t)w->kappa_rows < rows) {
        double *k = realloc(w->kappa_stages, sizeof(double) * rows * rows_n);
        if (!k)
            return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory sizing a workspace for %d "
                             "deviation vectors", n_dev);
        w->kappa_stages = k;
        w->kappa_rows = (int)rows;
    }
    return FPL_OK;
}

void fpl_work_free(fpl_work **work)
{
    if (!work || !*work) return;
    fpl_work *w = *work;
    free(w->phi);
    free(w->kappa);
    free(w->dphi);
    free(w->fft);
    free(w->ek);
    free(w->kappa_stages);
    free(w->tile);
    free(w->sweep_rows);
    free(w->sweep_carry);
    fpl_rdft_free(&w->rdft);
    free(w);
    *work = NULL;
}
