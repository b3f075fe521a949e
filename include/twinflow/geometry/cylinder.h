/**
 * @file cylinder.h
 * @brief Finite solid cylinder in 3D, arbitrary axis, exact signed distance.
 */
#ifndef TWINFLOW_GEOMETRY_CYLINDER_H
#define TWINFLOW_GEOMETRY_CYLINDER_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::geometry
{
  /**
   * @brief Finite solid circular cylinder in 3D (lateral surface plus two
   *        flat caps), with an arbitrary axis direction.
   *
   * For a point p, let h = (p - center) . axis be its axial coordinate and
   * rho its distance from the axis line. With q_r = rho - radius and
   * q_a = |h| - length / 2 the signed distance is, exactly,
   *   - outside: sqrt(max(q_r, 0)^2 + max(q_a, 0)^2) (covers the lateral
   *     surface, the caps and the rims: beyond a rim it is the Euclidean
   *     distance to the rim circle);
   *   - inside:  max(q_r, q_a) (<= 0).
   *
   * normal() is the gradient of the distance. Conventions where it is not
   * differentiable:
   *   - inside or on the surface, the nearest part wins: the radial direction
   *     if q_r >= q_a (lateral surface, also on the rims), else the cap normal
   *     sign(h) axis;
   *   - sign(0) = +1 (the mid-plane gets the +axis cap normal);
   *   - on the axis (rho = 0) the radial direction is a fixed unit vector
   *     perpendicular to the axis (see radial_reference()).
   *
   * In 2D, the cross-section of a cylinder is a Disk (ball.h).
   */
  class Cylinder
  {
  public:
    /// Space dimension.
    static constexpr int dimension = 3;

    /// Uninitialised cylinder (trivial type).
    Cylinder() = default;

    /**
     * @brief Cylinder centred at @p center, with axis direction @p axis (any
     *        non-zero length; normalised here), radius @p radius and total
     *        length @p length along the axis (caps at center +- length/2 axis).
     */
    TWINFLOW_HD Cylinder(const Vec<3> &center,
                         const Vec<3> &axis,
                         const double  radius,
                         const double  length)
      : center_(center)
      , axis_(normalized(axis))
      , radius_(radius)
      , half_length_(0.5 * length)
    {
      // Reference radial direction: axis x (coordinate axis least aligned
      // with the axis), which is never parallel to the axis.
      int k = 0;
      for (int i = 1; i < 3; ++i)
        if (::fabs(axis_[i]) < ::fabs(axis_[k]))
          k = i;
      radial_ref_ = normalized(cross(axis_, Vec<3>::unit(k)));
    }

    /// Cylinder whose axis segment runs from cap centre @p a to cap centre @p b.
    TWINFLOW_HD static Cylinder
    from_endpoints(const Vec<3> &a, const Vec<3> &b, const double radius)
    {
      return Cylinder(0.5 * (a + b), b - a, radius, norm(b - a));
    }

    /// Centre (midpoint of the axis segment).
    TWINFLOW_HD const Vec<3> &center() const { return center_; }
    /// Unit axis direction.
    TWINFLOW_HD const Vec<3> &axis() const { return axis_; }
    /// Radius.
    TWINFLOW_HD double radius() const { return radius_; }
    /// Total length along the axis.
    TWINFLOW_HD double length() const { return 2.0 * half_length_; }
    /// Unit vector perpendicular to the axis, used as normal on the axis.
    TWINFLOW_HD const Vec<3> &radial_reference() const { return radial_ref_; }

    /// Signed distance: negative inside, positive outside, exact.
    TWINFLOW_HD double signed_distance(const Vec<3> &p) const
    {
      const Vec<3> d  = p - center_;
      const double h  = dot(d, axis_);
      const double qr = norm(d - h * axis_) - radius_;
      const double qa = ::fabs(h) - half_length_;
      if (qr > 0.0 || qa > 0.0)
        {
          const double r = detail::max(qr, 0.0);
          const double a = detail::max(qa, 0.0);
          return ::sqrt(r * r + a * a);
        }
      return detail::max(qr, qa);
    }

    /// Outward unit normal (gradient of signed_distance(), see class docs).
    TWINFLOW_HD Vec<3> normal(const Vec<3> &p) const
    {
      const Vec<3> d      = p - center_;
      const double h      = dot(d, axis_);
      const Vec<3> radial = d - h * axis_;
      const double rho    = norm(radial);
      const Vec<3> e_r    = (rho > 0.0) ? radial / rho : radial_ref_;
      const Vec<3> e_a    = detail::sign(h) * axis_;
      const double qr     = rho - radius_;
      const double qa     = ::fabs(h) - half_length_;
      if (qr > 0.0 || qa > 0.0)
        {
          const double r = detail::max(qr, 0.0);
          const double a = detail::max(qa, 0.0);
          return (r * e_r + a * e_a) / ::sqrt(r * r + a * a);
        }
      return (qr >= qa) ? e_r : e_a;
    }

  private:
    Vec<3> center_;
    Vec<3> axis_;
    double radius_;
    double half_length_;
    Vec<3> radial_ref_;
  };
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_CYLINDER_H
