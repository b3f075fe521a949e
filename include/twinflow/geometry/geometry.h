/**
 * @file geometry.h
 * @brief Umbrella header of the shared (host/device) signed-distance geometry.
 *
 * Header-only, no deal.II/Eigen/STL containers: usable from the FEM solver
 * and from CUDA SPH kernels. See shapes.h for the common shape interface.
 */
#ifndef TWINFLOW_GEOMETRY_GEOMETRY_H
#define TWINFLOW_GEOMETRY_GEOMETRY_H

#include <twinflow/geometry/csg.h>
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/shapes.h>
#include <twinflow/geometry/transform.h>
#include <twinflow/geometry/vec.h>

#endif // TWINFLOW_GEOMETRY_GEOMETRY_H
