// Unit tests of the shared signed-distance geometry (twinflow/geometry/):
// exact distances and normals against hand-computed values, rigid-motion
// invariance, CSG, and normals equal to finite-difference gradients.

#include <twinflow/geometry/geometry.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

using namespace twinflow::geometry;

namespace
{
  constexpr double tol = 1e-12;
  const double     pi  = std::acos(-1.0);

  template <int dim>
  void expect_vec_near(const Vec<dim> &a, const Vec<dim> &b, const double eps = tol)
  {
    for (int i = 0; i < dim; ++i)
      EXPECT_NEAR(a[i], b[i], eps) << "component " << i;
  }

  /// Expects distance @p d and normal @p n of @p shape at @p p.
  template <typename Shape, int dim>
  void expect_sd(const Shape &shape, const Vec<dim> &p, const double d, const Vec<dim> &n)
  {
    EXPECT_NEAR(shape.signed_distance(p), d, tol);
    expect_vec_near(shape.normal(p), n);
  }

  template <int dim>
  Vec<dim> random_vec(std::mt19937 &rng, const double lo, const double hi)
  {
    std::uniform_real_distribution<double> u(lo, hi);
    Vec<dim>                               v;
    for (int i = 0; i < dim; ++i)
      v[i] = u(rng);
    return v;
  }

  Rotation<3> random_rotation(std::mt19937 &rng)
  {
    const Vec<3> axis = random_vec<3>(rng, -1.0, 1.0);
    return Rotation<3>::from_axis_angle(axis, std::uniform_real_distribution<double>(-pi, pi)(rng));
  }

  /**
   * At random points in [lo, hi]^dim: the normal has unit length, and, away
   * from kinks (detected as a jump of the normal within 1e-4), it equals the
   * central finite-difference gradient of the distance.
   */
  template <typename Shape>
  void check_gradient(const Shape &shape, const double lo, const double hi)
  {
    constexpr int dim = Shape::dimension;
    std::mt19937  rng(42);
    const double  h = 1e-6, delta = 1e-4;
    int           checked = 0;
    const int     n_points = 2000;
    for (int k = 0; k < n_points; ++k)
      {
        const Vec<dim> p = random_vec<dim>(rng, lo, hi);
        const Vec<dim> n = shape.normal(p);
        EXPECT_NEAR(norm(n), 1.0, tol);
        bool near_kink = false;
        for (int i = 0; i < dim; ++i)
          for (const double s : {-delta, delta})
            near_kink |= norm(shape.normal(p + s * Vec<dim>::unit(i)) - n) > 1e-2;
        if (near_kink)
          continue;
        Vec<dim> fd;
        for (int i = 0; i < dim; ++i)
          fd[i] = (shape.signed_distance(p + h * Vec<dim>::unit(i)) -
                   shape.signed_distance(p - h * Vec<dim>::unit(i))) / (2 * h);
        expect_vec_near(n, fd, 1e-6);
        ++checked;
      }
    EXPECT_GT(checked, n_points / 2);
  }
} // namespace

TEST(Vec, Arithmetic)
{
  const Vec<3> a{1.0, 2.0, 3.0}, b{-2.0, 0.5, 4.0};
  expect_vec_near(a + b, Vec<3>{-1.0, 2.5, 7.0});
  expect_vec_near(a - b, Vec<3>{3.0, 1.5, -1.0});
  expect_vec_near(2.0 * a, Vec<3>{2.0, 4.0, 6.0});
  expect_vec_near(a * 2.0 / 4.0, Vec<3>{0.5, 1.0, 1.5});
  expect_vec_near(-a, Vec<3>{-1.0, -2.0, -3.0});
  EXPECT_DOUBLE_EQ(dot(a, b), 11.0);
  EXPECT_DOUBLE_EQ(norm(Vec<2>{3.0, 4.0}), 5.0);
  expect_vec_near(cross(a, b), Vec<3>{6.5, -10.0, 4.5});
  expect_vec_near(cross(Vec<3>::unit(0), Vec<3>::unit(1)), Vec<3>::unit(2));
  expect_vec_near(Vec<2>{}, Vec<2>::zero());
}

