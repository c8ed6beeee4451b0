/* Checkpoints: the whole state of a run in one small HDF5 file, written atomically
 * (temporary file in the same folder, fsync, rename, fsync of the folder), validated strictly
 * when loaded. The file's first 512 bytes (an HDF5 user block, which HDF5 skips) hold its size
 * and a checksum of every byte after them: a damaged or truncated checkpoint is refused before
 * HDF5 parses a byte of it (libhdf5 can crash or loop on corrupt metadata). A second checksum
 * over the numbers that define the continuation guards the values themselves. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fsutil.h"
#include "h5util.h"
#include "integrator_impl.h"

#define SCHEMA "fputlab-checkpoint/1"

static unsigned long long checksum(long steps, double t, const double *y, long dim,
                                   const double *v, int n, const double *extra, int n_extra)
{
    unsigned long long h = FPL_FNV_OFFSET;
    long long s = steps;
    h = fpl_fnv1a(h, &s, sizeof s);
    h = fpl_fnv1a(h, &t, sizeof t);
    h = fpl_fnv1a(h, y, sizeof(double) * (size_t)dim);
    h = fpl_fnv1a(h, v, sizeof(double) * (size_t)n);
    return fpl_fnv1a(h, extra, sizeof(double) * (size_t)n_extra);
}

/* The run description of the checkpoint comes from the integrator itself (method, options, t0,
 * deviation vectors); info adds what the integrator does not know (kind, disorder). */
static fpl_run_info describe(const fpl_integrator *h, const fpl_run_info *info)
{
    fpl_run_info d;
    if (info) d = *info; else fpl_run_info_init(&d);
    d.method = h->method->name;
    d.dt = h->method->backend->adaptive ? NAN : h->opt.dt;
    d.rtol = h->method->backend->adaptive ? h->opt.rtol : NAN;
    d.atol = h->method->backend->adaptive ? h->opt.atol : NAN;
    d.t0 = h->t0;
    d.n_dev = h->n_dev;
    return d;
}

/* ---- the byte checksum in the user block ------------------------------------------------- */
#define USERBLOCK 512
#define MAGIC "fputlab-checkpoint-bytes/1\n"
#define MAX_CHECKPOINT_BYTES (1L << 30)

static unsigned long long bytes_hash(const unsigned char *b, size_t n)
{
    return fpl_fnv1a(FPL_FNV_OFFSET, b, n);
}

/* Read a whole file (at most MAX_CHECKPOINT_BYTES) into a new buffer. */
static unsigned char *slurp(const char *path, long *len, int *too_big)
{
    *too_big = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    struct stat sb;
    unsigned char *b = NULL;
    if (fstat(fileno(fp), &sb) == 0 && S_ISREG(sb.st_mode)) {
        if (sb.st_size > MAX_CHECKPOINT_BYTES) *too_big = 1;
        else if ((b = malloc((size_t)sb.st_size + 1)) &&
                 fread(b, 1, (size_t)sb.st_size, fp) != (size_t)sb.st_size) {
            free(b);
            b = NULL;
        }
        *len = (long)sb.st_size;
    }
    fclose(fp);
    return b;
}

static void format_header(char *hdr, long len, unsigned long long sum)
{
    memset(hdr, 0, USERBLOCK);
    snprintf(hdr, USERBLOCK, MAGIC "size %ld\nfnv1a64 %016llx\n", len, sum);
}

/* The whole user block is exactly the header of these values (text, then zeros). */
static int header_is(const char *hdr, long len, unsigned long long sum)
{
    char want[USERBLOCK];
    format_header(want, len, sum);
    return memcmp(hdr, want, USERBLOCK) == 0;
}

/* Stamp the user block of a freshly written checkpoint with its size and checksum. */
static int stamp(const char *tmp)
{
    long len = 0;
    int too_big;
    unsigned char *b = slurp(tmp, &len, &too_big);
    if (!b || len < USERBLOCK) {
        free(b);
        return -1;
    }
    char hdr[USERBLOCK];
    format_header(hdr, len, bytes_hash(b + USERBLOCK, (size_t)(len - USERBLOCK)));
    free(b);
    int fd = open(tmp, O_WRONLY);
    if (fd < 0) return -1;
    int ok = pwrite(fd, hdr, sizeof hdr, 0) == (ssize_t)sizeof hdr;
    return close(fd) == 0 && ok ? 0 : -1;
}

