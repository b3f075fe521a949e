#include <twinflow/sph/particle_setup.h>

#include <twinflow/core/errors.h>
#include <twinflow/geometry/geometry.h>
#include <twinflow/sph/open_boundary.h>

#include <cmath>

namespace twinflow::sph
{
  template <int dim>
  DomainBox<dim> domain_box(const Scene &scene)
  {
    DomainBox<dim> box;
    for (int d = 0; d < dim; ++d)
    {
      box.lower[d]    = scene.domain.lower[d];
      box.upper[d]    = scene.domain.upper[d];
      box.periodic[d] = scene.periodic[d];
    }
    return box;
  }

  namespace
  {
    /// Signed distance to the scene's solids (min over them), +∞ if none; @p which: the
    /// index of the nearest solid.
    template <int dim>
    double solid_distance(const Scene &scene, const geometry::Vec<dim> &x, geometry::Vec<dim> &normal, int &which)
    {
      double best = 1e300;
      which       = -1;
      for (std::size_t k = 0; k < scene.solids.size(); ++k)
      {
        const Solid       &s = scene.solids[k];
        geometry::Vec<dim> c;
        for (int d = 0; d < dim; ++d)
          c[d] = s.center[d];
        double             phi = 1e300;
        geometry::Vec<dim> n   = geometry::Vec<dim>::zero();
        if constexpr (dim == 2)
        {
          if (s.shape == "disk")
          {
            const geometry::Ball<2> b(c, s.radius);
            phi = b.signed_distance(x);
            n   = b.normal(x);
          }
          else
          {
            const geometry::Plate<2> p(c, s.length, s.thickness, s.angle);
            phi = p.signed_distance(x);
            n   = p.normal(x);
          }
        }
        else if (s.shape == "cylinder")
        {
          // axis along z; one that spans a periodic depth is infinite (no caps inside the fluid)
          const double span = scene.domain.upper[2] - scene.domain.lower[2];
          if (scene.periodic[2] && s.length >= span * (1 - 1e-9))
          {
            geometry::Vec<2> c2{{c[0], c[1]}}, x2{{x[0], x[1]}};
            const geometry::Ball<2> b(c2, s.radius);
            phi = b.signed_distance(x2);
            const geometry::Vec<2> n2 = b.normal(x2);
            n   = geometry::Vec<dim>::zero();
            n[0] = n2[0], n[1] = n2[1];
          }
          else
          {
            geometry::Vec<3> c3{{c[0], c[1], c[dim - 1]}}, x3{{x[0], x[1], x[dim - 1]}};
            const geometry::Cylinder cyl(c3, geometry::Vec<3>::unit(2), s.radius, s.length);
            phi = cyl.signed_distance(x3);
            const geometry::Vec<3> n3 = cyl.normal(x3);
            for (int d = 0; d < dim; ++d)
              n[d] = n3[d];
          }
        }
        else
          throw InputError("Solids/" + s.name + "/Shape = " + s.shape +
                           ": this 3D solid is not available in SPH; allowed in 3D: cylinder (axis z)");
        if (phi < best)
        {
          best   = phi;
          normal = n;
          which  = static_cast<int>(k);
        }
      }
      return best;
    }
  } // namespace

  template <int dim>
  std::size_t make_particles(const Scene &scene, const double dx, const int layers, const double rho0,
                             HostParticles<dim> &P)
  {
    P = HostParticles<dim>();
    const OpenFace open = open_face(scene); // throws for the inflow/outflow faces SPH cannot treat
    int                 n[3] = {1, 1, 1}, lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    geometry::Vec<dim>  box_lo, box_hi;
    for (int d = 0; d < dim; ++d)
    {
      const double L = scene.domain.upper[d] - scene.domain.lower[d];
      n[d]           = static_cast<int>(std::lround(L / dx));
      if (std::abs(n[d] * dx - L) > 1e-6 * L)
        throw InputError("SPH/Particle spacing = " + std::to_string(dx) + ": the domain length " + std::to_string(L) +
                         " in direction " + "xyz"[d] + " must be a whole multiple of the spacing");
      lo[d] = scene.periodic[d] ? 0 : -layers;
      hi[d] = scene.periodic[d] ? n[d] : n[d] + layers;
      box_lo[d] = scene.domain.lower[d];
      box_hi[d] = scene.domain.upper[d];
    }
    const geometry::Box<dim> box(box_lo, box_hi);
    // Top of the fluid column: hydrostatic initial pressure below it.
    const int    up    = dim - 1;
    const double g     = -scene.gravity[up];
    const double y_top = scene.fluid_region ? scene.fluid_region->upper[up] : scene.domain.upper[up];
    std::size_t  n_fluid = 0;
    int          i[3]    = {0, 0, 0};
    for (i[2] = dim == 3 ? lo[2] : 0; i[2] < (dim == 3 ? hi[2] : 1); ++i[2])
      for (i[1] = lo[1]; i[1] < hi[1]; ++i[1])
        for (i[0] = lo[0]; i[0] < hi[0]; ++i[0])
        {
          geometry::Vec<dim> x;
          bool               inside = true;
          for (int d = 0; d < dim; ++d)
          {
            x[d] = scene.domain.lower[d] + (i[d] + 0.5) * dx;
            inside = inside && i[d] >= 0 && i[d] < n[d];
          }
          geometry::Vec<dim> n_solid;
          int                solid_index = -1;
          const double       phi_s = solid_distance<dim>(scene, x, n_solid, solid_index);
          int                kind  = -1;
          geometry::Vec<dim> normal = geometry::Vec<dim>::zero();
          if (!inside && open.active() && open.beyond(x[open.axis]))
            continue; // the open top has no wall
          if (!inside)
          {
            kind   = ParticleKind::wall;
            normal = -box.normal(x); // into the fluid
          }
          else if (phi_s < 0)
          {
            if (phi_s > -layers * dx)
            {
              kind   = ParticleKind::solid;
              normal = n_solid;
            }
          }
          else
          {
            bool in_region = true;
            if (scene.fluid_region)
              for (int d = 0; d < dim; ++d)
                in_region = in_region && x[d] > scene.fluid_region->lower[d] && x[d] < scene.fluid_region->upper[d];
            if (in_region)
              kind = ParticleKind::fluid;
          }
          if (kind < 0)
            continue;
          // hydrostatic below the top of the column, BCE markers too (they extrapolate the fluid's)
          P.add(x, geometry::Vec<dim>::zero(), rho0 * g * std::max(0.0, y_top - x[up]),
                rho0, kind, normal, kind == ParticleKind::solid ? solid_index : -1);
          n_fluid += kind == ParticleKind::fluid;
        }
    if (n_fluid == 0)
      throw InputError("Fluids/Initial region of fluid 1: no SPH particle falls inside it at spacing " +
                       std::to_string(dx) + "; enlarge the region or reduce SPH/Particle spacing");
    return n_fluid;
  }

  template DomainBox<2> domain_box<2>(const Scene &);
  template DomainBox<3> domain_box<3>(const Scene &);
  template std::size_t make_particles<2>(const Scene &, double, int, double, HostParticles<2> &);
  template std::size_t make_particles<3>(const Scene &, double, int, double, HostParticles<3> &);
} // namespace twinflow::sph
