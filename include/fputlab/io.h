/* fputlab — results and checkpoints in HDF5 (serial C API; schema in docs/hdf5.md).
 *
 * Results: a file written incrementally while a run goes on. Samples are buffered in memory one
 * chunk at a time (chunk_rows rows), then appended as a new whole chunk to chunked, compressed,
 * extendible datasets and flushed, so a run of any length holds at most one chunk of history, a
 * crash loses at most the samples of the chunk in progress, and data already written is never
 * rewritten (only fpl_results_close writes a partial last chunk).
 *
 *   fpl_run_info info;  fpl_run_info_init(&info);  info.method = "yoshida4";  info.dt = 0.01;
 *   fpl_results *r;
 *   fpl_results_create("run.h5", lat, &info, &r);
 *   ... fpl_results_append(r, t, y);  ...       // t, mode energies, energy (and y if asked)
 *   fpl_results_set_status(r, "completed", "");
 *   fpl_results_close(&r);
 *
 * Checkpoints: the full state of a run (step count, time, orbit and deviation vectors, the
 * lattice with its v, method and options, run-specific accumulators such as the chaos log-norm
 * sums) in one small HDF5 file, written atomically (a temporary file in the same folder, fsync,
 * rename), so that at any moment the checkpoint on disk is complete. Loading one validates it
 * against the run it is meant to continue (library version, N, model, alpha, beta, v bit for bit,
 * method, dt, deviation vectors, checksum) and refuses a corrupt or mismatched file without
 * touching it. For fixed-step methods the continuation is bit-for-bit identical to an
 * uninterrupted run. */
#ifndef FPUTLAB_IO_H
#define FPUTLAB_IO_H

#include "fputlab/common.h"
#include "fputlab/integrator.h"
#include "fputlab/lattice.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a run is, recorded as attributes of results and checkpoints. */
typedef struct fpl_run_info {
    const char *kind;      /* "simulate", "chaos", ... (free text, <= 63 chars) */
    const char *method;    /* integrator name */
    double dt, rtol, atol; /* integrator options as used */
    double t0;             /* start time */
    int n_dev;             /* deviation vectors carried */
    double tau;            /* disorder tolerance in percent (NaN: none / user v) */
    long seed;             /* disorder seed (-1: none) */
    const char *disorder;  /* "gaussian", "truncated", "uniform", "user" or "" */
    int store_states;      /* results: also store the full state at every sample */
    int chunk_rows;        /* results: samples per chunk (0 = 256) */
} fpl_run_info;

/* kind "simulate", method "", dt = rtol = atol = NaN, t0 = 0, n_dev = 0, tau = NaN, seed = -1,
 * disorder "", store_states 0, chunk_rows 0. */
FPL_API void fpl_run_info_init(fpl_run_info *info);

/* ---- results ---------------------------------------------------------------------------- */
typedef struct fpl_results fpl_results;

/* Create (or truncate) a results file for runs of this lattice. */
FPL_API int fpl_results_create(const char *path, const fpl_lattice *lattice, const fpl_run_info *info,
                               fpl_results **out);
/* Continue a results file for a run restarted from `checkpoint` (written with this results
 * handle, see fpl_checkpoint_write): the file must describe the same lattice (N, model, alpha,
 * beta, v) and method and hold, unchanged, the rows the checkpoint covers (read back and
 * compared with the checkpoint's checksums). Those rows are copied into a fresh file that then
 * replaces the old one (rename; the old file is only read), and the rows of the chunk then in
 * progress come back from the checkpoint. */
FPL_API int fpl_results_resume(const char *path, const fpl_lattice *lattice, const fpl_run_info *info,
                               const char *checkpoint, fpl_results **out);
/* The read-only part of fpl_results_resume: check that `path` and `checkpoint` belong together
 * and read back every row the resume keeps (each chunk's checksum verified). Changes nothing;
 * meant to be run where a fault inside libhdf5 on a damaged file cannot take down a long-running
 * process (fputlab's Python layer runs it in a child process first). */
FPL_API int fpl_results_verify(const char *path, const fpl_lattice *lattice, const fpl_run_info *info,
                               const char *checkpoint);
FPL_API const char *fpl_results_errmsg(const fpl_results *results);

/* Append a sample at time t of state y (length 2N(1 + n_dev)): t, the orbit's mode energies and
 * energy, and y itself when store_states. Refuses non-finite states (nothing NaN reaches a file). */
FPL_API int fpl_results_append(fpl_results *results, double t, const double *y);
/* Append a chaos sample (group /chaos); sali and gali may be NaN (one deviation vector). */
FPL_API int fpl_results_append_chaos(fpl_results *results, double t, double mle, double sali,
                                     double gali);
/* Record how the run ended: status "running", "completed", "event", "failed", "interrupted";
 * message free text. For "event", also the time and the criterion (fpl_results_set_event). */
FPL_API int fpl_results_set_status(fpl_results *results, const char *status, const char *message);
FPL_API int fpl_results_set_event(fpl_results *results, double t, const char *criterion);
/* Samples written so far (including the buffered ones). */
FPL_API long fpl_results_count(const fpl_results *results);
/* Write the buffered samples and flush the file to disk. */
FPL_API int fpl_results_flush(fpl_results *results);
/* Flush and close; *results becomes NULL. Returns the status of the final flush. */
FPL_API int fpl_results_close(fpl_results **results);

/* ---- checkpoints ------------------------------------------------------------------------ */
/* run-specific accumulators a checkpoint can hold (a Lyapunov spectrum of k exponents needs
 * k + 5) */
enum { FPL_CHECKPOINT_MAX_EXTRA = 8192 };

/* Write the integrator's state, the run description, n_extra run-specific numbers
 * (accumulators) and, if results is not NULL, where that results file stands (its rows on disk
 * and the pending ones) atomically to path. A results file only ever receives whole chunks,
 * so a process killed at any moment leaves the rows covered by its last checkpoint intact. */
FPL_API int fpl_checkpoint_write(const char *path, const fpl_integrator *integrator,
                                 const fpl_run_info *info, const double *extra, int n_extra,
                                 const fpl_results *results);

/* Validate the checkpoint at path against the integrator (created for the same lattice, method,
 * options, t0 and number of deviation vectors) and info->kind, then restore the integrator to it
 * and copy its accumulators into extra (at most max_extra; *n_extra gets how many it holds).
 * Errors: FPL_ERR_IO (unreadable, corrupt: checksum), FPL_ERR_ARG (mismatch, with what differs).
 * The file is only read. */
FPL_API int fpl_checkpoint_load(const char *path, fpl_integrator *integrator,
                                const fpl_run_info *info, double *extra, int max_extra,
                                int *n_extra);

/* Time and step count stored in a checkpoint (no validation beyond readability). */
FPL_API int fpl_checkpoint_peek(const char *path, double *t, long *n_steps);

#ifdef __cplusplus
}
#endif
#endif
