/* Results files: samples appended chunk by chunk to extendible, chunked, compressed HDF5
 * datasets (schema in docs/hdf5.md). Memory use is one chunk, whatever the length of the run. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "h5util.h"
#include <hdf5_hl.h>   /* dimension scales (H5DS) */
#include "internal.h"

#define SCHEMA "fputlab-results/1"
#define MAX_CHUNK_BYTES (1 << 20)

/* One extendible dataset of rows of `cols` doubles (cols = 0: a 1-D dataset). */
typedef struct series {
    hid_t d;
    int cols;
    long rows;      /* rows on disk */
} series;

enum { S_T, S_ENERGY, S_MODE_ENERGIES, S_STATES, S_COUNT };
enum { C_T, C_MLE, C_SALI, C_GALI, C_COUNT };

struct fpl_results {
    hid_t file;
    fpl_lattice *lat;
    long dim;                  /* 2N(1 + n_dev) */
    int store_states, chunk;
    series s[S_COUNT];         /* S_STATES.d < 0 unless store_states */
    series c[C_COUNT];         /* /chaos, created on the first chaos sample */
    double *buf[S_COUNT];      /* chunk rows each */
    double *cbuf[C_COUNT];
    int nbuf, ncbuf;           /* buffered rows */
    double *ek;                /* N */
    char h5msg[256];           /* HDF5's message, taken at the failing call (cleanup clears it) */
    char errmsg[FPL_ERRMSG_LEN];
};

static int ensure_chaos(fpl_results *r);
static int label_dimensions(fpl_results *r, int chaos);
static const char *s_names[S_COUNT] = {"t", "energy", "mode_energies", "states"};
static const char *c_names[C_COUNT] = {"chaos/t", "chaos/mle", "chaos/sali", "chaos/gali"};

static int fail(fpl_results *r, int status)
{
    if (r) memcpy(r->errmsg, fpl_last_error(), sizeof r->errmsg);
    return status;
}

static int h5_fail(fpl_results *r, const char *what)
{
    char msg[256];
    fpl_h5_error_text(msg, sizeof msg);
    if (!msg[0] && r) memcpy(msg, r->h5msg, sizeof msg);
    return fail(r, fpl_error(NULL, FPL_ERR_IO, "HDF5: %s failed: %s", what, msg));
}

/* Every dataset of a file has chunks of the same number of rows, the buffer's: each buffer
 * written is exactly one new chunk of each dataset, and no chunk is ever written twice. */
static hid_t create_series(hid_t loc, const char *name, int cols, int chunk_rows)
{
    int rank = cols ? 2 : 1;
    hsize_t dims[2] = {0, (hsize_t)cols}, maxdims[2] = {H5S_UNLIMITED, (hsize_t)cols};
    hsize_t chunk[2] = {(hsize_t)chunk_rows, (hsize_t)cols};
    hid_t space = H5Screate_simple(rank, dims, maxdims), dcpl = H5Pcreate(H5P_DATASET_CREATE);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE), d = -1;
    if (space >= 0 && dcpl >= 0 && lcpl >= 0 && H5Pset_chunk(dcpl, rank, chunk) >= 0 &&
        H5Pset_shuffle(dcpl) >= 0 && H5Pset_deflate(dcpl, 4) >= 0 &&
        H5Pset_create_intermediate_group(lcpl, 1) >= 0)
        d = H5Dcreate2(loc, name, H5T_NATIVE_DOUBLE, space, lcpl, dcpl, H5P_DEFAULT);
    if (space >= 0) H5Sclose(space);
    if (dcpl >= 0) H5Pclose(dcpl);
    if (lcpl >= 0) H5Pclose(lcpl);
    return d;
}

/* Append n rows from buf to a series; on failure HDF5's message goes to errbuf. */
static int append_rows(series *s, const double *buf, int n, char *errbuf, size_t errlen)
{
    if (n == 0 || s->d < 0) return 0;
    int rank = s->cols ? 2 : 1;
    hsize_t size[2] = {(hsize_t)(s->rows + n), (hsize_t)s->cols};
    hsize_t start[2] = {(hsize_t)s->rows, 0}, count[2] = {(hsize_t)n, (hsize_t)s->cols};
    if (H5Dset_extent(s->d, size) < 0) {
        fpl_h5_error_text(errbuf, errlen);
        return -1;
    }
    hid_t fs = H5Dget_space(s->d), ms = H5Screate_simple(rank, count, NULL);
    int ok = fs >= 0 && ms >= 0 &&
             H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
             H5Dwrite(s->d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, buf) >= 0;
    if (!ok) fpl_h5_error_text(errbuf, errlen);
    if (fs >= 0) H5Sclose(fs);
    if (ms >= 0) H5Sclose(ms);
    if (ok) s->rows += n;
    return ok ? 0 : -1;
}