// Shapes are passed by value to kernels and may live in __constant__ memory.
template <typename... T>
constexpr bool trivial =
  (... && (std::is_trivially_copyable_v<T> && std::is_trivially_default_constructible_v<T>));
static_assert(trivial<Vec<2>, Vec<3>, Box<2>, Box<3>, Disk, Sphere, Cylinder, HalfSpace<3>,
                      Plate<2>, Plate<3>, Rotation<3>, RigidTransform<2>, Transformed<Cylinder>,
                      Union<Disk, Box<2>>, Complement<Sphere>, Difference<Box<3>, Cylinder>>);

TEST(Box, Exact2D)
{
  const Box<2> box(Vec<2>{0.0, 0.0}, Vec<2>{2.0, 1.0});
  // Inside: distance to the nearest face, normal of that face.
  expect_sd(box, Vec<2>{0.3, 0.6}, -0.3, Vec<2>{-1.0, 0.0});
  expect_sd(box, Vec<2>{1.5, 0.9}, -0.1, Vec<2>{0.0, 1.0});
  expect_sd(box, Vec<2>{1.0, 0.5}, -0.5, Vec<2>{0.0, 1.0}); // centre: + side
  // Outside a face and outside corners (Euclidean distance to the corner).
  expect_sd(box, Vec<2>{3.0, 0.5}, 1.0, Vec<2>{1.0, 0.0});
  expect_sd(box, Vec<2>{1.0, -0.25}, 0.25, Vec<2>{0.0, -1.0});
  expect_sd(box, Vec<2>{3.0, 2.0}, std::sqrt(2.0), Vec<2>{1.0, 1.0} / std::sqrt(2.0));
  expect_sd(box, Vec<2>{-3.0, 5.0}, 5.0, Vec<2>{-0.6, 0.8});
  // On the surface; at a corner the lowest axis wins.
  expect_sd(box, Vec<2>{2.0, 0.5}, 0.0, Vec<2>{1.0, 0.0});
  expect_sd(box, Vec<2>{0.5, 0.0}, 0.0, Vec<2>{0.0, -1.0});
  expect_sd(box, Vec<2>{2.0, 1.0}, 0.0, Vec<2>{1.0, 0.0});
  EXPECT_EQ(Box<2>(Vec<2>{0.1, 0.2}, Vec<2>{0.3, 0.7}).signed_distance(Vec<2>{0.3, 0.5}), 0.0);
}

TEST(Box, Exact3D)
{
  const Box<3> box(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{1.0, 2.0, 3.0});
  expect_sd(box, Vec<3>{2.0, 3.0, 5.0}, std::sqrt(6.0), Vec<3>{1.0, 1.0, 2.0} / std::sqrt(6.0));
  expect_sd(box, Vec<3>{2.0, 3.0, 1.5}, std::sqrt(2.0), Vec<3>{1.0, 1.0, 0.0} / std::sqrt(2.0));
  expect_sd(box, Vec<3>{0.5, 1.9, 1.5}, -0.1, Vec<3>{0.0, 1.0, 0.0});
  expect_sd(box, Vec<3>{0.5, 1.0, -4.0}, 4.0, Vec<3>{0.0, 0.0, -1.0});
  expect_sd(box, Vec<3>{0.5, 1.0, 3.0}, 0.0, Vec<3>{0.0, 0.0, 1.0});
}

TEST(Box, MatchesClosestFacePoint)
{
  // |distance| = min over the 6 faces of the distance to the (clamped) face point.
  const Vec<3> lo{-1.0, 0.0, 0.5}, hi{2.0, 1.0, 3.0};
  const Box<3> box(lo, hi);
  std::mt19937 rng(1);
  for (int k = 0; k < 1000; ++k)
    {
      const Vec<3> p    = random_vec<3>(rng, -3.0, 5.0);
      double       best = 1e300;
      for (int axis = 0; axis < 3; ++axis)
        for (const double plane : {lo[axis], hi[axis]})
          {
            Vec<3> q = p;
            for (int i = 0; i < 3; ++i)
              q[i] = std::min(std::max(p[i], lo[i]), hi[i]);
            q[axis] = plane;
            best    = std::min(best, norm(p - q));
          }
      EXPECT_NEAR(std::abs(box.signed_distance(p)), best, tol);
    }
}

