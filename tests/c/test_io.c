/* HDF5 results and checkpoints: round trip through the HDF5 C API (read back independently of
 * the writer), chunked appends across chunk boundaries, resume truncation, bit-for-bit restart
 * of plain and chaos runs, and refusal of mismatched and corrupt checkpoints. */
#define _POSIX_C_SOURCE 200809L
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "check.h"
#include "fputlab.h"

enum { N = 8 };

static char dir[256];

static const char *tmpfile_in(const char *name)
{
    static char buf[4][512];
    static int k = 0;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

/* rows of a dataset read with the plain HDF5 API */
static long read_rows(const char *path, const char *name, double *out, long cap)
{
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) return -1;
    hid_t d = H5Dopen2(f, name, H5P_DEFAULT), s = H5Dget_space(d);
    hsize_t dims[2] = {0, 1};
    int rank = H5Sget_simple_extent_dims(s, dims, NULL);
    long n = (long)dims[0] * (rank == 2 ? (long)dims[1] : 1);
    if (n <= cap && n > 0) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
    int nfilt = -1;
    hid_t dcpl = H5Dget_create_plist(d);
    nfilt = H5Pget_nfilters(dcpl);
    H5Pclose(dcpl);
    H5Sclose(s);
    H5Dclose(d);
    H5Fclose(f);
    return nfilt >= 3 ? (long)dims[0] : -2; /* shuffle + deflate + Fletcher-32 expected */
}

static unsigned char *slurp(const char *path, long *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    fseek(fp, 0, SEEK_END);
    *len = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)*len);
    if (fread(b, 1, (size_t)*len, fp) != (size_t)*len) { free(b); b = NULL; }
    fclose(fp);
    return b;
}