static int set_rows(series *s, long rows)
{
    hsize_t size[2] = {(hsize_t)rows, (hsize_t)s->cols};
    if (s->d < 0) return 0;
    if (H5Dset_extent(s->d, size) < 0) return -1;
    s->rows = rows;
    return 0;
}

static long series_rows(hid_t d)
{
    hid_t space = H5Dget_space(d);
    hsize_t dims[2] = {0, 0};
    if (space < 0) return -1;
    int ok = H5Sget_simple_extent_dims(space, dims, NULL) >= 1;
    H5Sclose(space);
    return ok ? (long)dims[0] : -1;
}

static void release(fpl_results *r)
{
    for (int i = 0; i < S_COUNT; i++) {
        if (r->s[i].d >= 0) H5Dclose(r->s[i].d);
        free(r->buf[i]);
    }
    for (int i = 0; i < C_COUNT; i++) {
        if (r->c[i].d >= 0) H5Dclose(r->c[i].d);
        free(r->cbuf[i]);
    }
    if (r->file >= 0) H5Fclose(r->file);
    free(r->ek);
    free(r);
}

static int check_info(const fpl_lattice *lat, const fpl_run_info *info)
{
    if (!lat) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!info) return fpl_error(NULL, FPL_ERR_ARG, "info: NULL run description");
    if (info->n_dev < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 0 (got %d)", info->n_dev);
    if (info->chunk_rows < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "chunk_rows must be >= 0 (got %d)", info->chunk_rows);
    return FPL_OK;
}

/* Allocate the handle and its buffers (file not yet open). */
static int new_handle(fpl_lattice *lat, const fpl_run_info *info, fpl_results **out)
{
    fpl_results *r = calloc(1, sizeof *r);
    if (!r) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (results)");
    r->file = -1;
    r->lat = lat;
    r->dim = 2L * lat->n * (1 + info->n_dev);
    r->store_states = info->store_states != 0;
    r->chunk = info->chunk_rows ? info->chunk_rows : 256;
    long rows_fit = MAX_CHUNK_BYTES / (8L * (r->store_states ? r->dim : lat->n));
    if (rows_fit < 1) rows_fit = 1;
    if (r->chunk > rows_fit) r->chunk = (int)rows_fit;   /* chunks of at most 1 MiB */
    const int cols[S_COUNT] = {0, 0, lat->n, (int)r->dim};
    int bad = !(r->ek = malloc(sizeof(double) * (size_t)lat->n));
    for (int i = 0; i < S_COUNT; i++) {
        r->s[i] = (series){-1, cols[i], 0};
        if (i == S_STATES && !r->store_states) continue;
        bad |= !(r->buf[i] = malloc(sizeof(double) * (size_t)r->chunk * (cols[i] ? cols[i] : 1)));
    }
    for (int i = 0; i < C_COUNT; i++) {
        r->c[i] = (series){-1, 0, 0};
        bad |= !(r->cbuf[i] = malloc(sizeof(double) * (size_t)r->chunk));
    }
    if (bad) {
        release(r);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (results buffers, %d rows)", info->chunk_rows);
    }
    *out = r;
    return FPL_OK;
}

int fpl_results_create(const char *path, fpl_lattice *lat, const fpl_run_info *info,
                       fpl_results **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!path || !*path) return fpl_error(NULL, FPL_ERR_ARG, "path: empty file name");
    int st = check_info(lat, info);
    if (st) return st;
    fpl_results *r;
    if ((st = new_handle(lat, info, &r))) return st;
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    r->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (r->file < 0) {
        char msg[256];
        fpl_h5_error_text(msg, sizeof msg);
        st = fpl_error(NULL, FPL_ERR_IO, "cannot create results file %s: %s", path, msg);
        goto done;
    }
    if (fpl_h5_write_description(r->file, SCHEMA, lat, info) ||
        fpl_h5_set_string(r->file, "status", "running") ||
        fpl_h5_set_string(r->file, "message", "")) {
        st = h5_fail(r, "writing the run description");
        goto done;
    }
    for (int i = 0; i < S_COUNT; i++) {
        if (i == S_STATES && !r->store_states) continue;
        if ((r->s[i].d = create_series(r->file, s_names[i], r->s[i].cols, r->chunk)) < 0) {
            st = h5_fail(r, "creating the datasets");
            goto done;
        }
    }
    if (label_dimensions(r, 0)) {
        st = h5_fail(r, "labelling the dimensions");
        goto done;
    }
    if (H5Fflush(r->file, H5F_SCOPE_LOCAL) < 0) st = h5_fail(r, "flush");