TEST(Ball, Exact)
{
  const Disk disk(Vec<2>{1.0, 2.0}, 0.5);
  expect_sd(disk, Vec<2>{4.0, 6.0}, 4.5, Vec<2>{0.6, 0.8});
  expect_sd(disk, Vec<2>{1.0, 2.25}, -0.25, Vec<2>{0.0, 1.0});
  expect_sd(disk, Vec<2>{1.0, 1.5}, 0.0, Vec<2>{0.0, -1.0});
  expect_sd(disk, Vec<2>{1.0, 2.0}, -0.5, Vec<2>{1.0, 0.0}); // centre convention
  const Sphere sphere(Vec<3>{0.0, 0.0, 0.0}, 1.0);
  expect_sd(sphere, Vec<3>{2.0, 3.0, 6.0}, 6.0, Vec<3>{2.0, 3.0, 6.0} / 7.0);
}

TEST(Cylinder, ExactAxisAligned)
{
  // Axis z, radius 1, caps at z = -2 and z = 2.
  const Cylinder cyl(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{0.0, 0.0, 2.0}, 1.0, 4.0);
  EXPECT_DOUBLE_EQ(cyl.length(), 4.0);
  expect_sd(cyl, Vec<3>{3.0, 4.0, 1.0}, 4.0, Vec<3>{0.6, 0.8, 0.0});   // lateral
  expect_sd(cyl, Vec<3>{0.3, 0.4, 5.0}, 3.0, Vec<3>{0.0, 0.0, 1.0});   // top cap
  expect_sd(cyl, Vec<3>{0.0, 0.0, -2.5}, 0.5, Vec<3>{0.0, 0.0, -1.0}); // bottom cap
  // Beyond the rim: distance to the rim point (0.6, 0.8, 2).
  expect_sd(cyl, Vec<3>{3.0, 4.0, 6.0}, std::sqrt(32.0), Vec<3>{0.6, 0.8, 1.0} / std::sqrt(2.0));
  expect_sd(cyl, Vec<3>{0.0, -2.0, -3.0}, std::sqrt(2.0), Vec<3>{0.0, -1.0, -1.0} / std::sqrt(2.0));
  // Inside: nearest of lateral surface and caps.
  expect_sd(cyl, Vec<3>{0.9, 0.0, 0.0}, -0.1, Vec<3>{1.0, 0.0, 0.0});
  expect_sd(cyl, Vec<3>{0.0, 0.5, 1.8}, -0.2, Vec<3>{0.0, 0.0, 1.0});
  // On the surface: lateral, cap, and rim (lateral wins the tie).
  expect_sd(cyl, Vec<3>{0.0, 1.0, 0.0}, 0.0, Vec<3>{0.0, 1.0, 0.0});
  expect_sd(cyl, Vec<3>{0.5, 0.0, 2.0}, 0.0, Vec<3>{0.0, 0.0, 1.0});
  expect_sd(cyl, Vec<3>{1.0, 0.0, -2.0}, 0.0, Vec<3>{1.0, 0.0, 0.0});
  // On the axis: the reference radial direction.
  EXPECT_NEAR(cyl.signed_distance(Vec<3>{0.0, 0.0, 0.5}), -1.0, tol);
  expect_vec_near(cyl.normal(Vec<3>{0.0, 0.0, 0.5}), cyl.radial_reference());
  EXPECT_NEAR(dot(cyl.radial_reference(), cyl.axis()), 0.0, tol);
}

