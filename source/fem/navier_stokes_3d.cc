// Explicit instantiation of NavierStokes<3> (split per dimension to keep builds parallel).
#include "navier_stokes.templates.h"
#include "navier_stokes_momentum.templates.h"
#include "navier_stokes_postprocess.templates.h"
#include "navier_stokes_projection.templates.h"
#include "navier_stokes_transfer.templates.h"

template class twinflow::fem::NavierStokes<3>;