done:
    fpl_h5_quiet_end(&q);
    if (st) {
        release(r);
        return st;
    }
    *out = r;
    return FPL_OK;
}

/* ---- pending rows: results <-> checkpoint ----------------------------------------------- */
static const char *p_names[S_COUNT] = {"pending_t", "pending_energy", "pending_mode_energies",
                                       "pending_states"};
static const char *pc_names[C_COUNT] = {"pending_chaos_t", "pending_chaos_mle",
                                        "pending_chaos_sali", "pending_chaos_gali"};

static unsigned long long pending_hash(const fpl_results *r)
{
    unsigned long long h = FPL_FNV_OFFSET;
    long counts[4] = {r->s[S_T].rows, r->c[C_T].rows, r->nbuf, r->ncbuf};
    h = fpl_fnv1a(h, counts, sizeof counts);
    for (int i = 0; i < S_COUNT; i++)
        if (r->buf[i])
            h = fpl_fnv1a(h, r->buf[i], sizeof(double) * (size_t)r->nbuf * (r->s[i].cols ? r->s[i].cols : 1));
    for (int i = 0; i < C_COUNT; i++) h = fpl_fnv1a(h, r->cbuf[i], sizeof(double) * (size_t)r->ncbuf);
    return h;
}

int fpl_results_save_pending(const fpl_results *r, hid_t f)
{
    int bad = fpl_h5_set_long(f, "results_rows", r->s[S_T].rows) ||
              fpl_h5_set_long(f, "results_chaos_rows", r->c[C_T].rows) ||
              fpl_h5_set_long(f, "results_store_states", r->store_states) ||
              fpl_h5_set_long(f, "results_chunk_rows", r->chunk) ||
              fpl_h5_set_u64(f, "results_checksum", pending_hash(r));
    for (int i = 0; i < S_COUNT && !bad; i++)
        if (r->buf[i])
            bad = fpl_h5_write_vector(f, p_names[i], r->buf[i],
                                      (size_t)r->nbuf * (r->s[i].cols ? r->s[i].cols : 1));
    for (int i = 0; i < C_COUNT && !bad; i++)
        bad = fpl_h5_write_vector(f, pc_names[i], r->cbuf[i], (size_t)r->ncbuf);
    return bad ? -1 : 0;
}

/* Read the rows on disk and the pending rows of the checkpoint into r (buffers). */
static int load_pending(fpl_results *r, const char *checkpoint, long *rows, long *crows)
{
    hid_t f = H5Fopen(checkpoint, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) {
        char msg[256];
        fpl_h5_error_text(msg, sizeof msg);
        return fpl_error(NULL, FPL_ERR_IO, "cannot read checkpoint %s: %s", checkpoint, msg);
    }
    long store = -1, chunk = -1;
    unsigned long long sum = 0;
    int st = FPL_OK;
    if (fpl_h5_get_long(f, "results_rows", rows) || fpl_h5_get_long(f, "results_chaos_rows", crows) ||
        fpl_h5_get_long(f, "results_store_states", &store) ||
        fpl_h5_get_long(f, "results_chunk_rows", &chunk) || fpl_h5_get_u64(f, "results_checksum", &sum)) {
        st = fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s does not record a results file", checkpoint);
        goto out;
    }
    if (store != r->store_states || chunk != r->chunk) {
        st = fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s was written for results with states %s and "
                       "%ld-row chunks; this run: states %s, %d-row chunks", checkpoint,
                       store ? "stored" : "not stored", chunk, r->store_states ? "stored" : "not stored",
                       r->chunk);
        goto out;
    }
    size_t n = (size_t)r->chunk;
    for (int i = 0; i < S_COUNT && !st; i++) {
        if (!r->buf[i]) continue;
        size_t cols = (size_t)(r->s[i].cols ? r->s[i].cols : 1), len = n * cols;
        if (fpl_h5_read_vector(f, p_names[i], r->buf[i], &len) || len % cols)
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: %s missing or too long", checkpoint, p_names[i]);
        else
            r->nbuf = (int)(len / cols);
    }
    for (int i = 0; i < C_COUNT && !st; i++) {
        size_t len = n;
        if (fpl_h5_read_vector(f, pc_names[i], r->cbuf[i], &len))
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: %s missing or too long", checkpoint, pc_names[i]);
        else
            r->ncbuf = (int)len;
    }
    if (!st) {
        long keep_rows = r->s[S_T].rows, keep_crows = r->c[C_T].rows;
        r->s[S_T].rows = *rows;
        r->c[C_T].rows = *crows;
        if (pending_hash(r) != sum)
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt (results checksum mismatch)",
                           checkpoint);
        r->s[S_T].rows = keep_rows;
        r->c[C_T].rows = keep_crows;
    }
