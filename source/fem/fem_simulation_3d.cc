// Explicit instantiation of FemSimulation<3>.
#include "fem_simulation_free_surface.templates.h"
#include "fem_simulation.templates.h"
#include "fem_simulation_io.templates.h"

template class twinflow::fem::FemSimulation<3>;
