// FemSimulation<dim>: the free surface (two phases, level set of Algorithm 1) — composition,
// initial state and monitors.
#pragma once
#include <twinflow/core/errors.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/geometry/box.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/snapshots.h>

#include <fstream>
#include <iomanip>

#include <deal.II/base/function.h>

#include <algorithm>
#include <cmath>

namespace twinflow::fem
{
  using namespace dealii;

  namespace internal
  {
    /// The initial water region of the scene as a box whose faces on the domain boundary are
    /// pushed outwards (a wall is not a free surface): lower/upper corners.
    template <int dim>
    std::pair<geometry::Vec<dim>, geometry::Vec<dim>> water_box(const Scene &scene)
    {
      geometry::Vec<dim> lo, hi;
      const double       far = 1e3 * (1 + scene.domain.upper[0] - scene.domain.lower[0]);
      for (int d = 0; d < dim; ++d)
      {
        const double span = scene.domain.upper[d] - scene.domain.lower[d], tol = 1e-12 * span;
        lo[d] = scene.fluid_region->lower[d] <= scene.domain.lower[d] + tol ? scene.domain.lower[d] - far
                                                                            : scene.fluid_region->lower[d];
        hi[d] = scene.fluid_region->upper[d] >= scene.domain.upper[d] - tol ? scene.domain.upper[d] + far
                                                                            : scene.fluid_region->upper[d];
      }
      return {lo, hi};
    }

    /// Signed distance to the initial free surface: negative in the water (the paper's sign).
    template <int dim>
    class InitialWaterDistance : public Function<dim>
    {
    public:
      explicit InitialWaterDistance(const Scene &scene)
      {
        const auto [lo, hi] = water_box<dim>(scene);
        box                 = geometry::Box<dim>(lo, hi);
      }
      double value(const Point<dim> &p, unsigned int = 0) const override
      {
        geometry::Vec<dim> x;
        for (int d = 0; d < dim; ++d)
          x[d] = p[d];
        return box.signed_distance(x);
      }

    private:
      geometry::Box<dim> box;
    };

    /// Hydrostatic pressure of water under air, p = 0 at the top of the domain: |g| times the
    /// column of ρ(H_ε(φ₀)) above the point, with the ε of the interface cells, so that the
    /// discrete state starts in balance (a sharp-interface pressure against the smoothed ρ
    /// would push the light side of the band at ∼ τ g ρ_w/ρ(φ) in the first step).
    template <int dim>
    class TwoPhaseHydrostatic : public Function<dim>
    {
    public:
      TwoPhaseHydrostatic(const Scene &scene, const TwoFluids &f, unsigned int axis,
                          std::shared_ptr<Function<dim>> distance, double epsilon)
        : f(f), axis(axis), top(scene.domain.upper[axis]), g(std::abs(scene.gravity[axis]))
        , distance(std::move(distance)), eps(epsilon)
      {}
      double value(const Point<dim> &p, unsigned int = 0) const override
      {
        // Column [p, top]: exact for air where φ > ε; Gauss–Legendre (2 points) on sub-intervals
        // of ε/8 elsewhere.
        const double length = top - p[axis];
        if (length <= 0)
          return 0;
        const unsigned int n = std::max(1u, static_cast<unsigned int>(std::ceil(8 * length / eps)));
        const double       h = length / n, gp = 0.5 / std::sqrt(3.0);
        double             column = 0;
        Point<dim>         x      = p;
        for (unsigned int k = 0; k < n; ++k)
          for (const double s : {0.5 - gp, 0.5 + gp})
          {
            x[axis] = p[axis] + (k + s) * h;
            const double H = smoothed_heaviside(distance->value(x), eps);
            column += 0.5 * h * (f.rho_water + (f.rho_air - f.rho_water) * H);
          }
        return g * column;
      }

    private:
      TwoFluids                      f;
      unsigned int                   axis;
      double                         top, g;
      std::shared_ptr<Function<dim>> distance;
      double                         eps;
    };
  } // namespace internal

