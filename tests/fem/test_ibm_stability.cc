// Hard cases of the immersed boundary (issue 11, label stability): a huge volume penalty, an
// interface half a cell wide, a solid touching the wall, and a step at the CFL limit. Each
// must stay finite with its kinetic energy below the bounds of the driven channel started
// from rest: the power of the body force is ∫ρ g u_x ≤ g (2 ρ V KE)^½ (walls and the solid
// only dissipate), so KE(t) ≤ ½ ρ V (g t)²; and at most the Poiseuille flow of the empty
// channel develops (an obstacle only adds drag), KE ≤ ½ ρ L (g / 2ν)² H⁵ / 30.
#include "scene_fixtures.h"

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace twinflow;
using namespace twinflow::fem;
using namespace twinflow::testing;

namespace
{
  constexpr double rho = 20, mu = 0.1, g = 1, H = 0.4, L = 1;

  double poiseuille_energy()
  {
    const double nu = mu / rho, a = g / (2 * nu);
    return 0.5 * rho * L * a * a * std::pow(H, 5) / 30;
  }

  std::string scene(const std::string &center, const std::string &fem_extra)
  {
    return periodic_cylinder_scene(1.0, band_levels(2, 5) + fem_extra, center);
  }

  /// Rows (time, kinetic energy) of an energy.csv monitor (two header lines).
  std::vector<std::pair<double, double>> energy_series(const std::string &path)
  {
    std::ifstream in(path);
    std::string   line;
    std::getline(in, line);
    std::getline(in, line);
    std::vector<std::pair<double, double>> rows;
    while (std::getline(in, line))
    {
      std::stringstream s(line);
      std::string       t, e;
      std::getline(s, t, ',');
      std::getline(s, e, ',');
      rows.emplace_back(std::stod(t), std::stod(e));
    }
    return rows;
  }

  void expect_bounded(const std::string &name, const std::string &center, const std::string &fem_extra)
  {
    const auto [s, p] = load_scene(scene(center, fem_extra));
    FemRunResult r;
    ASSERT_NO_THROW(r = run_fem<2>(s, p, name)) << name;
    double ke_max = 0, worst_ratio = 0;
    for (const auto &[t, ke] : energy_series(name + "/energy.csv"))
    {
      ASSERT_TRUE(std::isfinite(ke)) << name << " at t = " << t;
      ke_max      = std::max(ke_max, ke);
      worst_ratio = std::max(worst_ratio, ke / (0.5 * rho * L * H * g * g * t * t));
    }
    std::cout << name << ": max KE " << ke_max << " J (Poiseuille " << poiseuille_energy()
              << "), max KE / (rho V (g t)^2 / 2) = " << worst_ratio << ", C_d " << r.monitors.at("C_d")
              << ", steps " << r.steps << std::endl;
    EXPECT_TRUE(std::isfinite(r.monitors.at("C_d")));
    EXPECT_GT(ke_max, 0);
    EXPECT_LT(ke_max, poiseuille_energy());
    EXPECT_LE(worst_ratio, 1.0);
    EXPECT_GT(r.monitors.at("C_d"), 0); // the fluid pushes the body downstream
  }
} // namespace

TEST(ImmersedBoundaryStability, HugeVolumePenalty)
{
  // γ_β = 1e8: C_β ~ 1e11 against ρ/τ = 2e3 — a matrix conditioned by the penalty rows.
  expect_bounded("ibm_huge_penalty", "0.5, 0.2", "subsection Immersed boundary\n set Volume penalty = 1e8\nend");
}

TEST(ImmersedBoundaryStability, InterfaceHalfACellWide)
{
  // ε = h/2: δ_ε is sampled by ~1 quadrature point across the interface.
  expect_bounded("ibm_thin_interface", "0.5, 0.2", "subsection Immersed boundary\n set Interface width = 0.5\nend");
}

TEST(ImmersedBoundaryStability, SolidTouchingTheWall)
{
  // The disk touches the bottom wall (y = 0): the penalty, the Nitsche band and the Dirichlet
  // wall overlap.
  expect_bounded("ibm_touching_wall", "0.5, 0.05", "");
}

TEST(ImmersedBoundaryStability, StepAtTheCflLimit)
{
  // dt = CFL h_min / |u|_max with CFL = 1 (the cap 0.05 is never reached once the flow runs).
  expect_bounded("ibm_cfl_limit", "0.5, 0.2", "set CFL number = 1\nset Time step = 0.05");
}
