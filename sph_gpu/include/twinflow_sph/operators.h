#pragma once
/**
 * @file operators.h
 * SPH discretisation operators as matrices sharing the neighbour-list pattern:
 * volumes V_i = 1/Σ_j W_ij, the correction tensors G (Eq. 24) and L (Eq. 25–26), and the
 * gradient A^G (Eq. 19 / 22, 36–39) and Laplacian A^L (Eq. 20 / 23, 27–29) matrices.
 */
#include <memory>

#include <twinflow_sph/backend.h>
#include <twinflow_sph/domain.h>
#include <twinflow_sph/kernel.h>
#include <twinflow_sph/neighbor_search.h>
#include <twinflow_sph/solver_settings.h>

namespace twinflow::sph
{
  enum class OperatorKind { standard, consistent };

  /// Small dense dim × dim matrix usable on host and device.
  template <int dim>
  struct Tensor2
  {
    double a[dim][dim];
  };

  namespace TWINFLOW_SPH_BACKEND
  {
    /// Values of A^G (one array per direction) and A^L, aligned with NeighborList::indices:
    /// (A f)_i = Σ_{k in offsets[i]..offsets[i+1]} value[k] f[indices[k]] (diagonal included).
    template <int dim>
    struct OperatorMatrices
    {
      dvec<double> gradient[dim];
      dvec<double> laplacian;
    };

    /// V_i = 1 / Σ_j W_ij (Eq. 17).
    template <int dim>
    void compute_volumes(const dvec<Vec<dim>> &x, const NeighborList &nl, const DomainBox<dim> &box,
                         const CubicSpline<dim> &W, dvec<double> &V);

    /// G_i = (−Σ_j r_ij ⊗ ∇_i W_ij V_j)^{-1} (Eq. 24) and L_i from Eq. 25–26; where the
    /// support is too deficient to invert (isolated particles), the identity is used; with
    /// `checks` (CorrectionChecks), an L_i that is not positive definite is replaced by I, and
    /// so is one with an eigenvalue above 4 where the particle or a neighbour is flagged in
    /// @p surface (free-surface particles; null: none). Returns the number of particles whose
    /// G or L was replaced. With @p rows, only the particles i with rows[i] ≠ 0 are computed;
    /// the others get G = L = I (e.g. BCE markers with no fluid in their support, whose rows
    /// no system uses).
    template <int dim>
    int compute_corrections(const dvec<Vec<dim>> &x, const dvec<double> &V, const NeighborList &nl,
                            const DomainBox<dim> &box, const CubicSpline<dim> &W, dvec<Tensor2<dim>> &G,
                            dvec<Tensor2<dim>> &L, const CorrectionChecks &checks = {},
                            const dvec<int> *surface = nullptr, const dvec<int> *rows = nullptr);

    /// Assembles A^G and A^L, standard (Eq. 19–20) or consistent (Eq. 22–23, using G, L). With
    /// @p rows, the rows i with rows[i] = 0 are zero. Standard kind: every standard row is
    /// multiplied by @p standard_scale (lattice_scale()), and with @p corrected the rows with
    /// corrected[i] ≠ 0 are consistent rows (G, L computed there), e.g. the rows a free surface
    /// truncates.
    template <int dim>
    void assemble_operators(const dvec<Vec<dim>> &x, const dvec<double> &V, const NeighborList &nl,
                            const DomainBox<dim> &box, const CubicSpline<dim> &W, OperatorKind kind,
                            const dvec<Tensor2<dim>> &G, const dvec<Tensor2<dim>> &L, OperatorMatrices<dim> &A,
                            const dvec<int> *rows = nullptr, const dvec<int> *corrected = nullptr,
                            double standard_scale = 1.0);

    /// What make_gradient_conservative() did: CG iterations, the norm of the constraint
    /// defect of the antisymmetrised consistent pair, and the relative residual left.
    struct ConservativeGradientReport
    {
      int    iterations = 0;
      double initial    = 0;
      double residual   = 0;
      bool   converged  = true;
    };

    namespace conservative_detail
    {
      template <int dim>
      class CoarseSpace; // conservative_coarse.inl (host code, CPU backend)
    }

    /// Work arrays of make_gradient_conservative(), kept between steps (y: the multipliers, a
    /// warm start while the particle count is unchanged; coarse: the two-level preconditioner's
    /// coarse level, set up every step in buffers kept between steps).
    template <int dim>
    struct ConservativeGradientWork
    {
      dvec<int>    rows;
      dvec<double> free_weight; ///< f_i ∈ [0, 1]: how free ω_i is (FreeWeightF)
      dvec<double> y, b, r, z, p, q, blocks;
      dvec<double> weight; ///< out: the quadrature weight ω_i of each row (V_i where not free)
      dvec<Vec<dim>> shift;
      std::shared_ptr<conservative_detail::CoarseSpace<dim>> coarse;
    };

    /// Rewrites the fluid rows of the consistent A^G as a summation-by-parts pair: coefficients
    /// a_ij = ω_i A^G_ij antisymmetric over fluid pairs, the diagonal in the sum form
    /// (A^G p)_i = Σ_j a_ij (p_i + p_j) / ω_i, whose divergence partner Σ_j a_ij·(u_j − u_i) / ω_i
    /// is its negative adjoint in the ω inner product: the pressure does no work on the fluid but
    /// at the walls and through the free-surface rows' pressure. ω_i = V_i but on the rows with a
    /// free-surface particle in their support, whose weights are unknowns of the least squares
    /// too (the boundary weights of a diagonal-norm SBP operator; work.weight returns them). Exact for linear fields on every fluid row (on a
    /// free-surface row, @p surface, for those that vanish @p surface_depth above it along the
    /// last step's ∇p, @p grad_p (dim arrays; null: the neighbours' centroid), which is the
    /// free-surface offset) and zero for constants off the free surface. The smallest correction
    /// of the antisymmetric part of Eq. 22 that does so (conservative_gradient.inl); its
    /// multipliers are solved by CG to @p tolerance. On rows with fewer neighbour entries than
    /// @p relax_below the constraints are relaxed by @p regularisation (least squares).
    /// Experimental: not a scene option (doc/benchmarks.md, "A summation-by-parts consistent
    /// gradient").
    template <int dim>
    ConservativeGradientReport make_gradient_conservative(const dvec<Vec<dim>> &x, const dvec<double> &V,
                                                          const NeighborList &nl, const DomainBox<dim> &box,
                                                          const CubicSpline<dim> &W, const dvec<Tensor2<dim>> &G,
                                                          const dvec<int> &kind, const dvec<int> *surface,
                                                          OperatorMatrices<dim> &A, ConservativeGradientWork<dim> &work,
                                                          double surface_depth, const dvec<double> *grad_p,
                                                          double regularisation, double relax_below, double tolerance,
                                                          int max_iterations);

    /// dim / tr G^{-1} on the regular lattice of spacing @p spacing (the particle setup's), with
    /// tr G^{-1} = −Σ_j V_j r_ij·∇_i W_ij (Eq. 24): there G = (tr G^{-1}/dim)^{-1} I, and both the
    /// kernel gradient of a linear field and Eq. 29 of a quadratic one (whose sum is the same
    /// Σ_j V_j r_ij·∇W_ij) fall short by tr G^{-1}/dim: 0.9 % for the cubic spline at h = 1.2 Δx.
    /// Standard rows multiplied by it are exact on that lattice.
    template <int dim>
    double lattice_scale(const CubicSpline<dim> &W, double spacing);
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
