/* fputlab — simulation and analysis of ordered and disordered FPUT lattices.
 * Umbrella header; SUNDIALS-form callbacks are in <fputlab/sundials.h>. */
#ifndef FPUTLAB_H
#define FPUTLAB_H
#include "fputlab/common.h"
#include "fputlab/lattice.h"
#include "fputlab/modes.h"
#include "fputlab/disorder.h"
#include "fputlab/splitting.h"
#include "fputlab/events.h"
#include "fputlab/integrator.h"
#include "fputlab/chaos.h"
#include "fputlab/chaos_batch.h"
#include "fputlab/spectrum.h"
#include "fputlab/reduction.h"
#include "fputlab/io.h"
#endif