static void test_results(fpl_lattice *lat)
{
    const char *path = tmpfile_in("results.h5");
    fpl_run_info info;
    fpl_run_info_init(&info);
    info.method = "yoshida4";
    info.dt = 0.01;
    info.chunk_rows = 4;
    info.store_states = 1;
    double y[2 * N], ys[10][2 * N];
    fpl_results *r = NULL;
    CHECK_OK(fpl_results_create(path, lat, &info, &r));
    for (int i = 0; i < 10; i++) {
        for (int j = 0; j < 2 * N; j++) ys[i][j] = y[j] = 0.01 * (i + 1) * sin(j + 1.0);
        CHECK_OK(fpl_results_append(r, (double)i, y));
    }
    CHECK(fpl_results_count(r) == 10, "count %ld", fpl_results_count(r));
    y[3] = NAN;
    CHECK(fpl_results_append(r, 10.0, y) == FPL_ERR_NONFINITE, "NaN state must be refused");
    CHECK(strstr(fpl_results_errmsg(r), "y[3]") != NULL, "message names the entry: %s",
          fpl_results_errmsg(r));
    CHECK_OK(fpl_results_set_status(r, "completed", "ok"));
    CHECK(fpl_results_set_status(r, "bogus", "") == FPL_ERR_ARG, "unknown status refused");
    CHECK_OK(fpl_results_close(&r));
    CHECK(r == NULL, "close clears the handle");

    double t[16], st[16 * 2 * N], ek[16 * N];
    CHECK(read_rows(path, "t", t, 16) == 10, "10 rows of t, compressed");
    CHECK(read_rows(path, "states", st, 16 * 2 * N) == 10, "10 states");
    CHECK(read_rows(path, "mode_energies", ek, 16 * N) == 10, "10 rows of mode energies");
    int same = 1;
    for (int i = 0; i < 10; i++) {
        same &= t[i] == i;
        same &= memcmp(st + i * 2 * N, ys[i], sizeof ys[i]) == 0;
        double e[N], sum = 0, ref = 0;
        fpl_modes_energies(lat, ys[i], e);
        for (int k = 0; k < N; k++) { sum += ek[i * N + k]; ref += e[k]; }
        same &= fabs(sum - ref) <= 1e-15 * fabs(ref);
    }
    CHECK(same, "rows read back equal what was appended");

    /* checkpoint mid-chunk: rows 0..5 appended (one whole chunk of 4 on disk, 2 pending), the
     * run goes on to row 8 (a second chunk written) and is "killed"; resuming cuts the file
     * back to the first chunk, refills the 2 pending rows from the checkpoint, and continues */
    const char *ck = tmpfile_in("results.ckpt");
    fpl_integrator *h;
    fpl_integrator_options iopt;
    fpl_integrator_options_init(&iopt);
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 0, &iopt, 0.0, ys[0], &h));
    CHECK_OK(fpl_results_create(path, lat, &info, &r));
    for (int i = 0; i < 6; i++) CHECK_OK(fpl_results_append(r, (double)i, ys[i]));
    CHECK_OK(fpl_checkpoint_write(ck, h, &info, NULL, 0, r));
    for (int i = 6; i < 9; i++) CHECK_OK(fpl_results_append(r, (double)i, ys[i]));
    CHECK(read_rows(path, "t", t, 16) == 8, "two whole chunks on disk before closing");
    CHECK_OK(fpl_results_close(&r));              /* the partial chunk only at the end */
    CHECK(read_rows(path, "t", t, 16) == 9, "9 rows after closing");
    CHECK_OK(fpl_results_resume(path, lat, &info, ck, &r));
    CHECK(fpl_results_count(r) == 6, "resume keeps 4 rows on disk + 2 pending, got %ld",
          fpl_results_count(r));
    CHECK_OK(fpl_results_append(r, 6.0, ys[6]));
    CHECK_OK(fpl_results_close(&r));
    CHECK(read_rows(path, "t", t, 16) == 7 && t[3] == 3.0 && t[4] == 4.0 && t[5] == 5.0 && t[6] == 6.0,
          "7 rows after resume, the pending ones restored");
    CHECK(read_rows(path, "states", st, 16 * 2 * N) == 7 &&
              memcmp(st + 5 * 2 * N, ys[5], sizeof ys[5]) == 0, "pending states restored");
    fpl_integrator_free(&h);

    /* a results file of another lattice cannot be resumed */
    fpl_lattice *other;
    fpl_lattice_create(N + 1, 0.25, 0.0, FPL_MODEL_HOMOGENEOUS, NULL, &other);
    CHECK(fpl_results_resume(path, other, &info, ck, &r) == FPL_ERR_ARG && r == NULL,
          "resume with another N refused: %s", fpl_last_error());
    fpl_lattice_free(&other);
    CHECK(fpl_results_create(tmpfile_in("no/such/dir.h5"), lat, &info, &r) == FPL_ERR_IO,
          "unwritable path is an I/O error");
    CHECK(strstr(fpl_last_error(), "no/such/dir.h5") != NULL, "message names the file: %s",
          fpl_last_error());
}

static void run_to(fpl_lattice *lat, double t1, const double *y0, double *y_out,
                   const char *ckpt, double t_ckpt)
{
    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.dt = 0.01;
    fpl_integrator *h;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
    if (ckpt) {
        double extra[2] = {1.5, -2.0};
        CHECK_OK(fpl_integrator_advance(h, t_ckpt, NULL));
        CHECK_OK(fpl_checkpoint_write(ckpt, h, NULL, extra, 2, NULL));
    }
    CHECK_OK(fpl_integrator_advance(h, t1, y_out));
    fpl_integrator_free(&h);
}

