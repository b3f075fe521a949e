/**
 * @file hd.h
 * @brief Host/device function qualifiers for code shared by the FEM solver
 *        (host, g++/clang) and the CUDA SPH kernels (device, nvcc).
 *
 * Every function in twinflow/geometry/ is marked with TWINFLOW_HD so that the
 * same header compiles as plain C++17 and under nvcc, where it becomes
 * callable from both host and device code.
 */
#ifndef TWINFLOW_GEOMETRY_HD_H
#define TWINFLOW_GEOMETRY_HD_H

#ifdef __CUDACC__
/// Marks a function callable from host and device code (nvcc), empty otherwise.
#  define TWINFLOW_HD __host__ __device__
#else
/// Marks a function callable from host and device code (nvcc), empty otherwise.
#  define TWINFLOW_HD
#endif

/// TWINFLOW_HD plus `inline`, for free functions defined in headers.
#define TWINFLOW_HD_INLINE TWINFLOW_HD inline

#endif // TWINFLOW_GEOMETRY_HD_H
