/**
 * @file shapes.h
 * @brief All primitive signed-distance shapes.
 *
 * Every shape S in twinflow::geometry has the same duck-typed interface,
 * callable on host and device (see hd.h):
 *   - `static constexpr int dimension;`
 *   - `TWINFLOW_HD double signed_distance(const Vec<dimension> &p) const;`
 *     negative inside, positive outside, zero on the surface;
 *   - `TWINFLOW_HD Vec<dimension> normal(const Vec<dimension> &p) const;`
 *     the unit gradient of the distance (outward normal on the surface), with
 *     a documented choice where the distance is not differentiable.
 *
 * Primitives: Box<dim> (axis-aligned), Ball<dim> (Disk, Sphere), Cylinder
 * (3D), HalfSpace<dim>, Plate<dim> (oriented box). For rigid motions see
 * transform.h, for CSG see csg.h; geometry.h includes everything.
 */
#ifndef TWINFLOW_GEOMETRY_SHAPES_H
#define TWINFLOW_GEOMETRY_SHAPES_H

#include <twinflow/geometry/ball.h>
#include <twinflow/geometry/box.h>
#include <twinflow/geometry/cylinder.h>
#include <twinflow/geometry/halfspace.h>
#include <twinflow/geometry/plate.h>

#endif // TWINFLOW_GEOMETRY_SHAPES_H
