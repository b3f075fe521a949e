#pragma once
// Initial particles of an SPH scene: fluid lattice and BCE markers (walls, solids).
#include <twinflow/core/scene.h>
#include <twinflow_sph/engine.h>

namespace twinflow::sph
{
  /// Fills @p particles for @p scene with spacing @p dx and @p layers BCE layers (none beyond an
  /// open top, open_boundary.h); the fluid starts at rest with hydrostatic pressure below its
  /// top. Returns the number of fluid particles. Throws InputError for inflow/outflow faces
  /// other than an open top.
  template <int dim>
  std::size_t make_particles(const Scene &scene, double dx, int layers, double rho0, HostParticles<dim> &particles);

  template <int dim>
  DomainBox<dim> domain_box(const Scene &scene);
} // namespace twinflow::sph