TEST(Cylinder, ExactObliqueAxis)
{
  const Vec<3>   c{1.0, -1.0, 2.0}, u = Vec<3>{1.0, 2.0, 2.0} / 3.0, e = Vec<3>{2.0, 1.0, -2.0} / 3.0;
  const Cylinder cyl(c, 3.0 * u, 0.5, 3.0);
  const Cylinder cyl2 = Cylinder::from_endpoints(c - 1.5 * u, c + 1.5 * u, 0.5);
  for (const Cylinder &s : {cyl, cyl2})
    {
      expect_sd(s, c + 2.5 * u + 1.5 * e, std::sqrt(2.0), (u + e) / std::sqrt(2.0)); // rim
      expect_sd(s, c + 0.5 * u + 0.2 * e, -0.3, e);
      expect_sd(s, c - 1.4 * u - 0.1 * e, -0.1, -u);
      expect_sd(s, c - 2.0 * u + 0.5 * e, 0.5, -u);
    }
  // |distance| = min over lateral surface and caps of the distance to the patch.
  std::mt19937 rng(2);
  for (int k = 0; k < 1000; ++k)
    {
      const Vec<3> p   = c + random_vec<3>(rng, -3.0, 3.0);
      const double h   = dot(p - c, u);
      const double rho = norm(p - c - h * u);
      const double ch  = std::min(std::max(h, -1.5), 1.5);
      const double lateral = std::hypot(rho - 0.5, h - ch);
      const double cap = std::hypot(std::max(rho - 0.5, 0.0), std::abs(h) - 1.5);
      EXPECT_NEAR(std::abs(cyl.signed_distance(p)), std::min(lateral, cap), tol);
    }
}

TEST(HalfSpace, Exact)
{
  const HalfSpace<2> hs(Vec<2>{1.0, 1.0}, Vec<2>{3.0, 4.0});
  expect_sd(hs, Vec<2>{4.0, 5.0}, 5.0, Vec<2>{0.6, 0.8});
  expect_sd(hs, Vec<2>{1.0, 0.0}, -0.8, Vec<2>{0.6, 0.8});
}

TEST(Plate, Rotated2D)
{
  const double angle = pi / 6.0;
  const Vec<2> c{1.0, 1.0}, t{std::cos(angle), std::sin(angle)}, n{-std::sin(angle), std::cos(angle)};
  const Plate<2> plate(c, 2.0, 0.2, angle);
  expect_sd(plate, c + 1.5 * t + 0.3 * n, std::sqrt(0.29), (0.5 * t + 0.2 * n) / std::sqrt(0.29));
  expect_sd(plate, c + 0.5 * t + 0.05 * n, -0.05, n);
  expect_sd(plate, c - 0.2 * n, 0.1, -n);
  expect_sd(plate, c - 1.25 * t, 0.25, -t);
  expect_vec_near(plate.length_direction(), t);
  expect_vec_near(plate.thickness_direction(), n);

  // A hanging gate from (0, 0) down to (0, -1), thickness 0.1.
  const Plate<2> gate = Plate<2>::from_segment(Vec<2>{0.0, 0.0}, Vec<2>{0.0, -1.0}, 0.1);
  EXPECT_NEAR(gate.length(), 1.0, tol);
  expect_sd(gate, Vec<2>{0.2, -0.5}, 0.15, Vec<2>{1.0, 0.0});
  expect_sd(gate, Vec<2>{-0.01, -0.5}, -0.04, Vec<2>{-1.0, 0.0});
  expect_sd(gate, Vec<2>{0.0, -1.3}, 0.3, Vec<2>{0.0, -1.0});
  expect_sd(gate, Vec<2>{0.45, -1.3}, 0.5, Vec<2>{0.8, -0.6});
  expect_sd(gate, Vec<2>{0.05, -1.0}, 0.0, Vec<2>{0.0, -1.0}); // corner: length axis wins
}

