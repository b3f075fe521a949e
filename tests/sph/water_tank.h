#pragma once
/// @file water_tank.h  2D scene of the SPH tests: a tank width × height, water at rest up to
/// @p depth (ρ = 1000, μ = 1e-3), gravity 9.8 along −y.
#include <twinflow/core/scene.h>

namespace twinflow::testing
{
  inline Scene water_tank(const double width, const double height, const double depth)
  {
    Scene scene;
    scene.dimension    = 2;
    scene.domain.lower = {{0, 0, 0}};
    scene.domain.upper = {{width, height, 0}};
    Region water;
    water.lower        = {{0, 0, 0}};
    water.upper        = {{width, depth, 0}};
    scene.fluid_region = water;
    scene.fluids.push_back({"water", 1000, 1e-3});
    scene.gravity = {{0, -9.8, 0}};
    return scene;
  }
} // namespace twinflow::testing
