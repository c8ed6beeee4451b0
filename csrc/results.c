/* Results files: samples appended chunk by chunk to extendible, chunked, compressed HDF5
 * datasets (schema in docs/hdf5.md). Memory use is one chunk, whatever the length of the run.
 * Every chunk carries a Fletcher-32 checksum and the file uses HDF5's 1.8 format, whose
 * superblock and object headers (attributes included) are checksummed too: a damaged file gives
 * an error when read, not wrong numbers. (Not the 1.10 format: its superblock marks a file
 * open for writing, and a run killed by SIGKILL would leave a file nobody can open.) Resuming
 * reads back every row it keeps (verified) before it changes anything. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fsutil.h"
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
    unsigned long long hash;   /* FNV-1a of the bytes of those rows, in order */
} series;

enum { S_T, S_ENERGY, S_MODE_ENERGIES, S_STATES, S_COUNT };
enum { C_T, C_MLE, C_SALI, C_GALI, C_COUNT };

struct fpl_results {
    hid_t file;
    const fpl_lattice *lat;
    fpl_work *work;            /* the mode transform's scratch for appended rows */
    long dim;                  /* 2N(1 + n_dev) */
    int store_states, chunk;
    int root;                  /* the orbit series t, energy, mode_energies exist (not in a chaos
                                  file, whose samples are all in /chaos) */
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
static int describe_variables(hid_t file);
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
        H5Pset_shuffle(dcpl) >= 0 && H5Pset_deflate(dcpl, 4) >= 0 && H5Pset_fletcher32(dcpl) >= 0 &&
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
    if (ok) {
        s->rows += n;
        s->hash = fpl_fnv1a(s->hash, buf, sizeof(double) * (size_t)n * (s->cols ? s->cols : 1));
    }
    return ok ? 0 : -1;
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
    fpl_work_free(&r->work);
    free(r);
}

static int check_info(const fpl_lattice *lat, const fpl_run_info *info)
{
    if (!lat) return fpl_error(NULL, FPL_ERR_ARG, "lattice: NULL handle");
    if (!info) return fpl_error(NULL, FPL_ERR_ARG, "info: NULL run description");
    long dim;
    int st = fpl_state_length(lat->n, info->n_dev, &dim);
    if (st) return st;
    if (info->store_states && dim > INT_MAX)   /* the columns of `states` are an int */
        return fpl_error(NULL, FPL_ERR_ARG, "store_states: a state of %ld doubles is too wide to "
                         "store as one row", dim);
    if (info->chunk_rows < 0)
        return fpl_error(NULL, FPL_ERR_ARG, "chunk_rows must be >= 0 (got %d)", info->chunk_rows);
    return FPL_OK;
}

/* Allocate the handle and its buffers (file not yet open). */
static int new_handle(const fpl_lattice *lat, const fpl_run_info *info, fpl_results **out)
{
    fpl_results *r = calloc(1, sizeof *r);
    if (!r) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (results)");
    r->file = -1;
    r->lat = lat;
    r->dim = 2L * lat->n * (1 + info->n_dev);
    r->store_states = info->store_states != 0;
    r->root = !(info->kind && strcmp(info->kind, "chaos") == 0) || r->store_states;
    r->chunk = info->chunk_rows ? info->chunk_rows : 256;
    long rows_fit = MAX_CHUNK_BYTES / (8L * (r->store_states ? r->dim : lat->n));
    if (rows_fit < 1) rows_fit = 1;
    if (r->chunk > rows_fit) r->chunk = (int)rows_fit;   /* chunks of at most 1 MiB */
    const int cols[S_COUNT] = {0, 0, lat->n, (int)r->dim};
    int bad = !(r->ek = malloc(sizeof(double) * (size_t)lat->n));
    bad |= fpl_work_create(lat->n, FPL_WORK_MODES_OF(lat), &r->work) != FPL_OK;
    for (int i = 0; i < S_COUNT; i++) {
        r->s[i] = (series){-1, cols[i], 0, FPL_FNV_OFFSET};
        if (i == S_STATES && !r->store_states) continue;
        bad |= !(r->buf[i] = malloc(sizeof(double) * (size_t)r->chunk * (cols[i] ? cols[i] : 1)));
    }
    for (int i = 0; i < C_COUNT; i++) {
        r->c[i] = (series){-1, 0, 0, FPL_FNV_OFFSET};
        bad |= !(r->cbuf[i] = malloc(sizeof(double) * (size_t)r->chunk));
    }
    if (bad) {
        release(r);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (results buffers, %d rows)", info->chunk_rows);
    }
    *out = r;
    return FPL_OK;
}

