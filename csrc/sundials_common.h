/* Private part shared by the SUNDIALS back ends (backend_arkode.c, backend_cvode.c,
 * backend_sprk.c): their data, set-up failures and the classification of a solver return.
 * Each package keeps its own configure/evolve calls in its own file. */
#ifndef FPUTLAB_SUNDIALS_COMMON_H
#define FPUTLAB_SUNDIALS_COMMON_H

#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>
#include "integrator_impl.h"
#include "sundials_compat.h"

typedef struct fpl_sun_data {
    SUNContext ctx;
    void *logger;               /* 7.x: our silent logger (sundials_compat.c) */
    N_Vector y;                 /* solver output; h->y keeps the last good state */
    void *mem;                  /* solver memory, freed by the back end's release */
    SUNMatrix A;                /* CVODE BDF only */
    SUNLinearSolver LS;         /* CVODE BDF only */
    SUNNonlinearSolver NLS;     /* CVODE only */
    long base_steps, base_rhs;  /* counters accumulated before the last ReInit */
    const char *package;        /* "ARKODE", "CVODE": prefix of the messages */
    fpl_sun_msgbuf err;         /* last SUNDIALS error message */
    void *extra;                /* back-end private (SPRKStep: the compensated sums' carry);
                                   the back end's release frees it */
} fpl_sun_data;

/* What the classification needs from a package. */
typedef struct fpl_sun_ops {
    int root_return;                          /* ARK_ROOT_RETURN / CV_ROOT_RETURN */
    int rhs_errors[3];                        /* flags meaning "the right-hand side failed" */
    int (*root_info)(void *mem, int *found);  /* ...GetRootInfo */
    char *(*flag_name)(long flag);            /* ...GetReturnFlagName (malloc'd) */
    int (*restart)(fpl_integrator *h);        /* re-initialise from (h->t, h->y) */
} fpl_sun_ops;

/* Allocate h->data (context that never prints, state vector = h->y). Errors via fpl_error. */
int fpl_sun_data_create(fpl_integrator *h, const char *package);
/* Free what fpl_sun_data_create and the CVODE solvers allocated (the back end frees d->mem
 * first) and clear h->data. */
void fpl_sun_data_free(fpl_integrator *h);
/* "<PACKAGE> <method>: <what> failed (flag f): <SUNDIALS message>" as FPL_ERR_BACKEND. */
int fpl_sun_setup_failed(fpl_integrator *h, const char *what, int flag);
/* After an evolve call returned flag with the state at tret: update h (event, success, or the
 * last good state on failure, then restart) and return FPL_EVENT, FPL_OK or an error. The
 * counters (h->n_steps, h->n_force) are the caller's. */
int fpl_sun_classify(fpl_integrator *h, const fpl_sun_ops *ops, int flag, double tret,
                     double t_target, double *y_out);

#endif
