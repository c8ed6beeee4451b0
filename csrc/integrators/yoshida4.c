/* Yoshida / Forest-Ruth 4th-order composition of leapfrog, three force evaluations per step:
 * w1 = 1/(2 - 2^(1/3)), w0 = -2^(1/3) w1; kicks (w1, w0, w1), drifts (w1/2, (w0+w1)/2, ...).
 * The paper's integrator for the homogeneous lattice (dt = 0.01). */
#include "../internal.h"

#define CBRT2 1.2599210498948731647672106072782283505702514647015
#define W1 (1.0 / (2.0 - CBRT2))
#define W0 (-CBRT2 / (2.0 - CBRT2))

static const double drift[] = {0.5 * W1, 0.5 * (W0 + W1), 0.5 * (W0 + W1), 0.5 * W1};
static const double kick[] = {W1, W0, W1};

const fpl_splitting fpl_scheme_yoshida4 = {
    .name = "yoshida4",
    .order = 4,
    .n_kicks = 3,
    .drift = drift,
    .kick = kick,
    .reference = "Yoshida, Phys. Lett. A 150, 262 (1990); Forest & Ruth, Physica D 43, 105 (1990)",
};
