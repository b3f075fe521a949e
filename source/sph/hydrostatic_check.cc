#include <twinflow/core/errors.h>
#include <twinflow/sph/hydrostatic_check.h>

#include <algorithm>
#include <cmath>

namespace twinflow::sph
{
  template <int dim>
  HydrostaticCheck hydrostatic_check(const Scene &scene, const double dx, const HostParticles<dim> &P,
                                     const bool surface_offset)
  {
    constexpr int up = dim - 1;
    if (!scene.fluid_region)
      throw InputError("References/Hydrostatic pressure: the check needs Fluids/Initial region of fluid 1 "
                       "(H is the top of that region)");
    for (int d = 0; d < dim; ++d)
      if (d != up && scene.gravity[d] != 0)
        throw InputError("References/Hydrostatic pressure: the check needs Forces/Gravity along the last "
                         "coordinate (0, -g in 2D; 0, 0, -g in 3D)");
    if (!(scene.gravity[up] < 0))
      throw InputError("References/Hydrostatic pressure: the check needs Forces/Gravity pointing down the last "
                       "coordinate (0, -g in 2D; 0, 0, -g in 3D)");

    const double rho    = scene.fluids.front().density;
    const double g      = -scene.gravity[up];
    const double H      = scene.fluid_region->upper[up];
    const double margin = hydrostatic_bulk_margin * dx;

    HydrostaticCheck c;
    double           error2 = 0, speed2 = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
    {
      if (P.kind[i] != ParticleKind::fluid)
        continue;
      double u2 = 0;
      for (int d = 0; d < dim; ++d)
        u2 += P.u[i][d] * P.u[i][d];
      const double speed = std::sqrt(u2);
      c.max_speed        = std::max(c.max_speed, speed);
      speed2 += u2;
      ++c.fluid_particles;

      // bulk: more than `margin` below the surface and away from the walls
      const double y    = P.x[i][up];
      bool         bulk = y <= H - margin;
      for (int d = 0; d < dim && bulk; ++d)
        if (!scene.periodic[d])
          bulk = P.x[i][d] >= scene.domain.lower[d] + margin && P.x[i][d] <= scene.domain.upper[d] - margin;
      if (!bulk)
        continue;
      const double exact = rho * g * (H - (surface_offset ? 0.0 : 0.5 * dx) - y);
      const double e     = std::abs(P.p[i] - exact) / exact;
      c.max_relative_error = std::max(c.max_relative_error, e);
      c.bulk_max_speed     = std::max(c.bulk_max_speed, speed);
      error2 += e * e;
      ++c.bulk_particles;
    }
    // no bulk particle: nothing measured, and NaN fails every tolerance
    c.rms_relative_error = c.bulk_particles ? std::sqrt(error2 / c.bulk_particles) : std::nan("");
    if (c.bulk_particles == 0)
      c.max_relative_error = std::nan("");
    c.rms_speed          = std::sqrt(speed2 / std::max<std::size_t>(1, c.fluid_particles));
    return c;
  }

  template HydrostaticCheck hydrostatic_check<2>(const Scene &, double, const HostParticles<2> &, bool);
  template HydrostaticCheck hydrostatic_check<3>(const Scene &, double, const HostParticles<3> &, bool);
} // namespace twinflow::sph
