#pragma once
/**
 * @file backend.h
 * One kernel source, two backends. Every file under sph_gpu/src is compiled twice:
 * as C++ with Thrust's OpenMP device system into libtwinflow_sph_cpu (namespace
 * twinflow::sph::cpu), and by nvcc with Thrust's CUDA system into libtwinflow_sph_cuda
 * (namespace twinflow::sph::cuda). Kernels are functors marked TWINFLOW_HD run through
 * Thrust algorithms with the `exec` policy; nothing here includes deal.II.
 */
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

#include <thrust/device_vector.h>
#include <thrust/execution_policy.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>

#ifndef TWINFLOW_SPH_BACKEND
#  error "TWINFLOW_SPH_BACKEND must be defined to cpu or cuda by the build"
#endif

namespace twinflow::sph
{
  namespace TWINFLOW_SPH_BACKEND
  {
    /// Device array (host memory with the OpenMP system, GPU memory with CUDA).
    template <typename T>
    using dvec = thrust::device_vector<T>;

    /// Execution policy of the backend. CUDA: `par_nosync`, so that a kernel launch does not
    /// wait for the GPU to finish (with thrust::device every for_each synchronises: one
    /// multigrid-BiCGStab iteration, ~150 launches, took 3–4 ms at any size on an H200,
    /// doc/performance.md); algorithms that return a value to the host still synchronise.
    /// host_threads: the OpenMP backend, where a kernel is a parallel loop of the calling thread's team.
#if defined(__CUDACC__) && THRUST_DEVICE_SYSTEM == THRUST_DEVICE_SYSTEM_CUDA
    inline constexpr auto &exec         = thrust::cuda::par_nosync;
    inline constexpr bool  host_threads = false;
#else
    inline constexpr auto &exec         = thrust::device;
    inline constexpr bool  host_threads = true;
#endif

    template <int dim>
    using Vec = geometry::Vec<dim>;

    /// Raw pointer of a device array, for use inside functors.
    template <typename T>
    T *ptr(dvec<T> &v) { return thrust::raw_pointer_cast(v.data()); }
    template <typename T>
    const T *ptr(const dvec<T> &v) { return thrust::raw_pointer_cast(v.data()); }

    /// Runs f(i) for i in [0, n) with the backend. On the OpenMP backend a loop of fewer than
    /// `serial_below` items runs on the calling thread: starting and joining the team costs a few
    /// µs, more than a short loop's work (the multigrid's coarse levels, the Krylov vector
    /// updates of a few thousand particles; doc/performance.md).
    template <typename F>
    void for_index(long long n, const F &f, long long serial_below)
    {
      if constexpr (host_threads)
        if (n < serial_below)
        {
          for (int i = 0; i < int(n); ++i)
            f(i);
          return;
        }
      thrust::for_each(exec, thrust::counting_iterator<int>(0), thrust::counting_iterator<int>(int(n)), f);
    }

    /// Name of this backend ("cpu" or "cuda").
    const char *backend_name();
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
