/**
 * @file plate.h
 * @brief Thin plate (oriented box), e.g. the flexible gate.
 */
#ifndef TWINFLOW_GEOMETRY_PLATE_H
#define TWINFLOW_GEOMETRY_PLATE_H

#include <twinflow/geometry/box.h>
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/transform.h>
#include <twinflow/geometry/vec.h>

#include <type_traits>

namespace twinflow::geometry
{
  /**
   * @brief A plate: a box of extents length x thickness (x width in 3D),
   *        centred at a point and arbitrarily oriented (an oriented box).
   *
   * In body coordinates the plate is the axis-aligned box centred at the
   * origin with extents size = (length, thickness[, width]): body axis 0 is
   * the length direction, axis 1 the thickness direction, axis 2 (3D) the
   * width direction. The placement maps body to world coordinates.
   *
   * Distance and normal are those of Transformed<Box<dim>>: exact everywhere,
   * including outside edges and corners, with the Box conventions at kinks
   * (in body axes: nearest face, ties to the lowest body axis, i.e. the
   * length-direction end faces first).
   */
  template <int dim>
  class Plate
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised plate (trivial type).
    Plate() = default;

    /// General form: body box of extents @p size centred at the body origin,
    /// placed by @p placement.
    TWINFLOW_HD Plate(const RigidTransform<dim> &placement, const Vec<dim> &size)
      : size_(size)
      , shape_(Box<dim>(-0.5 * size, 0.5 * size), placement)
    {}

    /// 2D: rectangle of @p length x @p thickness centred at @p center whose
    /// length direction is (cos angle, sin angle).
    template <int d = dim, std::enable_if_t<d == 2, int> = 0>
    TWINFLOW_HD Plate(const Vec<2> &center,
                      const double  length,
                      const double  thickness,
                      const double  angle = 0.0)
      : Plate(RigidTransform<2>(Rotation<2>::from_angle(angle), center),
              Vec<2>{{length, thickness}})
    {}

    /// 3D: box of @p length x @p thickness x @p width centred at @p center,
    /// whose body axes (length, thickness, width) are rotated by @p orientation.
    template <int d = dim, std::enable_if_t<d == 3, int> = 0>
    TWINFLOW_HD Plate(const Vec<3>      &center,
                      const double       length,
                      const double       thickness,
                      const double       width,
                      const Rotation<3> &orientation)
      : Plate(RigidTransform<3>(orientation, center), Vec<3>{{length, thickness, width}})
    {}

    /// 2D: plate whose mid-line runs from @p a to @p b (so length = |b - a|;
    /// the end faces pass through a and b), of thickness @p thickness.
    template <int d = dim, std::enable_if_t<d == 2, int> = 0>
    TWINFLOW_HD static Plate
    from_segment(const Vec<2> &a, const Vec<2> &b, const double thickness)
    {
      const Vec<2> t = normalized(b - a);
      const double m[2][2] = {{t[0], -t[1]}, {t[1], t[0]}};
      return Plate(RigidTransform<2>(Rotation<2>::from_matrix(m), 0.5 * (a + b)),
                   Vec<2>{{norm(b - a), thickness}});
    }

    /// Extents in body coordinates (length, thickness[, width]).
    TWINFLOW_HD const Vec<dim> &size() const { return size_; }
    /// Length (extent along body axis 0).
    TWINFLOW_HD double length() const { return size_[0]; }
    /// Thickness (extent along body axis 1).
    TWINFLOW_HD double thickness() const { return size_[1]; }
    /// Centre in world coordinates.
    TWINFLOW_HD const Vec<dim> &center() const { return placement().translation(); }
    /// Body-to-world motion.
    TWINFLOW_HD const RigidTransform<dim> &placement() const { return shape_.placement(); }
    /// Unit vector along the length in world coordinates.
    TWINFLOW_HD Vec<dim> length_direction() const
    {
      return placement().vector_to_world(Vec<dim>::unit(0));
    }
    /// Unit vector across the thickness in world coordinates.
    TWINFLOW_HD Vec<dim> thickness_direction() const
    {
      return placement().vector_to_world(Vec<dim>::unit(1));
    }

    /// Signed distance: negative inside, positive outside, exact.
    TWINFLOW_HD double signed_distance(const Vec<dim> &p) const
    {
      return shape_.signed_distance(p);
    }

    /// Outward unit normal (see class docs for kinks).
    TWINFLOW_HD Vec<dim> normal(const Vec<dim> &p) const { return shape_.normal(p); }

  private:
    Vec<dim>                 size_;
    Transformed<Box<dim>>    shape_;
  };
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_PLATE_H
