/* SRKN_14^a of Blanes & Moan, "Practical symplectic partitioned Runge-Kutta and
 * Runge-Kutta-Nystrom methods", J. Comput. Appl. Math. 142 (2002) 313-330 (Table 3): symmetric
 * ABA composition of order 6 with 14 kicks (force evaluations) and 15 drifts,
 *   A(a1) B(b1) A(a2) ... A(a7) B(b7) A(a8) B(b7) A(a7) ... B(b1) A(a1),
 * A = drift (x += h p/m, the kinetic part), B = kick (p += h F(x)). An RKN method: its order 6
 * relies on [B,[B,[B,A]]] = 0, i.e. on B being the potential part, so A and B must not be
 * swapped. a8 = 1 - 2(a1+...+a7) and b7 = 1/2 - (b1+...+b6) as in the paper.
 * Coefficients (all digits the paper gives) cross-checked against Principia
 * (integrators/methods.hpp, BlanesMoan2002SRKN14A, type ABA with A the position update) and
 * SeLaLib (sll_p_order6_tvt, "O6-14 of Blanes", starting with T). */
#include "../internal.h"

#define A1 0.0378593198406116
#define A2 0.102635633102435
#define A3 (-0.0258678882665587)
#define A4 0.314241403071447
#define A5 (-0.130144459517415)
#define A6 0.106417700369543
#define A7 (-0.00879424312851058)
#define A8 0.20730506905689536     /* 1 - 2(a1 + ... + a7), exact in the digits above */
#define B1 0.09171915262446165
#define B2 0.183983170005006
#define B3 (-0.05653436583288827)
#define B4 0.004914688774712854
#define B5 0.143761127168358
#define B6 0.328567693746804
#define B7 (-0.196411466486454234) /* 1/2 - (b1 + ... + b6), exact in the digits above */

static const double drift[] = {A1, A2, A3, A4, A5, A6, A7, A8, A7, A6, A5, A4, A3, A2, A1};
static const double kick[] = {B1, B2, B3, B4, B5, B6, B7, B7, B6, B5, B4, B3, B2, B1};

const fpl_splitting fpl_scheme_srkn14a6 = {
    .name = "srkn14a6",
    .order = 6,
    .n_kicks = 14,
    .drift = drift,
    .kick = kick,
    .reference = "Blanes & Moan, J. Comput. Appl. Math. 142, 313 (2002), SRKN_14^a (order 6)",
};
