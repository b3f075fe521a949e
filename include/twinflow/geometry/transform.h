/**
 * @file transform.h
 * @brief Rotations, rigid transformations and rigidly moved shapes.
 */
#ifndef TWINFLOW_GEOMETRY_TRANSFORM_H
#define TWINFLOW_GEOMETRY_TRANSFORM_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

#include <type_traits>

namespace twinflow::geometry
{
  /**
   * @brief A rotation of R^dim stored as an orthogonal matrix (row-major).
   *
   * Create it with identity(), from_angle() (2D, counter-clockwise),
   * from_axis_angle() / from_quaternion() / from_basis() (3D), or
   * from_matrix(). Distances are preserved only if the matrix is orthogonal
   * with determinant +1; from_matrix() and from_basis() do not check this.
   */
  template <int dim>
  class Rotation
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised rotation (trivial type); use identity() for I.
    Rotation() = default;

    /// The identity.
    TWINFLOW_HD static Rotation identity()
    {
      Rotation r;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          r.m_[i][j] = (i == j) ? 1.0 : 0.0;
      return r;
    }

    /// Rotation with the given (orthogonal) row-major matrix.
    TWINFLOW_HD static Rotation from_matrix(const double (&m)[dim][dim])
    {
      Rotation r;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          r.m_[i][j] = m[i][j];
      return r;
    }

    /// 2D: counter-clockwise rotation by @p angle (radians).
    template <int d = dim>
    TWINFLOW_HD static std::enable_if_t<d == 2, Rotation>
    from_angle(const double angle)
    {
      const double c = ::cos(angle), s = ::sin(angle);
      const double m[2][2] = {{c, -s}, {s, c}};
      return from_matrix(m);
    }

    /// 3D: right-handed rotation by @p angle (radians) about @p axis
    /// (any non-zero length), by Rodrigues' formula.
    template <int d = dim>
    TWINFLOW_HD static std::enable_if_t<d == 3, Rotation>
    from_axis_angle(const Vec<3> &axis, const double angle)
    {
      const Vec<3> u = normalized(axis);
      const double c = ::cos(angle), s = ::sin(angle), t = 1.0 - c;
      const double m[3][3] = {
        {c + t * u[0] * u[0], t * u[0] * u[1] - s * u[2], t * u[0] * u[2] + s * u[1]},
        {t * u[1] * u[0] + s * u[2], c + t * u[1] * u[1], t * u[1] * u[2] - s * u[0]},
        {t * u[2] * u[0] - s * u[1], t * u[2] * u[1] + s * u[0], c + t * u[2] * u[2]}};
      return from_matrix(m);
    }

