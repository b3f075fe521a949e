#pragma once
/**
 * @file neighbor_search.h
 * Uniform cell grid of size κh, particles sorted by cell with Thrust (sort_by_key,
 * vectorised lower/upper bound), neighbour lists in CSR form.
 */
#include <twinflow_sph/backend.h>
#include <twinflow_sph/domain.h>
#include <twinflow_sph/kernel.h>
#include <twinflow_sph/kernel_views.h>

#include <cstddef>

namespace twinflow::sph
{
  namespace TWINFLOW_SPH_BACKEND
  {
    /// Neighbours of each particle in CSR form: the neighbours of i (i itself included)
    /// are indices[offsets[i] .. offsets[i+1]), ascending. offsets has n + 1 entries.
    struct NeighborList
    {
      dvec<int> offsets;
      dvec<int> indices;
      int       n = 0;
      std::size_t n_entries() const { return indices.size(); }
    };

    /// The list of the positions x as the kernels read it (NeighborView, kernel_views.h).
    template <int dim>
    NeighborView<dim> neighbor_view(const dvec<Vec<dim>> &x, const NeighborList &list, const DomainBox<dim> &box,
                                    const CubicSpline<dim> &W)
    {
      NeighborView<dim> nb;
      nb.x       = ptr(x);
      nb.offsets = ptr(list.offsets);
      nb.indices = ptr(list.indices);
      nb.box     = box;
      nb.W       = W;
      return nb;
    }

    /// Builds neighbour lists of all pairs closer than @p radius (minimum image in the
    /// box's periodic directions). In non-periodic directions the grid covers the
    /// particles' bounding box (wall markers may lie outside the box).
    template <int dim>
    class NeighborSearch
    {
    public:
      NeighborSearch(const DomainBox<dim> &box, double radius);
      void build(const dvec<Vec<dim>> &positions, NeighborList &list);

    private:
      DomainBox<dim> box;
      double         radius;
      dvec<int>      cell_of, sorted_index, cell_start, cell_end;
      dvec<int>      buffer;       ///< per particle a slot of `capacity` neighbour indices
      int            capacity = 0; ///< slot length: the longest row seen and a margin
    };
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