out:
    H5Fclose(f);
    return st;
}

int fpl_results_resume(const char *path, fpl_lattice *lat, const fpl_run_info *info,
                       const char *checkpoint, fpl_results **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    if (!path || !*path) return fpl_error(NULL, FPL_ERR_ARG, "path: empty file name");
    if (!checkpoint || !*checkpoint) return fpl_error(NULL, FPL_ERR_ARG, "checkpoint: empty file name");
    int st = check_info(lat, info);
    if (st) return st;
    fpl_results *r;
    if ((st = new_handle(lat, info, &r))) return st;
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    long rows = 0, crows = 0;
    r->file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (r->file < 0) {
        char msg[256];
        fpl_h5_error_text(msg, sizeof msg);
        st = fpl_error(NULL, FPL_ERR_IO, "cannot open results file %s to resume: %s", path, msg);
        goto done;
    }
    if ((st = fpl_h5_check_description(r->file, path, SCHEMA, lat, info->method))) goto done;
    if ((st = load_pending(r, checkpoint, &rows, &crows))) goto done;
    for (int i = 0; i < S_COUNT; i++) {
        if (i == S_STATES && !r->store_states) continue;
        if (H5Lexists(r->file, s_names[i], H5P_DEFAULT) <= 0 ||
            (r->s[i].d = H5Dopen2(r->file, s_names[i], H5P_DEFAULT)) < 0) {
            H5Eclear2(H5E_DEFAULT);
            st = fpl_error(NULL, FPL_ERR_ARG, "%s has no dataset %s (was it written with the same "
                           "options?)", path, s_names[i]);
            goto done;
        }
    }
    if (crows > 0 && ensure_chaos(r)) {
        st = h5_fail(r, "opening the chaos datasets");
        goto done;
    }
    long have = series_rows(r->s[S_T].d), chave = crows > 0 ? series_rows(r->c[C_T].d) : 0;
    if (have < rows || chave < crows) {
        st = fpl_error(NULL, FPL_ERR_ARG, "%s has %ld rows (%ld chaos rows), fewer than the %ld (%ld) "
                       "its checkpoint %s records: not the file of that run", path, have, chave,
                       rows, crows, checkpoint);
        goto done;
    }
    /* cut back to whole chunks written before the checkpoint; later ones go */
    int bad = 0;
    for (int i = 0; i < S_COUNT && !bad; i++) bad = set_rows(&r->s[i], rows) != 0;
    for (int i = 0; i < C_COUNT && !bad; i++) bad = set_rows(&r->c[i], crows) != 0;
    if (bad || fpl_h5_set_string(r->file, "status", "running") ||
        H5Fflush(r->file, H5F_SCOPE_LOCAL) < 0)
        st = h5_fail(r, "cutting the results back to the checkpoint");
done:
    fpl_h5_quiet_end(&q);
    if (st) {
        release(r);
        return st;
    }
    *out = r;
    return FPL_OK;
}

const char *fpl_results_errmsg(const fpl_results *r) { return r ? r->errmsg : ""; }

long fpl_results_count(const fpl_results *r) { return r ? r->s[S_T].rows + r->nbuf : -1; }

/* Dimension scales (the netCDF-4 convention), so that netCDF readers (xarray with
 * engine="h5netcdf", ncdump) name the dimensions instead of inventing phony_dim_*: `t` is the
 * scale of the sample axis of every series; `mode` (1..N), `site` (1..N, for v) and `component`
 * (1..2N(1+n_dev), for states) are small index datasets made scales of the column axes. In
 * /chaos, chaos/t is the scale of mle, sali, gali. Called once, when the datasets are created
 * (a resumed file has them already). Returns 0, or -1 with HDF5's message in r->h5msg. */