static void test_checkpoint(fpl_lattice *lat, const double *y0)
{
    const char *ck = tmpfile_in("ck.h5");
    double ref[4 * N], y[4 * N];
    run_to(lat, 50.0, y0, ref, ck, 23.456);
    double tc;
    long nc;
    CHECK_OK(fpl_checkpoint_peek(ck, &tc, &nc));
    CHECK(nc == 2345 && tc == 23.45, "checkpoint at the last grid point: n = %ld, t = %.17g", nc, tc);
    CHECK(access(tmpfile_in("ck.h5.tmp"), F_OK) != 0, "no temporary file left behind");

    fpl_integrator_options opt;
    fpl_integrator_options_init(&opt);
    opt.dt = 0.01;
    fpl_integrator *h;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
    double extra[8];
    int n_extra = 0;
    CHECK_OK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra));
    CHECK(n_extra == 2 && extra[0] == 1.5 && extra[1] == -2.0, "accumulators restored");
    CHECK_OK(fpl_integrator_advance(h, 50.0, y));
    CHECK(memcmp(y, ref, sizeof ref) == 0, "restart is bit-for-bit identical");
    fpl_integrator_free(&h);

    long len0;
    unsigned char *before = slurp(ck, &len0);
    /* mismatches: other v, other method, other dt, other number of deviation vectors */
    double v[N];
    for (int j = 0; j < N; j++) v[j] = 1.0 + 0.01 * j;
    fpl_lattice *lat2;
    CHECK_OK(fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat2));
    CHECK_OK(fpl_integrator_create(lat2, "yoshida4", 1, &opt, 0.0, y0, &h));
    CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "v differs"), "other v refused: %s", fpl_last_error());
    fpl_integrator_free(&h);
    fpl_lattice_free(&lat2);
    CHECK_OK(fpl_integrator_create(lat, "leapfrog", 1, &opt, 0.0, y0, &h));
    CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "method"), "other method refused: %s", fpl_last_error());
    fpl_integrator_free(&h);
    opt.dt = 0.02;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
    CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "dt"), "other dt refused: %s", fpl_last_error());
    fpl_integrator_free(&h);
    opt.dt = 0.01;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 0, &opt, 0.0, y0, &h));
    CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_ARG &&
              strstr(fpl_last_error(), "deviation"), "other n_dev refused: %s", fpl_last_error());
    CHECK(fpl_checkpoint_load(tmpfile_in("missing.h5"), h, NULL, NULL, 0, NULL) == FPL_ERR_IO,
          "missing file is an I/O error");
    fpl_integrator_free(&h);
    long len1;
    unsigned char *after = slurp(ck, &len1);
    CHECK(before && after && len0 == len1 && memcmp(before, after, (size_t)len0) == 0,
          "refused loads leave the checkpoint untouched");

    /* corrupt: flip one byte of the stored state (found by its bit pattern) */
    double probe;
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
    CHECK_OK(fpl_integrator_restore(h, nc, tc, y0)); /* any state */
    fpl_integrator_free(&h);
    {
        fpl_integrator *g;
        CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &g));
        CHECK_OK(fpl_checkpoint_load(ck, g, NULL, extra, 8, &n_extra));
        double s[4 * N];
        fpl_integrator_get_state(g, s);
        probe = s[5];
        fpl_integrator_free(&g);
    }
    long at = -1;
    for (long i = 0; i + 8 <= len0 && at < 0; i++)
        if (memcmp(before + i, &probe, 8) == 0) at = i;
    CHECK(at >= 0, "state bytes found in the file");
    if (at >= 0) {
        before[at] ^= 0x01;
        FILE *fp = fopen(ck, "wb");
        fwrite(before, 1, (size_t)len0, fp);
        fclose(fp);
        CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
        CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_IO &&
                  strstr(fpl_last_error(), "checksum"), "corrupt state refused: %s", fpl_last_error());
        fpl_integrator_free(&h);
    }
    FILE *fp = fopen(ck, "wb");
    fwrite("not hdf5", 1, 8, fp);
    fclose(fp);
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 1, &opt, 0.0, y0, &h));
    CHECK(fpl_checkpoint_load(ck, h, NULL, extra, 8, &n_extra) == FPL_ERR_IO,
          "garbage file refused: %s", fpl_last_error());
    fpl_integrator_free(&h);
    free(before);
    free(after);
}

