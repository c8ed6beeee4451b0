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

/* Record an error (thread-local, and in the handle's message buffer `handle_msg` of
 * FPL_ERRMSG_LEN chars if not NULL) and return status. */
int fpl_error(char *handle_msg, int status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Checked sizes. Every count that sizes a buffer (2N(1 + n_dev), dim^2, chunk x columns, ...)
 * is a product of caller-supplied integers: these refuse one that overflows or that could not
 * be held in this machine's physical memory, with a status and a message, instead of wrapping
 * round (a too-small buffer, then a crash) or letting a lazily committed allocation stall the
 * machine until the OOM killer ends the process. */
/* a * b into *out; -1 (and *out untouched) on overflow. */
int fpl_size_mul(size_t a, size_t b, size_t *out);
/* FPL_OK if count elements of size bytes (both as given) fit in physical memory, else
 * FPL_ERR_NOMEM naming `what` and the bytes. */
int fpl_check_alloc(size_t count, size_t size, const char *what);
/* The state length 2N(1 + n_dev) of a lattice of n sites: FPL_ERR_ARG for n_dev < 0, or if the
 * length overflows a long or the state could not fit in memory (FPL_ERR_NOMEM). */
int fpl_state_length(int n, int n_dev, long *len);

/* Scratch of the kernels for one lattice size, owned by whoever runs (an integrator, a chaos or
 * batch handle, a Galerkin handle, an fpl_system). The lattice itself is read-only physics, so
 * one lattice can serve several runs and threads, each with its own workspace. */
typedef struct fpl_work {
    int n;
    double *phi;    /* N+1: bond forces */
    double *kappa;  /* N+1: bond curvatures dphi/dR - dL/dR part */
    double *dphi;   /* N+1: tangent bond forces; the velocities in fpl_modes_energies_work */
    double *fft;    /* 2(N+1) for the sine transform (N for the Fourier one) */
    struct fpl_rdft *rdft;  /* the real FFT of the mode transform; NULL without modes */
    double *ek;     /* N: mode energies for the event criteria */
    /* FPL_KAPPA_STAGES x (N+1): the bond curvatures of every kick of one step, for the fused
     * steppers with many deviation vectors (each vector then runs the whole step while it stays
     * in cache); NULL for N > FPL_KAPPA_STAGES_MAX_N, where a vector does not stay in cache. */
    double *kappa_stages;
    int kappa_rows;  /* rows of kappa_stages: FPL_KAPPA_STAGES, more after fpl_work_reserve_vectors */
    /* 2 x FPL_VEC_TILE x N: one tile of deviation vectors in the vector-inner layout of the
     * many-vector step (models.c); NULL until fpl_work_reserve_vectors asks for it. */
    double *tile;
    /* The long-chain many-vector sweep (models.c, N > FPL_VEC_INNER_MAX_N, 3 or more vectors):
     * FPL_SWEEP_STAGES rows of FPL_SWEEP_ROW bond curvatures of one chain block, and the bond
     * terms carried from one block to the next (per stage 2 of the orbit, 1 per vector); NULL
     * until fpl_work_reserve_vectors asks for them. sweep_dev: the vectors sweep_carry holds. */
    double *sweep_rows;
    double *sweep_carry;
    int sweep_dev;
} fpl_work;
/* The most kicks a step of a kinetic splitting scheme has (srkn14a6), and the largest N with a
 * kappa_stages array (14 x 8193 doubles, 0.9 MB). */
#define FPL_KAPPA_STAGES 14
#define FPL_KAPPA_STAGES_MAX_N 8192
/* The vector-inner many-vector step (models.c): deviation vectors per tile (two AVX2 registers a
 * row), the chains it serves (a tile of 2 x 8 x 1024 doubles, 128 kB, stays in L2), the fewest
 * vectors it takes, and the doubles of kappa rows kept for a group of steps (256 kB). */
#define FPL_VEC_TILE 8
#define FPL_VEC_INNER_MAX_N 1024
#define FPL_VEC_INNER_MIN_DEV 3
#define FPL_KAPPA_GROUP_DOUBLES 32768
#define FPL_KAPPA_ROWS_MAX 1024
/* The sweep: particles per chain block (a vector's block, 8 kB, stays in L1 through the sweep's
 * stages), the most stages a sweep takes (the block's drift and kick regions move one particle
 * left per stage), and the length of a kappa row (the block, the stages' shift and the two
 * bonds at its ends). */
#define FPL_SWEEP_BLOCK 512
#define FPL_SWEEP_STAGES 32
#define FPL_SWEEP_ROW (FPL_SWEEP_BLOCK + FPL_SWEEP_STAGES + 2)
/* Whom the sweep serves: 3 or more vectors on chains beyond the vector-inner tiles, and 1 or 2
 * vectors where the state exceeds FPL_SWEEP_FEW_MIN_BYTES (10 MiB: N > 218 453 with two vectors,
 * N > 327 680 with one); there the stage-fused pass streams every stage through memory, and at
 * N a multiple of 512 its 9 arrays (model 2, two vectors) share each L1 set of 8 ways
 * (benchmarks/README.md). Without vectors the sweep is slower (its kappa rows and loop overhead
 * buy nothing). */
#define FPL_SWEEP_FEW_MIN_BYTES (10.0 * 1048576.0)
static inline int fpl_sweep_serves(int n, int n_dev)
{
    if (n <= FPL_VEC_INNER_MAX_N || n_dev < 1) return 0;
    return n_dev >= FPL_VEC_INNER_MIN_DEV || 16.0 * n * (n_dev + 1) > FPL_SWEEP_FEW_MIN_BYTES;
}

/* A real DFT of any length m in O(m log m) (fft.c): GSL's mixed radix, or Bluestein's algorithm
 * for lengths with a large prime factor. forward: data (length m) -> GSL's half-complex layout
 * (X_0, Re X_1, Im X_1, ..., and Re X_{m/2} last for even m), in place. */
typedef struct fpl_rdft fpl_rdft;
int fpl_rdft_create(size_t m, fpl_rdft **out);
int fpl_rdft_forward(fpl_rdft *plan, double *data);
void fpl_rdft_free(fpl_rdft **plan);

/* The mode transform a workspace carries: none, the fixed chain's sine transform (a real FFT of
 * length 2(N+1)) or the periodic chain's Fourier transform (length N). */
enum { FPL_WORK_NO_MODES = 0, FPL_WORK_SINE_MODES = 1, FPL_WORK_FOURIER_MODES = 2 };
#define FPL_WORK_MODES_OF(lat) \
    ((lat)->boundary == FPL_BOUNDARY_PERIODIC ? FPL_WORK_FOURIER_MODES : FPL_WORK_SINE_MODES)

/* Allocate a workspace for lattices of N = n (errors via fpl_error); modes: also the FFT plan of
 * that mode transform (fpl_modes_energies_work, mode-energy criteria). */
int fpl_work_create(int n, int modes, fpl_work **out);
void fpl_work_free(fpl_work **work);
/* Size the scratch of the vector-inner many-vector step for runs with n_dev deviation vectors
 * (the kappa rows of a group of steps and one tile): called where a run is created (an
 * integrator, fpl_splitting_advance, a batch handle), never inside a step. Nothing to do for
 * chains or vector counts the step does not serve; FPL_ERR_NOMEM (the workspace unchanged) if
 * out of memory. A workspace without this scratch takes the vector-by-vector step: the same
 * numbers. */
int fpl_work_reserve_vectors(fpl_work *work, int n_dev);

/* A model is data: per-particle coefficient arrays plus a table of kernels.
 * Bond b = 0..N joins particle b-1 and b (0-based, particles -1 and N are the fixed ends):
 *   L_b = cl[b] x[b] - cl[b-1] x[b-1]   (linear stretch)
 *   R_b = cn[b] x[b] - cn[b-1] x[b-1]   (nonlinear stretch)
 *   phi_b = L_b + alpha R_b^2 + beta R_b^3,   F_i = s[i] (phi_{i+1} - phi_i),   x_i' = minv[i] p_i
 * Each model's entry in the table of models.c says how its coefficients follow from v. */
typedef struct fpl_model_ops {
    int model;
    const char *name;
    /* cl, cn, s, minv of particle j from its variability v_j (called once, at lattice create). */
    void (*coefficients)(double v, double *cl, double *cn, double *s, double *minv);
    /* x^(m) += h minv p^(m) for the orbit and the n_dev deviation vectors (ctx: fpl_lattice_ctx;
     * the drift of the lattice's fpl_split_system; stage unused). */
    void (*drift)(void *ctx, double *y, int stage, double h);
    /* p += h F(x) and dp^(m) += h J(x) dx^(m), m < n_dev (y is the full state); ctx is an
     * fpl_lattice_ctx (the kick of the lattice's fpl_split_system, called directly). */
    void (*kick)(void *ctx, double *y, double h);
    /* optional: n steps of a kinetic drift-kick scheme with drift and kick inlined (ctx: an
     * fpl_lattice_ctx), bit-identical to n fpl_split_step calls on drift/kick; see
     * fpl_split_system.steps */
    void (*steps)(const fpl_splitting *scheme, void *ctx, double *y, double dt, long n);
    /* energy of a 2N state */
    double (*energy)(const fpl_lattice *lat, const double *y);
    /* The entries below are zero for the polynomial fixed-end models of models.c' ops_table.
     * boundary: FPL_BOUNDARY_FIXED or FPL_BOUNDARY_PERIODIC (the lookup is by model and
     * boundary, fpl_model_ops_lookup). force, tangent, jacobian_entries: optional replacements of
     * the generic kernels fpl_kernel_force, fpl_kernel_tangent, fpl_kernel_jacobian_entries (the
     * periodic chains and the Toda lattice, models_any.c). */
    int boundary;
    void (*force)(const fpl_lattice *lat, fpl_work *work, const double *x, double *f);
    void (*tangent)(const fpl_lattice *lat, fpl_work *work, const double *x, int n_dev,
                    const double *dx, double *df);
    void (*jacobian_entries)(const fpl_lattice *lat, const double *y, int n_dev,
                             void (*emit)(void *ctx, long row, long col, double value), void *ctx);
} fpl_model_ops;

/* Immutable after fpl_lattice_create. */
struct fpl_lattice {
    int n;
    int boundary;   /* FPL_BOUNDARY_FIXED or FPL_BOUNDARY_PERIODIC */
    double alpha, beta;
    const fpl_model_ops *ops;
    double *v;      /* N */
    double *cl;     /* N */
    double *cn;     /* N */
    double *s;      /* N */
    double *minv;   /* N */
};

/* NULL, or the model's entry (fixed ends). */
const fpl_model_ops *fpl_model_ops_for(int model);
/* NULL, or the entry of the model with that boundary condition. */
const fpl_model_ops *fpl_model_ops_lookup(int model, int boundary);
/* FPL_ERR_UNKNOWN "model %d is unknown (1 homogeneous, ...)" listing the table. */
int fpl_model_unknown(int model);

/* Stopping criteria (events.c). */
/* Validate a set for lattices of size n (message prefixed "events: "). */
int fpl_events_check(const fpl_event_set *events, int n);
/* "max |x_{j+1} - x_j| > 4" etc. into buf (96 chars). */
void fpl_events_describe(const fpl_event_set *events, int index, char *buf, size_t size);
/* g_i(y) of the criteria, no validation. */
void fpl_events_eval(const fpl_lattice *lat, fpl_work *work, const fpl_event_set *events,
                     const double *y, double *g);

/* The {lattice, criteria, workspace} of one run: user_data of the SUNDIALS callbacks, and what
 * an integrator runs on. */
struct fpl_system {
    const fpl_lattice *lat;
    fpl_event_set events;
    char event_desc[8][96];
    fpl_work *work;
    char errmsg[FPL_ERRMSG_LEN];
};

/* Generic kernels used by the public wrappers (all models). */
void fpl_kernel_force(const fpl_lattice *lat, fpl_work *work, const double *x, double *f);
void fpl_kernel_tangent(const fpl_lattice *lat, fpl_work *work, const double *x, int n_dev,
                        const double *dx, double *df);
/* Enumerate the non-zeros of the Jacobian of the first-order system with n_dev vectors. */
typedef void (*fpl_emit_fn)(void *ctx, long row, long col, double value);
void fpl_kernel_jacobian_entries(const fpl_lattice *lat, const double *y, int n_dev,
                                 fpl_emit_fn emit, void *ctx);
/* y' = f(y) with n_dev vectors, no validation. */
void fpl_kernel_rhs(const fpl_lattice *lat, fpl_work *work, const double *y, int n_dev,
                    double *ydot);

/* Mode energies with a caller's workspace (modes.c). */
int fpl_modes_energies_work(const fpl_lattice *lat, fpl_work *work, const double *y,
                            double *energies);

/* What a lattice kick works on: the lattice, the scratch, the number of deviation vectors. */
typedef struct fpl_lattice_ctx {
    const fpl_lattice *lat;
    fpl_work *work;
    int n_dev;
} fpl_lattice_ctx;

/* ---- splitting: one second-order system, one step, one grid driver ------------------------ */

/* A system for the drift-kick compositions (as gsl_odeiv2_system, or SPRKStep's f1/f2): a state
 * y of length dim whose drift advances the positions by the momenta and whose kick advances the
 * momenta by the forces. The lattice (orbit and deviation vectors, kinetic or harmonic split),
 * the Galerkin truncation and the two-mode ODE are such systems (splitting.c, harmonic_split.c,
 * reduction.c). */
typedef struct fpl_split_system {
    long dim;
    /* flow of the drift part for time h; stage = i of the drift coefficient a_i (for systems that
     * keep per-stage data, the harmonic split) */
    void (*drift)(void *ctx, double *y, int stage, double h);
    void (*kick)(void *ctx, double *y, double h);
    /* optional: called before the stages of each step of dt (the harmonic split's cache) */
    void (*begin_step)(void *ctx, const fpl_splitting *scheme, double dt);
    void *ctx;
    /* optional: n whole steps of dt in one call, the same operations in the same order as n
     * fpl_split_step calls on drift/kick (bit-identical), with the kernels inlined into the
     * stage loop: a model's fused stepper (models.c), worth ~1.2x at N <= 64 where the indirect
     * calls and per-call set-up of each stage are a fifth of the work. */
    void (*steps)(const fpl_splitting *scheme, void *ctx, double *y, double dt, long n);
} fpl_split_system;

/* One step of dt: drift a_0, kick b_0, drift a_1, ..., kick b_{s-1}, drift a_s. */
void fpl_split_step(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                    double dt);
/* n such steps (sys->steps if the system has it). */
void fpl_split_steps(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                     double dt, long n);

/* How often (in steps) stopping criteria are evaluated on a fixed-step run (the splitting back
 * end and the chaos batch kernel alike): their cost is O(N), like a force. */
#define FPL_EVENT_BLOCK 16

/* How often (in steps) the grid driver looks for NaN/Inf: a blow-up is caught early, placed in
 * time, and the state rolled back to the last finite grid state (a copy every chunk costs
 * ~1/1000 of the work). */
#define FPL_FINITE_CHECK_INTERVAL 1024

/* The fixed-step grid driver: whole steps of dt take y from grid step *step to n_target, with a
 * NaN/Inf check every FPL_FINITE_CHECK_INTERVAL steps. On a non-finite state y is put back to the
 * last finite grid state (backup: dim doubles of scratch), *step is its step, *step_bad the step
 * at which the non-finite state was found, and FPL_ERR_NONFINITE is returned without a message
 * (the caller words it); else FPL_OK with *step = n_target. */
int fpl_split_grid_advance(const fpl_splitting *scheme, const fpl_split_system *sys, double *y,
                           double *backup, long *step, long n_target, double dt, long *step_bad);

typedef struct fpl_split_run fpl_split_run;

/* Splitting schemes: one table per file in csrc/integrators/. */
struct fpl_splitting {
    const char *name;
    int order;
    int n_kicks;           /* s; there are s+1 drifts */
    const double *drift;   /* a_0..a_s */
    const double *kick;    /* b_0..b_{s-1} */
    /* Optional, for schemes that are not the kinetic drift-kick split of the lattice: set up a
     * run (check that the scheme applies to the lattice, allocate run->state, replace run->sys by
     * the scheme's own split), once per run before any step (the step itself never allocates);
     * state_free frees run->state. */
    int (*run_setup)(const fpl_splitting *scheme, fpl_split_run *run);
    void (*state_free)(void *state);
    const char *reference;
    /* An explicit Runge-Kutta-Nystrom method instead of a composition (drift/kick NULL, n_kicks
     * = its stages): run by rkn.c on the same system (run_setup = fpl_rkn_run_setup). */
    const struct fpl_rkn_table *rkn;
};

/* Explicit RKN method for x'' = M^-1 F(x) (rkn.c): s stages
 *   X_i = x + c_i h v + h^2 sum_{j<i} a_ij M^-1 K_j,  K_i = F(X_i),
 *   x' = x + h v + h^2 sum_i b_i M^-1 K_i,  v' = v + h sum_i bp_i M^-1 K_i   (v = M^-1 p),
 * not symplectic. a is s x s row-major (strictly lower triangular), c[0] = 0. */
typedef struct fpl_rkn_table {
    int stages;
    const double *a, *b, *bp, *c;
} fpl_rkn_table;
int fpl_rkn_run_setup(const fpl_splitting *scheme, fpl_split_run *run);
void fpl_rkn_state_free(void *state);

/* A scheme run on a lattice: its system (by default the kinetic split: drift x += h p/m, kick
 * p += h F(x), each with the tangent map for the deviation vectors) and the scheme's state. */
struct fpl_split_run {
    fpl_lattice_ctx lc;    /* first member: the run is the lattice kicks' ctx */
    const fpl_splitting *scheme;
    void *state;           /* from scheme->run_setup, NULL for the kinetic split */
    fpl_split_system sys;  /* ctx = the run */
};
/* Fill run for the lattice with n_dev deviation vectors (errors via fpl_error). */
int fpl_split_run_init(fpl_split_run *run, const fpl_splitting *scheme, const fpl_lattice *lat,
                       fpl_work *work, int n_dev);
void fpl_split_run_release(fpl_split_run *run);
/* The harmonic split (harmonic_split.c): drift = exact flow of the harmonic chain (each normal
 * mode rotated by w_k h), kick = the anharmonic force only. */
int fpl_harmonic_run_setup(const fpl_splitting *scheme, fpl_split_run *run);
void fpl_harmonic_state_free(void *state);

extern const fpl_splitting fpl_scheme_leapfrog;
extern const fpl_splitting fpl_scheme_yoshida4;
extern const fpl_splitting fpl_scheme_aba864;
extern const fpl_splitting fpl_scheme_aba864_harmonic;
extern const fpl_splitting fpl_scheme_srkn14a6;
extern const fpl_splitting fpl_scheme_dprkn8;
extern const fpl_splitting fpl_scheme_dprkn12;

/* Anharmonic part of the force (bond forces alpha R^2 + beta R^3, R from cn) for lattices whose
 * linear part is the homogeneous chain; keeps kappa_b = 2 alpha R + 3 beta R^2 in work->kappa
 * for fpl_kernel_anharmonic_tangent (df = J_anh(x) dx at the same x). */
void fpl_kernel_anharmonic_force(const fpl_lattice *lat, fpl_work *work, const double *x,
                                 double *f);
void fpl_kernel_anharmonic_tangent(const fpl_lattice *lat, fpl_work *work, const double *dx,
                                   double *df);

int fpl_is_finite_array(const double *a, long len, long *first_bad);

/* The nearest barrier of the bond potential in |stretch|, min(-lower, upper) of
 * fpl_lattice_barrier: INFINITY if there is none (barrier.c). */
double fpl_barrier_stretch(const fpl_lattice *lattice);

/* One renormalisation of MEGNO (Cincotta & Simo 2000) from the log-growth ell of the first
 * deviation vector: ell went from ell_prev to ell over an interval h ending s after t0.
 * acc = {int ell ds, int Y ds, Y at the previous renormalisation} (trapezoid rule):
 *   Y = 2 ell - (2/s) int ell ds,  returns <Y> = (1/s) int Y ds.
 * Shared by fpl_chaos and the batched lanes, which thereby agree bit for bit. */
static inline double fpl_megno_step(double *acc, double h, double s, double ell_prev, double ell)
{
    acc[0] += 0.5 * h * (ell_prev + ell);
    const double y = 2.0 * ell - 2.0 * acc[0] / s;
    acc[1] += 0.5 * h * (acc[2] + y);
    acc[2] = y;
    return acc[1] / s;
}

/* Replace the integrator's n_dev deviation vectors by w (n_dev x 2N, row-major; the caller
 * checked it finite), with the back end's reset as fpl_integrator_transform_deviations: how the
 * spectrum puts its orthonormal Q in place without the round-off of a transformation matrix. */
int fpl_integrator_set_deviations(fpl_integrator *h, const double *w);

#endif
