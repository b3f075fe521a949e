#pragma once
/**
 * @file kernel_views.h
 * What the per-particle kernels of the engine read, by name (the views SPHinXsys builds its
 * kernels from): the particle state (ParticleView), the neighbour list with the geometry of its
 * pairs (NeighborView) and the operator matrices (OperatorView). Views hold device pointers and
 * are copied into the functors; a functor is built by assigning its views and named scalars.
 * for_each_neighbor() is the one neighbour loop of the kernels. Host-safe: no Thrust here.
 */
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>
#include <twinflow_sph/domain.h>
#include <twinflow_sph/engine.h>
#include <twinflow_sph/kernel.h>

namespace twinflow::sph
{
  /// One array per component of a vector field stored component-wise (∇p, the rows of A^G).
  template <int dim>
  struct Components
  {
    const double *c[dim] = {};
    TWINFLOW_HD const double *operator[](const int d) const { return c[d]; }
  };

  /// The particle state the kernels read (structure of arrays); writes go through the named
  /// outputs of each functor.
  template <int dim>
  struct ParticleView
  {
    const geometry::Vec<dim> *x = nullptr, *u = nullptr;
    const int                *kind = nullptr;
    const int                *surface = nullptr; ///< 1: free-surface particle (p = 0)
    const int                *body    = nullptr; ///< solid of each `solid` marker; null: all solid 0
    const double             *V = nullptr, *rho = nullptr, *support = nullptr, *pressure = nullptr;
    /// BCE markers: u^p, a^p (Eq. 59, 61) and the wall normal n
    const geometry::Vec<dim> *wall_velocity = nullptr, *wall_acceleration = nullptr, *normal = nullptr;

    TWINFLOW_HD bool fluid(const int i) const { return kind[i] == ParticleKind::fluid; }
    /// True for a `solid` marker of solid @p target.
    TWINFLOW_HD bool marker_of(const int i, const int target) const
    {
      return kind[i] == ParticleKind::solid && (body ? body[i] == target : target == 0);
    }
  };

  /// The neighbour list (CSR rows, itself included) of the positions x it was built for, with
  /// the periodic box of the pair vectors and the kernel W.
  template <int dim>
  struct NeighborView
  {
    const geometry::Vec<dim> *x       = nullptr;
    const int                *offsets = nullptr, *indices = nullptr;
    DomainBox<dim>            box;
    CubicSpline<dim>          W;

    /// Entries of row i (the particle itself included).
    TWINFLOW_HD int count(const int i) const { return offsets[i + 1] - offsets[i]; }
    /// W_ij for the pair vector r_ij (Eq. 18).
    TWINFLOW_HD double w(const geometry::Vec<dim> &r) const { return W.value(geometry::norm(r)); }
    /// ∇_i W_ij for the pair vector r_ij (Eq. 21).
    TWINFLOW_HD geometry::Vec<dim> grad_w(const geometry::Vec<dim> &r) const { return W.gradient(r); }
  };

  /// The matrices A^G (one array per direction) and A^L, aligned with NeighborView::indices.
  template <int dim>
  struct OperatorView
  {
    Components<dim> gradient;
    const double   *laplacian = nullptr;
  };

  /// The neighbour loop: f(j, k, r_ij) for each entry k of row i, j = indices[k] (i itself
  /// included), r_ij = x_i − x_j with the minimum image in periodic directions.
  template <int dim, typename F>
  TWINFLOW_HD_INLINE void for_each_neighbor(const NeighborView<dim> &nb, const int i, F &&f)
  {
    for (int k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
    {
      const int j = nb.indices[k];
      f(j, k, nb.box.difference(nb.x[i], nb.x[j]));
    }
  }

  /// True if pred(j) holds for a neighbour j of i (itself included); stops at the first.
  template <int dim, typename P>
  TWINFLOW_HD_INLINE bool any_neighbor(const NeighborView<dim> &nb, const int i, P &&pred)
  {
    for (int k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
      if (pred(nb.indices[k]))
        return true;
    return false;
  }

  /// The CSR entry of the diagonal (i, i) of row i, or −1.
  template <int dim>
  TWINFLOW_HD_INLINE int diagonal_entry(const NeighborView<dim> &nb, const int i)
  {
    for (int k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
      if (nb.indices[k] == i)
        return k;
    return -1;
  }
} // namespace twinflow::sph
