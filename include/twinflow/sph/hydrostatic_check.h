#pragma once
/**
 * @file hydrostatic_check.h
 * Hydrostatic reference check of an SPH fluid at rest (scene entry References/Hydrostatic
 * pressure, tests/sph/test_still_water.cc): the pressure of the bulk particles against
 * the hydrostatic pressure below the discrete free surface. One implementation for the test
 * and for the run's summary.
 */
#include <twinflow/core/scene.h>
#include <twinflow_sph/engine.h>

#include <cstddef>

namespace twinflow::sph
{
  /// Outcome of hydrostatic_check(): pressure errors over the bulk, speeds of the fluid.
  struct HydrostaticCheck
  {
    std::size_t bulk_particles  = 0;   ///< fluid particles in the bulk (where the error is measured)
    std::size_t fluid_particles = 0;
    double      max_relative_error = 0;  ///< max over the bulk of |p - p_exact| / p_exact
    double      rms_relative_error = 0;  ///< RMS over the bulk of |p - p_exact| / p_exact
    double      bulk_max_speed     = 0;  ///< max |u| over the bulk [m/s]
    double      max_speed          = 0;  ///< max |u| over all fluid particles [m/s]
    double      rms_speed          = 0;  ///< RMS |u| over all fluid particles [m/s]
  };

  /// Bulk margin of hydrostatic_check(), in particle spacings.
  inline constexpr double hydrostatic_bulk_margin = 4;

  /**
   * Compares the pressure of the fluid particles of @p particles with the hydrostatic
   * pressure of @p scene's initial fluid region (fluid 1 density rho, gravity g along -e_{dim-1}):
   *
   *   p_exact(y) = rho |g| (H_0 - y),   H_0 = H with @p surface_offset, else H - dx/2,
   *
   * H the top of Fluids/Initial region of fluid 1 and y the vertical (last) coordinate. The
   * centres of the top particle layer (the free-surface particles) lie at H - dx/2. With
   * EngineSettings::offsets_surface() (@p surface_offset) they carry the pressure of the half
   * spacing above them and p = 0 lies at H, the top of the liquid; otherwise (standard
   * operators, the paper's form) p = 0 is imposed at their centres. The bulk are the fluid
   * particles more than hydrostatic_bulk_margin spacings @p dx below H and away from every
   * non-periodic wall of the domain box (the
   * bottom included); without bulk particles the errors are NaN. Throws InputError if the scene has no initial fluid region or its
   * gravity is not along -e_{dim-1}.
   */
  template <int dim>
  HydrostaticCheck hydrostatic_check(const Scene &scene, double dx, const HostParticles<dim> &particles,
                                     bool surface_offset);
} // namespace twinflow::sph
