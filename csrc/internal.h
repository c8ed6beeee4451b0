/* Private definitions shared by the C core. Not installed. */
#ifndef FPUTLAB_INTERNAL_H
#define FPUTLAB_INTERNAL_H

#include <stddef.h>
#include "fputlab.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define FPL_ERRMSG_LEN 512

/* Hot kernels are compiled twice on x86-64 (baseline SSE2 and x86-64-v3: AVX2 + FMA) and the
 * loader picks the best one for the CPU (GCC target_clones / ifunc): portable binaries that
 * still use 4-wide vectors where the machine has them. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define FPL_HOT __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define FPL_HOT
#endif

/* Record an error (thread-local, and on the handle if one is given) and return status. */
int fpl_error(fpl_lattice *lattice, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Clear the handle's message at the start of a call. */
void fpl_error_clear(fpl_lattice *lattice);

/* A model is data: per-particle coefficient arrays plus a table of kernels.
 * Bond b = 0..N joins particle b-1 and b (0-based, particles -1 and N are the fixed ends):
 *   L_b = cl[b] x[b] - cl[b-1] x[b-1]   (linear stretch)
 *   R_b = cn[b] x[b] - cn[b-1] x[b-1]   (nonlinear stretch)
 *   phi_b = L_b + alpha R_b^2 + beta R_b^3,   F_i = s[i] (phi_{i+1} - phi_i),   x_i' = minv[i] p_i
 *   model 1: cl = cn = s = minv = 1;  model 2: cl = cn = s = v, minv = 1/v;  model 3: cl = s = minv = 1, cn = v. */
typedef struct fpl_model_ops {
    int model;
    const char *name;
    /* p += h F(x) and dp^(m) += h J(x) dx^(m), m < n_dev (y is the full state). */
    void (*kick)(fpl_lattice *lat, double *y, int n_dev, double h);
    /* energy of a 2N state */
    double (*energy)(const fpl_lattice *lat, const double *y);
} fpl_model_ops;

struct fpl_lattice {
    int n;
    double alpha, beta;
    const fpl_model_ops *ops;
    double *v;      /* N */
    double *cl;     /* N */
    double *cn;     /* N */
    double *s;      /* N */
    double *minv;   /* N */
    double *phi;    /* N+1 scratch: bond forces */
    double *kappa;  /* N+1 scratch: bond curvatures dphi/dR - dL/dR part */
    double *dphi;   /* N+1 scratch: tangent bond forces */
    double *fft;    /* 2(N+1) scratch for the sine transform */
    void *fft_wavetable;
    void *fft_workspace;
    double *ek;     /* N scratch: mode energies for event criteria */
    /* Harmonic-split schemes (harmonic_split.c), allocated by their prepare hook: */
    struct fpl_harmonic_cache *harm; /* Chebyshev coefficients of the drifts for one dt (opaque) */
    double *harmwork;                /* 4N scratch */
    fpl_event_set events;          /* stopping criteria (events.c) */
    char event_desc[8][96];
    char errmsg[FPL_ERRMSG_LEN];
};

/* g_i(y) of the lattice's criteria, no validation (events.c). */
void fpl_events_eval(fpl_lattice *lat, const double *y, double *g);

const fpl_model_ops *fpl_model_ops_for(int model);

/* Generic kernels used by the public wrappers (all models). */
void fpl_kernel_force(fpl_lattice *lat, const double *x, double *f);
void fpl_kernel_tangent(fpl_lattice *lat, const double *x, int n_dev, const double *dx,
                        double *df);
/* Enumerate the non-zeros of the Jacobian of the first-order system with n_dev vectors. */
typedef void (*fpl_emit_fn)(void *ctx, long row, long col, double value);
void fpl_kernel_jacobian_entries(fpl_lattice *lat, const double *y, int n_dev, fpl_emit_fn emit,
                                 void *ctx);
/* y' = f(y) with n_dev vectors, no validation. */
void fpl_kernel_rhs(fpl_lattice *lat, const double *y, int n_dev, double *ydot);

/* Splitting schemes: one table per file in csrc/integrators/. */
typedef void (*fpl_step_fn)(const fpl_splitting *scheme, fpl_lattice *lat, double *y, int n_dev,
                            double dt);
struct fpl_splitting {
    const char *name;
    int order;
    int n_kicks;           /* s; there are s+1 drifts */
    const double *drift;   /* a_0..a_s */
    const double *kick;    /* b_0..b_{s-1} */
    fpl_step_fn step;
    /* Optional: check that the scheme applies to the lattice and set up what its step needs
     * (called once per run before any step; the step itself never allocates). */
    int (*prepare)(const fpl_splitting *scheme, fpl_lattice *lat);
    const char *reference;
};
/* Drift-kick composition: A = x += h p/m (kinetic), B = p += h F(x) (whole force). */
void fpl_step_aba(const fpl_splitting *scheme, fpl_lattice *lat, double *y, int n_dev, double dt);
/* Near-integrable composition (harmonic_split.c): A = exact flow of the harmonic chain (each
 * normal mode rotated by w_k h), B = kick by the anharmonic force only. */
void fpl_step_harmonic(const fpl_splitting *scheme, fpl_lattice *lat, double *y, int n_dev,
                       double dt);
int fpl_harmonic_prepare(const fpl_splitting *scheme, fpl_lattice *lat);
/* Run a scheme's prepare hook, if it has one. */
int fpl_splitting_prepare(const fpl_splitting *scheme, fpl_lattice *lat);

extern const fpl_splitting fpl_scheme_leapfrog;
extern const fpl_splitting fpl_scheme_yoshida4;
extern const fpl_splitting fpl_scheme_aba864;
extern const fpl_splitting fpl_scheme_aba864_harmonic;
extern const fpl_splitting fpl_scheme_srkn14a6;

/* Sine-transform workspace owned by the lattice (modes.c). */
int fpl_modes_alloc(fpl_lattice *lat);
void fpl_modes_release(fpl_lattice *lat);

/* Anharmonic part of the force (bond forces alpha R^2 + beta R^3, R from cn) for lattices whose
 * linear part is the homogeneous chain; keeps kappa_b = 2 alpha R + 3 beta R^2 in lat->kappa
 * for fpl_kernel_anharmonic_tangent (df = J_anh(x) dx at the same x). */
void fpl_kernel_anharmonic_force(fpl_lattice *lat, const double *x, double *f);
void fpl_kernel_anharmonic_tangent(fpl_lattice *lat, const double *dx, double *df);

int fpl_is_finite_array(const double *a, long len, long *first_bad);

#endif
