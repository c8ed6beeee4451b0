/* Private interface between the generic integrator handle (integrator.c) and its back ends
 * (backend_*.c). A back end is a constant table of operations; a method is a name bound to a
 * back end plus method data (a splitting table, a Butcher table id, ...). */
#ifndef FPUTLAB_INTEGRATOR_IMPL_H
#define FPUTLAB_INTEGRATOR_IMPL_H

#include "fputlab/integrator.h"
#include "internal.h"

typedef struct fpl_backend {
    const char *family;                       /* "splitting", "arkode", "cvode", "gsl" */
    int adaptive;
    /* allocate back-end data for h (h->y holds y0 at h->t) */
    int (*init)(fpl_integrator *h);
    /* bring the state to exactly t_target and copy it to y_out (never NULL here). Fixed-step
     * back ends may leave h->y at an earlier grid time. Errors via fpl_error(). */
    int (*advance)(fpl_integrator *h, double t_target, double *y_out);
    /* h->y was changed in place at h->t (deviation vectors transformed) */
    int (*reset)(fpl_integrator *h);
    void (*release)(fpl_integrator *h);
    /* optional (SPRKStep with compensated sums): copy out / set (NULL: zero) the carry of the
     * compensated summation, length dim; FPL_ERR_ARG when the integrator has none */
    int (*get_compensation)(const fpl_integrator *h, double *carry);
    int (*set_compensation)(fpl_integrator *h, const double *carry);
} fpl_backend;

typedef struct fpl_method {
    const char *name;
    int order;
    const fpl_backend *backend;
    const void *data;                         /* back-end specific (e.g. const fpl_splitting *) */
} fpl_method;

struct fpl_integrator {
    const fpl_lattice *lat;
    fpl_system *sys;                          /* {lattice, criteria (opt.events), workspace}: the
                                                 SUNDIALS back ends' user_data */
    const fpl_method *method;
    int n_dev;
    long dim;                                 /* 2N(1 + n_dev) */
    double t0;
    double t;                                 /* time of y */
    double *y;                                /* internal state, dim */
    double *scratch;                          /* dim, for samples off the internal time */
    fpl_integrator_options opt;               /* opt.events is NULL: the criteria are in sys */
    long n_steps, n_force;
    void *data;                               /* back-end private */
    int stopped;                              /* an event fired: h->y, h->t are the event */
    int event_index;                          /* which criterion (index into sys->events) */
    double budget;                            /* seconds per call, 0 = none (set_budget) */
    long paused_steps;                        /* internal steps of the paused calls towards the
                                                 current target (max_steps counts them all) */
    char errmsg[FPL_ERRMSG_LEN];
};

extern const fpl_backend fpl_backend_splitting;

/* Methods provided by the SUNDIALS/GSL back ends (terminated by a {NULL} entry). */
extern const fpl_method fpl_methods_arkode[];
extern const fpl_method fpl_methods_cvode[];
extern const fpl_method fpl_methods_gsl[];
extern const fpl_method fpl_methods_sprk[];  /* empty without SPRKStep (SUNDIALS < 6.6) */

/* A clear FPL_ERR_UNKNOWN if name is an SPRKStep method this build lacks, else 0. */
int fpl_sprk_missing(const char *name);

#endif