static void test_chaos_restart(fpl_lattice *lat, const double *y0)
{
    fpl_chaos_options co;
    fpl_chaos_options_init(&co);
    co.t_end = 300.0;
    co.n_samples = 20;
    co.n_dev = 2;
    fpl_integrator_options io;
    fpl_integrator_options_init(&io);
    double t_ref[20], m_ref[20], s_ref[20], t2[20], m2[20], s2[20];
    fpl_chaos_result ref, res;
    CHECK_OK(fpl_chaos_run(lat, "yoshida4", &io, 0.0, y0, NULL, &co, t_ref, m_ref, s_ref, NULL, &ref));

    const char *ck = tmpfile_in("chaos.h5");
    fpl_run_info info;
    fpl_run_info_init(&info);
    info.kind = "chaos";
    fpl_chaos *c;
    double acc[FPL_CHAOS_N_ACCUMULATORS];
    CHECK_OK(fpl_chaos_create(lat, "yoshida4", &io, 0.0, y0, NULL, &co, &c));
    CHECK_OK(fpl_chaos_advance(c, 123.4, t2, m2, s2, NULL));
    CHECK_OK(fpl_chaos_save(c, acc));
    CHECK_OK(fpl_checkpoint_write(ck, fpl_chaos_integrator(c), &info, acc, FPL_CHAOS_N_ACCUMULATORS,
                                  NULL));
    fpl_chaos_free(&c);

    CHECK_OK(fpl_chaos_create(lat, "yoshida4", &io, 0.0, y0, NULL, &co, &c));
    int n_extra;
    fpl_run_info other = info;
    other.kind = "simulate";
    CHECK(fpl_checkpoint_load(ck, fpl_chaos_integrator(c), &other, acc, FPL_CHAOS_N_ACCUMULATORS,
                              &n_extra) == FPL_ERR_ARG, "checkpoint of another kind refused");
    CHECK_OK(fpl_checkpoint_load(ck, fpl_chaos_integrator(c), &info, acc, FPL_CHAOS_N_ACCUMULATORS,
                                 &n_extra));
    CHECK_OK(fpl_chaos_restore(c, acc));
    while (!fpl_chaos_done(c)) CHECK_OK(fpl_chaos_advance(c, 1e300, t2, m2, s2, NULL));
    CHECK_OK(fpl_chaos_get_result(c, &res));
    fpl_chaos_free(&c);
    CHECK(res.n_samples == ref.n_samples && memcmp(&res.mle, &ref.mle, sizeof ref.mle) == 0 &&
              memcmp(t2, t_ref, sizeof(double) * ref.n_samples) == 0 &&
              memcmp(m2, m_ref, sizeof(double) * ref.n_samples) == 0 &&
              memcmp(s2, s_ref, sizeof(double) * ref.n_samples) == 0,
          "chaos restart bit-for-bit: mle %.17g vs %.17g, %d vs %d samples", res.mle, ref.mle,
          res.n_samples, ref.n_samples);
}

/* Damaged files: a truncated or bit-flipped checkpoint and changed results rows are refused by
 * checksums (before HDF5 parses the checkpoint); a symlinked checkpoint stays a link. */
