// Cell-list neighbour search (single source for the CPU and CUDA backends).
//
// 1. Grid: cells of size `radius` over the particles' bounding box in non-periodic
//    directions; in periodic directions an integer number of cells n = max(1, ⌊L/radius⌋)
//    of size L/n ≥ radius over the box, cell coordinates wrapped modulo n.
// 2. Cell id per particle; `sort_by_key(cell, index)`; per cell the range of sorted
//    particles by vectorised lower/upper bound over the cell ids.
// 3. Per particle, count the neighbours (|r_ij| < radius, minimum image) in the 3^dim
//    surrounding cells, each distinct cell visited once (periodic directions with fewer
//    than three cells wrap onto the same cell); exclusive scan to CSR offsets; fill and
//    insertion-sort each (short) row ascending.
//
// When the dense grid would have many more cells than particles (a stray particle far
// from the others), cells are hashed into a table of ≈ 2N buckets instead; a bucket then
// may hold particles of several cells, which the distance test sorts out.
#include <twinflow_sph/neighbor_search.h>

#include <thrust/binary_search.h>
#include <thrust/extrema.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/functional.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/reduce.h>
#include <thrust/scan.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/transform.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace neighbor_detail
  {
    /// The cell grid (dense or hashed), copied by value into the functors.
    template <int dim>
    struct Grid
    {
      double    lower[dim];     ///< origin of cell (0, …, 0)
      double    inv_size[dim];  ///< 1 / cell size
      long long n[dim];         ///< cells per direction
      bool      periodic[dim];
      bool      hashed;         ///< bucket = hash(cell) mod n_buckets instead of the dense index
      long long n_buckets;      ///< number of cell ids (dense cells or hash buckets)

      TWINFLOW_HD void cell_of(const geometry::Vec<dim> &x, long long c[dim]) const
      {
        for (int d = 0; d < dim; ++d)
        {
          const double t = ::floor((x[d] - lower[d]) * inv_size[d]);
          if (periodic[d])
          {
            // floor-based wrap (robust to positions a few periods outside the box)
            const double m = t - n[d] * ::floor(t / n[d]);
            c[d]     = (long long)m;
            if (c[d] < 0) c[d] = 0;
            if (c[d] >= n[d]) c[d] = n[d] - 1;
          }
          else
          {
            // clamp (round-off at the upper end, non-finite positions)
            c[d] = t >= 0 ? (t < (double)(n[d] - 1) ? (long long)t : n[d] - 1) : 0;
          }
        }
      }

      TWINFLOW_HD int bucket(const long long c[dim]) const
      {
        if (!hashed)
        {
          long long id = 0;
          for (int d = dim - 1; d >= 0; --d)
            id = id * n[d] + c[d];
          return (int)id;
        }
        const unsigned long long primes[3] = {73856093ULL, 19349663ULL, 83492791ULL};
        unsigned long long       h         = 0;
        for (int d = 0; d < dim; ++d)
          h ^= (unsigned long long)c[d] * primes[d];
        h ^= h >> 29;
        h *= 0xbf58476d1ce4e5b9ULL;
        h ^= h >> 32;
        return (int)(h % (unsigned long long)n_buckets);
      }

      /// Distinct cell ids of the 3^dim cells around @p c (outside cells dropped);
      /// returns how many were written to @p ids.
      TWINFLOW_HD int surrounding(const long long c[dim], int ids[27]) const
      {
        int count = 0;
        int total = 1;
        for (int d = 0; d < dim; ++d)
          total *= 3;
        for (int s = 0; s < total; ++s)
        {
          long long nc[dim];
          int       code   = s;
          bool      inside = true;
          for (int d = 0; d < dim; ++d)
          {
            nc[d] = c[d] + (code % 3) - 1;
            code /= 3;
            if (periodic[d])
            {
              if (nc[d] < 0) nc[d] += n[d];
              if (nc[d] >= n[d]) nc[d] -= n[d];
            }
            else if (nc[d] < 0 || nc[d] >= n[d])
              inside = false;
          }
          if (!inside)
            continue;
          const int id   = bucket(nc);
          bool      seen = false;
          for (int k = 0; k < count; ++k)
            if (ids[k] == id)
              seen = true;
          if (!seen)
            ids[count++] = id;
        }
        return count;
      }
    };

    template <int dim>
    struct CellId
    {
      Grid<dim> grid;
      TWINFLOW_HD int operator()(const geometry::Vec<dim> &x) const
      {
        long long c[dim];
        grid.cell_of(x, c);
        return grid.bucket(c);
      }
    };

    template <int dim>
    struct MinVec
    {
      TWINFLOW_HD geometry::Vec<dim> operator()(const geometry::Vec<dim> &a, const geometry::Vec<dim> &b) const
      {
        geometry::Vec<dim> r;
        for (int d = 0; d < dim; ++d)
          r[d] = a[d] < b[d] ? a[d] : b[d];
        return r;
      }
    };

    template <int dim>
    struct MaxVec
    {
      TWINFLOW_HD geometry::Vec<dim> operator()(const geometry::Vec<dim> &a, const geometry::Vec<dim> &b) const
      {
        geometry::Vec<dim> r;
        for (int d = 0; d < dim; ++d)
          r[d] = a[d] > b[d] ? a[d] : b[d];
        return r;
      }
    };

    /// Finds the neighbours of particle i: counts[i] = their number, and the first `capacity` of
    /// them (in cell order) in its slot buffer[i capacity …] (one pass over the candidate cells;
    /// a row longer than the slot is found again after the slots are enlarged).
    template <int dim>
    struct Neighbours
    {
      Grid<dim>                 grid;
      DomainBox<dim>            box;
      double                    radius2;
      const geometry::Vec<dim> *x;
      const int                *sorted_index, *cell_start, *cell_end;
      int                       capacity;
      int                      *counts, *buffer;

      TWINFLOW_HD void operator()(const int i) const
      {
        const geometry::Vec<dim> xi = x[i];
        long long                c[dim];
        grid.cell_of(xi, c);
        int       ids[27];
        const int n_ids = grid.surrounding(c, ids);
        int       count = 0;
        int      *slot  = buffer + static_cast<long long>(i) * capacity;
        for (int q = 0; q < n_ids; ++q)
          for (int k = cell_start[ids[q]]; k < cell_end[ids[q]]; ++k)
          {
            const int                j = sorted_index[k];
            const geometry::Vec<dim> r = box.difference(xi, x[j]);
            double                   r2 = 0;
            for (int d = 0; d < dim; ++d)
              r2 += r[d] * r[d];
            if (r2 < radius2 || j == i)
            {
              if (count < capacity)
                slot[count] = j;
              ++count;
            }
          }
        counts[i] = count;
      }
    };

    /// Copies the slot of particle i into its CSR row, ascending.
    struct CompactRow
    {
      int        capacity;
      const int *buffer, *offsets;
      int       *indices;

      TWINFLOW_HD void operator()(const int i) const
      {
        const int *slot  = buffer + static_cast<long long>(i) * capacity;
        int       *row   = indices + offsets[i];
        const int  count = offsets[i + 1] - offsets[i];
        // rows are short (tens of entries): insertion sort
        for (int a = 0; a < count; ++a)
        {
          const int v = slot[a];
          int       b = a - 1;
          while (b >= 0 && row[b] > v)
          {
            row[b + 1] = row[b];
            --b;
          }
          row[b + 1] = v;
        }
      }
    };
  } // namespace neighbor_detail

  template <int dim>
  NeighborSearch<dim>::NeighborSearch(const DomainBox<dim> &box_, const double radius_)
    : box(box_), radius(radius_)
  {
    if (!(radius > 0.0) || !std::isfinite(radius))
      throw std::invalid_argument("NeighborSearch: the search radius must be positive and finite");
    for (int d = 0; d < dim; ++d)
      if (box.periodic[d] && !(box.upper[d] > box.lower[d]))
        throw std::invalid_argument("NeighborSearch: a periodic direction needs upper > lower");
  }

  template <int dim>
  void NeighborSearch<dim>::build(const dvec<Vec<dim>> &positions, NeighborList &list)
  {
    using namespace neighbor_detail;
    const int n = static_cast<int>(positions.size());
    list.n      = n;
    list.offsets.assign(n + 1, 0);
    if (n == 0)
    {
      list.indices.clear();
      return;
    }

    // --- grid
    Vec<dim> init_lo, init_hi;
    for (int d = 0; d < dim; ++d)
    {
      init_lo[d] = HUGE_VAL;
      init_hi[d] = -HUGE_VAL;
    }
    const Vec<dim> lo = thrust::reduce(exec, positions.begin(), positions.end(), init_lo, MinVec<dim>());
    const Vec<dim> hi = thrust::reduce(exec, positions.begin(), positions.end(), init_hi, MaxVec<dim>());

    // cells a hair larger than the radius, so that round-off in (x − lower)/size never
    // puts two particles closer than the radius two cells apart
    const double size = radius * (1.0 + 1e-12);
    Grid<dim>    grid;
    double       total_cells = 1;
    for (int d = 0; d < dim; ++d)
    {
      grid.periodic[d] = box.periodic[d];
      if (box.periodic[d])
      {
        const double L   = box.upper[d] - box.lower[d];
        const double nd  = std::floor(L / size);
        grid.n[d]        = nd < 1 ? 1 : static_cast<long long>(nd < 1e9 ? nd : 1e9);
        grid.lower[d]    = box.lower[d];
        grid.inv_size[d] = static_cast<double>(grid.n[d]) / L;
      }
      else
      {
        double extent = hi[d] - lo[d];
        if (!std::isfinite(extent) || extent < 0)
          extent = 0;
        const double nd  = std::floor(extent / size) + 1;
        grid.n[d]        = static_cast<long long>(nd < 1e15 ? nd : 1e15);
        grid.lower[d]    = std::isfinite(lo[d]) ? lo[d] : 0.0;
        grid.inv_size[d] = 1.0 / size;
      }
      total_cells *= static_cast<double>(grid.n[d]);
    }
    const double dense_limit = std::max(8.0 * n, 65536.0);
    grid.hashed              = total_cells > dense_limit;
    if (grid.hashed)
    {
      long long m = 1;
      while (m < 2LL * n)
        m *= 2;
      grid.n_buckets = m;
    }
    else
      grid.n_buckets = static_cast<long long>(total_cells);
    const int n_ids = static_cast<int>(grid.n_buckets);

    // --- sort particles by cell
    cell_of.resize(n);
    sorted_index.resize(n);
    thrust::transform(exec, positions.begin(), positions.end(), cell_of.begin(), CellId<dim>{grid});
    thrust::sequence(exec, sorted_index.begin(), sorted_index.end());
    thrust::sort_by_key(exec, cell_of.begin(), cell_of.end(), sorted_index.begin());
    cell_start.resize(n_ids);
    cell_end.resize(n_ids);
    thrust::counting_iterator<int> first_id(0);
    thrust::lower_bound(exec, cell_of.begin(), cell_of.end(), first_id, first_id + n_ids, cell_start.begin());
    thrust::upper_bound(exec, cell_of.begin(), cell_of.end(), first_id, first_id + n_ids, cell_end.begin());

    // --- find (into slots of the last build's longest row and a margin), scan, compact
    Neighbours<dim> f;
    f.grid         = grid;
    f.box          = box;
    f.radius2      = radius * radius;
    f.x            = ptr(positions);
    f.sorted_index = ptr(sorted_index);
    f.cell_start   = ptr(cell_start);
    f.cell_end     = ptr(cell_end);
    f.counts       = ptr(list.offsets);
    thrust::counting_iterator<int> first(0);
    for (;;)
    {
      buffer.resize(static_cast<std::size_t>(n) * capacity);
      f.capacity = capacity;
      f.buffer   = ptr(buffer);
      thrust::for_each(exec, first, first + n, f);
      const int longest = thrust::reduce(exec, list.offsets.begin(), list.offsets.begin() + n, 0, thrust::maximum<int>());
      if (longest <= capacity)
        break;
      capacity = longest + longest / 4 + 4; // the first build, or rows grown since the last
    }
    // offsets[n] is 0 before the scan, so the in-place exclusive scan leaves the total there.
    thrust::exclusive_scan(exec, list.offsets.begin(), list.offsets.end(), list.offsets.begin());
    const int total = list.offsets[n];
    list.indices.resize(total);
    thrust::for_each(exec, first, first + n, CompactRow{capacity, ptr(buffer), ptr(list.offsets), ptr(list.indices)});
  }

  template class NeighborSearch<2>;
  template class NeighborSearch<3>;
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
