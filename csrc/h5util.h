/* Private HDF5 helpers shared by results.c and checkpoint.c: silence HDF5's own error printing
 * for the duration of a call (the library never prints), turn HDF5's error stack into our
 * message, and read/write scalar and string attributes and whole 1-D arrays. */
#ifndef FPUTLAB_H5UTIL_H
#define FPUTLAB_H5UTIL_H

#include <hdf5.h>
#include <stddef.h>

/* Saved HDF5 auto-print handler: restored at the end so callers' own HDF5 use is untouched. */
typedef struct fpl_h5_quiet {
    H5E_auto2_t func;
    void *data;
} fpl_h5_quiet;
void fpl_h5_quiet_begin(fpl_h5_quiet *q);
void fpl_h5_quiet_end(const fpl_h5_quiet *q);

/* Innermost message on HDF5's error stack ("" if none), cleared afterwards. */
const char *fpl_h5_error_text(char *buf, size_t len);

/* Attributes (an existing one of the same name is replaced). 0 on success, -1 on failure. */
int fpl_h5_set_double(hid_t obj, const char *name, double value);
int fpl_h5_set_long(hid_t obj, const char *name, long value);
int fpl_h5_set_u64(hid_t obj, const char *name, unsigned long long value);
int fpl_h5_set_string(hid_t obj, const char *name, const char *value);
/* Read attributes; -1 if missing or of another kind. */
int fpl_h5_get_double(hid_t obj, const char *name, double *value);
int fpl_h5_get_long(hid_t obj, const char *name, long *value);
int fpl_h5_get_u64(hid_t obj, const char *name, unsigned long long *value);
int fpl_h5_get_string(hid_t obj, const char *name, char *buf, size_t len);

/* Whole 1-D double datasets: write (contiguous) and read with a length check
 * (*len in: capacity, out: length; -1 if missing, not 1-D or longer than the capacity). */
int fpl_h5_write_vector(hid_t loc, const char *name, const double *a, size_t n);
int fpl_h5_read_vector(hid_t loc, const char *name, double *a, size_t *len);

/* The run description every fputlab file carries: fputlab_version, schema, kind, N, model,
 * model_name, alpha, beta, method, dt, rtol, atol, t0, n_dev, tau, seed, disorder (attributes)
 * and the dataset v. */
#include "fputlab/io.h"
int fpl_h5_write_description(hid_t file, const char *schema, const fpl_lattice *lattice,
                             const fpl_run_info *info);
/* Check that the file at `path` (open as `file`, of schema `schema`) describes this lattice
 * (N, model, alpha, beta and v, bit for bit) and method (if method is not NULL). Returns 0 or
 * FPL_ERR_ARG / FPL_ERR_IO with a message naming what differs. */
int fpl_h5_check_description(hid_t file, const char *path, const char *schema,
                             const fpl_lattice *lattice, const char *method);

/* FNV-1a, 64 bit, continued from h (start with FPL_FNV_OFFSET). */
#define FPL_FNV_OFFSET 14695981039346656037ULL
unsigned long long fpl_fnv1a(unsigned long long h, const void *data, size_t n);

/* Results <-> checkpoints (results.c). A results file only ever receives whole chunks, appended
 * (a chunk that holds committed rows is never rewritten, so a process killed while writing can
 * only damage rows that no checkpoint covers); the rows of the chunk in progress travel in the
 * checkpoint instead: how many rows the file had, and the pending ones. */
int fpl_results_save_pending(const fpl_results *results, hid_t checkpoint_file);

/* Check a checkpoint's bytes against the size and checksum in its header (checkpoint.c), before
 * HDF5 parses it: FPL_OK or FPL_ERR_IO with the message set. */
int fpl_checkpoint_verify_bytes(const char *path);
/* The file-system helpers (fsync, links, stale temporaries) are in fsutil.h. */

#endif
