/* RKN8(6) of Dormand, El-Mikkawy & Prince, "High-order embedded Runge-Kutta-Nystrom formulae",
 * IMA J. Numer. Anal. 7 (1987) 423-430: explicit Runge-Kutta-Nystrom method of order 8 with 9
 * stages (force evaluations) per step, run at a fixed step by rkn.c (the embedded order-6 pair
 * is not used). Not symplectic. The coefficients are the formula's exact rationals (as
 * tabulated in OrdinaryDiffEq.jl's DPRKN8 tableau) rounded to the nearest double; the order
 * conditions are checked in tests/c/test_splitting.c. */
#include "../internal.h"

#define S 9
/* a[i][j], j < i (row-major, s x s; the rest is 0) */
static const double a[9 * 9] = {
    /* row 1 */
    [1 * S + 0] = 0.00125,
    /* row 2 */
    [2 * S + 0] = 0.0016666666666666668, [2 * S + 1] = 0.0033333333333333335,
    /* row 3 */
    [3 * S + 0] = 0.045, [3 * S + 1] = -0.09, [3 * S + 2] = 0.09,
    /* row 4 */
    [4 * S + 0] = -0.3379798532571243, [4 * S + 1] = 0.8611516478170984,
    [4 * S + 2] = -0.48613644655235316, [4 * S + 3] = 0.0879646519923791,
    /* row 5 */
    [5 * S + 0] = 0.7461462641043086, [5 * S + 1] = -1.804347430246737,
    [5 * S + 2] = 1.2761518285888953, [5 * S + 3] = -0.031220932716737166,
    [5 * S + 4] = 0.05827027027027027,
    /* row 6 */
    [6 * S + 0] = -1.2551623461807584, [6 * S + 1] = 3.257463187064823,
    [6 * S + 2] = -2.068866619575089, [6 * S + 3] = 0.4206478455603251,
    [6 * S + 4] = -0.018382978723404254, [6 * S + 5] = 0.06930091185410335,
    /* row 7 */
    [7 * S + 0] = 3.772901830095941, [7 * S + 1] = -9.669613121677195,
    [7 * S + 2] = 6.7991544547851674, [7 * S + 3] = -0.8490343907823893,
    [7 * S + 4] = 0.4671734865470852, [7 * S + 5] = -0.04939742152466368,
    [7 * S + 6] = 0.028815162556053812,
    /* row 8 */
    [8 * S + 0] = 0.028092718568909044, [8 * S + 2] = 0.1457093253968254,
    [8 * S + 3] = 0.1529431216931217, [8 * S + 4] = 0.09151785714285714,
    [8 * S + 5] = 0.06554705215419501, [8 * S + 6] = 0.01618992504409171,
};
static const double b[9] = {
    0.028092718568909044, 0.0, 0.1457093253968254, 0.1529431216931217, 0.09151785714285714,
    0.06554705215419501, 0.01618992504409171, 0.0, 0.0,
};
static const double bp[9] = {
    0.028092718568909044, 0.0, 0.1618992504409171, 0.2184901738473167, 0.18303571428571427,
    0.2184901738473167, 0.1618992504409171, 0.028092718568909044, 0.0,
};
static const double c[9] = {
    0.0, 0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.0,
};

static const fpl_rkn_table table = {S, a, b, bp, c};

const fpl_splitting fpl_scheme_dprkn8 = {
    .name = "dprkn8",
    .order = 8,
    .n_kicks = S,
    .run_setup = fpl_rkn_run_setup,
    .state_free = fpl_rkn_state_free,
    .reference = "Dormand, El-Mikkawy & Prince, IMA J. Numer. Anal. 7, 423 (1987), "
                 "RKN8(6) (order 8, not symplectic)",
    .rkn = &table,
};
