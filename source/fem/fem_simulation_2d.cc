// Explicit instantiation of run_fem<2>.
#include "fem_simulation.templates.h"

template twinflow::fem::FemRunResult
twinflow::fem::run_fem<2>(const twinflow::Scene &, const twinflow::fem::FemParameters &, const std::string &);