TEST(Plate, Rotated3D)
{
  // Rotated by 90 degrees about z: length along world y, thickness along -x.
  const Plate<3> plate(Vec<3>{0.0, 0.0, 0.0}, 2.0, 0.2, 1.0,
                       Rotation<3>::from_axis_angle(Vec<3>{0.0, 0.0, 1.0}, pi / 2.0));
  expect_sd(plate, Vec<3>{0.0, 3.0, 0.0}, 2.0, Vec<3>{0.0, 1.0, 0.0});
  expect_sd(plate, Vec<3>{0.5, 0.0, 0.0}, 0.4, Vec<3>{1.0, 0.0, 0.0});
  expect_sd(plate, Vec<3>{0.0, 0.2, -0.45}, -0.05, Vec<3>{0.0, 0.0, -1.0});
  expect_sd(plate, Vec<3>{0.02, 0.2, 0.0}, -0.08, Vec<3>{1.0, 0.0, 0.0});
  expect_sd(plate, Vec<3>{0.3, 1.5, 1.0}, std::sqrt(0.54), Vec<3>{0.2, 0.5, 0.5} / std::sqrt(0.54));
}

TEST(Csg, UnionIntersectionComplement)
{
  const Disk a(Vec<2>{0.0, 0.0}, 1.0), b(Vec<2>{3.0, 0.0}, 1.0);
  const auto u = make_union(a, b);
  expect_sd(u, Vec<2>{1.5, 0.0}, 0.5, Vec<2>{1.0, 0.0}); // tie: first operand
  expect_sd(u, Vec<2>{5.0, 0.0}, 1.0, Vec<2>{1.0, 0.0});
  expect_sd(u, Vec<2>{0.0, 0.5}, -0.5, Vec<2>{0.0, 1.0});
  EXPECT_NEAR(u.signed_distance(Vec<2>{1.5, 2.0}), 1.5, tol); // exact outside

  // Overlapping boxes: inside, min() only bounds the depth (true depth 1.5).
  const auto boxes = make_union(Box<2>(Vec<2>{0.0, 0.0}, Vec<2>{2.0, 4.0}),
                                Box<2>(Vec<2>{1.0, 0.0}, Vec<2>{3.0, 4.0}));
  EXPECT_NEAR(boxes.signed_distance(Vec<2>{1.5, 2.0}), -0.5, tol);

  const Box<2> square(Vec<2>{0.0, 0.0}, Vec<2>{2.0, 2.0});
  const Disk   disk(Vec<2>{2.0, 2.0}, 1.5);
  const Intersection<Box<2>, Disk> lens(square, disk);
  expect_sd(lens, Vec<2>{1.2, 1.6}, -0.4, Vec<2>{0.0, 1.0});
  expect_sd(lens, Vec<2>{0.2, 1.9}, std::sqrt(3.25) - 1.5, Vec<2>{-1.8, -0.1} / std::sqrt(3.25));

  // Quarter plane: outside, max() is a lower bound (1 < sqrt(2)).
  const auto quarter = make_intersection(HalfSpace<2>(Vec<2>{0.0, 0.0}, Vec<2>{1.0, 0.0}),
                                         HalfSpace<2>(Vec<2>{0.0, 0.0}, Vec<2>{0.0, 1.0}));
  EXPECT_NEAR(quarter.signed_distance(Vec<2>{1.0, 1.0}), 1.0, tol);
  expect_sd(quarter, Vec<2>{-3.0, -1.0}, -1.0, Vec<2>{0.0, 1.0});

  const auto outside = make_complement(disk);
  expect_sd(outside, Vec<2>{2.0, 5.0}, -1.5, Vec<2>{0.0, -1.0});
  expect_sd(outside, Vec<2>{2.0, 2.5}, 1.0, Vec<2>{0.0, -1.0});
}

