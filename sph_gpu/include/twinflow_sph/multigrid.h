#pragma once
/**
 * @file multigrid.h
 * Cell-aggregation multigrid preconditioner for the particle systems (the pressure Poisson
 * equation with its BCE and free-surface rows). One source for both backends.
 *
 * Level 0 is the particle matrix, row-scaled by its diagonal (Â = D⁻¹A, so fluid Laplacian
 * rows and BCE force-balance rows weigh alike). The aggregates of level 1 are the cells of a
 * uniform grid of size ≥ the kernel support over the particles (so a particle's neighbours
 * lie in the 3^dim surrounding cells), and each coarser level merges 2^dim cells. Prolongation
 * is piecewise constant (unsmoothed aggregation), restriction its transpose, coarse matrices
 * the Galerkin products Pᵀ Â P, stored as 3^dim-point stencils on the structured cell grids
 * (no sparse matrix–matrix product, no sort beyond the particles' cell order). The cycle is
 * a V(ν,ν) cycle with damped Jacobi smoothing and a scaled coarse-grid correction; the
 * coarsest level (≤ 64 cells) is smoothed to convergence. Only the cells with particles below
 * them are visited (the dense grids cover the bounding box, mostly empty in a dam break). It is
 * a fixed linear operator, as BiCGStab requires.
 *
 * The setup keeps, per particle, its row of Â P (3^dim cell coefficients; their sums per cell
 * are the level-1 stencil). With ν = 1 the post-smoothing residual after the coarse correction
 * x' = x + c P x_c is then res − c (Â P) x_c, res being the residual before the correction: the
 * last sweep needs no second pass over the particle matrix. Each cell level keeps its cells'
 * stencil neighbours and parents as index tables, built once per setup.
 */
#include <twinflow_sph/domain.h>
#include <twinflow_sph/linear_solver.h>

#include <cstddef>
#include <vector>

namespace twinflow::sph
{
  struct MultigridSettings
  {
    int    smoothing_steps = 1;     ///< ν pre- and post-smoothing sweeps per level
    double jacobi_damping  = 0.9;   ///< ω of the damped Jacobi smoother
    double over_correction = 1.8;   ///< factor of the coarse-grid correction (unsmoothed aggregation)
    int    coarsest_sweeps = 30;    ///< Jacobi sweeps on the coarsest level
  };

  namespace TWINFLOW_SPH_BACKEND
  {
    template <int dim>
    class CellMultigrid : public Preconditioner
    {
    public:
      explicit CellMultigrid(const MultigridSettings &settings = {}) : settings(settings) {}

      /// Builds the hierarchy of the CSR matrix (offsets, indices, values) of the particles
      /// at @p x; @p cell_size ≥ the largest distance of coupled particles.
      void setup(const dvec<Vec<dim>> &x, const DomainBox<dim> &box, double cell_size, const dvec<int> &offsets,
                 const dvec<int> &indices, const dvec<double> &values);

      /// z = M⁻¹ r: one V-cycle from z = 0.
      void apply(const dvec<double> &r, dvec<double> &z) const override;

      /// Number of levels including the particle level (after setup).
      int n_levels() const { return 1 + int(levels.size()); }
      /// Device memory held by the hierarchy and its work vectors [bytes].
      std::size_t memory_bytes() const
      {
        std::size_t b = sizeof(double) * (inv_diag.size() + x0.size() + f0.size() + res0.size() + coupling.size()) +
                        sizeof(int) * (cell.size() + sorted.size() + cell_start.size() + keys.size());
        for (const Level &L : levels)
          b += sizeof(double) * (L.stencil.size() + L.x.size() + L.f.size() + L.res.size()) +
               sizeof(int) * (L.active.size() + L.neighbours.size() + L.parent.size());
        return b;
      }
      /// Cells (rows) of coarse level l ≥ 1.
      long long n_cells(int l) const { return levels.at(l - 1).n_total; }

    private:
      struct Level
      {
        long long    n[dim];   ///< cells per direction
        long long    n_total = 0;
        dvec<double> stencil;  ///< 3^dim values per cell: the Galerkin operator
        dvec<int>    active;   ///< cells with a row (particles below them); the others stay 0
        dvec<int>    neighbours; ///< per active cell, 3^dim cell ids of its stencil (−1: none)
        dvec<int>    parent;     ///< per active cell, its cell on the next coarser level
        mutable dvec<double> x, f, res;
      };

      void cycle(int l) const;

      MultigridSettings settings;
      bool              periodic[dim];
      // level 0 (particles)
      const dvec<int>    *offsets = nullptr, *indices = nullptr;
      const dvec<double> *values  = nullptr;
      dvec<double>        inv_diag;
      dvec<int>           cell, sorted, cell_start, keys;
      dvec<double>        coupling;     ///< per particle, row i of D⁻¹ A P as a 3^dim cell stencil
      mutable dvec<double> x0, f0, res0;
      std::vector<Level>  levels;
    };
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
