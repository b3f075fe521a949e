// "The scene decides what is simulated": the FEM simulation builds only the modules a scene
// needs, reports them, and refuses (with a clear input error) what is not available.
#include <twinflow/core/errors.h>
#include <twinflow/core/scene.h>
#include <twinflow/fem/fem_simulation.h>

#include "scene_fixtures.h"

#include <deal.II/base/parameter_handler.h>

#include <gtest/gtest.h>

using namespace twinflow;

namespace
{
  const std::string base = R"(
set Dimension = 2
subsection Scene
  set End time = 0.02
end
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 2, 1
end
subsection Monitors
  set Monitors = energy
end
subsection FEM
  set Global refinements = 1
  set Time step = 0.01
end
)";

  std::pair<Scene, fem::FemParameters> load(const std::string &extra) { return twinflow::testing::load_scene(base + extra); }

  bool mentions(const std::vector<std::string> &list, const std::string &word)
  {
    for (const auto &s : list)
      if (s.find(word) != std::string::npos)
        return true;
    return false;
  }
} // namespace

TEST(Composition, SinglePhaseBuildsOnlyNavierStokes)
{
  const auto [scene, prm] = load("");
  const auto r            = fem::run_fem<2>(scene, prm, "composition_single");
  ASSERT_EQ(r.active_physics.size(), 1u);
  EXPECT_TRUE(mentions(r.active_physics, "navier-stokes"));
  EXPECT_FALSE(mentions(r.active_physics, "level set"));
  EXPECT_FALSE(mentions(r.active_physics, "immersed"));
  // Only velocity (Q2, 2 components) and pressure (Q1) DoFs exist: 4 x 2 cells → 9x5 and 5x3 nodes.
  EXPECT_EQ(r.dofs, 2u * 9 * 5 + 5 * 3);
  EXPECT_EQ(r.steps, 2u);
}

TEST(Composition, PeriodicDirectionIsReported)
{
  const auto [scene, prm] = load("subsection Domain\n set Periodic directions = x\nend\n");
  const auto r            = fem::run_fem<2>(scene, prm, "composition_periodic");
  EXPECT_TRUE(mentions(r.active_physics, "periodic x"));
  // periodic x: the right column of nodes is identified with the left one, but DoFs are
  // still distributed on both (constraints tie them): the count is unchanged.
  EXPECT_EQ(r.dofs, 2u * 9 * 5 + 5 * 3);
}

TEST(Composition, FreeSurfaceBuildsTheLevelSetOnlyWhenTheSceneHasOne)
{
  {
    const auto [scene, prm] = load("");
    fem::FemSimulation<2> sim(scene, prm, "composition_single_phase");
    EXPECT_EQ(sim.level_set(), nullptr);
    EXPECT_EQ(sim.level_set_space(), nullptr);
    EXPECT_EQ(sim.physics_list().size(), 1u);
  }
  {
    const auto [scene, prm] = load("subsection Fluids\n set Number of fluids = 2\n set Initial region of fluid 1 = 0, 0; 1, 0.5\n"
                                   " subsection Fluid 2\n  set Density = 1.2\n end\nend\n"
                                   "subsection Forces\n set Gravity = 0, -9.81\nend\n");
    fem::FemSimulation<2> sim(scene, prm, "composition_two_phase_built");
    ASSERT_NE(sim.level_set(), nullptr);
    // Algorithm 1 in order: space, Navier-Stokes, NCLS, VOF, redistancing, mass correction.
    std::vector<std::string> names;
    for (const auto *p : sim.physics_list())
      names.push_back(p->name());
    EXPECT_EQ(names, (std::vector<std::string>{"level-set space", "navier-stokes", "NCLS", "VOF", "redistancing",
                                               "mass correction"}));
    EXPECT_TRUE(mentions(sim.active_physics(), "level set"));
  }
}

TEST(Composition, UnavailableModulesAreRefusedClearly)
{
  {
    const auto [scene, prm] = load("subsection Fluids\n set Number of fluids = 2\nend\n");
    try
    {
      fem::run_fem<2>(scene, prm, "composition_two_phase");
      FAIL() << "two fluids without an initial water region must be refused";
    }
    catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("level set"), std::string::npos) << e.what();
    }
  }
  {
    const auto [scene, prm] = load("subsection Solids\n set Number of solids = 1\n subsection Solid 1\n"
                                   "  set Center = 1, 0.5\n  set Radius = 0.1\n  set Motion = elastic\n end\nend\n");
    try
    {
      fem::run_fem<2>(scene, prm, "composition_elastic");
      FAIL() << "an elastic solid must be refused until the ANCF coupling exists";
    }
    catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("allowed now: fixed, rigid"), std::string::npos) << e.what();
    }
  }
}

