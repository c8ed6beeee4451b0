/* Leapfrog / Stormer-Verlet, order 2, one force evaluation per step (drift-kick-drift). */
#include "../internal.h"

static const double drift[] = {0.5, 0.5};
static const double kick[] = {1.0};

const fpl_splitting fpl_scheme_leapfrog = {
    .name = "leapfrog",
    .order = 2,
    .n_kicks = 1,
    .drift = drift,
    .kick = kick,
    .reference = "Verlet, Phys. Rev. 159, 98 (1967)",
};
