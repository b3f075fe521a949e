/**
 * @file geometry_nvcc_check.cu
 * @brief Compile check: the shared geometry headers work in CUDA device code.
 *
 * Built as the target twinflow_geometry_nvcc_check when nvcc is available
 * (cmake/twinflow_cuda.cmake). It instantiates every shape, combinator and
 * transform, constructs them on the device and calls signed_distance() and
 * normal() inside __global__ kernels. Nothing here is run by the tests; a
 * successful build is the check.
 */

#include <twinflow/geometry/geometry.h>

namespace twinflow::geometry::nvcc_check
{
  /// Evaluates @p shape at @p n points: distance[i], normal[i].
  template <typename Shape>
  __global__ void evaluate(const Shape                         shape,
                           const Vec<Shape::dimension> *const points,
                           const int                           n,
                           double *const                       distance,
                           Vec<Shape::dimension> *const        normal)
  {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n)
      {
        distance[i] = shape.signed_distance(points[i]);
        normal[i]   = shape.normal(points[i]);
      }
  }

  /// Adds distance and normal components of @p shape at @p p to @p acc.
  template <typename Shape>
  __device__ void accumulate(const Shape &shape, const Vec<Shape::dimension> &p, double &acc)
  {
    acc += shape.signed_distance(p);
    const Vec<Shape::dimension> n = shape.normal(p);
    acc += dot(n, n);
  }

  /// Builds every shape on the device (all constructors and factories) and
  /// evaluates it at a thread-dependent point; out[i] gets the sum.
  __global__ void construct_on_device(double *const out, const int n)
  {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
      return;
    const double s  = 0.01 * i;
    const Vec<2> p2{s, 1.0 - s};
    const Vec<3> p3{s, -s, 0.5};
    double       acc = 0.0;

    const Box<2> box2(Vec<2>{0.0, 0.0}, Vec<2>{1.0, 2.0});
    const Box<3> box3(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{1.0, 2.0, 3.0});
    const Disk   disk(Vec<2>{0.5, 0.5}, 0.2);
    const Sphere sphere(Vec<3>{0.0, 0.0, 0.0}, 1.0);
    const Cylinder cyl(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{0.0, 1.0, 1.0}, 0.3, 2.0);
    const Cylinder cyl2 = Cylinder::from_endpoints(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{1.0, 0.0, 0.0}, 0.1);
    const HalfSpace<2> hs2(Vec<2>{0.0, 0.0}, Vec<2>{1.0, 1.0});
    const HalfSpace<3> hs3(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{0.0, 0.0, 1.0});
    const Plate<2> plate2(Vec<2>{0.5, 0.5}, 1.0, 0.05, 0.3);
    const Plate<2> gate = Plate<2>::from_segment(Vec<2>{0.0, 0.0}, Vec<2>{0.0, -1.0}, 0.1);
    const Rotation<3> rq = Rotation<3>::from_quaternion(1.0, 0.1, 0.2, 0.3);
    const Rotation<3> ra = Rotation<3>::from_axis_angle(Vec<3>{1.0, 0.0, 0.0}, 0.4);
    const Rotation<3> rb = Rotation<3>::from_basis(Vec<3>::unit(1), Vec<3>::unit(2), Vec<3>::unit(0));
    const Plate<3> plate3(Vec<3>{0.0, 0.0, 0.0}, 1.0, 0.1, 0.5, rq * ra * rb);
    const Plate<3> plate3g(RigidTransform<3>::identity(), Vec<3>{1.0, 0.1, 0.5});
    const RigidTransform<2> T2(Rotation<2>::from_angle(0.5), Vec<2>{1.0, 0.0});
    const RigidTransform<3> T3 = RigidTransform<3>(ra, Vec<3>{0.0, 1.0, 0.0}) *
                                 RigidTransform<3>::from_translation(Vec<3>{1.0, 0.0, 0.0}).inverse();

    accumulate(box2, p2, acc);
    accumulate(box3, p3, acc);
    accumulate(disk, p2, acc);
    accumulate(sphere, p3, acc);
    accumulate(cyl, p3, acc);
    accumulate(cyl2, p3, acc);
    accumulate(hs2, p2, acc);
    accumulate(hs3, p3, acc);
    accumulate(plate2, p2, acc);
    accumulate(gate, p2, acc);
    accumulate(plate3, p3, acc);
    accumulate(plate3g, p3, acc);
    accumulate(make_transformed(box2, T2), p2, acc);
    accumulate(make_transformed(cyl, T3), p3, acc);
    accumulate(make_union(disk, box2), p2, acc);
    accumulate(make_intersection(sphere, hs3), p3, acc);
    accumulate(make_complement(cyl), p3, acc);
    accumulate(make_difference(box3, cyl), p3, acc);
    accumulate(make_transformed(make_difference(box2, make_union(disk, gate)), T2), p2, acc);
    acc += T3.to_body(p3)[0] + T2.inverse().to_world(p2)[1];
    out[i] = acc;
  }

  // Explicit instantiations of the evaluation kernel for every shape type.
  template __global__ void evaluate<Box<2>>(Box<2>, const Vec<2> *, int, double *, Vec<2> *);
  template __global__ void evaluate<Box<3>>(Box<3>, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Disk>(Disk, const Vec<2> *, int, double *, Vec<2> *);
  template __global__ void evaluate<Sphere>(Sphere, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Cylinder>(Cylinder, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void
  evaluate<HalfSpace<2>>(HalfSpace<2>, const Vec<2> *, int, double *, Vec<2> *);
  template __global__ void
  evaluate<HalfSpace<3>>(HalfSpace<3>, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Plate<2>>(Plate<2>, const Vec<2> *, int, double *, Vec<2> *);
  template __global__ void evaluate<Plate<3>>(Plate<3>, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Transformed<Cylinder>>(Transformed<Cylinder>,
                                                           const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Union<Disk, Box<2>>>(Union<Disk, Box<2>>,
                                                         const Vec<2> *, int, double *, Vec<2> *);
  template __global__ void evaluate<Intersection<Sphere, HalfSpace<3>>>(
    Intersection<Sphere, HalfSpace<3>>, const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Complement<Cylinder>>(Complement<Cylinder>,
                                                          const Vec<3> *, int, double *, Vec<3> *);
  template __global__ void evaluate<Difference<Box<2>, Disk>>(Difference<Box<2>, Disk>,
                                                              const Vec<2> *, int, double *, Vec<2> *);

  /// Host-side launch of construct_on_device (also checks the launch syntax).
  void launch_construct_on_device(double *const device_out, const int n)
  {
    const int block = 128;
    construct_on_device<<<(n + block - 1) / block, block>>>(device_out, n);
  }
} // namespace twinflow::geometry::nvcc_check
