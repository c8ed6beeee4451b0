/* The version-dependent SUNDIALS set-up (see sundials_compat.h): context creation and where
 * error messages and warnings go. */
#include <stdio.h>
#include <stdlib.h>
#include "fputlab/common.h"
#include "sundials_compat.h"
#if FPL_SUNDIALS7
#include <sundials/sundials_errors.h>
#include <sundials/sundials_logger.h>
#endif

#if FPL_SUNDIALS7
/* 7.x SUNErrHandlerFn: keep the message and the function that reported it, never print. Only
 * errors reach the handler (warnings go to the logger). */
static void err_handler7(int line, const char *func, const char *file, const char *msg,
                         SUNErrCode err_code, void *user_data, SUNContext ctx)
{
    (void)line; (void)file; (void)err_code; (void)ctx;
    fpl_sun_msgbuf *buf = user_data;
    snprintf(buf->msg, sizeof buf->msg, "%s (%s)", msg ? msg : "", func ? func : "?");
}
#else
void fpl_sun_err_handler6(int error_code, const char *module, const char *function, char *msg,
                          void *user_data)
{
    (void)module;
    fpl_sun_msgbuf *buf = user_data;
    if (error_code > 0) return; /* ARK_WARNING / CV_WARNING */
    snprintf(buf->msg, sizeof buf->msg, "%s (%s)", msg ? msg : "", function ? function : "?");
}
#endif

int fpl_sun_context_create(SUNContext *ctx, void **logger, fpl_sun_msgbuf *buf)
{
    *ctx = NULL;
    *logger = NULL;
#if FPL_SUNDIALS7
    if (SUNContext_Create(SUN_COMM_NULL, ctx) != SUN_SUCCESS || !*ctx) return -1;
    /* Our handler replaces the default one (SUNLogErrHandlerFn, which prints). */
    if (SUNContext_ClearErrHandlers(*ctx) != SUN_SUCCESS ||
        SUNContext_PushErrHandler(*ctx, err_handler7, buf) != SUN_SUCCESS)
        return -1;
#if SUNDIALS_LOGGING_LEVEL > 0
    /* A logger built with logging enabled writes warnings to stdout and errors to stderr unless
     * told otherwise, and its public API has no "nowhere": point both at the null device. */
    SUNLogger lg = NULL;
    if (SUNLogger_Create(SUN_COMM_NULL, 0, &lg) != SUN_SUCCESS || !lg) return -1;
    *logger = lg;
    if (SUNLogger_SetErrorFilename(lg, "/dev/null") != SUN_SUCCESS ||
        SUNLogger_SetWarningFilename(lg, "/dev/null") != SUN_SUCCESS ||
        SUNContext_SetLogger(*ctx, lg) != SUN_SUCCESS)
        return -1;
#endif
#else
    (void)buf;
    if (SUNContext_Create(NULL, ctx) != 0 || !*ctx) return -1;
#endif
    return 0;
}

void fpl_sun_context_free(SUNContext *ctx, void **logger)
{
    if (*ctx) SUNContext_Free(ctx);
#if FPL_SUNDIALS7
    if (*logger) {
        SUNLogger lg = *logger;
        SUNLogger_Destroy(&lg);
    }
#endif
    *logger = NULL;
}

const char *fpl_sundials_version(void) { return SUNDIALS_VERSION; }