TEST(Csg, DifferenceAndNesting)
{
  // Rectangle with a semicircular notch of radius 1 at (2, 0).
  const auto notched = make_difference(Box<2>(Vec<2>{0.0, 0.0}, Vec<2>{4.0, 2.0}),
                                       Disk(Vec<2>{2.0, 0.0}, 1.0));
  expect_sd(notched, Vec<2>{2.0, 0.5}, 0.5, Vec<2>{0.0, -1.0});
  expect_sd(notched, Vec<2>{2.0, 1.5}, -0.5, Vec<2>{0.0, 1.0});
  expect_sd(notched, Vec<2>{0.5, 0.25}, -0.25, Vec<2>{0.0, -1.0});
  expect_sd(notched, Vec<2>{2.0, -1.0}, 1.0, Vec<2>{0.0, -1.0});

  // Fluid channel around a cylinder: box minus disk, moved rigidly.
  using Channel        = Difference<Box<2>, Disk>;
  const Channel chan   = make_difference(Box<2>(Vec<2>{0.0, 0.0}, Vec<2>{2.2, 0.41}),
                                         Disk(Vec<2>{0.2, 0.2}, 0.05));
  const RigidTransform<2> T(Rotation<2>::from_angle(0.7), Vec<2>{-1.0, 3.0});
  const Transformed<Channel> moved(chan, T);
  expect_sd(moved, T.to_world(Vec<2>{0.2, 0.3}), -0.05, T.vector_to_world(Vec<2>{0.0, -1.0}));
}

TEST(Transform, RotationsAndComposition)
{
  std::mt19937      rng(3);
  const Rotation<3> r = random_rotation(rng);
  const Vec<3>      v = random_vec<3>(rng, -1.0, 1.0);
  EXPECT_NEAR(norm(r.apply(v)), norm(v), tol);
  expect_vec_near(r.apply_inverse(r.apply(v)), v);
  expect_vec_near((r * r.inverse()).apply(v), v);
  // Quaternion and axis-angle agree.
  const Vec<3>      axis = normalized(Vec<3>{1.0, -2.0, 0.5});
  const double      th   = 1.1;
  const Rotation<3> qa   = Rotation<3>::from_quaternion(std::cos(th / 2), std::sin(th / 2) * axis[0],
                                                     std::sin(th / 2) * axis[1], std::sin(th / 2) * axis[2]);
  expect_vec_near(qa.apply(v), Rotation<3>::from_axis_angle(axis, th).apply(v));
  expect_vec_near(Rotation<2>::from_angle(pi / 2).apply(Vec<2>{1.0, 0.0}), Vec<2>{0.0, 1.0});
  expect_vec_near(Rotation<3>::from_axis_angle(Vec<3>{0.0, 0.0, 1.0}, pi / 2).apply(Vec<3>{1.0, 0.0, 0.0}),
                  Vec<3>{0.0, 1.0, 0.0});

  const RigidTransform<3> A(random_rotation(rng), random_vec<3>(rng, -2.0, 2.0));
  const RigidTransform<3> B(random_rotation(rng), random_vec<3>(rng, -2.0, 2.0));
  expect_vec_near(A.to_body(A.to_world(v)), v);
  expect_vec_near(A.inverse().to_world(v), A.to_body(v));
  expect_vec_near((A * B).to_world(v), A.to_world(B.to_world(v)));
  expect_vec_near(RigidTransform<3>::from_translation(v).to_world(v), 2.0 * v);
}

TEST(Transform, HandComputed)
{
  // Box [-1,1]x[-0.5,0.5] rotated by 90 degrees and moved to (5, 0).
  const Transformed<Box<2>> box(Box<2>(Vec<2>{-1.0, -0.5}, Vec<2>{1.0, 0.5}),
                                RigidTransform<2>(Rotation<2>::from_angle(pi / 2), Vec<2>{5.0, 0.0}));
  expect_sd(box, Vec<2>{5.0, 2.0}, 1.0, Vec<2>{0.0, 1.0});
  expect_sd(box, Vec<2>{6.0, 0.0}, 0.5, Vec<2>{1.0, 0.0});
  expect_sd(box, Vec<2>{6.5, 3.0}, std::sqrt(5.0), Vec<2>{1.0, 2.0} / std::sqrt(5.0));
}

