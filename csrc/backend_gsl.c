/* placeholder: the gsl back end is being written */
#include "integrator_impl.h"
const fpl_method fpl_methods_gsl[] = {{NULL, 0, NULL, NULL}};
