/* Every difference between the SUNDIALS versions fputlab builds against (Debian 12's 6.4 and
 * 7.x) lives in this private header; the back ends and the examples' tests spell each call once.
 *
 *   context       6.x SUNContext_Create(void *comm = NULL, ...); 7.x SUNContext_Create(SUNComm,
 *                 ...) with SUN_COMM_NULL (MPI_COMM_NULL when SUNDIALS was built with MPI);
 *                 the public fputlab/sundials.h has FPL_SUN_COMM_NULL for embedders.
 *   error report  6.x per solver (ERKStepSetErrHandlerFn, CVodeSetErrHandlerFn); 7.x removed them:
 *                 errors go to the context's handler stack (SUNContext_PushErrHandler), warnings
 *                 to the context's logger, which by default prints (errors to stderr, warnings to
 *                 stdout). fpl_sun_context_create() installs our handler and a logger that writes
 *                 nowhere, so the messages reach the integrator handle and the library never
 *                 prints. (Warnings are dropped in both versions, as before.)
 *   ARKODE        7.1 moved the stepper-independent functions to ARKode* (ARKodeSStolerances,
 *                 ARKodeEvolve, ...) and deprecated the ERKStep and SPRKStep copies: FPL_ARK(Name)
 *                 picks ARKodeName on >= 7.1 and the stepper's own name (ERKStep or SPRKStep,
 *                 FPL_ARK_STEPPER) before. Stepper-specific calls (ERKStepCreate, ERKStepSetTable,
 *                 ERKStepReInit, SPRKStepCreate, ...) are the same in both.
 *                 7.2 deprecated ERKStepGetNumRhsEvals and SPRKStepGetNumRhsEvals for
 *                 ARKodeGetNumRhsEvals(mem, partition, &n) (FPL_ERK_NUM_RHS, FPL_SPRK_NUM_F1),
 *                 7.4 SPRKStepSetUseCompensatedSums for ARKodeSetUseCompensatedSums
 *                 (FPL_SPRK_SET_COMPENSATED_SUMS).
 *   SPRKStep      exists from 6.6 (FPL_HAVE_SPRKSTEP).
 *   libraries     7.x: sundials_core (meson.build); 6.x: sundials_generic (optional).
 *   types         sunrealtype, sunbooleantype, sunindextype exist in both (realtype was removed
 *                 in 7.0, so the library uses the sun* names only). */
#ifndef FPUTLAB_SUNDIALS_COMPAT_H
#define FPUTLAB_SUNDIALS_COMPAT_H

#include <stdio.h> /* arkode_butcher.h (6.4) uses FILE without including it */
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_types.h>

#define FPL_SUN_VERSION (SUNDIALS_VERSION_MAJOR * 100 + SUNDIALS_VERSION_MINOR)
#define FPL_SUNDIALS7 (SUNDIALS_VERSION_MAJOR >= 7)
#define FPL_HAVE_SPRKSTEP (FPL_SUN_VERSION >= 606)
#define FPL_ARKODE_GENERIC (FPL_SUN_VERSION >= 701)

#if FPL_ARKODE_GENERIC
#define FPL_ARK_CAT_(stepper, name) ARKode##name
#else
#define FPL_ARK_CAT_(stepper, name) stepper##name
#endif
/* FPL_ARK(ERKStep, SStolerances)(mem, ...): ARKodeSStolerances on >= 7.1, else ERKStepSStolerances. */
#define FPL_ARK(stepper, name) FPL_ARK_CAT_(stepper, name)

/* Right-hand-side evaluations so far: ERKStep's f (FPL_ERK_NUM_RHS) and SPRKStep's f1, the force
 * (FPL_SPRK_NUM_F1; partition 0 of ARKodeGetNumRhsEvals). */
#if FPL_SUN_VERSION >= 702
#define FPL_ERK_NUM_RHS(mem, n) ARKodeGetNumRhsEvals((mem), 0, (n))
#define FPL_SPRK_NUM_F1(mem, n) ARKodeGetNumRhsEvals((mem), 0, (n))
#else
#define FPL_ERK_NUM_RHS(mem, n) ERKStepGetNumRhsEvals((mem), (n))
#define FPL_SPRK_NUM_F1(mem, n) SPRKStepGetNumRhsEvals((mem), (n), &(long int){0})
#endif

/* SPRKStep's compensated summation on or off. */
#if FPL_SUN_VERSION >= 704
#define FPL_SPRK_SET_COMPENSATED_SUMS ARKodeSetUseCompensatedSums
#else
#define FPL_SPRK_SET_COMPENSATED_SUMS SPRKStepSetUseCompensatedSums
#endif

/* Messages of the last SUNDIALS failure: the buffer the error handler writes into. */
typedef struct fpl_sun_msgbuf {
    char msg[320];
} fpl_sun_msgbuf;

/* Create a context whose errors are written to *buf (7.x; 6.x: see FPL_SUN_SET_ERR_HANDLER) and
 * which never prints. *logger receives a logger to free with fpl_sun_context_free (7.x), or NULL.
 * 0 on success. */
int fpl_sun_context_create(SUNContext *ctx, void **logger, fpl_sun_msgbuf *buf);
void fpl_sun_context_free(SUNContext *ctx, void **logger);

#if FPL_SUNDIALS7
/* 7.x: nothing to do per solver (the handler is on the context). */
#define FPL_SUN_SET_ERR_HANDLER(set_fn, mem, buf) ((void)(mem), (void)(buf), 0)
#else
/* 6.x error handler (ARKErrHandlerFn / CVErrHandlerFn): keeps the message in the fpl_sun_msgbuf
 * given as user data; warnings (positive codes, e.g. "t + h = t") are not kept. */
void fpl_sun_err_handler6(int error_code, const char *module, const char *function, char *msg,
                          void *user_data);
#define FPL_SUN_SET_ERR_HANDLER(set_fn, mem, buf) set_fn((mem), fpl_sun_err_handler6, (buf))
#endif

#endif