TEST(Transform, RigidMotionInvariance)
{
  std::mt19937   rng(4);
  const Cylinder cyl(Vec<3>{0.1, 0.2, 0.3}, Vec<3>{0.0, 1.0, 1.0}, 0.4, 1.5);
  const Box<3>   box(Vec<3>{-0.5, -0.2, 0.0}, Vec<3>{0.5, 0.3, 1.0});
  for (int k = 0; k < 20; ++k)
    {
      const RigidTransform<3> T(random_rotation(rng), random_vec<3>(rng, -5.0, 5.0));
      const auto tc = make_transformed(cyl, T);
      const auto tb = make_transformed(box, T);
      for (int j = 0; j < 50; ++j)
        {
          const Vec<3> x = random_vec<3>(rng, -2.0, 2.0);
          EXPECT_NEAR(tc.signed_distance(T.to_world(x)), cyl.signed_distance(x), tol);
          EXPECT_NEAR(tb.signed_distance(T.to_world(x)), box.signed_distance(x), tol);
          expect_vec_near(tc.normal(T.to_world(x)), T.vector_to_world(cyl.normal(x)));
          expect_vec_near(tb.normal(T.to_world(x)), T.vector_to_world(box.normal(x)));
        }
    }
  const RigidTransform<2> T2(Rotation<2>::from_angle(-2.0), Vec<2>{0.3, -4.0});
  const Plate<2>          plate(Vec<2>{0.0, 0.0}, 1.0, 0.1, 0.4);
  const auto              tp = make_transformed(plate, T2);
  for (int j = 0; j < 100; ++j)
    {
      const Vec<2> x = random_vec<2>(rng, -1.0, 1.0);
      EXPECT_NEAR(tp.signed_distance(T2.to_world(x)), plate.signed_distance(x), tol);
      expect_vec_near(tp.normal(T2.to_world(x)), T2.rotation().apply(plate.normal(x)));
    }
}

TEST(Gradient, NormalsAreUnitFiniteDifferenceGradients)
{
  std::mt19937 rng(5);
  check_gradient(Box<2>(Vec<2>{-0.5, -0.2}, Vec<2>{0.7, 0.4}), -1.0, 1.0);
  check_gradient(Box<3>(Vec<3>{-0.5, -0.2, 0.0}, Vec<3>{0.7, 0.4, 0.3}), -1.0, 1.0);
  check_gradient(Disk(Vec<2>{0.1, -0.2}, 0.6), -1.0, 1.0);
  check_gradient(Sphere(Vec<3>{0.1, -0.2, 0.3}, 0.6), -1.0, 1.0);
  check_gradient(Cylinder(Vec<3>{0.1, 0.0, -0.1}, Vec<3>{1.0, 2.0, 2.0}, 0.4, 1.2), -1.0, 1.0);
  check_gradient(HalfSpace<3>(Vec<3>{0.1, 0.0, 0.0}, Vec<3>{1.0, 1.0, -1.0}), -1.0, 1.0);
  check_gradient(Plate<2>(Vec<2>{0.1, 0.1}, 1.2, 0.3, 0.8), -1.0, 1.0);
  check_gradient(Plate<3>(Vec<3>{0.0, 0.1, 0.0}, 1.2, 0.3, 0.8, random_rotation(rng)), -1.0, 1.0);
  check_gradient(make_union(Disk(Vec<2>{-0.3, 0.0}, 0.4), Box<2>(Vec<2>{0.0, -0.2}, Vec<2>{0.8, 0.3})),
                 -1.0, 1.0);
  check_gradient(make_difference(Box<3>(Vec<3>{-0.8, -0.8, -0.5}, Vec<3>{0.8, 0.8, 0.5}),
                                 Cylinder(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{0.0, 0.0, 1.0}, 0.3, 2.0)),
                 -1.0, 1.0);
  check_gradient(make_transformed(Cylinder(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{1.0, 0.0, 0.0}, 0.3, 1.0),
                                  RigidTransform<3>(random_rotation(rng), Vec<3>{0.1, 0.2, 0.0})),
                 -1.0, 1.0);
}
