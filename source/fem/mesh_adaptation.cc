#include <twinflow/core/errors.h>
#include <twinflow/fem/mesh_adaptation.h>

#include <deal.II/base/mpi.h>

#include <cmath>
#include <limits>

namespace twinflow::fem
{
  using namespace dealii;

  void MeshAdaptationParameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Minimum level", "0", Patterns::Integer(0, 14),
                      "Coarsest refinement level (of the scene's coarse mesh) away from every interface.");
    prm.declare_entry("Maximum level", "0", Patterns::Integer(0, 14),
                      "Refinement level in the bands around the interfaces (solid surface phi_s = 0, free "
                      "surface phi = 0). 0: no adaptation, the mesh stays uniform at 'Global refinements'.");
    prm.declare_entry("Band width", "4", Patterns::Double(0),
                      "Half-width c of the refined band |phi| < c h_max, in cells of the maximum level. It must "
                      "cover the smoothed interface (FEM/Immersed boundary/Interface width) plus the distance "
                      "the interface travels between adaptations.");
    prm.declare_entry("Interval", "10", Patterns::Integer(1),
                      "Steps between adaptation checks (a fixed interface refines once).");
    prm.declare_entry("Move fraction", "0.25", Patterns::Double(0, 1),
                      "Re-adapt when an interface has moved more than this fraction of the band half-width.");
    prm.declare_entry("Kelly threshold", "0", Patterns::Double(0, 1),
                      "Cells whose Kelly indicator of the velocity exceeds this fraction of the largest one refine "
                      "on top of the bands, up to the maximum level (a threshold relative to the global maximum "
                      "marks the same cells on any number of ranks); 0: bands only. With it, the mesh is "
                      "re-adapted every 'Interval' steps.");
  }

  void MeshAdaptationParameters::parse(ParameterHandler &prm)
  {
    minimum_level  = prm.get_integer("Minimum level");
    maximum_level  = prm.get_integer("Maximum level");
    band_width     = prm.get_double("Band width");
    interval       = prm.get_integer("Interval");
    move_fraction  = prm.get_double("Move fraction");
    kelly_threshold = prm.get_double("Kelly threshold");
    require(maximum_level == 0 || minimum_level <= maximum_level, "FEM/Mesh adaptation/Minimum level",
            std::to_string(minimum_level),
            "the minimum level must not exceed the maximum level (" + std::to_string(maximum_level) + ")");
    require(maximum_level == 0 || band_width > 0, "FEM/Mesh adaptation/Band width", prm.get("Band width"),
            "the band must be wider than 0 cells");
  }

  template <int dim>
  MeshAdaptation<dim>::MeshAdaptation(parallel::distributed::Triangulation<dim> &tria,
                                      const MeshAdaptationParameters            &parameters)
    : tria(tria), prm(parameters)
  {
    // Coarse cells: the smallest edge-length equivalent (cells are squares/cubes here).
    double h = std::numeric_limits<double>::max();
    for (const auto &cell : tria.cell_iterators_on_level(0))
      h = std::min(h, cell->diameter() / std::sqrt(double(dim)));
    coarse_cell_size = h;
  }

  template <int dim>
  double MeshAdaptation<dim>::finest_cell_size() const
  {
    return coarse_cell_size / double(1u << prm.maximum_level);
  }

  template <int dim>
  bool MeshAdaptation<dim>::in_band(const typename Triangulation<dim>::active_cell_iterator &cell) const
  {
    const double reach = 0.5 * cell->diameter() + band_half_width();
    for (const auto *i : tracked)
      if (std::abs(i->cell_distance(cell)) < reach)
        return true;
    return false;
  }

  template <int dim>
  bool MeshAdaptation<dim>::mark(const Vector<float> *indicator)
  {
    const int lo = prm.minimum_level, hi = prm.maximum_level;
    double threshold = std::numeric_limits<double>::max();
    if (indicator != nullptr && prm.kelly_threshold > 0)
    {
      float largest = 0;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          largest = std::max(largest, (*indicator)[cell->active_cell_index()]);
      threshold = prm.kelly_threshold * Utilities::MPI::max(double(largest), tria.get_communicator());
    }
    for (const auto &cell : tria.active_cell_iterators())
    {
      cell->clear_refine_flag();
      if (cell->is_locally_owned() && indicator != nullptr && (*indicator)[cell->active_cell_index()] > threshold)
        cell->set_refine_flag();
    }
    for (const auto &cell : tria.active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      cell->clear_coarsen_flag();
      const int level = cell->level();
      if (in_band(cell))
        cell->set_refine_flag();
      else if (!cell->refine_flag_set() && level > lo)
        cell->set_coarsen_flag();
      if (cell->refine_flag_set() && level >= hi)
        cell->clear_refine_flag();
      if (level < lo)
        cell->set_refine_flag(); // below the minimum level (e.g. a coarse start)
    }
    // A coarsen flag takes effect only when all siblings carry it: count what p4est will do.
    tria.prepare_coarsening_and_refinement();
    bool effective = false;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && (cell->refine_flag_set() || cell->coarsen_flag_set()))
        effective = true;
    return Utilities::MPI::logical_or(effective, tria.get_communicator());
  }

  template <int dim>
  bool MeshAdaptation<dim>::due(const unsigned int step) const
  {
    if (step % prm.interval != 0)
      return false;
    if (prm.kelly_threshold > 0)
      return true;
    for (const auto *i : tracked)
      if (i->displacement_since_adaptation() > prm.move_fraction * band_half_width())
        return true;
    return false;
  }

  template <int dim>
  void MeshAdaptation<dim>::mark_adapted()
  {
    for (auto *i : tracked)
      i->mark_adapted();
  }

  template class MeshAdaptation<2>;
  template class MeshAdaptation<3>;
} // namespace twinflow::fem
