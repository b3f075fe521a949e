# Optional CUDA support, included by the top-level CMakeLists.txt.
#
# If a CUDA compiler (nvcc) is found, CUDA is enabled as a language and the
# target twinflow_geometry_nvcc_check is built: it compiles the shared
# host/device geometry headers (include/twinflow/geometry) inside __global__
# kernels, proving that they work under nvcc.
#
# Sets TWINFLOW_HAVE_CUDA (ON/OFF).
# User options:
#   -DTWINFLOW_ENABLE_CUDA=OFF          skip CUDA even if nvcc is installed
#   -DCMAKE_CUDA_COMPILER=/path/nvcc    pick the compiler (or env CUDACXX)
#   -DCMAKE_CUDA_ARCHITECTURES="80;90"  target GPUs (default 75;80;90; CUDA 13
#                                       supports compute capability >= 7.5)

option(TWINFLOW_ENABLE_CUDA "Build the CUDA parts if nvcc is available" ON)
set(TWINFLOW_HAVE_CUDA OFF)

if(TWINFLOW_ENABLE_CUDA)
  # Look for nvcc on PATH first, then in the usual install locations (often
  # not on PATH), and hand the result to check_language() through CUDACXX.
  if(NOT DEFINED CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
    find_program(_twinflow_nvcc nvcc
      PATHS ENV CUDA_PATH ENV CUDA_HOME /usr/local/cuda PATH_SUFFIXES bin)
    if(_twinflow_nvcc)
      set(ENV{CUDACXX} ${_twinflow_nvcc})
    endif()
    unset(_twinflow_nvcc CACHE)
  endif()

  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    # Must be set before enable_language() so that CMake does not pick its own.
    # deal.IIConfig.cmake sets CMAKE_CUDA_ARCHITECTURES to "" as a normal
    # variable, which hides a cache value given with -D: fall back to that.
    if(NOT CMAKE_CUDA_ARCHITECTURES)
      set(_twinflow_cuda_arch "$CACHE{CMAKE_CUDA_ARCHITECTURES}")
      if(NOT _twinflow_cuda_arch)
        set(_twinflow_cuda_arch 75 80 90)
        set(CMAKE_CUDA_ARCHITECTURES "${_twinflow_cuda_arch}" CACHE STRING
          "CUDA architectures to build for")
      endif()
      set(CMAKE_CUDA_ARCHITECTURES "${_twinflow_cuda_arch}")
      unset(_twinflow_cuda_arch)
    endif()
    enable_language(CUDA)
    set(CMAKE_CUDA_STANDARD 17)
    set(CMAKE_CUDA_STANDARD_REQUIRED ON)
    set(TWINFLOW_HAVE_CUDA ON)
  endif()
endif()

if(TWINFLOW_HAVE_CUDA)
  message(STATUS "Twinflow: CUDA enabled (${CMAKE_CUDA_COMPILER}, version "
    "${CMAKE_CUDA_COMPILER_VERSION}, architectures ${CMAKE_CUDA_ARCHITECTURES})")

  # nvcc compile check of the shared geometry headers.
  add_library(twinflow_geometry_nvcc_check STATIC
    ${CMAKE_SOURCE_DIR}/sph_gpu/geometry_nvcc_check.cu)
  target_link_libraries(twinflow_geometry_nvcc_check PRIVATE twinflow_headers)
  target_compile_options(twinflow_geometry_nvcc_check PRIVATE
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra>)
elseif(TWINFLOW_ENABLE_CUDA)
  message(STATUS "Twinflow: no CUDA compiler (nvcc) found, building without CUDA")
else()
  message(STATUS "Twinflow: CUDA disabled (TWINFLOW_ENABLE_CUDA=OFF)")
endif()