int fpl_checkpoint_verify_bytes(const char *path)
{
    long len = 0;
    int too_big;
    unsigned char *b = slurp(path, &len, &too_big);
    if (!b) {
        if (too_big)
            return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt: %ld bytes, more than any "
                             "checkpoint", path, len);
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s cannot be read (not a regular file?)", path);
    }
    int st = FPL_OK;
    long size = -1;
    unsigned long long sum = 0;
    char hdr[USERBLOCK + 1];
    memcpy(hdr, b, len < USERBLOCK ? (size_t)len : USERBLOCK);
    hdr[len < USERBLOCK ? len : USERBLOCK] = '\0';
    if (len < USERBLOCK || strncmp(hdr, MAGIC, strlen(MAGIC)) != 0 ||
        sscanf(hdr + strlen(MAGIC), "size %ld\nfnv1a64 %llx", &size, &sum) != 2)
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt or not an fputlab checkpoint "
                       "(no valid header: checksum missing)", path);
    else if (!header_is(hdr, size, sum))
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt (its header is damaged)", path);
    else if (size != len)
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt: %ld bytes, its header says %ld "
                       "(truncated or extended; checksum not verifiable)", path, len, size);
    else if (bytes_hash(b + USERBLOCK, (size_t)(len - USERBLOCK)) != sum)
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt (checksum mismatch over its "
                       "bytes)", path);
    free(b);
    return st;
}

int fpl_checkpoint_write(const char *path_in, const fpl_integrator *h, const fpl_run_info *info,
                         const double *extra, int n_extra, const fpl_results *results)
{
    const char *path = path_in;
    if (!path || !*path) return fpl_error(NULL, FPL_ERR_ARG, "path: empty file name");
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    char target[4096];
    if (fpl_resolve_target(path_in, target, sizeof target) != 0)
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: cannot resolve the path (symbolic link "
                         "loop or name too long)", path_in);
    path = target;
    if (n_extra < 0 || n_extra > FPL_CHECKPOINT_MAX_EXTRA || (n_extra > 0 && !extra))
        return fpl_error(NULL, FPL_ERR_ARG, "n_extra must be 0..%d with extra non-NULL (got %d)",
                         FPL_CHECKPOINT_MAX_EXTRA, n_extra);
    const fpl_lattice *lat = h->lat;
    fpl_run_info d = describe(h, info);
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid()) >= (int)sizeof tmp)
        return fpl_error(NULL, FPL_ERR_ARG, "path: file name too long");

    fpl_remove_stale_temporaries(path, ".tmp-");
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    char msg[256] = "";
    int st = FPL_OK;
    double *carry = NULL;
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    hid_t f = fcpl >= 0 && H5Pset_userblock(fcpl, USERBLOCK) >= 0
                  ? H5Fcreate(tmp, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT) : -1;
    if (f < 0) fpl_h5_error_text(msg, sizeof msg);   /* before H5Pclose clears the stack */
    if (fcpl >= 0) H5Pclose(fcpl);
    if (f < 0) {
        st = fpl_error(NULL, FPL_ERR_IO, "cannot create checkpoint %s: %s", tmp, msg);
        goto out;
    }
    unsigned long long sum = checksum(h->n_steps, h->t, h->y, h->dim, lat->v, lat->n, extra, n_extra);
    /* compensated sums: the carry belongs to the state (a restart without it is not bit for bit) */
    const int comp = h->opt.compensated_sums;
    if (comp && !(carry = malloc(sizeof(double) * (size_t)h->dim))) {
        st = fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (checkpoint compensation)");
        H5Fclose(f);
        goto out;
    }
    if (comp && (st = fpl_integrator_get_compensation(h, carry))) {
        H5Fclose(f);
        goto out;
    }
    if (comp) sum = fpl_fnv1a(sum, carry, sizeof(double) * (size_t)h->dim);
    int bad = fpl_h5_write_description(f, SCHEMA, lat, &d) ||
              fpl_h5_set_long(f, "compensated_sums", comp) ||
              (comp && fpl_h5_write_vector(f, "compensation", carry, (size_t)h->dim)) ||
              fpl_h5_set_long(f, "n_steps", h->n_steps) || fpl_h5_set_double(f, "t", h->t) ||
              fpl_h5_set_u64(f, "checksum", sum) ||
              fpl_h5_write_vector(f, "state", h->y, (size_t)h->dim) ||
              fpl_h5_write_vector(f, "extra", extra, (size_t)n_extra) ||
              (results && fpl_results_save_pending(results, f));
    if (bad) fpl_h5_error_text(msg, sizeof msg);
    if (H5Fclose(f) < 0 && !bad) {
        bad = 1;
        fpl_h5_error_text(msg, sizeof msg);
    }
    if (bad) {
        st = fpl_error(NULL, FPL_ERR_IO, "writing checkpoint %s failed: %s", tmp, msg);
        goto out;
    }
    char dir[4096];
    fpl_folder_of(path, dir, sizeof dir);
    errno = 0;
    if (stamp(tmp) != 0) {
        st = fpl_error(NULL, FPL_ERR_IO, "writing checkpoint %s failed: cannot stamp its checksum%s%s",
                       tmp, errno ? ": " : "", errno ? strerror(errno) : "");
        goto out;
    }
    if (fpl_fsync_path(tmp) != 0 || rename(tmp, path) != 0) {
        st = fpl_error(NULL, FPL_ERR_IO, "cannot move checkpoint %s into place as %s: %s", tmp, path,
                       strerror(errno));
        goto out;
    }
    fpl_fsync_path(dir); /* best effort: some file systems refuse fsync on folders */
