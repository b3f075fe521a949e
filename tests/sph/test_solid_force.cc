// Archimedes: the SPH force on a fixed disk submerged in still water (BCE markers of kind
// `solid`, Engine::solid_force) equals the buoyancy rho g A of the displaced fluid, with no
// horizontal component. Checks the force formula of doc/equations.md "Forces on solids":
// the pair sum of (p_a + p_b) ∇W over the marker/fluid interface is the SPH form of ∮ p n dS.
#include <twinflow/core/scene.h>
#include <twinflow/sph/particle_setup.h>
#include <twinflow/sph/sph_simulation.h>
#include <twinflow_sph/engine.h>

#include "water_tank.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace twinflow;
using namespace twinflow::sph;

namespace
{
  struct Buoyancy
  {
    double fx = 0, fy = 0, exact = 0, lattice = 0;
  };

  /// Still water (depth 0.5) in a 0.6 x 0.6 tank around a disk of radius @p R at (0.3, 0.25).
  Buoyancy submerged_disk(const double dx, const double R)
  {
    const double rho = 1000, g = 9.8;
    Scene        scene = twinflow::testing::water_tank(0.6, 0.6, 0.5);
    Solid disk;
    disk.name   = "disk";
    disk.shape  = "disk";
    disk.center = {{0.3, 0.25, 0}};
    disk.radius = R;
    scene.solids.push_back(disk);

    SphParameters prm;
    prm.spacing = dx;
    const double     h      = prm.h_over_dx * dx;
    const int        layers = static_cast<int>(std::ceil(2.0 * h / dx - 1e-9));
    HostParticles<2> P;
    make_particles<2>(scene, dx, layers, rho, P);
    auto engine = make_engine<2>("cpu", domain_box<2>(scene), make_engine_settings(scene, prm));
    engine->set_particles(P);
    EXPECT_EQ(engine->n_solids(), 1);

    // The staircase disk the lattice resolves: lattice points inside the circle, dx^2 each.
    Buoyancy b;
    for (double x = 0.5 * dx; x < 0.6; x += dx)
      for (double y = 0.5 * dx; y < 0.6; y += dx)
        if (std::hypot(x - 0.3, y - 0.25) < R)
          b.lattice += dx * dx;
    b.lattice *= rho * g;
    b.exact = rho * g * M_PI * R * R;

    // Average over the last 100 of 300 steps (0.6 s at rest).
    int n = 0;
    for (int k = 0; k < 300; ++k)
    {
      engine->step(2e-3);
      if (k >= 200)
      {
        const auto F = engine->solid_force(0);
        b.fx += F[0];
        b.fy += F[1];
        ++n;
      }
    }
    b.fx /= n;
    b.fy /= n;
    std::cout << "submerged disk R = " << R << ", dx = " << dx << ": F = (" << b.fx << ", " << b.fy
              << ") N/m; rho g pi R^2 = " << b.exact << ", rho g (lattice area) = " << b.lattice
              << "; relative error " << (b.fy - b.exact) / b.exact << std::endl;
    return b;
  }
} // namespace

TEST(SolidForce, ArchimedesDisk)
{
  const Buoyancy b = submerged_disk(0.02, 0.1);
  EXPECT_NEAR(b.fy, b.exact, 0.03 * b.exact);
  EXPECT_LT(std::abs(b.fx), 0.01 * b.exact);
}

TEST(SolidForce, NoSolidNoForce)
{
  Scene scene;
  scene.dimension    = 2;
  scene.domain.upper = {{0.2, 0.2, 0}};
  scene.fluids.push_back({"water", 1000, 1e-3});
  SphParameters    prm;
  HostParticles<2> P;
  make_particles<2>(scene, 0.02, 3, 1000, P);
  auto engine = make_engine<2>("cpu", domain_box<2>(scene), make_engine_settings(scene, prm));
  engine->set_particles(P);
  engine->step(1e-3);
  EXPECT_EQ(engine->n_solids(), 0);
  EXPECT_EQ(engine->solid_force(0)[0], 0.0);
}