static hid_t index_scale(hid_t loc, const char *name, long n)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = H5Screate_simple(1, dims, NULL), d = -1;
    int *idx = malloc(sizeof(int) * (size_t)n);
    if (idx && space >= 0) {
        for (long i = 0; i < n; i++) idx[i] = (int)(i + 1);
        d = H5Dcreate2(loc, name, H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (d >= 0 && (H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, idx) < 0 ||
                       H5DSset_scale(d, name) < 0)) {
            H5Dclose(d);
            d = -1;
        }
    }
    free(idx);
    if (space >= 0) H5Sclose(space);
    return d;
}

static int label_dimensions(fpl_results *r, int chaos)
{
    int bad = 0;
    if (chaos) {
        bad |= H5DSset_scale(r->c[C_T].d, "t") < 0;
        for (int i = C_T + 1; i < C_COUNT && !bad; i++)
            bad |= H5DSattach_scale(r->c[i].d, r->c[C_T].d, 0) < 0;
    } else {
        hid_t mode = index_scale(r->file, "mode", r->lat->n);
        hid_t site = index_scale(r->file, "site", r->lat->n);
        hid_t comp = r->store_states ? index_scale(r->file, "component", r->dim) : 0;
        hid_t v = H5Dopen2(r->file, "v", H5P_DEFAULT);
        bad = mode < 0 || site < 0 || comp < 0 || v < 0 || H5DSset_scale(r->s[S_T].d, "t") < 0;
        for (int i = S_T + 1; i < S_COUNT && !bad; i++)
            if (r->s[i].d >= 0) bad |= H5DSattach_scale(r->s[i].d, r->s[S_T].d, 0) < 0;
        if (!bad) bad |= H5DSattach_scale(r->s[S_MODE_ENERGIES].d, mode, 1) < 0;
        if (!bad && r->store_states) bad |= H5DSattach_scale(r->s[S_STATES].d, comp, 1) < 0;
        if (!bad) bad |= H5DSattach_scale(v, site, 0) < 0;
        if (mode >= 0) H5Dclose(mode);
        if (site >= 0) H5Dclose(site);
        if (comp > 0) H5Dclose(comp);
        if (v >= 0) H5Dclose(v);
    }
    if (bad) fpl_h5_error_text(r->h5msg, sizeof r->h5msg);
    return bad ? -1 : 0;
}

static int ensure_chaos(fpl_results *r)
{
    if (r->c[C_T].d >= 0) return 0;
    int created = 0;
    for (int i = 0; i < C_COUNT; i++) {
        if (H5Lexists(r->file, "chaos", H5P_DEFAULT) > 0 &&
            H5Lexists(r->file, c_names[i], H5P_DEFAULT) > 0)
            r->c[i].d = H5Dopen2(r->file, c_names[i], H5P_DEFAULT);
        else {
            r->c[i].d = create_series(r->file, c_names[i], 0, r->chunk);
            created = 1;
        }
        if (r->c[i].d < 0) return -1;
    }
    return created ? label_dimensions(r, 1) : 0;
}

/* Write the buffers: only full ones (whole chunks), unless `all` (closing the file). */
static int write_buffers(fpl_results *r, int all)
{
    if (r->nbuf == r->chunk || (all && r->nbuf)) {
        for (int i = 0; i < S_COUNT; i++)
            if (append_rows(&r->s[i], r->buf[i], r->nbuf, r->h5msg, sizeof r->h5msg)) return -1;
        r->nbuf = 0;
    }
    if (r->ncbuf == r->chunk || (all && r->ncbuf)) {
        if (ensure_chaos(r)) return -1;
        for (int i = 0; i < C_COUNT; i++)
            if (append_rows(&r->c[i], r->cbuf[i], r->ncbuf, r->h5msg, sizeof r->h5msg)) return -1;
        r->ncbuf = 0;
    }
    return 0;
}

static int flush(fpl_results *r, int all)
{
    if (!r) return fpl_error(NULL, FPL_ERR_ARG, "results: NULL handle");
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    int st = write_buffers(r, all) || H5Fflush(r->file, H5F_SCOPE_LOCAL) < 0
                 ? h5_fail(r, "writing samples") : FPL_OK;
    fpl_h5_quiet_end(&q);
    return st;
}

int fpl_results_flush(fpl_results *r) { return flush(r, 0); }

