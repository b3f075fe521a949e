/**
 * @file csg.h
 * @brief Constructive solid geometry on signed-distance shapes.
 *
 * The combinators work on any shape type providing `dimension`,
 * `signed_distance(p)` and `normal(p)`, and can be nested freely, e.g.
 * `Union<Box<2>, Intersection<Disk, HalfSpace<2>>>`. They are plain value
 * types (no virtual functions, no heap), so they can be copied to the device.
 *
 * Exactness: the min/max/negation formulas give a function with the correct
 * sign and zero level set, but the value is in general only a bound on the
 * true Euclidean distance:
 *   - Union (min): exact outside the union; inside it is a lower bound on the
 *     magnitude (|d| <= true depth) wherever the operands overlap.
 *   - Intersection (max): exact inside the intersection; outside it is a
 *     lower bound on the true distance (e.g. near concave corners).
 *   - Complement (negation): exact wherever the operand is exact.
 *   - Difference A \ B = Intersection<A, Complement<B>>: a lower bound outside.
 * Normals are the normal of the operand that attains the min/max (the
 * gradient wherever the combined function is differentiable); ties go to the
 * first operand.
 */
#ifndef TWINFLOW_GEOMETRY_CSG_H
#define TWINFLOW_GEOMETRY_CSG_H

#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::geometry
{
  /**
   * @brief Union of two shapes: signed distance min(d_A, d_B).
   *
   * Exact outside the union, a bound inside where A and B overlap. The
   * normal is that of the operand with the smaller distance (A on ties).
   */
  template <typename A, typename B>
  class Union
  {
    static_assert(A::dimension == B::dimension, "Union: operands of different dimension");

  public:
    /// Space dimension.
    static constexpr int dimension = A::dimension;

    /// Uninitialised (trivial if A and B are).
    Union() = default;

    /// Union of @p a and @p b.
    TWINFLOW_HD Union(const A &a, const B &b)
      : a_(a)
      , b_(b)
    {}

    /// First operand.
    TWINFLOW_HD const A &first() const { return a_; }
    /// Second operand.
    TWINFLOW_HD const B &second() const { return b_; }

    /// min(d_A, d_B).
    TWINFLOW_HD double signed_distance(const Vec<dimension> &p) const
    {
      return detail::min(a_.signed_distance(p), b_.signed_distance(p));
    }

    /// Normal of the nearer operand (A on ties).
    TWINFLOW_HD Vec<dimension> normal(const Vec<dimension> &p) const
    {
      return (b_.signed_distance(p) < a_.signed_distance(p)) ? b_.normal(p) : a_.normal(p);
    }

  private:
    A a_;
    B b_;
  };

  /**
   * @brief Intersection of two shapes: signed distance max(d_A, d_B).
   *
   * Exact inside the intersection, a bound outside. The normal is that of
   * the operand with the larger distance (A on ties).
   */
  template <typename A, typename B>
  class Intersection
  {
    static_assert(A::dimension == B::dimension,
                  "Intersection: operands of different dimension");

  public:
    /// Space dimension.
    static constexpr int dimension = A::dimension;

    /// Uninitialised (trivial if A and B are).
    Intersection() = default;

    /// Intersection of @p a and @p b.
    TWINFLOW_HD Intersection(const A &a, const B &b)
      : a_(a)
      , b_(b)
    {}

    /// First operand.
    TWINFLOW_HD const A &first() const { return a_; }
    /// Second operand.
    TWINFLOW_HD const B &second() const { return b_; }

    /// max(d_A, d_B).
    TWINFLOW_HD double signed_distance(const Vec<dimension> &p) const
    {
      return detail::max(a_.signed_distance(p), b_.signed_distance(p));
    }

    /// Normal of the operand with the larger distance (A on ties).
    TWINFLOW_HD Vec<dimension> normal(const Vec<dimension> &p) const
    {
      return (b_.signed_distance(p) > a_.signed_distance(p)) ? b_.normal(p) : a_.normal(p);
    }

  private:
    A a_;
    B b_;
  };

  /**
   * @brief Complement of a shape (its outside): signed distance -d_A.
   *
   * Exact wherever d_A is exact; normal -n_A. Use it for fluid domains
   * around obstacles and, with Intersection, for differences.
   */
  template <typename A>
  class Complement
  {
  public:
    /// Space dimension.
    static constexpr int dimension = A::dimension;

    /// Uninitialised (trivial if A is).
    Complement() = default;

    /// Complement of @p a.
    TWINFLOW_HD explicit Complement(const A &a)
      : a_(a)
    {}

    /// The complemented shape.
    TWINFLOW_HD const A &operand() const { return a_; }

    /// -d_A.
    TWINFLOW_HD double signed_distance(const Vec<dimension> &p) const
    {
      return -a_.signed_distance(p);
    }

    /// -n_A.
    TWINFLOW_HD Vec<dimension> normal(const Vec<dimension> &p) const { return -a_.normal(p); }

  private:
    A a_;
  };

  /// Set difference A \ B, as Intersection<A, Complement<B>>.
  template <typename A, typename B>
  using Difference = Intersection<A, Complement<B>>;

  /// Convenience: Union<A, B>(a, b).
  template <typename A, typename B>
  TWINFLOW_HD_INLINE Union<A, B> make_union(const A &a, const B &b)
  {
    return Union<A, B>(a, b);
  }

  /// Convenience: Intersection<A, B>(a, b).
  template <typename A, typename B>
  TWINFLOW_HD_INLINE Intersection<A, B> make_intersection(const A &a, const B &b)
  {
    return Intersection<A, B>(a, b);
  }

  /// Convenience: Complement<A>(a).
  template <typename A>
  TWINFLOW_HD_INLINE Complement<A> make_complement(const A &a)
  {
    return Complement<A>(a);
  }

  /// Convenience: Difference<A, B> (a without b).
  template <typename A, typename B>
  TWINFLOW_HD_INLINE Difference<A, B> make_difference(const A &a, const B &b)
  {
    return Difference<A, B>(a, Complement<B>(b));
  }
} // namespace twinflow::geometry

#endif // TWINFLOW_GEOMETRY_CSG_H
