/**
 * @file halfspace.h
 * @brief Half-space {x : (x - point) . n <= 0} with exact signed distance.
 */
#ifndef TWINFLOW_GEOMETRY_HALFSPACE_H
#define TWINFLOW_GEOMETRY_HALFSPACE_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::geometry
{
  /**
   * @brief Half-space bounded by the plane (line in 2D) through @p point with
   *        outward normal @p n; the solid is on the side opposite to n.
   *
   * signed_distance(p) = (p - point) . n (exact); normal(p) = n everywhere.
   * Useful for flat walls and, combined with Intersection, for clipping.
   */
  template <int dim>
  class HalfSpace
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised half-space (trivial type).
    HalfSpace() = default;

    /// Half-space through @p point with outward normal @p outward_normal
    /// (any non-zero length; it is normalised here).
    TWINFLOW_HD HalfSpace(const Vec<dim> &point, const Vec<dim> &outward_normal)
      : point_(point)
      , normal_(normalized(outward_normal))
    {}

    /// A point on the boundary plane.
    TWINFLOW_HD const Vec<dim> &point() const { return point_; }

    /// Signed distance: negative inside, positive outside, exact.
    TWINFLOW_HD double signed_distance(const Vec<dim> &p) const
    {
      return dot(p - point_, normal_);
    }

    /// Outward unit normal (constant).
    TWINFLOW_HD Vec<dim> normal(const Vec<dim> & /*p*/) const { return normal_; }

  private:
    Vec<dim> point_;
    Vec<dim> normal_;
  };
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_HALFSPACE_H