  template <int dim>
  void FemSimulation<dim>::compose_free_surface()
  {
    if (body_fitted)
      throw InputError("Fluids/Number of fluids = 2 with Domain/Geometry = " + scene.geometry +
                       ": the FEM free surface needs a box mesh (solids enter as immersed boundaries); allowed: box");
    if (!scene.fluid_region)
      throw InputError("Fluids/Initial region of fluid 1: required with 2 fluids (the initial water region, "
                       "'x0, y0; x1, y1'), the FEM level set starts from its signed distance");
    int axis = -1, count = 0;
    for (unsigned int d = 0; d < dim; ++d)
      if (scene.gravity[d] != 0)
      {
        axis = d;
        ++count;
      }
    if (count != 1 || scene.gravity[axis] > 0)
      throw InputError("Forces/Gravity: a free surface needs gravity along one axis pointing to the lower corner "
                       "(e.g. 0, -9.81); got a direction the FEM level set does not know as 'down'");
    vertical_axis = axis;
    double diameter_sq = 0;
    for (unsigned int d = 0; d < dim; ++d)
      diameter_sq += (scene.domain.upper[d] - scene.domain.lower[d]) * (scene.domain.upper[d] - scene.domain.lower[d]);
    domain_diameter = std::sqrt(diameter_sq);
    two_fluids    = {scene.fluids[0].density, scene.fluids[0].viscosity, scene.fluids[1].density,
                     scene.fluids[1].viscosity};
    if (prm.adaptation.enabled() && prm.level_set.interface_width > prm.adaptation.band_width)
      throw InputError("FEM/Mesh adaptation/Band width = " + std::to_string(prm.adaptation.band_width) +
                       ": the band must cover the smoothed free surface (FEM/Level set/Interface width = " +
                       std::to_string(prm.level_set.interface_width) + " cells)");
    initial_water_distance = std::make_shared<internal::InitialWaterDistance<dim>>(scene);
    ls_space = std::make_unique<LevelSetSpace<dim>>(tria, prm.level_set, initial_water_distance);
    material = std::make_unique<TwoPhaseMaterial<dim>>(*ls_space, two_fluids);
  }

  template <int dim>
  void FemSimulation<dim>::initialize_free_surface()
  {
    ncls->initialize(*initial_water_distance);
    TrilinosWrappers::MPI::Vector theta;
    ls_space->reinit_ghosted(theta);
    ls_space->project_heaviside(ncls->value(), theta);
    vof->set(theta);
  }

  template <int dim>
  FreeSurfaceMeasures FemSimulation<dim>::free_surface_measures() const
  {
    Tensor<1, dim> g;
    for (unsigned int d = 0; d < dim; ++d)
      g[d] = scene.gravity[d];
    return measure_free_surface(*ls_space, *ncls, *navier_stokes, two_fluids, g, scene.domain.lower[vertical_axis]);
  }

