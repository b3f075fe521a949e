// The coarse 3D immersed cylinder scene (parameters/cylinder_3d_immersed.prm) on the ranks it
// is given (registered on 2): the 3D signed distance (a cylinder along z), band adaptation of
// hexahedra, the Nitsche + penalty terms and the distributed solvers run together, and the
// startup flow stays physical: finite, pushing the cylinder downstream, and no faster than the
// potential-flow bound around a cylinder between walls (twice the inflow maximum).
#include "scene_fixtures.h"

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace twinflow;
using namespace twinflow::fem;
using namespace twinflow::testing;

TEST(ImmersedBoundary3d, CoarseCylinderAcrossTheSpan)
{
  std::ifstream     in(std::string(TWINFLOW_SOURCE_DIR) + "/parameters/cylinder_3d_immersed.prm");
  std::stringstream text;
  text << in.rdbuf();
  auto [scene, prm] = load_scene(text.str());
  scene.end_time    = 0.15; // three steps of the scene's 0.05
  FemSimulation<3> sim(scene, prm, "ibm_3d");
  const auto       r = sim.run();
  ASSERT_NE(sim.immersed_boundary(), nullptr);
  ASSERT_NE(sim.mesh_adaptation(), nullptr);
  EXPECT_EQ(r.steps, 3u);
  // 6 x 1 x 1 coarse cells, level 1 everywhere (48) plus the band refined to level 4.
  EXPECT_GT(r.cells, 48u * 4);
  EXPECT_LT(r.cells, 48u << 9); // far below uniform level 4 (24576 cells)
  EXPECT_TRUE(std::isfinite(r.monitors.at("C_d")));
  EXPECT_GT(r.monitors.at("C_d"), 0);
  EXPECT_LT(r.monitors.at("max velocity"), 2 * 0.45);
  // the solid is held: far below the flow speed inside it
  EXPECT_LT(r.monitors.at("solid velocity L2") / std::sqrt(M_PI * 0.05 * 0.05 * 0.41), 0.05 * 0.45);
}