static void test_integrity(fpl_lattice *lat, const double *y0)
{
    const char *path = tmpfile_in("integrity.h5"), *ck = tmpfile_in("integrity.ckpt");
    fpl_run_info info;
    fpl_run_info_init(&info);
    info.method = "yoshida4";
    info.dt = 0.01;
    info.chunk_rows = 4;
    fpl_integrator *h;
    fpl_integrator_options iopt;
    fpl_integrator_options_init(&iopt);
    CHECK_OK(fpl_integrator_create(lat, "yoshida4", 0, &iopt, 0.0, y0, &h));
    fpl_results *r;
    CHECK_OK(fpl_results_create(path, lat, &info, &r));
    for (int i = 0; i < 10; i++) CHECK_OK(fpl_results_append(r, (double)i, y0));
    CHECK_OK(fpl_checkpoint_write(ck, h, &info, NULL, 0, r));
    CHECK_OK(fpl_results_close(&r));
    CHECK_OK(fpl_results_verify(path, lat, &info, ck));
    long len;
    unsigned char *good = slurp(ck, &len);
    for (int trial = 0; trial < 3; trial++) {
        FILE *fp = fopen(ck, "wb");
        if (trial == 0) fwrite(good, 1, (size_t)len / 2, fp);           /* truncated */
        else {
            good[trial == 1 ? 600 : 100] ^= 0x10;                     /* a flip: data, header */
            fwrite(good, 1, (size_t)len, fp);
            good[trial == 1 ? 600 : 100] ^= 0x10;
        }
        fclose(fp);
        double t;
        CHECK(fpl_checkpoint_peek(ck, &t, NULL) == FPL_ERR_IO && strstr(fpl_last_error(), "corrupt"),
              "damaged checkpoint %d refused before parsing: %s", trial, fpl_last_error());
        CHECK(fpl_results_verify(path, lat, &info, ck) == FPL_ERR_IO,
              "verify refuses damaged checkpoint %d", trial);
    }
    FILE *fp = fopen(ck, "wb");
    fwrite(good, 1, (size_t)len, fp);
    fclose(fp);
    free(good);
    /* a row the checkpoint covers, changed through HDF5 itself (valid Fletcher-32): the
     * checkpoint's row hashes catch it */
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t d = H5Dopen2(f, "energy", H5P_DEFAULT), fs = H5Dget_space(d);
    hsize_t start[1] = {1}, count[1] = {1};
    H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
    hid_t ms = H5Screate_simple(1, count, NULL);
    double forged = 42.0;
    H5Dwrite(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, &forged);
    H5Sclose(ms);
    H5Sclose(fs);
    H5Dclose(d);
    H5Fclose(f);
    CHECK(fpl_results_verify(path, lat, &info, ck) == FPL_ERR_IO && strstr(fpl_last_error(), "energy"),
          "changed rows refused: %s", fpl_last_error());
    CHECK(fpl_results_resume(path, lat, &info, ck, &r) == FPL_ERR_IO && r == NULL,
          "resume refuses them too");
    /* a checkpoint path that is a symbolic link: the target gets the file, the link stays */
    const char *target = tmpfile_in("target.ckpt"), *link = tmpfile_in("link.ckpt");
    CHECK(symlink(target, link) == 0, "symlink");
    CHECK_OK(fpl_checkpoint_write(link, h, &info, NULL, 0, NULL));
    struct stat sb;
    CHECK(lstat(link, &sb) == 0 && S_ISLNK(sb.st_mode), "the link is still a link");
    CHECK(stat(target, &sb) == 0 && S_ISREG(sb.st_mode), "its target holds the checkpoint");
    fpl_integrator_free(&h);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/fputlab-test-io-XXXXXX");
    if (!mkdtemp(dir)) return 1;
    double v[N];
    CHECK_OK(fpl_disorder_draw(FPL_DISORDER_GAUSSIAN, 10.0, 1, N, v));
    fpl_lattice *lat;
    CHECK_OK(fpl_lattice_create(N, 0.25, 0.0, FPL_MODEL_NONLINEAR, v, &lat));
    double y0[2 * N];
    CHECK_OK(fpl_modes_initial_state(lat, 1, 3.0, y0));
    double y1[4 * N];
    memcpy(y1, y0, sizeof y0);
    for (int j = 0; j < 2 * N; j++) y1[2 * N + j] = cos(j + 0.5);

    test_results(lat);
    test_checkpoint(lat, y1);
    test_chaos_restart(lat, y0);
    test_integrity(lat, y0);
    fpl_lattice_free(&lat);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) return 1;
    return check_report("io");
}
