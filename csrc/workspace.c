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
    fpl_rdft_free(&w->rdft);
    free(w);
    *work = NULL;
}