TEST(Composition, NoSolidMeansNoImmersedBoundaryAndNoBandRefinement)
{
  // Adaptation asked for, but nothing to follow: the mesh stays uniform.
  const auto [scene, prm] = load("subsection FEM\n subsection Mesh adaptation\n  set Maximum level = 4\n end\nend\n");
  fem::FemSimulation<2> sim(scene, prm, "composition_no_solid");
  const auto            r = sim.run();
  EXPECT_EQ(sim.immersed_boundary(), nullptr);
  EXPECT_EQ(sim.mesh_adaptation(), nullptr);
  EXPECT_FALSE(mentions(r.active_physics, "immersed"));
  EXPECT_FALSE(mentions(r.active_physics, "adaptation"));
  EXPECT_EQ(r.cells, 8u); // 2 x 1 coarse cells, 1 global refinement
  EXPECT_EQ(r.adaptations, 0u);
}

TEST(Composition, FixedSolidBuildsImmersedBoundaryButNoRigidBody)
{
  const auto [scene, prm] = load("subsection Solids\n set Number of solids = 1\n subsection Solid 1\n"
                                 "  set Center = 1, 0.5\n  set Radius = 0.1\n end\nend\n"
                                 "subsection FEM\n subsection Mesh adaptation\n  set Minimum level = 1\n"
                                 "  set Maximum level = 4\n  set Band width = 2\n end\nend\n");
  fem::FemSimulation<2> sim(scene, prm, "composition_fixed_solid");
  const auto            r = sim.run();
  ASSERT_NE(sim.immersed_boundary(), nullptr);
  ASSERT_NE(sim.mesh_adaptation(), nullptr);
  EXPECT_TRUE(mentions(r.active_physics, "immersed boundary"));
  EXPECT_TRUE(mentions(r.active_physics, "band at phi_s = 0"));
  EXPECT_FALSE(mentions(r.active_physics, "rigid"));
  EXPECT_FALSE(mentions(r.active_physics, "level set"));
  EXPECT_GT(r.cells, 8u);          // refined towards the disk
  EXPECT_LT(r.cells, 256u);        // but not everywhere (uniform level 4: 512 cells)
  EXPECT_EQ(r.adaptations, 0u);    // a fixed solid: refined once, before the first step
}

TEST(Composition, RigidSolidWithoutFreeSurfaceBuildsNoLevelSet)
{
  // A heavy disk (20 rho_fluid) sinking in one fluid: rigid body + IBM, no level set; the band
  // follows the body (re-adaptation as it moves).
  const auto [scene, prm] = load("subsection Solids\n set Number of solids = 1\n subsection Solid 1\n"
                                 "  set Center = 1, 0.5\n  set Radius = 0.1\n  set Motion = rigid\n"
                                 "  set Density = 20\n  set Locked degrees of freedom = x, rz\n end\nend\n"
                                 "subsection Fluids\n subsection Fluid 1\n  set Density = 1\n  set Viscosity = 0.01\n"
                                 " end\nend\nsubsection Forces\n set Gravity = 0, -9.8\nend\n"
                                 "subsection Scene\n set End time = 0.1\nend\n"
                                 "subsection FEM\n set Time step = 0.005\n subsection Mesh adaptation\n"
                                 "  set Minimum level = 1\n  set Maximum level = 4\n  set Band width = 2\n"
                                 "  set Interval = 1\n end\nend\n");
  fem::FemSimulation<2> sim(scene, prm, "composition_rigid_solid");
  const auto            r = sim.run();
  ASSERT_NE(sim.immersed_boundary(), nullptr);
  EXPECT_TRUE(mentions(r.active_physics, "rigid body"));
  EXPECT_FALSE(mentions(r.active_physics, "level set"));
  EXPECT_EQ(sim.solid_drying(), nullptr); // no free surface: nothing to dry
  EXPECT_FALSE(mentions(r.active_physics, "drying"));
  EXPECT_GT(r.adaptations, 0u); // the band moved with the body
  // it sank, and by less than free fall (buoyancy 1/20 of the weight, drag)
  const double y = r.monitors.at("body solid final y");
  EXPECT_LT(y, 0.5 - 0.25 * 0.5 * 9.8 * 0.01);
  EXPECT_GT(y, 0.5 - 0.5 * 9.8 * 0.01 - 1e-9);
}

TEST(Composition, CflControlLimitsTheStep)
{
  // Body-force driven periodic channel; with CFL control the step falls below the cap.
  const auto [scene, prm] = load("subsection Domain\n set Periodic directions = x\nend\n"
                                 "subsection Forces\n set Body force = 50, 0\nend\n"
                                 "subsection Scene\n set End time = 0.2\nend\n"
                                 "subsection FEM\n set Time step = 0.1\n set CFL number = 0.5\nend\n");
  const auto r = fem::run_fem<2>(scene, prm, "composition_cfl");
  EXPECT_GT(r.steps, 2u); // 0.2 s at the cap would be 2 steps
  EXPECT_NEAR(r.final_time, 0.2, 1e-12);
}
