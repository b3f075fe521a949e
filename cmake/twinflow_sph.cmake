# SPH: every file in sph_gpu/src/*.inl is the single kernel source; sph_gpu/cpu/*.cc and
# sph_gpu/cuda/*.cu only include it. The CPU library (Thrust OpenMP system) is always built;
# the CUDA library whenever nvcc was found (TWINFLOW_HAVE_CUDA, cmake/twinflow_cuda.cmake).
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_path(TWINFLOW_THRUST_INCLUDE_DIR thrust/version.h
  PATHS /usr/local/cuda/include/cccl /usr/local/cuda/include /usr/include
  DOC "Thrust headers (CUDA toolkit's CCCL, or Debian's libthrust-dev)")
if(NOT TWINFLOW_THRUST_INCLUDE_DIR)
  message(FATAL_ERROR "Thrust headers not found: install the CUDA toolkit or Debian's libthrust-dev, "
    "or pass -DTWINFLOW_THRUST_INCLUDE_DIR=...")
endif()
# CCCL's libcu++ lives beside thrust/ (cuda/std/...).
set(_sph_includes ${CMAKE_SOURCE_DIR}/sph_gpu/include ${CMAKE_SOURCE_DIR}/include)

file(GLOB TWINFLOW_SPH_CPU_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/sph_gpu/cpu/*.cc)
add_library(twinflow_sph_cpu STATIC ${TWINFLOW_SPH_CPU_SOURCES})
target_include_directories(twinflow_sph_cpu PUBLIC ${_sph_includes})
target_include_directories(twinflow_sph_cpu SYSTEM PUBLIC ${TWINFLOW_THRUST_INCLUDE_DIR})
target_compile_definitions(twinflow_sph_cpu PUBLIC
  THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP TWINFLOW_SPH_BACKEND=cpu)
# deal.II empties CMAKE_CXX_FLAGS_RELEASE (it passes its own flags to its targets): the
# SPH libraries, which are not deal.II targets, set their optimisation themselves.
set(TWINFLOW_SPH_OPT $<$<NOT:$<CONFIG:Debug>>:-O3 -DNDEBUG>)
target_compile_options(twinflow_sph_cpu PRIVATE -Wall -Wextra ${TWINFLOW_SPH_OPT})
target_link_libraries(twinflow_sph_cpu PUBLIC OpenMP::OpenMP_CXX)
target_link_libraries(twinflow_sph_cpu PRIVATE Eigen3::Eigen) # the coarse solve of conservative_coarse.inl
find_library(TWINFLOW_CHOLMOD cholmod REQUIRED)
find_path(TWINFLOW_CHOLMOD_INCLUDE cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
target_include_directories(twinflow_sph_cpu PRIVATE ${TWINFLOW_CHOLMOD_INCLUDE})
target_link_libraries(twinflow_sph_cpu PRIVATE ${TWINFLOW_CHOLMOD})
set_target_properties(twinflow_sph_cpu PROPERTIES POSITION_INDEPENDENT_CODE ON)

if(TWINFLOW_HAVE_CUDA)
  file(GLOB TWINFLOW_SPH_CUDA_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/sph_gpu/cuda/*.cu)
  if(TWINFLOW_SPH_CUDA_SOURCES)
    add_library(twinflow_sph_cuda STATIC ${TWINFLOW_SPH_CUDA_SOURCES})
    target_include_directories(twinflow_sph_cuda PUBLIC ${_sph_includes})
    target_compile_definitions(twinflow_sph_cuda PRIVATE TWINFLOW_SPH_BACKEND=cuda TWINFLOW_WITH_CUDA=1)
    target_compile_options(twinflow_sph_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--extended-lambda> ${TWINFLOW_SPH_OPT})
    set_target_properties(twinflow_sph_cuda PROPERTIES CUDA_SEPARABLE_COMPILATION OFF)
  endif()
endif()

# The host side (source/sph, part of twinflow_lib) drives the backends through engine.h.
target_link_libraries(twinflow_lib twinflow_sph_cpu)
if(TARGET twinflow_sph_cuda)
  find_package(CUDAToolkit REQUIRED)
  target_link_libraries(twinflow_lib twinflow_sph_cuda CUDA::cudart)
  set_source_files_properties(${CMAKE_SOURCE_DIR}/source/sph/engine_factory.cc PROPERTIES
    COMPILE_DEFINITIONS TWINFLOW_WITH_CUDA=1)
endif()
