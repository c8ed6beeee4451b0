/* HDF5 helpers: quiet error handling and attribute/array plumbing (see h5util.h). */
#include "h5util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void fpl_h5_quiet_begin(fpl_h5_quiet *q)
{
    q->func = NULL;
    q->data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

void fpl_h5_quiet_end(const fpl_h5_quiet *q) { H5Eset_auto2(H5E_DEFAULT, q->func, q->data); }

typedef struct { char *buf; size_t len; } walk_ctx;

/* The stack is walked from the innermost (most specific) entry outwards: keep the first. */
static herr_t walk_first(unsigned n, const H5E_error2_t *err, void *ctx_)
{
    walk_ctx *ctx = ctx_;
    if (n == 0 && err && err->desc)
        snprintf(ctx->buf, ctx->len, "%s (in %s)", err->desc, err->func_name ? err->func_name : "?");
    return 0;
}

const char *fpl_h5_error_text(char *buf, size_t len)
{
    walk_ctx ctx = {buf, len};
    if (len) buf[0] = '\0';
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk_first, &ctx);
    H5Eclear2(H5E_DEFAULT);
    return buf;
}

static int set_attr(hid_t obj, const char *name, hid_t type, const void *value)
{
    if (H5Aexists(obj, name) > 0 && H5Adelete(obj, name) < 0) return -1;
    hid_t space = H5Screate(H5S_SCALAR);
    if (space < 0) return -1;
    hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    int ok = attr >= 0 && H5Awrite(attr, type, value) >= 0;
    if (attr >= 0) H5Aclose(attr);
    H5Sclose(space);
    return ok ? 0 : -1;
}

int fpl_h5_set_double(hid_t obj, const char *name, double value)
{
    return set_attr(obj, name, H5T_NATIVE_DOUBLE, &value);
}

int fpl_h5_set_long(hid_t obj, const char *name, long value)
{
    long long v = value;
    return set_attr(obj, name, H5T_NATIVE_LLONG, &v);
}

int fpl_h5_set_u64(hid_t obj, const char *name, unsigned long long value)
{
    return set_attr(obj, name, H5T_NATIVE_ULLONG, &value);
}

int fpl_h5_set_string(hid_t obj, const char *name, const char *value)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    if (type < 0) return -1;
    size_t n = strlen(value);
    int ok = H5Tset_size(type, n ? n : 1) >= 0 && H5Tset_strpad(type, H5T_STR_NULLPAD) >= 0 &&
             H5Tset_cset(type, H5T_CSET_UTF8) >= 0 &&
             set_attr(obj, name, type, n ? value : "") == 0;
    H5Tclose(type);
    return ok ? 0 : -1;
}

static int get_attr(hid_t obj, const char *name, hid_t type, void *value)
{
    if (H5Aexists(obj, name) <= 0) return -1;
    hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
    if (attr < 0) return -1;
    hid_t space = H5Aget_space(attr);
    int ok = space >= 0 && H5Sget_simple_extent_npoints(space) == 1 &&
             H5Aread(attr, type, value) >= 0;
    if (space >= 0) H5Sclose(space);
    H5Aclose(attr);
    return ok ? 0 : -1;
}

int fpl_h5_get_double(hid_t obj, const char *name, double *value)
{
    return get_attr(obj, name, H5T_NATIVE_DOUBLE, value);
}

int fpl_h5_get_long(hid_t obj, const char *name, long *value)
{
    long long v = 0;
    if (get_attr(obj, name, H5T_NATIVE_LLONG, &v)) return -1;
    *value = (long)v;
    return 0;
}

int fpl_h5_get_u64(hid_t obj, const char *name, unsigned long long *value)
{
    return get_attr(obj, name, H5T_NATIVE_ULLONG, value);
}

int fpl_h5_get_string(hid_t obj, const char *name, char *buf, size_t len)
{
    if (!len || H5Aexists(obj, name) <= 0) return -1;
    hid_t attr = H5Aopen(obj, name, H5P_DEFAULT);
    if (attr < 0) return -1;
    hid_t ftype = H5Aget_type(attr);
    int ok = 0;
    if (ftype >= 0 && H5Tget_class(ftype) == H5T_STRING && !H5Tis_variable_str(ftype)) {
        size_t n = H5Tget_size(ftype);
        if (n < len) {
            hid_t mtype = H5Tcopy(ftype);
            memset(buf, 0, len);
            ok = mtype >= 0 && H5Aread(attr, mtype, buf) >= 0;
            if (mtype >= 0) H5Tclose(mtype);
        }
    }
    if (ftype >= 0) H5Tclose(ftype);
    H5Aclose(attr);
    return ok ? 0 : -1;
}

int fpl_h5_write_vector(hid_t loc, const char *name, const double *a, size_t n)
{
    hsize_t dims[1] = {n};
    hid_t space = H5Screate_simple(1, dims, NULL);
    if (space < 0) return -1;
    hid_t d = H5Dcreate2(loc, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int ok = d >= 0 && (n == 0 || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a) >= 0);
    if (d >= 0) H5Dclose(d);
    H5Sclose(space);
    return ok ? 0 : -1;
}

int fpl_h5_read_vector(hid_t loc, const char *name, double *a, size_t *len)
{
    if (H5Lexists(loc, name, H5P_DEFAULT) <= 0) return -1;
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (d < 0) return -1;
    hid_t space = H5Dget_space(d);
    int ok = 0;
    if (space >= 0 && H5Sget_simple_extent_ndims(space) == 1) {
        hsize_t n = 0;
        H5Sget_simple_extent_dims(space, &n, NULL);
        if (n <= *len) {
            ok = n == 0 || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a) >= 0;
            *len = (size_t)n;
        }
    }
    if (space >= 0) H5Sclose(space);
    H5Dclose(d);
    return ok ? 0 : -1;
}