/* Create the file at path for handle r: description, status "running", the datasets. */
static int create_in(fpl_results *r, const char *path, const fpl_run_info *info)
{
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    r->file = fapl >= 0 && H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_V18) >= 0
                  ? H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl) : -1;
    char msg[256] = "";
    if (r->file < 0) fpl_h5_error_text(msg, sizeof msg);   /* before any other call clears it */
    if (fapl >= 0) H5Pclose(fapl);
    if (r->file < 0)
        return fpl_error(NULL, FPL_ERR_IO, "cannot create results file %s: %s", path, msg);
    if (fpl_h5_write_description(r->file, SCHEMA, r->lat, info) ||
        fpl_h5_set_string(r->file, "status", "running") ||
        fpl_h5_set_string(r->file, "message", ""))
        return h5_fail(r, "writing the run description");
    for (int i = 0; i < S_COUNT && r->root; i++) {
        if (i == S_STATES && !r->store_states) continue;
        if ((r->s[i].d = create_series(r->file, s_names[i], r->s[i].cols, r->chunk)) < 0)
            return h5_fail(r, "creating the datasets");
    }
    if (label_dimensions(r, 0)) return h5_fail(r, "labelling the dimensions");
    if (describe_variables(r->file)) return h5_fail(r, "writing the variables' attributes");
    return H5Fflush(r->file, H5F_SCOPE_LOCAL) < 0 ? h5_fail(r, "flush") : FPL_OK;
}

