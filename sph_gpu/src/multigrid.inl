// Cell-aggregation multigrid preconditioner (single source for the CPU and CUDA backends);
// see multigrid.h for the method. Every loop is a functor over cells or particles run with
// thrust::for_each; each thread writes only its own row/cell (gathers, no atomics).
#include <twinflow_sph/multigrid.h>

#include <thrust/binary_search.h>
#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/transform_reduce.h>

#include <cmath>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace multigrid_detail
  {
    template <int dim>
    TWINFLOW_HD constexpr int stencil_size() { return dim == 2 ? 9 : 27; }

    /// A structured grid of cells: coordinates ↔ ids, neighbours with periodic wrap.
    template <int dim>
    struct CellGrid
    {
      long long n[dim];
      bool      periodic[dim];

      TWINFLOW_HD void decode(long long id, long long c[dim]) const
      {
        for (int d = 0; d < dim; ++d)
          c[d] = id % n[d], id /= n[d];
      }
      TWINFLOW_HD long long encode(const long long c[dim]) const
      {
        long long id = 0;
        for (int d = dim - 1; d >= 0; --d)
          id = id * n[d] + c[d];
        return id;
      }
      /// Stencil slot of cell J seen from cell I (adjacent, minimum image in periodic directions).
      TWINFLOW_HD int slot(const long long cI[dim], const long long cJ[dim]) const
      {
        int s = 0, stride = 1;
        for (int d = 0; d < dim; ++d)
        {
          long long o = cJ[d] - cI[d];
          if (periodic[d])
          {
            if (o > 1) o -= n[d];
            if (o < -1) o += n[d];
          }
          o = o < -1 ? -1 : (o > 1 ? 1 : o); // guard (cannot happen for coupled particles)
          s += int(o + 1) * stride;
          stride *= 3;
        }
        return s;
      }
      /// Neighbour of cell c in stencil slot s; false if outside a non-periodic direction.
      TWINFLOW_HD bool neighbour(const long long c[dim], int s, long long out[dim]) const
      {
        for (int d = 0; d < dim; ++d)
        {
          out[d] = c[d] + (s % 3) - 1;
          s /= 3;
          if (periodic[d])
            out[d] = out[d] < 0 ? out[d] + n[d] : (out[d] >= n[d] ? out[d] - n[d] : out[d]);
          else if (out[d] < 0 || out[d] >= n[d])
            return false;
        }
        return true;
      }
    };

    template <int dim>
    struct CellOfParticle
    {
      CellGrid<dim> grid;
      double        lower[dim], inv_size[dim];
      TWINFLOW_HD int operator()(const Vec<dim> &x) const
      {
        long long c[dim];
        for (int d = 0; d < dim; ++d)
        {
          double t = ::floor((x[d] - lower[d]) * inv_size[d]);
          if (grid.periodic[d])
            t -= grid.n[d] * ::floor(t / grid.n[d]);
          c[d] = t < 0 ? 0 : (t >= double(grid.n[d] - 1) ? grid.n[d] - 1 : (long long)t);
        }
        return int(grid.encode(c));
      }
    };

    /// Per particle i = sorted[j]: B_i(s) = Σ_{k in row i, cell(k) in slot s of cell(i)} A_ik / A_ii,
    /// i.e. the row i of D⁻¹ A P (P: piecewise constant on the cells) as a 3^dim stencil around
    /// cell(i), stored at the particle's cell-sorted position j.
    template <int dim>
    struct ParticleCoupling
    {
      CellGrid<dim> grid;
      const int    *sorted, *cell, *offsets, *indices;
      const double *values, *inv_diag;
      double       *coupling;
      TWINFLOW_HD void operator()(int j) const
      {
        constexpr int S = stencil_size<dim>();
        const int     i = sorted[j];
        double        acc[S];
        for (int s = 0; s < S; ++s) acc[s] = 0;
        long long cI[dim], cJ[dim];
        grid.decode(cell[i], cI);
        for (int e = offsets[i]; e < offsets[i + 1]; ++e)
        {
          grid.decode(cell[indices[e]], cJ);
          acc[grid.slot(cI, cJ)] += inv_diag[i] * values[e];
        }
        for (int s = 0; s < S; ++s) coupling[(long long)j * S + s] = acc[s];
      }
    };

    /// Level-1 stencil of cell I (Galerkin P^T D⁻¹ A P): the sum of its particles' B_i.
    template <int dim>
    struct CellFromParticles
    {
      const int    *cell_start, *sorted;
      const double *coupling;
      double       *stencil;
      TWINFLOW_HD void operator()(int I) const
      {
        constexpr int S = stencil_size<dim>();
        double        acc[S];
        for (int s = 0; s < S; ++s) acc[s] = 0;
        for (int k = cell_start[I]; k < cell_start[I + 1]; ++k)
          for (int s = 0; s < S; ++s) acc[s] += coupling[(long long)k * S + s];
        for (int s = 0; s < S; ++s) stencil[(long long)I * S + s] = acc[s];
      }
    };

    /// Coarse stencil of cell I from the fine stencils of its 2^dim children.
    template <int dim>
    struct CellGalerkin
    {
      CellGrid<dim> fine, coarse;
      const double *fine_stencil;
      double       *stencil;
      TWINFLOW_HD void operator()(int I) const
      {
        constexpr int S = stencil_size<dim>();
        double        acc[S];
        for (int s = 0; s < S; ++s) acc[s] = 0;
        long long cI[dim], c[dim], nb[dim], cJ[dim];
        coarse.decode(I, cI);
        for (int b = 0; b < (1 << dim); ++b)
        {
          bool inside = true;
          for (int d = 0; d < dim; ++d)
          {
            c[d] = 2 * cI[d] + ((b >> d) & 1);
            inside = inside && c[d] < fine.n[d];
          }
          if (!inside) continue;
          const long long id = fine.encode(c);
          for (int s = 0; s < S; ++s)
          {
            const double v = fine_stencil[id * S + s];
            if (v == 0 || !fine.neighbour(c, s, nb)) continue;
            for (int d = 0; d < dim; ++d) cJ[d] = nb[d] / 2;
            acc[coarse.slot(cI, cJ)] += v;
          }
        }
        for (int s = 0; s < S; ++s) stencil[(long long)I * S + s] = acc[s];
      }
    };

    /// Per active cell k: the cell ids of its 3^dim stencil slots, −1 where the slot is outside a
    /// non-periodic direction (computed once per setup, so the cycle does no index arithmetic).
    template <int dim>
    struct NeighbourTable
    {
      CellGrid<dim> grid;
      const int    *active;
      int          *neighbours;
      TWINFLOW_HD void operator()(int k) const
      {
        constexpr int S = stencil_size<dim>();
        const int     I = active[k];
        long long     cI[dim], nb[dim];
        grid.decode(I, cI);
        for (int s = 0; s < S; ++s)
          neighbours[(long long)k * S + s] = grid.neighbour(cI, s, nb) ? int(grid.encode(nb)) : -1;
      }
    };

    /// res = f − S x on the active cells of a level (k: active index).
    template <int dim>
    struct CellResidual
    {
      const int    *active, *neighbours;
      const double *stencil, *x, *f;
      double       *res;
      TWINFLOW_HD void operator()(int k) const
      {
        constexpr int S = stencil_size<dim>();
        const int     I = active[k];
        double        sum = 0;
        for (int s = 0; s < S; ++s)
        {
          const int J = neighbours[(long long)k * S + s];
          if (J >= 0) sum += stencil[(long long)I * S + s] * x[J];
        }
        res[I] = f[I] - sum;
      }
    };

    /// x += ω res / S_II (empty cells, zero diagonal: x = 0).
    template <int dim>
    struct CellJacobi
    {
      const double *stencil, *res;
      double       *x;
      double        omega;
      TWINFLOW_HD void operator()(int I) const
      {
        constexpr int S = stencil_size<dim>();
        const double  d = stencil[(long long)I * S + S / 2];
        x[I]            = d != 0 ? x[I] + omega * res[I] / d : 0.0;
      }
    };

    /// Restriction: coarse f[I] = Σ of the fine residuals of the children cells.
    template <int dim>
    struct CellRestrict
    {
      CellGrid<dim> fine, coarse;
      const double *res;
      double       *f;
      TWINFLOW_HD void operator()(int I) const
      {
        long long cI[dim], c[dim];
        coarse.decode(I, cI);
        double sum = 0;
        for (int b = 0; b < (1 << dim); ++b)
        {
          bool inside = true;
          for (int d = 0; d < dim; ++d)
          {
            c[d] = 2 * cI[d] + ((b >> d) & 1);
            inside = inside && c[d] < fine.n[d];
          }
          if (inside) sum += res[fine.encode(c)];
        }
        f[I] = sum;
      }
    };

    /// Per active cell k: its parent cell on the next coarser level.
    template <int dim>
    struct ParentTable
    {
      CellGrid<dim> fine, coarse;
      const int    *active;
      int          *parent;
      TWINFLOW_HD void operator()(int k) const
      {
        long long c[dim];
        fine.decode(active[k], c);
        for (int d = 0; d < dim; ++d) c[d] /= 2;
        parent[k] = int(coarse.encode(c));
      }
    };

    /// Prolongation: fine x[I] += factor · coarse x[parent(I)] (k: active index).
    struct CellProlong
    {
      const int    *active, *parent;
      const double *xc;
      double       *x;
      double        factor;
      TWINFLOW_HD void operator()(int k) const { x[active[k]] += factor * xc[parent[k]]; }
    };

    /// Particle level: f0 = D⁻¹ r, x = ω f0 (first Jacobi sweep from zero).
    struct ScaleFirstSweep
    {
      const double *inv_diag, *r;
      double       *f, *x;
      double        omega;
      TWINFLOW_HD void operator()(int i) const
      {
        f[i] = inv_diag[i] * r[i];
        x[i] = omega * f[i];
      }
    };

    /// Particle level: res = f − D⁻¹ (A x), the SpMV fused in.
    struct ParticleResidual
    {
      const int    *offsets, *indices;
      const double *values, *inv_diag, *f, *x;
      double       *res;
      TWINFLOW_HD void operator()(int i) const
      {
        double sum = 0;
        for (int k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * x[indices[k]];
        res[i] = f[i] - inv_diag[i] * sum;
      }
    };

    /// out = x + a y (out may alias x).
    struct AddScaled
    {
      const double *x, *y;
      double       *out;
      double        a;
      TWINFLOW_HD void operator()(int i) const { out[i] = x[i] + a * y[i]; }
    };

    /// Restriction from particles: f[I] = Σ_{i in cell I} res[i].
    struct ParticleRestrict
    {
      const int    *cell_start, *sorted;
      const double *res;
      double       *f;
      TWINFLOW_HD void operator()(int I) const
      {
        double sum = 0;
        for (int k = cell_start[I]; k < cell_start[I + 1]; ++k) sum += res[sorted[k]];
        f[I] = sum;
      }
    };

    /// The coarse correction and the last post-smoothing sweep in one pass (ν = 1). With
    /// x' = x + c P x_c, the smoothed residual is f − D⁻¹A x' = res − c (D⁻¹ A P x_c)_i, where res
    /// is the residual before the correction and D⁻¹ A P is the per-particle coupling B:
    /// z = x' + ω (res − c B x_c), without a second pass over the particle matrix.
    template <int dim>
    struct CorrectAndSmooth
    {
      const int    *active, *cell_start, *sorted, *neighbours;
      const double *coupling, *xc, *x, *res;
      double       *z;
      double        c, omega;
      TWINFLOW_HD void operator()(int k) const // over the active level-1 cells
      {
        constexpr int S = stencil_size<dim>();
        const int     I = active[k];
        double        xs[S];
        for (int s = 0; s < S; ++s)
        {
          const int J = neighbours[(long long)k * S + s];
          xs[s]       = J >= 0 ? xc[J] : 0.0;
        }
        for (int j = cell_start[I]; j < cell_start[I + 1]; ++j)
        {
          const int i  = sorted[j];
          double    Bx = 0;
          for (int s = 0; s < S; ++s) Bx += coupling[(long long)j * S + s] * xs[s];
          z[i] = x[i] + c * xs[S / 2] + omega * (res[i] - c * Bx);
        }
      }
    };

    struct ParticleProlong
    {
      const int    *cell;
      const double *xc;
      double       *x;
      double        factor;
      TWINFLOW_HD void operator()(int i) const { x[i] += factor * xc[cell[i]]; }
    };

    template <int dim>
    struct MinMax
    {
      Vec<dim> lo, hi;
    };
    template <int dim>
    struct ToMinMax
    {
      TWINFLOW_HD MinMax<dim> operator()(const Vec<dim> &x) const { return {x, x}; }
    };
    template <int dim>
    struct MergeMinMax
    {
      TWINFLOW_HD MinMax<dim> operator()(const MinMax<dim> &a, const MinMax<dim> &b) const
      {
        MinMax<dim> r;
        for (int d = 0; d < dim; ++d)
        {
          r.lo[d] = a.lo[d] < b.lo[d] ? a.lo[d] : b.lo[d];
          r.hi[d] = a.hi[d] > b.hi[d] ? a.hi[d] : b.hi[d];
        }
        return r;
      }
    };

    /// Multigrid loops shorter than this run on the calling thread with OpenMP (backend.h): the
    /// coarsest level's 30 sweeps alone are ~60 loops per V-cycle.
    constexpr long long kSerialCells = 2048;

    template <typename F>
    void for_n(long long n, const F &f)
    {
      for_index(n, f, kSerialCells);
    }

    /// Runs a per-cell functor on the active cells of a level only.
    template <typename F>
    struct OnActive
    {
      const int *active;
      F          f;
      TWINFLOW_HD void operator()(int k) const { f(active[k]); }
    };
    template <typename F>
    void for_active(const dvec<int> &active, const F &f)
    {
      for_n((long long)active.size(), OnActive<F>{ptr(active), f});
    }

    /// Level 1: a cell is active if particles lie in it.
    struct HasParticles
    {
      const int *cell_start;
      TWINFLOW_HD bool operator()(int I) const { return cell_start[I + 1] > cell_start[I]; }
    };

    /// Coarser levels: a cell is active if its stencil row is not empty.
    template <int dim>
    struct HasRow
    {
      const double *stencil;
      TWINFLOW_HD bool operator()(int I) const
      {
        constexpr int S = stencil_size<dim>();
        for (int s = 0; s < S; ++s)
          if (stencil[(long long)I * S + s] != 0) return true;
        return false;
      }
    };

    struct SetZero
    {
      double *x;
      TWINFLOW_HD void operator()(int I) const { x[I] = 0; }
    };

    template <typename Pred>
    void select_active(long long n_total, const Pred &pred, dvec<int> &active)
    {
      active.resize(n_total);
      const auto end = thrust::copy_if(exec, thrust::counting_iterator<int>(0),
                                       thrust::counting_iterator<int>(int(n_total)), active.begin(), pred);
      active.resize(end - active.begin());
    }

    template <int dim, class LevelT>
    CellGrid<dim> grid_of(const LevelT &level, const bool (&periodic)[dim])
    {
      CellGrid<dim> g;
      for (int d = 0; d < dim; ++d) g.n[d] = level.n[d], g.periodic[d] = periodic[d];
      return g;
    }

    /// Cells with at most this many entries are the coarsest level.
    constexpr long long kCoarsestCells = 64;
  } // namespace multigrid_detail

  template <int dim>
  void CellMultigrid<dim>::setup(const dvec<Vec<dim>> &x, const DomainBox<dim> &box, const double cell_size,
                                 const dvec<int> &offsets_, const dvec<int> &indices_, const dvec<double> &values_)
  {
    using namespace multigrid_detail;
    offsets = &offsets_, indices = &indices_, values = &values_;
    const int n = int(x.size());
    inverse_diagonal(offsets_, indices_, values_, inv_diag);
    x0.resize(n), f0.resize(n), res0.resize(n);

    // level-1 grid over the particles (periodic directions: whole cells over the period)
    MinMax<dim> init;
    for (int d = 0; d < dim; ++d) init.lo[d] = 1e300, init.hi[d] = -1e300;
    const MinMax<dim> bb = thrust::transform_reduce(exec, x.begin(), x.end(), ToMinMax<dim>(), init, MergeMinMax<dim>());
    CellOfParticle<dim> locate;
    for (int d = 0; d < dim; ++d)
    {
      periodic[d] = locate.grid.periodic[d] = box.periodic[d];
      if (box.periodic[d])
      {
        const double L = box.upper[d] - box.lower[d];
        locate.grid.n[d] = std::max(1LL, (long long)std::floor(L / cell_size));
        locate.lower[d]  = box.lower[d];
        locate.inv_size[d] = locate.grid.n[d] / L;
      }
      else
      {
        const double extent = n > 0 ? bb.hi[d] - bb.lo[d] : 0;
        locate.grid.n[d]    = std::max(1LL, (long long)std::floor(extent / cell_size) + 1);
        locate.lower[d]     = n > 0 ? bb.lo[d] : 0;
        locate.inv_size[d]  = 1 / cell_size;
      }
    }
    long long n_cells = 1;
    for (int d = 0; d < dim; ++d) n_cells *= locate.grid.n[d];

    // particles in cell order
    cell.resize(n), sorted.resize(n), cell_start.resize(n_cells + 1);
    thrust::transform(exec, x.begin(), x.end(), cell.begin(), locate);
    keys.assign(cell.begin(), cell.end());
    thrust::sequence(exec, sorted.begin(), sorted.end());
    thrust::sort_by_key(exec, keys.begin(), keys.end(), sorted.begin());
    thrust::lower_bound(exec, keys.begin(), keys.end(), thrust::counting_iterator<int>(0),
                        thrust::counting_iterator<int>(int(n_cells) + 1), cell_start.begin());

    // level 1 from the particles, then 2^dim-coarsening down to ≤ kCoarsestCells cells
    // The levels' arrays are kept between setups (one per step): only resized, not reallocated.
    constexpr int S = stencil_size<dim>();
    std::size_t   used = 0;
    levels.reserve(64); // each level halves the cells: never exceeded, so references stay valid
    auto next_level = [&]() -> Level & {
      if (levels.size() <= used) levels.emplace_back();
      return levels[used++];
    };
    {
      Level &L1 = next_level();
      for (int d = 0; d < dim; ++d) L1.n[d] = locate.grid.n[d];
      L1.n_total = n_cells;
      L1.stencil.resize(n_cells * S);
      coupling.resize((long long)n * S);
      for_n(n, ParticleCoupling<dim>{locate.grid, ptr(sorted), ptr(cell), ptr(offsets_), ptr(indices_), ptr(values_), ptr(inv_diag),
                                     ptr(coupling)});
      for_n(n_cells, CellFromParticles<dim>{ptr(cell_start), ptr(sorted), ptr(coupling), ptr(L1.stencil)});
      select_active(n_cells, HasParticles{ptr(cell_start)}, L1.active);
    }
    while (levels[used - 1].n_total > kCoarsestCells && used < 64)
    {
      const Level &F = levels[used - 1];
      long long    n_coarse[dim], total = 1;
      bool         coarser = false;
      for (int d = 0; d < dim; ++d)
      {
        n_coarse[d] = (F.n[d] + 1) / 2;
        coarser     = coarser || n_coarse[d] < F.n[d];
        total *= n_coarse[d];
      }
      if (!coarser) break;
      Level &C = next_level();
      for (int d = 0; d < dim; ++d) C.n[d] = n_coarse[d];
      C.n_total = total;
      C.stencil.resize(C.n_total * S);
      for_n(C.n_total, CellGalerkin<dim>{grid_of<dim>(F, periodic), grid_of<dim>(C, periodic), ptr(F.stencil), ptr(C.stencil)});
      select_active(C.n_total, HasRow<dim>{ptr(C.stencil)}, C.active);
    }
    levels.resize(used);
    for (Level &L : levels)
    {
      L.neighbours.resize(L.active.size() * S);
      for_n((long long)L.active.size(), NeighbourTable<dim>{grid_of<dim>(L, periodic), ptr(L.active), ptr(L.neighbours)});
      if (&L != &levels.back())
      {
        L.parent.resize(L.active.size());
        for_n((long long)L.active.size(), ParentTable<dim>{grid_of<dim>(L, periodic), grid_of<dim>((&L)[1], periodic),
                                                           ptr(L.active), ptr(L.parent)});
      }
      // inactive cells must hold 0 (they are never written by the cycle)
      L.x.resize(L.n_total), L.f.resize(L.n_total), L.res.resize(L.n_total);
      thrust::fill(exec, L.x.begin(), L.x.end(), 0.0);
      thrust::fill(exec, L.f.begin(), L.f.end(), 0.0);
      thrust::fill(exec, L.res.begin(), L.res.end(), 0.0);
    }
  }

  template <int dim>
  void CellMultigrid<dim>::apply(const dvec<double> &r, dvec<double> &z) const
  {
    using namespace multigrid_detail;
    const int n = int(r.size());
    const double omega = settings.jacobi_damping;
    for_n(n, ScaleFirstSweep{ptr(inv_diag), ptr(r), ptr(f0), ptr(x0), omega});
    const ParticleResidual residual{ptr(*offsets), ptr(*indices), ptr(*values), ptr(inv_diag), ptr(f0), ptr(x0),
                                    ptr(res0)};
    for (int k = 1; k < settings.smoothing_steps; ++k)
      for_n(n, residual), for_n(n, AddScaled{ptr(x0), ptr(res0), ptr(x0), omega});
    for_n(n, residual);
    const Level &L1 = levels.front();
    for_active(L1.active, ParticleRestrict{ptr(cell_start), ptr(sorted), ptr(res0), ptr(L1.f)});
    cycle(0);
    if (z.size() != r.size()) z.resize(r.size());
    if (settings.smoothing_steps == 1)
    {
      for_n((long long)L1.active.size(),
            CorrectAndSmooth<dim>{ptr(L1.active), ptr(cell_start), ptr(sorted), ptr(L1.neighbours), ptr(coupling),
                                  ptr(L1.x), ptr(x0), ptr(res0), ptr(z), settings.over_correction, omega});
      return;
    }
    for_n(n, ParticleProlong{ptr(cell), ptr(L1.x), ptr(x0), settings.over_correction});
    if (settings.smoothing_steps == 0)
      thrust::copy(exec, x0.begin(), x0.end(), z.begin());
    for (int k = 0; k < settings.smoothing_steps; ++k) // the last sweep writes z
      for_n(n, residual), for_n(n, AddScaled{ptr(x0), ptr(res0), k + 1 == settings.smoothing_steps ? ptr(z) : ptr(x0), omega});
  }

  template <int dim>
  void CellMultigrid<dim>::cycle(const int l) const
  {
    using namespace multigrid_detail;
    const Level  &L     = levels[l];
    const auto    grid  = grid_of<dim>(L, periodic);
    const double  omega = settings.jacobi_damping;
    for_active(L.active, SetZero{ptr(L.x)}); // inactive cells are never written: they stay 0
    const CellResidual<dim> residual{ptr(L.active), ptr(L.neighbours), ptr(L.stencil), ptr(L.x), ptr(L.f), ptr(L.res)};
    auto sweep = [&] {
      for_n((long long)L.active.size(), residual);
      for_active(L.active, CellJacobi<dim>{ptr(L.stencil), ptr(L.res), ptr(L.x), omega});
    };
    if (l + 1 == int(levels.size()))
    {
      for (int k = 0; k < settings.coarsest_sweeps; ++k) sweep();
      return;
    }
    for (int k = 0; k < settings.smoothing_steps; ++k) sweep();
    const Level &C = levels[l + 1];
    for_n((long long)L.active.size(), residual);
    for_active(C.active, CellRestrict<dim>{grid, grid_of<dim>(C, periodic), ptr(L.res), ptr(C.f)});
    cycle(l + 1);
    for_n((long long)L.active.size(), CellProlong{ptr(L.active), ptr(L.parent), ptr(C.x), ptr(L.x), settings.over_correction});
    for (int k = 0; k < settings.smoothing_steps; ++k) sweep();
  }

  template class CellMultigrid<2>;
  template class CellMultigrid<3>;
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
