// Backend identification (compiled once per backend).
#include <twinflow_sph/backend.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
#define TWINFLOW_SPH_STRINGIFY2(x) #x
#define TWINFLOW_SPH_STRINGIFY(x) TWINFLOW_SPH_STRINGIFY2(x)
  const char *backend_name() { return TWINFLOW_SPH_STRINGIFY(TWINFLOW_SPH_BACKEND); }
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