int fpl_results_create(const char *path, const fpl_lattice *lat, const fpl_run_info *info,
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
    st = create_in(r, path, info);
    int created = r->file >= 0;
    if (st) release(r);   /* still quiet: closing a file that cannot be flushed reports errors */
    if (st && created) remove(path);   /* a half-written file of ours helps nobody */
    H5Eclear2(H5E_DEFAULT);
    fpl_h5_quiet_end(&q);
    if (st) return st;
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
    /* what the rows on disk hash to: a resume reads them back and compares, so that damage
     * HDF5 cannot see (its 1.8 chunk index has no checksum) is caught too */
    for (int i = 0; i < S_COUNT + C_COUNT && !bad; i++) {
        char name[32];
        snprintf(name, sizeof name, "results_data_hash_%d", i);
        bad = fpl_h5_set_u64(f, name, i < S_COUNT ? r->s[i].hash : r->c[i - S_COUNT].hash);
    }
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
    int vst = fpl_checkpoint_verify_bytes(checkpoint);
    if (vst) return vst;
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
    for (int i = 0; i < S_COUNT + C_COUNT; i++) {
        char name[32];
        snprintf(name, sizeof name, "results_data_hash_%d", i);
        if (fpl_h5_get_u64(f, name, i < S_COUNT ? &r->s[i].hash : &r->c[i - S_COUNT].hash)) {
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: %s missing", checkpoint, name);
            goto out;
        }
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

/* Read rows [at, at + n) of a series into buf. */
static int read_block(const series *s, double *buf, long at, long n)
{
    int rank = s->cols ? 2 : 1;
    hsize_t start[2] = {(hsize_t)at, 0}, count[2] = {(hsize_t)n, (hsize_t)s->cols};
    hid_t fs = H5Dget_space(s->d), ms = H5Screate_simple(rank, count, NULL);
    int ok = fs >= 0 && ms >= 0 &&
             H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
             H5Dread(s->d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, buf) >= 0;
    if (fs >= 0) H5Sclose(fs);
    if (ms >= 0) H5Sclose(ms);
    return ok ? 0 : -1;
}

/* Read rows [0, rows) of a series back in chunk-sized blocks (HDF5 verifies each chunk's
 * Fletcher-32 checksum) and compare their hash with the one recorded in s->hash. */
static int read_back(const series *s, double *buf, long rows, int chunk, int *mismatch)
{
    unsigned long long h = FPL_FNV_OFFSET;
    *mismatch = 0;
    for (long at = 0; at < rows; at += chunk) {
        long n = rows - at < chunk ? rows - at : chunk;
        if (read_block(s, buf, at, n)) return -1;
        h = fpl_fnv1a(h, buf, sizeof(double) * (size_t)n * (s->cols ? s->cols : 1));
    }
    *mismatch = h != s->hash;
    return 0;
}

/* Shape of a series on disk: rank and columns as expected; -1 otherwise. */
static long series_rows_checked(const series *s)
{
    hid_t space = H5Dget_space(s->d);
    hsize_t dims[2] = {0, 0};
    if (space < 0) return -1;
    int rank = H5Sget_simple_extent_ndims(space);
    int ok = rank == (s->cols ? 2 : 1) && H5Sget_simple_extent_dims(space, dims, NULL) == rank &&
             (!s->cols || dims[1] == (hsize_t)s->cols);
    H5Sclose(space);
    return ok ? (long)dims[0] : -1;
}

/* Open `path` (read-only or read-write) for a resume from `checkpoint`: check it describes this
 * lattice and method, read the checkpoint's pending rows, open the datasets and check their
 * shapes and that the file holds the rows the checkpoint records. With `verify`, also read all
 * those rows back. Nothing is changed. */
static int open_for_resume(fpl_results *r, const char *path, unsigned mode, const fpl_run_info *info,
                           const char *checkpoint, int verify, long *rows, long *crows)
{
    int st;
    r->file = H5Fopen(path, mode, H5P_DEFAULT);
    if (r->file < 0) {
        char msg[256];
        fpl_h5_error_text(msg, sizeof msg);
        /* HDF5 locks a file it opens (flock): EWOULDBLOCK means another process is writing it */
        if (strstr(msg, "lock") || strstr(msg, strerror(EWOULDBLOCK)))
            return fpl_error(NULL, FPL_ERR_IO, "results file %s is in use by another process (it "
                             "holds the file's lock): let that run finish first (%s)", path, msg);
        return fpl_error(NULL, FPL_ERR_IO, "cannot open results file %s to resume (missing or "
                         "corrupt?): %s", path, msg);
    }
    if ((st = fpl_h5_check_description(r->file, path, SCHEMA, r->lat, info->method))) return st;
    char kind[64] = "", status[32] = "";
    if (!fpl_h5_get_string(r->file, "kind", kind, sizeof kind) && info->kind &&
        strcmp(kind, info->kind) != 0)
        return fpl_error(NULL, FPL_ERR_ARG, "%s holds a %s run, this run is %s (refused, nothing "
                         "changed)", path, kind, info->kind);
    if ((st = load_pending(r, checkpoint, rows, crows))) return st;
    /* Nothing the file holds may be lost by a resume beyond the rows of a run that was killed
     * after its last checkpoint: a file with stored states continued by a run without them
     * would lose its `states`, and a finished file (status not "running": its last checkpoint
     * was written at its end) with more samples than the checkpoint covers belongs to a later
     * checkpoint than this one. */
    if (!r->store_states && H5Lexists(r->file, s_names[S_STATES], H5P_DEFAULT) > 0)
        return fpl_error(NULL, FPL_ERR_ARG, "%s stores the states at every sample, its checkpoint "
                         "%s is of a run without them: resuming would drop them (refused, nothing "
                         "changed; resume with the states stored)", path, checkpoint);
    H5Eclear2(H5E_DEFAULT);
    int finished = !fpl_h5_get_string(r->file, "status", status, sizeof status) &&
                   strcmp(status, "running") != 0;
    for (int i = 0; i < S_COUNT && r->root; i++) {
        if (i == S_STATES && !r->store_states) continue;
        if (H5Lexists(r->file, s_names[i], H5P_DEFAULT) <= 0 ||
            (r->s[i].d = H5Dopen2(r->file, s_names[i], H5P_DEFAULT)) < 0) {
            H5Eclear2(H5E_DEFAULT);
            return fpl_error(NULL, FPL_ERR_ARG, "%s has no dataset %s (was it written with the same "
                             "options?)", path, s_names[i]);
        }
    }
    if (*crows > 0) {
        if (H5Lexists(r->file, "chaos", H5P_DEFAULT) <= 0) {
            H5Eclear2(H5E_DEFAULT);
            return fpl_error(NULL, FPL_ERR_ARG, "%s has no /chaos group, its checkpoint %s records "
                             "%ld chaos rows", path, checkpoint, *crows);
        }
        for (int i = 0; i < C_COUNT; i++) {
            if (H5Lexists(r->file, c_names[i], H5P_DEFAULT) <= 0 ||
                (r->c[i].d = H5Dopen2(r->file, c_names[i], H5P_DEFAULT)) < 0) {
                H5Eclear2(H5E_DEFAULT);
                return fpl_error(NULL, FPL_ERR_IO, "%s: dataset %s missing or unreadable (corrupt?)",
                                 path, c_names[i]);
            }
        }
    }
    for (int i = 0; i < S_COUNT; i++) {
        if (r->s[i].d < 0) continue;
        long have = series_rows_checked(&r->s[i]);
        if (have < 0)
            return fpl_error(NULL, FPL_ERR_IO, "%s: dataset %s has the wrong shape (corrupt?)", path,
                             s_names[i]);
        if (have < *rows)
            return fpl_error(NULL, FPL_ERR_ARG, "%s has %ld rows in %s, fewer than the %ld its "
                             "checkpoint %s records: not the file of that run", path, have,
                             s_names[i], *rows, checkpoint);
        if (finished && have > *rows + r->nbuf)
            return fpl_error(NULL, FPL_ERR_ARG, "%s is a finished run (status %s) with %ld samples; "
                             "its checkpoint %s covers only %ld: the checkpoint is older than the "
                             "file and resuming would drop %ld samples (refused, nothing changed)",
                             path, status, have, checkpoint, *rows + r->nbuf, have - *rows - r->nbuf);
        int mismatch = 0;
        if (verify && read_back(&r->s[i], r->buf[i], *rows, r->chunk, &mismatch)) {
            char msg[256];
            fpl_h5_error_text(msg, sizeof msg);
            return fpl_error(NULL, FPL_ERR_IO, "%s is corrupt: reading back %s failed: %s", path,
                             s_names[i], msg);
        }
        if (mismatch)
            return fpl_error(NULL, FPL_ERR_IO, "%s is corrupt: its %s rows differ from those its "
                             "checkpoint %s covers (checksum mismatch)", path, s_names[i], checkpoint);
    }
    if (finished && *crows == 0 && H5Lexists(r->file, "chaos", H5P_DEFAULT) > 0 &&
        H5Lexists(r->file, c_names[C_T], H5P_DEFAULT) > 0) {
        hid_t d = H5Dopen2(r->file, c_names[C_T], H5P_DEFAULT);
        series probe = {d, 0, 0, 0};
        long have = d >= 0 ? series_rows_checked(&probe) : -1;
        if (d >= 0) H5Dclose(d);
        if (have > r->ncbuf)
            return fpl_error(NULL, FPL_ERR_ARG, "%s is a finished run (status %s) with %ld chaos "
                             "samples; its checkpoint %s covers only %d: the checkpoint is older "
                             "than the file (refused, nothing changed)", path, status, have,
                             checkpoint, r->ncbuf);
    }
    H5Eclear2(H5E_DEFAULT);
    for (int i = 0; i < C_COUNT && *crows > 0; i++) {
        long have = series_rows_checked(&r->c[i]);
        if (have < 0)
            return fpl_error(NULL, FPL_ERR_IO, "%s: dataset %s has the wrong shape (corrupt?)", path,
                             c_names[i]);
        if (have < *crows)
            return fpl_error(NULL, FPL_ERR_ARG, "%s has %ld rows in %s, fewer than the %ld its "
                             "checkpoint %s records: not the file of that run", path, have,
                             c_names[i], *crows, checkpoint);
        if (finished && have > *crows + r->ncbuf)
            return fpl_error(NULL, FPL_ERR_ARG, "%s is a finished run (status %s) with %ld chaos "
                             "samples; its checkpoint %s covers only %ld: the checkpoint is older "
                             "than the file (refused, nothing changed)", path, status, have,
                             checkpoint, *crows + r->ncbuf);
        int mismatch = 0;
        if (verify && read_back(&r->c[i], r->cbuf[i], *crows, r->chunk, &mismatch)) {
            char msg[256];
            fpl_h5_error_text(msg, sizeof msg);
            return fpl_error(NULL, FPL_ERR_IO, "%s is corrupt: reading back %s failed: %s", path,
                             c_names[i], msg);
        }
        if (mismatch)
            return fpl_error(NULL, FPL_ERR_IO, "%s is corrupt: its %s rows differ from those its "
                             "checkpoint %s covers (checksum mismatch)", path, c_names[i], checkpoint);
    }
    return FPL_OK;
}

static int resume_args(const char *path, const char *checkpoint)
{
    if (!path || !*path) return fpl_error(NULL, FPL_ERR_ARG, "path: empty file name");
    if (!checkpoint || !*checkpoint) return fpl_error(NULL, FPL_ERR_ARG, "checkpoint: empty file name");
    return FPL_OK;
}

int fpl_results_verify(const char *path, const fpl_lattice *lat, const fpl_run_info *info,
                       const char *checkpoint)
{
    int st = resume_args(path, checkpoint);
    if (st || (st = check_info(lat, info))) return st;
    fpl_results *r;
    if ((st = new_handle(lat, info, &r))) return st;
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    long rows = 0, crows = 0;
    st = open_for_resume(r, path, H5F_ACC_RDONLY, info, checkpoint, 1, &rows, &crows);
    release(r);
    H5Eclear2(H5E_DEFAULT);
    fpl_h5_quiet_end(&q);
    return st;
}

/* Copy rows [0, rows) of `from` into the (empty) series `to`, through buf (chunk rows). */
static int copy_rows(const series *from, series *to, double *buf, long rows, int chunk,
                     char *errbuf, size_t errlen)
{
    for (long at = 0; at < rows; at += chunk) {
        int n = (int)(rows - at < chunk ? rows - at : chunk);
        if (read_block(from, buf, at, n)) {
            fpl_h5_error_text(errbuf, errlen);
            return -1;
        }
        if (append_rows(to, buf, n, errbuf, errlen)) return -1;
    }
    return 0;
}

int fpl_results_resume(const char *path, const fpl_lattice *lat, const fpl_run_info *info,
                       const char *checkpoint, fpl_results **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    int st = fpl_results_verify(path, lat, info, checkpoint);   /* read-only: all or nothing */
    if (st) return st;
    /* The rows the checkpoint covers go into a fresh file, which then replaces the old one
     * (rename): the old file is only read, so neither a kill during the resume nor damage in
     * the old file's chunk index past those rows can reach the continued run. */
    char target[4096], tmp[4200];
    if (fpl_resolve_target(path, target, sizeof target) != 0)
        return fpl_error(NULL, FPL_ERR_IO, "results file %s: cannot resolve the path", path);
    snprintf(tmp, sizeof tmp, "%s.resume-%ld", target, (long)getpid());
    fpl_remove_stale_temporaries(target, ".resume-");
    fpl_results *old = NULL, *r = NULL;
    if ((st = new_handle(lat, info, &old))) return st;
    if ((st = new_handle(lat, info, &r))) {
        release(old);
        return st;
    }
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    long rows = 0, crows = 0;
    int created = 0;
    if ((st = open_for_resume(old, path, H5F_ACC_RDONLY, info, checkpoint, 0, &rows, &crows)))
        goto done;
    created = 1;
    if ((st = create_in(r, tmp, info))) goto done;
    if (crows > 0 && ensure_chaos(r)) {
        st = h5_fail(r, "creating the chaos datasets");
        goto done;
    }
    for (int i = 0; i < S_COUNT && !st; i++)
        if (old->s[i].d >= 0 && copy_rows(&old->s[i], &r->s[i], r->buf[i], rows, r->chunk,
                                          r->h5msg, sizeof r->h5msg))
            st = h5_fail(r, "copying the rows the checkpoint covers");
    for (int i = 0; i < C_COUNT && !st && crows > 0; i++)
        if (copy_rows(&old->c[i], &r->c[i], r->cbuf[i], crows, r->chunk, r->h5msg,
                      sizeof r->h5msg))
            st = h5_fail(r, "copying the chaos rows the checkpoint covers");
    if (st) goto done;
    for (int i = 0; i < S_COUNT + C_COUNT; i++) {
        const series *a = i < S_COUNT ? &old->s[i] : &old->c[i - S_COUNT];
        const series *b = i < S_COUNT ? &r->s[i] : &r->c[i - S_COUNT];
        if (a->hash != b->hash) {
            st = fpl_error(NULL, FPL_ERR_IO, "results file %s changed while resuming (rows differ "
                           "from its checkpoint %s)", path, checkpoint);
            goto done;
        }
    }
    /* the pending rows of the chunk in progress, from the checkpoint */
    for (int i = 0; i < S_COUNT; i++)
        if (r->buf[i])
            memcpy(r->buf[i], old->buf[i],
                   sizeof(double) * (size_t)old->nbuf * (r->s[i].cols ? r->s[i].cols : 1));
    for (int i = 0; i < C_COUNT; i++) memcpy(r->cbuf[i], old->cbuf[i], sizeof(double) * (size_t)old->ncbuf);
    r->nbuf = old->nbuf;
    r->ncbuf = old->ncbuf;
    if (H5Fflush(r->file, H5F_SCOPE_GLOBAL) < 0) {
        st = h5_fail(r, "flush");
        goto done;
    }
    if (fpl_fsync_path(tmp) != 0 || rename(tmp, target) != 0) {
        st = fpl_error(NULL, FPL_ERR_IO, "cannot move the resumed results %s into place as %s: %s",
                       tmp, target, strerror(errno));
        goto done;
    }
    created = 0;
done:
    release(old);
    if (st) {
        release(r);
        if (created) remove(tmp);
    }
    H5Eclear2(H5E_DEFAULT);
    fpl_h5_quiet_end(&q);
    if (st) return st;
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
/* CF-style attributes on every variable there is (xarray.open_dataset shows them, ncdump lists
 * them): a short `long_name` in words (what xarray puts on a plot axis), the formula in
 * `description`, and `units` only for a dimensional quantity -- fputlab's quantities are in the
 * lattice's dimensionless units, and CF lets a dimensionless one omit them (xarray would label
 * its axis "time [1]"). The same text as python/fputlab/_display.py's VARIABLES, so a file read
 * by xarray and a result's to_xarray() agree (tests/python/test_io.py compares them). */
static const char *const var_text[][4] = {
    /* variable, long_name, units ("1": none), description */
    {"t", "time", "1", "time in units of the inverse linear coupling"},
    {"energy", "energy", "1", "total energy H (Eq. Hamilt; not conserved for model 3)"},
    {"mode_energies", "mode energy", "1",
     "normal-mode energy E_k = (P_k^2 + omega_k^2 Q_k^2) / 2"},
    {"states", "state", "1", "y = [x_1..x_N, p_1..p_N] (orbit, then deviation vectors)"},
    {"v", "variability", "1", "variability v_j = 1 + (tau/300) z_j"},
    {"mode", "mode", "1", "normal-mode number k"},
    {"site", "particle", "1", "particle index j"},
    {"component", "component", "1", "state component (x_1..x_N, p_1..p_N)"},
    {"chaos/t", "time", "1", "times of the chaos-indicator samples"},
    {"chaos/mle", "Lyapunov exponent", "1/time", "finite-time maximum Lyapunov exponent lambda(t)"},
    {"chaos/sali", "SALI", "1", "smaller alignment index SALI(t)"},
    {"chaos/gali", "GALI", "1", "generalised alignment index GALI_k(t)"},
};

static int describe_variables(hid_t file)
{
    int bad = 0;
    for (size_t i = 0; i < sizeof var_text / sizeof *var_text && !bad; i++) {
        const char *name = var_text[i][0], *units = var_text[i][2];
        if (strchr(name, '/') && H5Lexists(file, "chaos", H5P_DEFAULT) <= 0) continue;
        if (H5Lexists(file, name, H5P_DEFAULT) <= 0) continue;
        hid_t d = H5Dopen2(file, name, H5P_DEFAULT);
        bad = d < 0 || fpl_h5_set_string(d, "long_name", var_text[i][1]) ||
              fpl_h5_set_string(d, "description", var_text[i][3]) ||
              (strcmp(units, "1") != 0 && fpl_h5_set_string(d, "units", units));
        if (d >= 0) H5Dclose(d);
    }
    return bad ? -1 : 0;
}

/* A dimension scale first, first + 1, ..., first + n - 1. */
static hid_t index_scale(hid_t loc, const char *name, long n, int first)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = H5Screate_simple(1, dims, NULL), d = -1;
    int *idx = malloc(sizeof(int) * (size_t)n);
    if (idx && space >= 0) {
        for (long i = 0; i < n; i++) idx[i] = (int)(i + first);
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
        /* modes k = 1..N of the fixed chain, wavenumbers 0..N-1 of a ring (fputlab/modes.h) */
        hid_t mode = r->root ? index_scale(r->file, "mode", r->lat->n,
                                           r->lat->boundary == FPL_BOUNDARY_PERIODIC ? 0 : 1) : 0;
        hid_t site = index_scale(r->file, "site", r->lat->n, 1);
        hid_t comp = r->store_states ? index_scale(r->file, "component", r->dim, 1) : 0;
        hid_t v = H5Dopen2(r->file, "v", H5P_DEFAULT);
        bad = mode < 0 || site < 0 || comp < 0 || v < 0 ||
              (r->root && H5DSset_scale(r->s[S_T].d, "t") < 0);
        for (int i = S_T + 1; i < S_COUNT && !bad && r->root; i++)
            if (r->s[i].d >= 0) bad |= H5DSattach_scale(r->s[i].d, r->s[S_T].d, 0) < 0;
        if (!bad && r->root) bad |= H5DSattach_scale(r->s[S_MODE_ENERGIES].d, mode, 1) < 0;
        if (!bad && r->store_states) bad |= H5DSattach_scale(r->s[S_STATES].d, comp, 1) < 0;
        if (!bad) bad |= H5DSattach_scale(v, site, 0) < 0;
        if (mode > 0) H5Dclose(mode);
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
    return created ? (label_dimensions(r, 1) || describe_variables(r->file)) : 0;
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
    if (!r->root)
        return fail(r, fpl_error(NULL, FPL_ERR_ARG, "this results file (kind \"chaos\") holds no "
                                 "orbit samples: write them to a file of kind \"simulate\""));
    if (!isfinite(t)) return fail(r, fpl_error(NULL, FPL_ERR_ARG, "t must be finite (got %g)", t));
    const long n = r->lat->n;
    long bad;
    if (!fpl_is_finite_array(y, r->store_states ? r->dim : 2 * n, &bad))
        return fail(r, fpl_error(NULL, FPL_ERR_NONFINITE,
                                 "state at t = %.17g has a non-finite entry y[%ld]: not written", t, bad));
    int st = fpl_modes_energies_work(r->lat, r->work, y, r->ek);
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