out:
    if (st) remove(tmp);
    free(carry);
    fpl_h5_quiet_end(&q);
    return st;
}

static int open_checkpoint(const char *path, hid_t *f)
{
    if (!path || !*path) return fpl_error(NULL, FPL_ERR_ARG, "path: empty file name");
    if (access(path, R_OK) != 0)
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s does not exist or is not readable", path);
    int st = fpl_checkpoint_verify_bytes(path);
    if (st) return st;
    *f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (*f < 0) {
        char msg[256];
        fpl_h5_error_text(msg, sizeof msg);
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is not a readable HDF5 file (corrupt?): %s",
                         path, msg);
    }
    return FPL_OK;
}

int fpl_checkpoint_peek(const char *path, double *t, long *n_steps)
{
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    hid_t f = -1;
    int st = open_checkpoint(path, &f);
    if (!st) {
        double tt;
        long n;
        if (fpl_h5_get_double(f, "t", &tt) || fpl_h5_get_long(f, "n_steps", &n))
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: t or n_steps missing", path);
        else {
            if (t) *t = tt;
            if (n_steps) *n_steps = n;
        }
        H5Fclose(f);
    }
    H5Eclear2(H5E_DEFAULT);
    fpl_h5_quiet_end(&q);
    return st;
}

static int same_double(double a, double b) { return memcmp(&a, &b, sizeof a) == 0 || (isnan(a) && isnan(b)); }

/* Everything but the lattice (checked by fpl_h5_check_description). */
static int check_run(hid_t f, const char *path, const fpl_integrator *h, const fpl_run_info *want)
{
    char buf[128];
    long n_dev = -1;
    double dt = NAN, rtol = NAN, atol = NAN, t0 = NAN;
    if (fpl_h5_get_string(f, "fputlab_version", buf, sizeof buf))
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: fputlab_version missing", path);
    if (strcmp(buf, fpl_version()) != 0)
        return fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s was written by fputlab %s; this is %s "
                         "(a restart must use the same version to continue bit for bit)", path,
                         buf, fpl_version());
    if (want->kind && (fpl_h5_get_string(f, "kind", buf, sizeof buf) || strcmp(buf, want->kind)))
        return fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s is of a '%s' run, not '%s'", path, buf,
                         want->kind);
    if (fpl_h5_get_long(f, "n_dev", &n_dev) || fpl_h5_get_double(f, "dt", &dt) ||
        fpl_h5_get_double(f, "rtol", &rtol) || fpl_h5_get_double(f, "atol", &atol) ||
        fpl_h5_get_double(f, "t0", &t0))
        return fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: run attributes missing", path);
    if (n_dev != want->n_dev)
        return fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s carries %ld deviation vectors, this run %d",
                         path, n_dev, want->n_dev);
    if (!same_double(dt, want->dt) || !same_double(rtol, want->rtol) || !same_double(atol, want->atol))
        return fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s used dt = %g, rtol = %g, atol = %g; this "
                         "run dt = %g, rtol = %g, atol = %g", path, dt, rtol, atol, want->dt,
                         want->rtol, want->atol);
    if (!same_double(t0, h->t0))
        return fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s started at t0 = %.17g, this run at %.17g",
                         path, t0, h->t0);
    return FPL_OK;
}

