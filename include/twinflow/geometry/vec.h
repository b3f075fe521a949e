/**
 * @file vec.h
 * @brief A tiny fixed-size vector usable on host and device.
 */
#ifndef TWINFLOW_GEOMETRY_VEC_H
#define TWINFLOW_GEOMETRY_VEC_H

#include <twinflow/geometry/hd.h>

#include <cmath>

namespace twinflow::geometry
{
  /**
   * @brief A point or vector in @p dim space dimensions (double components).
   *
   * Vec is an aggregate (trivially copyable, no constructors), so it can be
   * passed by value to CUDA kernels and initialised with braces:
   * `Vec<3> p{1.0, 2.0, 3.0};`. `Vec<dim> v{};` is the zero vector, while
   * `Vec<dim> v;` leaves the components uninitialised.
   */
  template <int dim>
  struct Vec
  {
    static_assert(dim >= 1 && dim <= 3, "Vec supports dim = 1, 2, 3");

    /// Number of components.
    static constexpr int dimension = dim;

    /// The components.
    double x[dim];

    /// Component access.
    TWINFLOW_HD double &operator[](const int i) { return x[i]; }
    /// Component access.
    TWINFLOW_HD const double &operator[](const int i) const { return x[i]; }

    /// The zero vector.
    TWINFLOW_HD static Vec zero()
    {
      Vec v;
      for (int i = 0; i < dim; ++i)
        v.x[i] = 0.0;
      return v;
    }

    /// The unit vector along axis @p axis (0 <= axis < dim).
    TWINFLOW_HD static Vec unit(const int axis)
    {
      Vec v = zero();
      v.x[axis] = 1.0;
      return v;
    }

    /// In-place addition.
    TWINFLOW_HD Vec &operator+=(const Vec &o)
    {
      for (int i = 0; i < dim; ++i)
        x[i] += o.x[i];
      return *this;
    }
    /// In-place subtraction.
    TWINFLOW_HD Vec &operator-=(const Vec &o)
    {
      for (int i = 0; i < dim; ++i)
        x[i] -= o.x[i];
      return *this;
    }
    /// In-place scaling.
    TWINFLOW_HD Vec &operator*=(const double s)
    {
      for (int i = 0; i < dim; ++i)
        x[i] *= s;
      return *this;
    }
    /// In-place division by a scalar.
    TWINFLOW_HD Vec &operator/=(const double s)
    {
      for (int i = 0; i < dim; ++i)
        x[i] /= s;
      return *this;
    }
  };

  /// Sum of two vectors.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator+(Vec<dim> a, const Vec<dim> &b)
  {
    return a += b;
  }
  /// Difference of two vectors.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator-(Vec<dim> a, const Vec<dim> &b)
  {
    return a -= b;
  }
  /// Negation.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator-(Vec<dim> a)
  {
    return a *= -1.0;
  }
  /// Vector times scalar.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator*(Vec<dim> a, const double s)
  {
    return a *= s;
  }
  /// Scalar times vector.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator*(const double s, Vec<dim> a)
  {
    return a *= s;
  }
  /// Vector divided by scalar.
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> operator/(Vec<dim> a, const double s)
  {
    return a /= s;
  }

  /// Euclidean inner product.
  template <int dim>
  TWINFLOW_HD_INLINE double dot(const Vec<dim> &a, const Vec<dim> &b)
  {
    double s = 0.0;
    for (int i = 0; i < dim; ++i)
      s += a.x[i] * b.x[i];
    return s;
  }

  /// Squared Euclidean norm.
  template <int dim>
  TWINFLOW_HD_INLINE double norm_square(const Vec<dim> &a)
  {
    return dot(a, a);
  }

  /// Euclidean norm.
  template <int dim>
  TWINFLOW_HD_INLINE double norm(const Vec<dim> &a)
  {
    return ::sqrt(dot(a, a));
  }

  /// @p a scaled to unit length (no check for the zero vector).
  template <int dim>
  TWINFLOW_HD_INLINE Vec<dim> normalized(const Vec<dim> &a)
  {
    return a / norm(a);
  }

  /// Cross product (3D only).
  TWINFLOW_HD_INLINE Vec<3> cross(const Vec<3> &a, const Vec<3> &b)
  {
    return Vec<3>{{a.x[1] * b.x[2] - a.x[2] * b.x[1],
                   a.x[2] * b.x[0] - a.x[0] * b.x[2],
                   a.x[0] * b.x[1] - a.x[1] * b.x[0]}};
  }

  namespace detail
  {
    /// max(a, b) without <algorithm> (usable on device); returns a on ties.
    TWINFLOW_HD_INLINE double max(const double a, const double b)
    {
      return (b > a) ? b : a;
    }
    /// min(a, b) without <algorithm> (usable on device); returns a on ties.
    TWINFLOW_HD_INLINE double min(const double a, const double b)
    {
      return (b < a) ? b : a;
    }
    /// Sign with the convention sign(0) = +1 (used to pick normals).
    TWINFLOW_HD_INLINE double sign(const double a)
    {
      return (a < 0.0) ? -1.0 : 1.0;
    }
  } // namespace detail
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_VEC_H
