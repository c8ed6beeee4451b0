/* Error reporting: a thread-local last-error message plus a per-handle copy. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "internal.h"

#ifndef FPL_VERSION_STRING
#define FPL_VERSION_STRING "0.0.0"
#endif

static _Thread_local char last_error[FPL_ERRMSG_LEN];

const char *fpl_version(void) { return FPL_VERSION_STRING; }

const char *fpl_last_error(void) { return last_error; }

const char *fpl_status_name(int status)
{
    switch (status) {
    case FPL_OK: return "ok";
    case FPL_EVENT: return "event";
    case FPL_ERR_ARG: return "invalid argument";
    case FPL_ERR_NOMEM: return "out of memory";
    case FPL_ERR_NONFINITE: return "non-finite state";
    case FPL_ERR_UNKNOWN: return "unknown name";
    case FPL_ERR_BACKEND: return "backend failure";
    case FPL_ERR_IO: return "input/output failure";
    default: return "unrecognised status";
    }
}

int fpl_error(fpl_lattice *lattice, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(last_error, sizeof last_error, fmt, ap);
    va_end(ap);
    if (lattice)
        memcpy(lattice->errmsg, last_error, sizeof last_error);
    return status;
}

void fpl_error_clear(fpl_lattice *lattice)
{
    if (lattice)
        lattice->errmsg[0] = '\0';
}