int fpl_checkpoint_load(const char *path, fpl_integrator *h, const fpl_run_info *info,
                        double *extra, int max_extra, int *n_extra)
{
    if (n_extra) *n_extra = 0;
    if (!h) return fpl_error(NULL, FPL_ERR_ARG, "integrator: NULL handle");
    if (max_extra < 0 || (max_extra > 0 && !extra))
        return fpl_error(NULL, FPL_ERR_ARG, "max_extra must be >= 0 with extra non-NULL (got %d)",
                         max_extra);
    fpl_run_info want = describe(h, info);
    if (!info) want.kind = NULL;
    fpl_h5_quiet q;
    fpl_h5_quiet_begin(&q);
    hid_t f = -1;
    double *y = NULL, *carry = NULL, ex[FPL_CHECKPOINT_MAX_EXTRA];
    int st = open_checkpoint(path, &f);
    if (st) goto out;
    if ((st = fpl_h5_check_description(f, path, SCHEMA, h->lat, h->method->name))) goto out;
    if ((st = check_run(f, path, h, &want))) goto out;
    long steps;
    double t;
    unsigned long long sum;
    size_t len = (size_t)h->dim, nex = FPL_CHECKPOINT_MAX_EXTRA;
    if (!(y = malloc(sizeof(double) * len))) {
        st = fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (checkpoint state)");
        goto out;
    }
    if (fpl_h5_get_long(f, "n_steps", &steps) || fpl_h5_get_double(f, "t", &t) ||
        fpl_h5_get_u64(f, "checksum", &sum) || fpl_h5_read_vector(f, "state", y, &len) ||
        len != (size_t)h->dim || fpl_h5_read_vector(f, "extra", ex, &nex)) {
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: state, extra, t, n_steps or checksum "
                       "missing or of the wrong size", path);
        goto out;
    }
    /* compensated sums (attribute absent in checkpoints of runs without them) */
    long comp = 0;
    if (H5Aexists(f, "compensated_sums") > 0 && fpl_h5_get_long(f, "compensated_sums", &comp)) {
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: compensated_sums unreadable", path);
        goto out;
    }
    if ((comp != 0) != (h->opt.compensated_sums != 0)) {
        st = fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s was written with compensated_sums = %ld, "
                       "this run has compensated_sums = %d", path, comp, h->opt.compensated_sums);
        goto out;
    }
    if (comp) {
        size_t clen = (size_t)h->dim;
        if (!(carry = malloc(sizeof(double) * clen))) {
            st = fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (checkpoint compensation)");
            goto out;
        }
        if (fpl_h5_read_vector(f, "compensation", carry, &clen) || clen != (size_t)h->dim) {
            st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s: compensation missing or of the wrong "
                           "size", path);
            goto out;
        }
    }
    unsigned long long expect = checksum(steps, t, y, h->dim, h->lat->v, h->lat->n, ex, (int)nex);
    if (comp) expect = fpl_fnv1a(expect, carry, sizeof(double) * (size_t)h->dim);
    if (expect != sum) {
        st = fpl_error(NULL, FPL_ERR_IO, "checkpoint %s is corrupt (checksum mismatch)", path);
        goto out;
    }
    if ((int)nex > max_extra) {
        st = fpl_error(NULL, FPL_ERR_ARG, "checkpoint %s holds %zu accumulators, room for %d", path,
                       nex, max_extra);
        goto out;
    }
    if ((st = fpl_integrator_restore(h, steps, t, y))) goto out;
    if (comp && (st = fpl_integrator_set_compensation(h, carry))) goto out;
    if (nex) memcpy(extra, ex, sizeof(double) * nex);
    if (n_extra) *n_extra = (int)nex;
out:
    free(y);
    free(carry);
    if (f >= 0) H5Fclose(f);
    H5Eclear2(H5E_DEFAULT);
    fpl_h5_quiet_end(&q);
    return st;
}
