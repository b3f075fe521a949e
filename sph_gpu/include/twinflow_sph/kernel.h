#pragma once
/**
 * @file kernel.h
 * Cubic spline kernel W(r, h) with support κh = 2h (Eq. 18) and its gradient (Eq. 21).
 * Normalisation σ_d: 5/(14π h²) in 2D and 1/(4π h³) in 3D for the bracket form
 * (2−q)³ − 4(1−q)³ (the paper prints the 2D constant with h³ in Eq. 18; we use the
 * normalised values, so that ∫W = 1 in each dimension).
 */
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::sph
{
  template <int dim>
  struct CubicSpline
  {
    double h       = 0; ///< smoothing length
    double sigma   = 0; ///< normalisation σ_d / h^dim
    double inv_h   = 0; ///< 1 / h (the pair loops multiply: no division per pair)
    double sigma_h = 0; ///< σ_d / h^(dim+1), the factor of dW/dr

    /// An unset kernel (h = 0), for views filled member by member (kernel_views.h).
    CubicSpline() = default;

    TWINFLOW_HD explicit CubicSpline(double h_) : h(h_), sigma(0), inv_h(1 / h_), sigma_h(0)
    {
      const double pi = 3.14159265358979323846;
      sigma           = dim == 2 ? 5.0 / (14.0 * pi * h * h) : 1.0 / (4.0 * pi * h * h * h);
      sigma_h         = sigma * inv_h;
    }

    TWINFLOW_HD double support() const { return 2.0 * h; }

    /// W(r, h), Eq. 18.
    TWINFLOW_HD double value(const double r) const
    {
      const double q = r * inv_h;
      if (q >= 2.0)
        return 0.0;
      const double a = 2.0 - q;
      double       w = a * a * a;
      if (q < 1.0)
      {
        const double b = 1.0 - q;
        w -= 4.0 * b * b * b;
      }
      return sigma * w;
    }

    /// dW/dr (≤ 0).
    TWINFLOW_HD double derivative(const double r) const
    {
      const double q = r * inv_h;
      if (q >= 2.0)
        return 0.0;
      const double a = 2.0 - q;
      double       d = -3.0 * a * a;
      if (q < 1.0)
      {
        const double b = 1.0 - q;
        d += 12.0 * b * b;
      }
      return sigma_h * d;
    }

    /// ∇_i W_ij for r_ij = x_i − x_j, Eq. 21 (zero for r = 0).
    TWINFLOW_HD geometry::Vec<dim> gradient(const geometry::Vec<dim> &rij) const
    {
      double r2 = 0;
      for (int d = 0; d < dim; ++d)
        r2 += rij[d] * rij[d];
      geometry::Vec<dim> g = geometry::Vec<dim>::zero();
      if (r2 <= 0.0)
        return g;
      const double r = sqrt(r2), f = derivative(r) / r;
      for (int d = 0; d < dim; ++d)
        g[d] = f * rij[d];
      return g;
    }
  };
} // namespace twinflow::sph
