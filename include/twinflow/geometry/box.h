/**
 * @file box.h
 * @brief Axis-aligned box with exact signed distance.
 */
#ifndef TWINFLOW_GEOMETRY_BOX_H
#define TWINFLOW_GEOMETRY_BOX_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::geometry
{
  /**
   * @brief Axis-aligned box [lower, upper] in @p dim dimensions.
   *
   * With q_i = max(lower_i - p_i, p_i - upper_i) (the signed distance to the
   * slab of axis i), the signed distance is exact everywhere:
   *   - outside: |max(q, 0)|, the Euclidean distance, including the regions
   *     outside edges and corners;
   *   - inside:  max_i q_i (<= 0), minus the distance to the nearest face.
   *
   * normal() is the gradient of the distance. Conventions at the points where
   * the distance is not differentiable:
   *   - points inside or on the surface use the face with the largest q_i
   *     (the nearest face); on ties (medial planes inside, edges and corners
   *     on the surface) the face with the lowest axis index wins;
   *   - the side of that face is + if p_i >= (lower_i + upper_i) / 2 (so the
   *     centre gets +e_0).
   * Outside, the gradient is unique, and it is the unit vector from the
   * closest box point to p.
   */
  template <int dim>
  class Box
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised box (trivial, so Box can live in __constant__ memory).
    Box() = default;

    /// Box with corners @p lower and @p upper (lower_i < upper_i for all i).
    TWINFLOW_HD Box(const Vec<dim> &lower, const Vec<dim> &upper)
      : lower_(lower)
      , upper_(upper)
    {}

    /// Lower corner.
    TWINFLOW_HD const Vec<dim> &lower() const { return lower_; }
    /// Upper corner.
    TWINFLOW_HD const Vec<dim> &upper() const { return upper_; }
    /// Centre (lower + upper) / 2.
    TWINFLOW_HD Vec<dim> center() const { return 0.5 * (lower_ + upper_); }

    /// Signed distance: negative inside, positive outside, exact.
    TWINFLOW_HD double signed_distance(const Vec<dim> &p) const
    {
      double outside2 = 0.0;
      double inside   = slab(p, 0);
      for (int i = 0; i < dim; ++i)
        {
          const double q = slab(p, i);
          if (q > 0.0)
            outside2 += q * q;
          inside = detail::max(inside, q);
        }
      return (outside2 > 0.0) ? ::sqrt(outside2) : inside;
    }

    /// Outward unit normal (gradient of signed_distance(), see class docs).
    TWINFLOW_HD Vec<dim> normal(const Vec<dim> &p) const
    {
      Vec<dim> n       = Vec<dim>::zero();
      double   outside2 = 0.0;
      int      nearest  = 0;
      double   q_max    = slab(p, 0);
      for (int i = 0; i < dim; ++i)
        {
          const double q = slab(p, i);
          if (q > 0.0)
            {
              n[i] = q * side(p, i);
              outside2 += q * q;
            }
          if (q > q_max)
            {
              q_max   = q;
              nearest = i;
            }
        }
      if (outside2 > 0.0)
        return n / ::sqrt(outside2);
      n[nearest] = side(p, nearest);
      return n;
    }

  private:
    /// Signed distance to the slab lower_i <= x_i <= upper_i.
    TWINFLOW_HD double slab(const Vec<dim> &p, const int i) const
    {
      return detail::max(lower_[i] - p[i], p[i] - upper_[i]);
    }

    /// +1 if p is in the upper half of the slab of axis i, -1 otherwise.
    TWINFLOW_HD double side(const Vec<dim> &p, const int i) const
    {
      return (p[i] - upper_[i] >= lower_[i] - p[i]) ? 1.0 : -1.0;
    }

    Vec<dim> lower_;
    Vec<dim> upper_;
  };
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_BOX_H
