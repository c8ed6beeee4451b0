/* fputlab — the lattice models in SUNDIALS callback form, for ARKODE and CVODE (SUNDIALS 6.x or
 * 7.x: the declarations use only types common to both, sunrealtype and sunindextype).
 *
 * user_data of every callback is an fpl_system* (fputlab/events.h): the read-only lattice, the
 * stopping criteria (for fpl_sun_roots; NULL = none) and the kernels' scratch, so one system
 * serves one solver at a time (one per thread; a lattice may be shared by several systems).
 * The number of deviation vectors is read from the N_Vector length, 2N(1 + n_dev), so the same
 * callbacks integrate the orbit alone or the orbit with its variational equations. Example
 * (CVODE, BDF, dense Jacobian):
 *
 *     fpl_system_create(lattice, NULL, &sys);
 *     CVodeInit(mem, fpl_sun_rhs, t0, y);
 *     CVodeSetUserData(mem, sys);
 *     A = SUNDenseMatrix(len, len, ctx);  LS = SUNLinSol_Dense(y, A, ctx);
 *     CVodeSetLinearSolver(mem, LS, A);  CVodeSetJacFn(mem, fpl_sun_jac);
 *
 * For a band matrix, take the bandwidths from fpl_sun_band_widths: with the [x, p] layout the
 * force Jacobian is tridiagonal but sits N columns away from the diagonal.
 * Callbacks return 0 on success, 1 (recoverable) if the state is not finite, -1 on a size
 * mismatch; the message is then on the system handle (fpl_system_errmsg). */
#ifndef FPUTLAB_SUNDIALS_H
#define FPUTLAB_SUNDIALS_H

#include <stdio.h> /* arkode_butcher.h of SUNDIALS 6.4 uses FILE without including stdio.h */
#include <arkode/arkode_butcher.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_matrix.h>
#include "fputlab/lattice.h"

/* The "no communicator" argument of SUNContext_Create in the SUNDIALS you compile against:
 * SUNContext_Create(FPL_SUN_COMM_NULL, &ctx) works with 6.x (void *comm, NULL) and 7.x
 * (SUNComm, SUN_COMM_NULL, which is MPI_COMM_NULL when SUNDIALS was built with MPI). */
#if SUNDIALS_VERSION_MAJOR >= 7
#define FPL_SUN_COMM_NULL SUN_COMM_NULL
#else
#define FPL_SUN_COMM_NULL NULL
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* y' = f(t, y) (ARKRhsFn / CVRhsFn). */
FPL_API int fpl_sun_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

/* The same system split for ARKODE's symplectic stepper SPRKStep (SUNDIALS >= 6.6):
 *     SPRKStepCreate(fpl_sun_force, fpl_sun_velocity, t0, y, ctx);  ARKodeSetUserData(mem, sys);
 * fpl_sun_force (f1) fills the momentum blocks, p' = F(x) and dp' = J(x) dx for each deviation
 * vector, and depends on the positions only; fpl_sun_velocity (f2) fills the position blocks,
 * x' = p/m and dx' = dp/m, and depends on the momenta only; each writes zeros in the other blocks,
 * so f1 + f2 = fpl_sun_rhs. Orbit and deviation vectors form one separable system, so SPRKStep
 * applies the tangent map of its own scheme to the deviation vectors. Same layout and return
 * values as fpl_sun_rhs. */
FPL_API int fpl_sun_force(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);
FPL_API int fpl_sun_velocity(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

/* Jacobian (ARKLsJacFn / CVLsJacFn) for SUNMATRIX_DENSE or SUNMATRIX_BAND matrices. */
FPL_API int fpl_sun_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void *user_data,
                        N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);

/* Upper and lower bandwidths needed by fpl_sun_jac for a band matrix. A periodic chain's
 * Jacobian is not banded (x_0 and x_{N-1} are coupled): FPL_ERR_ARG, and fpl_sun_jac refuses a
 * band matrix for it; use a dense one. */
FPL_API int fpl_sun_band_widths(const fpl_lattice *lattice, int n_dev, sunindextype *upper,
                                sunindextype *lower);

/* Root function (ARKRootFn / CVRootFn) of the system's stopping criteria (fpl_system_create,
 * fputlab/events.h): nrtfn = fpl_system_event_count(sys); each g_i
 * decreases through zero when criterion i fires (use root direction -1). A non-finite state
 * gives g_i = -DBL_MAX, i.e. every criterion fired. */
FPL_API int fpl_sun_roots(sunrealtype t, N_Vector y, sunrealtype *gout, void *user_data);

/* Jacobian-times-vector (ARKLsJacTimesVecFn / CVLsJacTimesVecFn) for matrix-free Krylov solvers. */
FPL_API int fpl_sun_jtimes(N_Vector v, N_Vector jv, sunrealtype t, N_Vector y, N_Vector fy,
                           void *user_data, N_Vector tmp);

/* ERKStep Butcher tables, safe from the SUNDIALS 6.4 ERKStep FSAL bug.
 * ERKStep 6.4 treats every table whose last node is c_s = 1 as first-same-as-last and reuses the
 * last stage's f as the next step's first stage, even when that stage is not at the new solution
 * (a_sj != b_j): Verner 8-5-6, Fehlberg 13-7-8 and DOP853 then lose their order (DOP853 at fixed
 * steps: ~5.7 instead of 8). fpl_sun_erk_fsal_safe returns a copy of any table with, if needed,
 * one more stage c = 1, a_(s+1)j = b_j, weight 0 (f at the new solution): truly FSAL, same
 * solution, no extra f evaluations. Harmless with SUNDIALS 7.
 * fpl_sun_erk_table gives the (safe) tables of fputlab's methods "dopri5", "verner65",
 * "fehlberg87", "dop853" (Hairer's DOP853 with its 5th-order embedding):
 *
 *     ARKodeButcherTable B;
 *     if (fpl_sun_erk_table("dop853", &B) == 0) { ERKStepSetTable(mem, B); ARKodeButcherTable_Free(B); }
 *
 * Both return a new table in *out (free it with ARKodeButcherTable_Free), or NULL and an error
 * status (unknown method name, NULL or incomplete table, out of memory). */
FPL_API int fpl_sun_erk_table(const char *method, ARKodeButcherTable *out);
FPL_API int fpl_sun_erk_fsal_safe(ARKodeButcherTable table, ARKodeButcherTable *out);

#ifdef __cplusplus
}
#endif
#endif
