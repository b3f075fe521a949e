/**
 * @file ball.h
 * @brief Ball (2D disk, 3D sphere) with exact signed distance.
 */
#ifndef TWINFLOW_GEOMETRY_BALL_H
#define TWINFLOW_GEOMETRY_BALL_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::geometry
{
  /**
   * @brief Ball of given centre and radius: a disk in 2D, a sphere in 3D.
   *
   * signed_distance(p) = |p - center| - radius (exact everywhere).
   * normal(p) = (p - center) / |p - center|; at the centre, where the
   * gradient is undefined, the normal is +e_0 by convention.
   */
  template <int dim>
  class Ball
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised ball (trivial, so Ball can live in __constant__ memory).
    Ball() = default;

    /// Ball of centre @p center and radius @p radius > 0.
    TWINFLOW_HD Ball(const Vec<dim> &center, const double radius)
      : center_(center)
      , radius_(radius)
    {}

    /// Centre.
    TWINFLOW_HD const Vec<dim> &center() const { return center_; }
    /// Radius.
    TWINFLOW_HD double radius() const { return radius_; }

    /// Signed distance: negative inside, positive outside, exact.
    TWINFLOW_HD double signed_distance(const Vec<dim> &p) const
    {
      return norm(p - center_) - radius_;
    }

    /// Outward unit normal (radial direction; +e_0 at the centre).
    TWINFLOW_HD Vec<dim> normal(const Vec<dim> &p) const
    {
      const Vec<dim> d = p - center_;
      const double   r = norm(d);
      return (r > 0.0) ? d / r : Vec<dim>::unit(0);
    }

  private:
    Vec<dim> center_;
    double   radius_;
  };

  /// A disk (2D ball); also the 2D cross-section of a Cylinder.
  using Disk = Ball<2>;
  /// A sphere (3D ball).
  using Sphere = Ball<3>;
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_BALL_H
