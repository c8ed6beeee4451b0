/* ABA(8,6,4) of Blanes, Casas, Farres, Laskar, Makazaga & Murua, "New families of symplectic
 * splitting methods for numerical integration in dynamical astronomy", Appl. Numer. Math. 68
 * (2013) 58-72. Symmetric ABA composition with s = 7 kicks (force evaluations) and 8 drifts:
 *   A(a1) B(b1) A(a2) B(b2) A(a3) B(b3) A(a4) B(b4) A(a4) B(b3) A(a3) B(b2) A(a2) B(b1) A(a1),
 * A = drift (x += h p/m), B = kick (p += h F(x)), as in Danieli, Many Manda, Mithun & Skokos,
 * Math. Eng. 1, 447 (2019) for FPUT. Order 4 generically; for H = A + eps B the error is
 * O(eps h^8 + eps^2 h^6 + eps^3 h^4) (hence "8,6,4").
 * Coefficients (40 digits, as published) cross-checked against REBOUND src/integrator_saba.c
 * (REB_SABA_8_6_4) and the Skokos-group codes: sum of drifts = sum of kicks = 1.
 *
 * Two tables share the coefficients, because the scheme's orders depend on the split:
 *  "aba864"          A = kinetic drift, B = the whole force (any model). Here B is not small,
 *                    so the order is 4 at every amplitude (only the error constant is small).
 *  "aba864-harmonic" A = exact normal-mode rotation of the harmonic chain, B = the anharmonic
 *                    force (harmonic_split.c; models 1 and 3). B is eps-small at small
 *                    amplitude: the (8,6,4) orders of the method's name. */
#include "../internal.h"

#define A1 0.0711334264982231177779387300061549964174
#define A2 0.241153427956640098736487795326289649618
#define A3 0.521411761772814789212136078067994229991
#define A4 (-0.333698616227678005726562603400438876027)
#define B1 0.183083687472197221961703757166430291072
#define B2 0.310782859898574869507522291054262796375
#define B3 (-0.0265646185119588006972121379164987592663)
#define B4 0.0653961422823734184559721793911134363710

static const double drift[] = {A1, A2, A3, A4, A4, A3, A2, A1};
static const double kick[] = {B1, B2, B3, B4, B3, B2, B1};

const fpl_splitting fpl_scheme_aba864 = {
    .name = "aba864",
    .order = 4,
    .n_kicks = 7,
    .drift = drift,
    .kick = kick,
    .reference = "Blanes, Casas, Farres, Laskar, Makazaga & Murua, Appl. Numer. Math. 68, 58 (2013), "
                 "ABA(8,6,4)",
};

const fpl_splitting fpl_scheme_aba864_harmonic = {
    .name = "aba864-harmonic",
    .order = 4,
    .n_kicks = 7,
    .drift = drift,
    .kick = kick,
    .run_setup = fpl_harmonic_run_setup,
    .state_free = fpl_harmonic_state_free,
    .reference = "Blanes, Casas, Farres, Laskar, Makazaga & Murua, Appl. Numer. Math. 68, 58 (2013), "
                 "ABA(8,6,4) on the near-integrable split harmonic chain + anharmonic force",
};