/* ---- run descriptions ------------------------------------------------------------------- */
#include <stdlib.h>
#include "internal.h"

static const char *str_or(const char *s, const char *dflt) { return s ? s : dflt; }

int fpl_h5_write_description(hid_t file, const char *schema, const fpl_lattice *lat,
                             const fpl_run_info *info)
{
    int bad = 0;
    bad |= fpl_h5_set_string(file, "schema", schema);
    bad |= fpl_h5_set_string(file, "fputlab_version", fpl_version());
    bad |= fpl_h5_set_string(file, "kind", str_or(info->kind, ""));
    bad |= fpl_h5_set_long(file, "N", lat->n);
    bad |= fpl_h5_set_long(file, "model", lat->ops->model);
    bad |= fpl_h5_set_string(file, "model_name", lat->ops->name);
    bad |= fpl_h5_set_string(file, "boundary",
                             lat->boundary == FPL_BOUNDARY_PERIODIC ? "periodic" : "fixed");
    bad |= fpl_h5_set_double(file, "alpha", lat->alpha);
    bad |= fpl_h5_set_double(file, "beta", lat->beta);
    bad |= fpl_h5_set_string(file, "method", str_or(info->method, ""));
    bad |= fpl_h5_set_double(file, "dt", info->dt);
    bad |= fpl_h5_set_double(file, "rtol", info->rtol);
    bad |= fpl_h5_set_double(file, "atol", info->atol);
    bad |= fpl_h5_set_double(file, "t0", info->t0);
    bad |= fpl_h5_set_long(file, "n_dev", info->n_dev);
    bad |= fpl_h5_set_double(file, "tau", info->tau);
    bad |= fpl_h5_set_long(file, "seed", info->seed);
    bad |= fpl_h5_set_string(file, "disorder", str_or(info->disorder, ""));
    if (H5Lexists(file, "v", H5P_DEFAULT) <= 0)
        bad |= fpl_h5_write_vector(file, "v", lat->v, (size_t)lat->n);
    return bad ? -1 : 0;
}

int fpl_h5_check_description(hid_t file, const char *path, const char *schema,
                             const fpl_lattice *lat, const char *method)
{
    char buf[128];
    long n = -1, model = -1;
    double alpha = NAN, beta = NAN;
    if (fpl_h5_get_string(file, "schema", buf, sizeof buf) || strcmp(buf, schema) != 0)
        return fpl_error(NULL, FPL_ERR_IO, "%s is not a %s file (schema attribute missing or other)",
                         path, schema);
    if (fpl_h5_get_long(file, "N", &n) || fpl_h5_get_long(file, "model", &model) ||
        fpl_h5_get_double(file, "alpha", &alpha) || fpl_h5_get_double(file, "beta", &beta))
        return fpl_error(NULL, FPL_ERR_IO, "%s: N, model, alpha or beta attribute missing", path);
    if (n != lat->n)
        return fpl_error(NULL, FPL_ERR_ARG, "%s is for N = %ld, this run has N = %d", path, n, lat->n);
    if (model != lat->ops->model)
        return fpl_error(NULL, FPL_ERR_ARG, "%s is for model %s, this run is model %s", path,
                         fpl_model_name((int)model), lat->ops->name);
    /* files written before periodic chains existed have no boundary attribute: fixed ends */
    const char *want = lat->boundary == FPL_BOUNDARY_PERIODIC ? "periodic" : "fixed";
    if (fpl_h5_get_string(file, "boundary", buf, sizeof buf)) strcpy(buf, "fixed");
    if (strcmp(buf, want) != 0)
        return fpl_error(NULL, FPL_ERR_ARG, "%s is for a chain with %s boundaries, this run's are %s",
                         path, buf, want);
    if (memcmp(&alpha, &lat->alpha, sizeof alpha) != 0 || memcmp(&beta, &lat->beta, sizeof beta) != 0)
        return fpl_error(NULL, FPL_ERR_ARG,
                         "%s is for alpha = %.17g, beta = %.17g; this run has alpha = %.17g, beta = %.17g",
                         path, alpha, beta, lat->alpha, lat->beta);
    double *v = malloc(sizeof(double) * (size_t)lat->n);
    if (!v) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (v)");
    size_t len = (size_t)lat->n;
    int rd = fpl_h5_read_vector(file, "v", v, &len);
    int same = rd == 0 && len == (size_t)lat->n &&
               memcmp(v, lat->v, sizeof(double) * (size_t)lat->n) == 0;
    free(v);
    if (rd) return fpl_error(NULL, FPL_ERR_IO, "%s: dataset v missing or of the wrong length", path);
    if (!same)
        return fpl_error(NULL, FPL_ERR_ARG,
                         "%s was written for another disorder realisation (v differs)", path);
    if (method) {
        if (fpl_h5_get_string(file, "method", buf, sizeof buf))
            return fpl_error(NULL, FPL_ERR_IO, "%s: method attribute missing", path);
        if (strcmp(buf, method) != 0)
            return fpl_error(NULL, FPL_ERR_ARG, "%s was written by method %s, this run uses %s",
                             path, buf, method);
    }
    return FPL_OK;
}

unsigned long long fpl_fnv1a(unsigned long long h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}
