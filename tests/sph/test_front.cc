// Surge-front monitor (sph/front.h): the leading edge of the connected water, spray ignored.
#include <twinflow/sph/front.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace twinflow::sph;

namespace
{
  // A dx-spaced block of fluid [0, nx dx) x [0, ny dx) plus a row of BCE markers below it.
  HostParticles<2> block(int nx, int ny, double dx)
  {
    HostParticles<2> P;
    for (int i = 0; i < nx; ++i)
    {
      for (int j = 0; j < ny; ++j)
      {
        P.x.push_back({{(i + 0.5) * dx, (j + 0.5) * dx}});
        P.kind.push_back(ParticleKind::fluid);
      }
      P.x.push_back({{(i + 0.5) * dx, -0.5 * dx}});
      P.kind.push_back(ParticleKind::wall);
    }
    return P;
  }

  void add_fluid(HostParticles<2> &P, double x, double y)
  {
    P.x.push_back({{x, y}});
    P.kind.push_back(ParticleKind::fluid);
  }
} // namespace

TEST(SphFront, LeadingEdgeOfBlock)
{
  const double dx = 0.01;
  const auto   P  = block(10, 4, dx);
  EXPECT_NEAR(surge_front(P, dx), 0.1, 1e-14);
  EXPECT_NEAR(foremost_particle(P, dx), 0.1, 1e-14);
}

TEST(SphFront, SprayAheadIsIgnored)
{
  const double dx = 0.01;
  auto         P  = block(10, 4, dx);
  add_fluid(P, 0.3, 0.5 * dx);          // a droplet sliding on the floor, far ahead
  add_fluid(P, 0.2, 0.05);              // a pair in flight
  add_fluid(P, 0.2 + 1.5 * dx, 0.05);
  add_fluid(P, 0.1 + 0.5 * dx, 0.3);    // a droplet above the front, touching nothing
  EXPECT_NEAR(foremost_particle(P, dx), 0.3 + 0.5 * dx, 1e-14);
  EXPECT_NEAR(surge_front(P, dx), 0.1, 1e-14);
}

TEST(SphFront, ThinSheetCounts)
{
  // a one-particle-thick sheet on the floor ahead of the block is connected water
  const double dx = 0.01;
  auto         P  = block(10, 4, dx);
  for (int k = 0; k < 5; ++k)
    add_fluid(P, 0.1 + (k + 0.5) * 1.2 * dx, 0.5 * dx);
  // its last particle has one neighbour, the one before it two: the front is there
  EXPECT_NEAR(surge_front(P, dx), 0.1 + 3.5 * 1.2 * dx + 0.5 * dx, 1e-12);
}

TEST(SphFront, NoFluid)
{
  HostParticles<2> P;
  EXPECT_TRUE(std::isinf(surge_front(P, 0.01)));
}

TEST(SphFront, FrontFarBehindTheSpray)
{
  // a long row of isolated droplets ahead of the block: the window has to grow several times
  const double dx = 0.01;
  auto         P  = block(10, 4, dx);
  for (int k = 0; k < 40; ++k)
    add_fluid(P, 0.15 + 3.0 * dx * k, 0.5 * dx);
  EXPECT_NEAR(surge_front(P, dx), 0.1, 1e-14);
}