  template <int dim>
  void FemSimulation<dim>::record_free_surface(const double dt, const double divergence)
  {
    const double              t = navier_stokes->time();
    const FreeSurfaceMeasures m = free_surface_measures();
    // the system: both phases and the moving bodies (the fluid inside a body is its ghost flow)
    const double e_water = m.kinetic_water + m.potential_water,
                 e_all   = m.kinetic_all + m.potential_all + bodies_energy();
    if (navier_stokes->n_steps() == 0 || initial_volume == 0)
    {
      initial_volume = m.water_volume;
      initial_energy = e_all;
    }
    const double drift = (m.water_volume - initial_volume) / initial_volume;
    const double rise  = (e_all - initial_energy) / std::abs(initial_energy);
    worst_volume_drift = std::max(worst_volume_drift, std::abs(drift));
    worst_energy_rise  = std::max(worst_energy_rise, rise);
    worst_phi_range    = std::max({worst_phi_range, -m.phi_min / domain_diameter, m.phi_max / domain_diameter});
    energy_csv->append({t, m.kinetic_water, m.potential_water, e_water, e_all, divergence, dt,
                        double(tria.n_global_active_cells())});
    front_csv->append({t, m.x_front, m.max_water_speed, m.x_foremost, navier_stokes->max_velocity()});
    std::vector<double> volume_row{t, m.water_volume, drift, correction->last_correction(),
                                   double(correction->last_newton_iterations()), m.phi_min, m.phi_max};
    if (ibm)
      volume_row.push_back(ls_space->water_volume(ncls->value(), [this](const Point<dim> &x) {
        for (const auto &s : ibm->solids())
          if (s->distance(x) < 0)
            return true;
        return false;
      }));
    volume_csv->append(volume_row);
    front_time.push_back(t);
    front_position.push_back(m.x_front);
    result.monitors["water volume"]               = m.water_volume;
    result.monitors["water volume drift (max)"]   = worst_volume_drift;
    result.monitors["energy rise (max)"]          = worst_energy_rise;
    result.monitors["level set |phi| / diameter (max)"] = worst_phi_range;
    result.monitors["x_front"]                    = m.x_front;
    result.monitors["kinetic energy"]             = m.kinetic_water;
    result.monitors["total energy"]               = e_water;
    result.monitors["system energy"]              = e_all;
  }

  template <int dim>
  void FemSimulation<dim>::write_snapshot(const double time) const
  {
    std::vector<double> local;
    for (const auto &[i, x] : ls_space->support_points())
    {
      for (unsigned int d = 0; d < dim; ++d)
        local.push_back(x[d]);
      local.push_back(ncls->value()[i]);
    }
    // 2D: the active cells as quadrilaterals (vertices 0, 1, 3, 2: around the cell), so that the
    // snapshot shows the mesh and its refinement bands
    std::vector<double> local_cells;
    if (dim == 2)
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int v : {0u, 1u, 3u, 2u})
            for (unsigned int d = 0; d < dim; ++d)
              local_cells.push_back(cell->vertex(v)[d]);
    const auto parts      = Utilities::MPI::gather(comm, local, 0);
    const auto cell_parts = Utilities::MPI::gather(comm, local_cells, 0);
    if (!io::is_root_process(comm))
      return;
    io::ensure_directory(dir + "/snapshots");
    const std::string file = dir + "/snapshots/" + io::snapshot_file_name("fem", time);
    std::ofstream     out(file);
    out << "# twinflow FEM snapshot: level set phi at the nodes (water where phi < 0), requested t = " << time
        << " s, written at t = " << navier_stokes->time() << " s\n";
    out << (dim == 2 ? "x [m],y [m],phi [m]\n" : "x [m],y [m],z [m],phi [m]\n");
    out << std::setprecision(9);
    for (const auto &part : parts)
      for (std::size_t k = 0; k + dim < part.size() + 0; k += dim + 1)
      {
        for (unsigned int d = 0; d <= dim; ++d)
          out << part[k + d] << (d == dim ? '\n' : ',');
      }
    if (!out)
      throw std::runtime_error("cannot write the snapshot " + file);
    if (dim == 2)
    {
      const std::string cells_file = file.substr(0, file.size() - 4) + "_cells.csv";
      std::ofstream     cells(cells_file);
      cells << "# twinflow FEM snapshot: the active cells (corners in order around each cell) at t = "
            << navier_stokes->time() << " s\n";
      cells << "x0 [m],y0 [m],x1 [m],y1 [m],x2 [m],y2 [m],x3 [m],y3 [m]\n" << std::setprecision(9);
      for (const auto &part : cell_parts)
        for (std::size_t k = 0; k + 8 <= part.size(); k += 8)
          for (unsigned int j = 0; j < 8; ++j)
            cells << part[k + j] << (j == 7 ? '\n' : ',');
      if (!cells)
        throw std::runtime_error("cannot write the snapshot " + cells_file);
    }
  }
} // namespace twinflow::fem