    /// 3D: rotation of the quaternion w + x i + y j + z k (normalised here).
    template <int d = dim>
    TWINFLOW_HD static std::enable_if_t<d == 3, Rotation>
    from_quaternion(double w, double x, double y, double z)
    {
      const double n = ::sqrt(w * w + x * x + y * y + z * z);
      w /= n, x /= n, y /= n, z /= n;
      const double m[3][3] = {
        {1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)},
        {2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)},
        {2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)}};
      return from_matrix(m);
    }

    /// 3D: rotation mapping the body axes e_0, e_1, e_2 to the given
    /// orthonormal, right-handed vectors (the columns of the matrix).
    template <int d = dim>
    TWINFLOW_HD static std::enable_if_t<d == 3, Rotation>
    from_basis(const Vec<3> &ex, const Vec<3> &ey, const Vec<3> &ez)
    {
      const double m[3][3] = {{ex[0], ey[0], ez[0]},
                              {ex[1], ey[1], ez[1]},
                              {ex[2], ey[2], ez[2]}};
      return from_matrix(m);
    }

    /// Matrix entry (row i, column j).
    TWINFLOW_HD double operator()(const int i, const int j) const { return m_[i][j]; }

    /// R v.
    TWINFLOW_HD Vec<dim> apply(const Vec<dim> &v) const
    {
      Vec<dim> r = Vec<dim>::zero();
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          r[i] += m_[i][j] * v[j];
      return r;
    }

    /// R^T v = R^{-1} v.
    TWINFLOW_HD Vec<dim> apply_inverse(const Vec<dim> &v) const
    {
      Vec<dim> r = Vec<dim>::zero();
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          r[i] += m_[j][i] * v[j];
      return r;
    }

    /// The inverse rotation (transpose).
    TWINFLOW_HD Rotation inverse() const
    {
      Rotation r;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          r.m_[i][j] = m_[j][i];
      return r;
    }

    /// Composition: (a * b) v = a (b v).
    TWINFLOW_HD friend Rotation operator*(const Rotation &a, const Rotation &b)
    {
      Rotation r;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          {
            r.m_[i][j] = 0.0;
            for (int k = 0; k < dim; ++k)
              r.m_[i][j] += a.m_[i][k] * b.m_[k][j];
          }
      return r;
    }

  private:
    double m_[dim][dim];
  };

  /**
   * @brief Rigid motion x_world = R x_body + t (rotation, then translation).
   *
   * It maps body (reference) coordinates, in which a shape is defined, to
   * world coordinates. to_body() is its inverse.
   */
  template <int dim>
  class RigidTransform
  {
  public:
    /// Space dimension.
    static constexpr int dimension = dim;

    /// Uninitialised transform (trivial type); use identity() for I.
    RigidTransform() = default;

    /// x_world = rotation x_body + translation.
    TWINFLOW_HD RigidTransform(const Rotation<dim> &rotation, const Vec<dim> &translation)
      : rotation_(rotation)
      , translation_(translation)
    {}

    /// The identity motion.
    TWINFLOW_HD static RigidTransform identity()
    {
      return RigidTransform(Rotation<dim>::identity(), Vec<dim>::zero());
    }

    /// A pure translation by @p t.
    TWINFLOW_HD static RigidTransform from_translation(const Vec<dim> &t)
    {
      return RigidTransform(Rotation<dim>::identity(), t);
    }

    /// The rotation R.
    TWINFLOW_HD const Rotation<dim> &rotation() const { return rotation_; }
    /// The translation t.
    TWINFLOW_HD const Vec<dim> &translation() const { return translation_; }

    /// Body point to world point: R x + t.
    TWINFLOW_HD Vec<dim> to_world(const Vec<dim> &x) const
    {
      return rotation_.apply(x) + translation_;
    }

    /// World point to body point: R^T (x - t).
    TWINFLOW_HD Vec<dim> to_body(const Vec<dim> &x) const
    {
      return rotation_.apply_inverse(x - translation_);
    }

    /// Body vector (direction) to world vector: R v.
    TWINFLOW_HD Vec<dim> vector_to_world(const Vec<dim> &v) const { return rotation_.apply(v); }

    /// World vector (direction) to body vector: R^T v.
    TWINFLOW_HD Vec<dim> vector_to_body(const Vec<dim> &v) const
    {
      return rotation_.apply_inverse(v);
    }

    /// The inverse motion (world to body).
    TWINFLOW_HD RigidTransform inverse() const
    {
      const Rotation<dim> ri = rotation_.inverse();
      return RigidTransform(ri, -ri.apply(translation_));
    }

    /// Composition: (a * b).to_world(x) = a.to_world(b.to_world(x)).
    TWINFLOW_HD friend RigidTransform operator*(const RigidTransform &a, const RigidTransform &b)
    {
      return RigidTransform(a.rotation_ * b.rotation_, a.to_world(b.translation_));
    }

  private:
    Rotation<dim> rotation_;
    Vec<dim>      translation_;
  };

  /**
   * @brief A shape moved rigidly: the set {placement.to_world(x) : x in shape}.
   *
   * Since rigid motions preserve distances, the signed distance is that of
   * the body shape at placement.to_body(p), and is exact wherever the body
   * shape's is; the normal is the body normal rotated back to world
   * coordinates (same conventions at kinks as the body shape).
   *
   * @tparam Shape any shape with `dimension`, `signed_distance()`, `normal()`.
   */
  template <typename Shape>
  class Transformed
  {
  public:
    /// Space dimension.
    static constexpr int dimension = Shape::dimension;

    /// Uninitialised (trivial if Shape is).
    Transformed() = default;

    /// @p shape (in body coordinates) placed by @p placement.
    TWINFLOW_HD Transformed(const Shape &shape, const RigidTransform<dimension> &placement)
      : shape_(shape)
      , placement_(placement)
    {}

    /// The shape in body coordinates.
    TWINFLOW_HD const Shape &shape() const { return shape_; }
    /// The body-to-world motion.
    TWINFLOW_HD const RigidTransform<dimension> &placement() const { return placement_; }
    /// Replace the placement (e.g. to move a rigid body in time).
    TWINFLOW_HD void set_placement(const RigidTransform<dimension> &placement)
    {
      placement_ = placement;
    }

    /// Signed distance of the moved shape.
    TWINFLOW_HD double signed_distance(const Vec<dimension> &p) const
    {
      return shape_.signed_distance(placement_.to_body(p));
    }

    /// Outward unit normal of the moved shape (body normal rotated to world).
    TWINFLOW_HD Vec<dimension> normal(const Vec<dimension> &p) const
    {
      return placement_.vector_to_world(shape_.normal(placement_.to_body(p)));
    }

  private:
    Shape                     shape_;
    RigidTransform<dimension> placement_;
  };

  /// Convenience: Transformed<Shape>(shape, placement).
  template <typename Shape>
  TWINFLOW_HD_INLINE Transformed<Shape>
  make_transformed(const Shape &shape, const RigidTransform<Shape::dimension> &placement)
  {
    return Transformed<Shape>(shape, placement);
  }
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_TRANSFORM_H
