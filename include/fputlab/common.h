/* fputlab — common definitions: export macro, status codes, error messages.
 *
 * Conventions (hold for every header):
 *   - every fallible call returns an int status: 0 ok, >0 informational, <0 error;
 *   - results come back through out-pointers;
 *   - on error a readable message is available from fpl_last_error() (thread-local,
 *     set by the failing call) and, for calls on a handle, from that handle too.
 *   - the library never prints, exits or aborts.
 *
 * This header is also read by the Python binding generator (tools/gen_cffi.py):
 * keep declarations plain C; preprocessor lines are dropped there. */
#ifndef FPUTLAB_COMMON_H
#define FPUTLAB_COMMON_H

#if defined(FPL_BUILDING_LIBRARY) && defined(__GNUC__)
#define FPL_API __attribute__((visibility("default")))
#else
#define FPL_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

enum fpl_status {
    FPL_OK = 0,
    FPL_EVENT = 1,             /* informational: an event stopped the run */
    FPL_ERR_ARG = -1,          /* invalid argument (value out of range, NaN, wrong length) */
    FPL_ERR_NOMEM = -2,        /* allocation failed */
    FPL_ERR_NONFINITE = -3,    /* the state became NaN/Inf (integration failure) */
    FPL_ERR_UNKNOWN = -4,      /* unknown name (method, model, disorder kind) */
    FPL_ERR_BACKEND = -5,      /* SUNDIALS or GSL reported a failure */
    FPL_ERR_IO = -6            /* file input/output failed */
};

/* Library version as "MAJOR.MINOR.PATCH". */
FPL_API const char *fpl_version(void);

/* Version of the SUNDIALS the library was built against, e.g. "6.4.1" or "7.1.1". */
FPL_API const char *fpl_sundials_version(void);

/* Message of the last failing fputlab call in this thread ("" if none). */
FPL_API const char *fpl_last_error(void);

/* Static, human-readable name of a status code. */
FPL_API const char *fpl_status_name(int status);

#ifdef __cplusplus
}
#endif
#endif
