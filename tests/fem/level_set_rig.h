#pragma once
// The level-set physics around a frozen velocity (tests of the transports and corrections).
#include <twinflow/fem/level_set.h>
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>

#include <cmath>
#include <memory>

namespace twinflow::testing
{
  using namespace dealii;
  using namespace twinflow::fem;

  /// Rigid rotation about (0.5, 0.5), one turn per second.
  class Rotation : public Function<2>
  {
  public:
    Rotation() : Function<2>(2) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      const double w = 2 * numbers::PI;
      return c == 0 ? -w * (p[1] - 0.5) : w * (p[0] - 0.5);
    }
  };

  /// LeVeque's single vortex, reversed at T/2: ψ = sin²(πx) sin²(πy) cos(πt/T)/π,
  /// u = (−∂ψ/∂y, ∂ψ/∂x); the disk is stretched into a spiral and comes back at t = T.
  class SingleVortex : public Function<2>
  {
  public:
    explicit SingleVortex(double period) : Function<2>(2), period(period) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      const double pi = numbers::PI, x = p[0], y = p[1], r = std::cos(pi * get_time() / period);
      return c == 0 ? -2 * std::sin(pi * x) * std::sin(pi * x) * std::sin(pi * y) * std::cos(pi * y) * r
                    : 2 * std::sin(pi * x) * std::cos(pi * x) * std::sin(pi * y) * std::sin(pi * y) * r;
    }
    double period;
  };

  /// The disk of the single vortex (centre (0.5, 0.75), R = 0.15), negative inside.
  class VortexDisk : public Function<2>
  {
  public:
    double value(const Point<2> &p, unsigned int = 0) const override { return p.distance(Point<2>(0.5, 0.75)) - 0.15; }
  };

  /// Zalesak's slotted disk (centre (0.5, 0.75), R = 0.15, slot 0.06 wide reaching y = 0.85
  /// from below), negative inside: CSG of signed distances (exact sign, distance near Γ).
  class SlottedDisk : public Function<2>
  {
  public:
    double value(const Point<2> &p, unsigned int = 0) const override
    {
      const double disk = p.distance(Point<2>(0.5, 0.75)) - 0.15;
      // slot: |x − 0.5| < 0.03, y < 0.85
      const double sx = std::abs(p[0] - 0.5) - 0.03, sy = p[1] - 0.85;
      const double slot = std::max(sx, sy) <= 0 ? std::max(sx, sy)
                                                : std::hypot(std::max(sx, 0.0), std::max(sy, 0.0));
      return std::max(disk, -slot);
    }
  };

  class Circle : public Function<2>
  {
  public:
    explicit Circle(double scale) : scale(scale) {}
    double value(const Point<2> &p, unsigned int = 0) const override
    {
      return scale * (p.distance(Point<2>(0.5, 0.5)) - 0.25);
    }
    double scale;
  };

  /// The level-set physics on the unit square (n × n cells) around a frozen Navier–Stokes
  /// state that only provides the velocity.
  struct LevelSetRig
  {
    parallel::distributed::Triangulation<2> tria{MPI_COMM_WORLD};
    LevelSetParameters                      prm;
    ConstantMaterial<2>                     material{1000, 1e-3};
    NavierStokesParameters                  nsp;
    std::unique_ptr<NavierStokes<2>>        flow;
    std::unique_ptr<LevelSetSpace<2>>       space;
    std::unique_ptr<NclsTransport<2>>       ncls;
    std::unique_ptr<VofTransport<2>>        vof;
    std::unique_ptr<Redistancing<2>>        redistance;
    std::unique_ptr<MassCorrection<2>>      correction;

    LevelSetRig(unsigned int refinements, const Function<2> &phi0, const Function<2> &velocity, bool mass_correction = true,
                unsigned int redistancing_interval = 1, bool far_field_redistancing = false)
    {
      prm.far_field_only = far_field_redistancing;
      GridGenerator::hyper_cube(tria, 0, 1, true);
      tria.refine_global(refinements);
      prm.mass_correction = mass_correction;
      prm.redistancing_interval = redistancing_interval;
      flow  = std::make_unique<NavierStokes<2>>(tria, nsp, material);
      space = std::make_unique<LevelSetSpace<2>>(tria, prm, nullptr);
      ncls  = std::make_unique<NclsTransport<2>>(*space, *flow);
      vof   = std::make_unique<VofTransport<2>>(*space, *flow, std::set<types::boundary_id>());
      redistance = std::make_unique<Redistancing<2>>(*space, *ncls);
      correction = std::make_unique<MassCorrection<2>>(*space, *ncls, *vof);
      for (FieldPhysics<2> *p : std::vector<FieldPhysics<2> *>{space.get(), flow.get(), ncls.get(), vof.get(),
                                                                redistance.get(), correction.get()})
        p->setup_dofs();
      Functions::ZeroFunction<2> zero(1);
      flow->initialize(velocity, zero, 0.0, &velocity, 1.0); // u^n = u^{n-1}: the midpoint velocity
      ncls->initialize(phi0);
      TrilinosWrappers::MPI::Vector theta;
      space->reinit_ghosted(theta);
      space->project_heaviside(ncls->value(), theta);
      vof->set(theta);
    }

    void step(double dt)
    {
      for (FieldPhysics<2> *p : std::vector<FieldPhysics<2> *>{ncls.get(), vof.get(), redistance.get(), correction.get()})
        p->advance(dt);
    }

    /// ∫|H(φ) − H(φ_ref)| with the sharp Heaviside (area between the two shapes).
    double shape_error(const Function<2> &reference) const
    {
      const QGauss<2>     quad(6);
      FEValues<2>         fev(space->mapping(), space->fe(), quad, update_values | update_JxW_values | update_quadrature_points);
      std::vector<double> phi(quad.size());
      double              e = 0;
      for (const auto &cell : space->dof_handler().active_cell_iterators())
        if (cell->is_locally_owned())
        {
          fev.reinit(cell);
          fev.get_function_values(ncls->value(), phi);
          for (unsigned int q = 0; q < quad.size(); ++q)
            e += std::abs(double(phi[q] < 0) - double(reference.value(fev.quadrature_point(q)) < 0)) * fev.JxW(q);
        }
      return Utilities::MPI::sum(e, MPI_COMM_WORLD);
    }
  };

  struct ZalesakResult
  {
    double shape_error, volume_change;
  };

  inline ZalesakResult rotate_zalesak(unsigned int refinements, bool mass_correction)
  {
    SlottedDisk disk;
    Rotation    rotation;
    // A rigid rotation keeps φ a distance function: redistancing every 20 steps (each call moves
    // the zero level by ~0.01 h; every step, 800 calls per turn cost 42 % of the area at 64²).
    LevelSetRig rig(refinements, disk, rotation, mass_correction, 20);
    rig.redistance->redistance();
    TrilinosWrappers::MPI::Vector theta; // θ of the redistanced initial level set
    rig.space->reinit_ghosted(theta);
    rig.space->project_heaviside(rig.ncls->value(), theta);
    rig.vof->set(theta);
    const double v0    = rig.space->water_volume(rig.ncls->value());
    const double h     = 1.0 / (1u << refinements);
    const unsigned int steps = std::lround(1.0 / (0.5 * h / (2 * numbers::PI * 0.5)));
    for (unsigned int k = 0; k < steps; ++k)
      rig.step(1.0 / steps);
    const double v1 = rig.space->water_volume(rig.ncls->value());
    return {rig.shape_error(disk), (v1 - v0) / v0};
  }

  /// The single vortex over one period T (CFL 0.5 at the largest speed, 1): shape error against
  /// the initial disk and the relative water-volume change.
  inline ZalesakResult reverse_vortex(unsigned int refinements, double period, bool mass_correction)
  {
    VortexDisk  disk;
    SingleVortex vortex(period);
    LevelSetRig rig(refinements, disk, vortex, mass_correction, 20);
    const double v0    = rig.space->water_volume(rig.ncls->value());
    const double h     = 1.0 / (1u << refinements);
    const unsigned int steps = std::lround(period / (0.5 * h));
    const double       dt    = period / steps;
    Functions::ZeroFunction<2> zero(1);
    for (unsigned int k = 0; k < steps; ++k)
    {
      // the frozen flow carries u(t_k) and u(t_{k+1}): the transport's midpoint velocity
      rig.flow->initialize(vortex, zero, (k + 1) * dt, &vortex, dt);
      rig.step(dt);
    }
    const double v1 = rig.space->water_volume(rig.ncls->value());
    return {rig.shape_error(disk), (v1 - v0) / v0};
  }
} // namespace twinflow::testing