int fpl_results_append(fpl_results *r, double t, const double *y)
{
    if (!r) return fpl_error(NULL, FPL_ERR_ARG, "results: NULL handle");
    if (!y) return fail(r, fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer"));
    if (!isfinite(t)) return fail(r, fpl_error(NULL, FPL_ERR_ARG, "t must be finite (got %g)", t));
    const long n = r->lat->n;
    long bad;
    if (!fpl_is_finite_array(y, r->store_states ? r->dim : 2 * n, &bad))
        return fail(r, fpl_error(NULL, FPL_ERR_NONFINITE,
                                 "state at t = %.17g has a non-finite entry y[%ld]: not written", t, bad));
    int st = fpl_modes_energies(r->lat, y, r->ek);
    if (st) return fail(r, st);
    double e = r->lat->ops->energy(r->lat, y);
    if (!isfinite(e) || !fpl_is_finite_array(r->ek, n, NULL))
        return fail(r, fpl_error(NULL, FPL_ERR_NONFINITE,
                                 "energies overflowed at t = %.17g (blow-up): not written", t));
    const int k = r->nbuf;
    r->buf[S_T][k] = t;
    r->buf[S_ENERGY][k] = e;
    memcpy(r->buf[S_MODE_ENERGIES] + (size_t)k * n, r->ek, sizeof(double) * (size_t)n);
    if (r->store_states) memcpy(r->buf[S_STATES] + (size_t)k * r->dim, y, sizeof(double) * (size_t)r->dim);
    r->nbuf++;
    return r->nbuf == r->chunk ? flush(r, 0) : FPL_OK;
}

int fpl_results_append_chaos(fpl_results *r, double t, double mle, double sali, double gali)
{
    if (!r) return fpl_error(NULL, FPL_ERR_ARG, "results: NULL handle");
    if (!isfinite(t) || !isfinite(mle))
        return fail(r, fpl_error(NULL, FPL_ERR_ARG, "t and mle must be finite (got %g, %g)", t, mle));
    if (r->c[C_T].d < 0) {
        fpl_h5_quiet q;
        fpl_h5_quiet_begin(&q);
        int st = ensure_chaos(r) ? h5_fail(r, "creating the chaos datasets") : FPL_OK;
        fpl_h5_quiet_end(&q);
        if (st) return st;
    }
    const int k = r->ncbuf;
    r->cbuf[C_T][k] = t;
    r->cbuf[C_MLE][k] = mle;
    r->cbuf[C_SALI][k] = sali;
    r->cbuf[C_GALI][k] = gali;
    r->ncbuf++;
    return r->ncbuf == r->chunk ? flush(r, 0) : FPL_OK;
}

int fpl_results_set_status(fpl_results *r, const char *status, const char *message)
{
    static const char *known[] = {"running", "completed", "event", "failed", "interrupted"};
    if (!r) return fpl_error(NULL, FPL_ERR_ARG, "results: NULL handle");
    int ok = 0;
    for (size_t i = 0; status && i < sizeof known / sizeof *known; i++) ok |= !strcmp(status, known[i]);
    if (!ok)
        return fail(r, fpl_error(NULL, FPL_ERR_ARG, "status must be running, completed, event, "
                                 "failed or interrupted (got %s)", status ? status : "NULL"));
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    int st = fpl_h5_set_string(r->file, "status", status) ||
             fpl_h5_set_string(r->file, "message", message ? message : "")
                 ? h5_fail(r, "writing the status") : FPL_OK;
    fpl_h5_quiet_end(&q);
    return st ? st : fpl_results_flush(r);
}

int fpl_results_set_event(fpl_results *r, double t, const char *criterion)
{
    if (!r) return fpl_error(NULL, FPL_ERR_ARG, "results: NULL handle");
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    int st = fpl_h5_set_double(r->file, "event_time", t) ||
             fpl_h5_set_string(r->file, "event_criterion", criterion ? criterion : "")
                 ? h5_fail(r, "writing the event") : FPL_OK;
    fpl_h5_quiet_end(&q);
    return st;
}

int fpl_results_close(fpl_results **rp)
{
    if (!rp || !*rp) return FPL_OK;
    int st = flush(*rp, 1);
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    release(*rp);
    fpl_h5_quiet_end(&q);
    *rp = NULL;
    return st;
}

void fpl_run_info_init(fpl_run_info *info)
{
    if (!info) return;
    memset(info, 0, sizeof *info);
    info->kind = "simulate";
    info->method = "";
    info->dt = info->rtol = info->atol = NAN;
    info->tau = NAN;
    info->seed = -1;
    info->disorder = "";
}
