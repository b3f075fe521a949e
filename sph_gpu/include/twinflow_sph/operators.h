#pragma once
/**
 * @file operators.h
 * SPH discretisation operators as matrices sharing the neighbour-list pattern:
 * volumes V_i = 1/Σ_j W_ij, the correction tensors G (Eq. 24) and L (Eq. 25–26), and the
 * gradient A^G (Eq. 19 / 22, 36–39) and Laplacian A^L (Eq. 20 / 23, 27–29) matrices.
 */
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

    /// dim / tr G^{-1} on the regular lattice of spacing @p spacing (the particle setup's), with
    /// tr G^{-1} = −Σ_j V_j r_ij·∇_i W_ij (Eq. 24): there G = (tr G^{-1}/dim)^{-1} I, and both the
    /// kernel gradient of a linear field and Eq. 29 of a quadratic one (whose sum is the same
    /// Σ_j V_j r_ij·∇W_ij) fall short by tr G^{-1}/dim: 0.9 % for the cubic spline at h = 1.2 Δx.
    /// Standard rows multiplied by it are exact on that lattice.
    template <int dim>
    double lattice_scale(const CubicSpline<dim> &W, double spacing);
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
