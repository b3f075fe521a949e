// Still water in a tank (SPH, Algorithm 2 with BCE walls): after 1 s at rest the pressure
// in the bulk is hydrostatic and the particles stay (nearly) at rest.
#include <twinflow/core/scene.h>
#include <twinflow/sph/hydrostatic_check.h>
#include <twinflow/sph/particle_setup.h>
#include <twinflow/sph/sph_simulation.h>
#include <twinflow_sph/engine.h>

#include "water_tank.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace twinflow;
using namespace twinflow::sph;

namespace
{
  HydrostaticCheck still_water(bool consistent, double alpha, PressureWall walls, bool paper_surface = false)
  {
    const Scene scene = twinflow::testing::water_tank(0.5, 0.6, 0.4);

    const double dx = 0.02, H = 0.4, rho = 1000, g = 9.8;
    HostParticles<2> P;
    make_particles<2>(scene, dx, 3, rho, P);
    SphParameters prm;
    prm.spacing    = dx;
    prm.consistent = consistent;
    prm.alpha      = alpha;
    prm.neumann_walls = walls == PressureWall::neumann;
    if (paper_surface) // the paper's form: the density criterion alone, no shifting, no pair separation
      prm.free_surface_divergence_ratio = prm.free_surface_neighbour_ratio = prm.shifting = prm.min_pair_distance = 0;
    const EngineSettings s = make_engine_settings(scene, prm);
    auto engine = make_engine<2>("cpu", domain_box<2>(scene), s);
    engine->set_particles(P);
    for (int k = 0; k < 500; ++k)
    {
      const auto &r = engine->step(2e-3);
      EXPECT_TRUE(r.pressure.converged) << "step " << k;
    }
    engine->get_particles(P);
    // bulk (4 spacings below the surface and from the walls) against rho g (H - y) where the
    // surface particles carry half a spacing of liquid (consistent operators), else rho g (H - dx/2 - y)
    const HydrostaticCheck o = hydrostatic_check<2>(scene, dx, P, s.offsets_surface());
    std::cout << "still water (" << (consistent ? "consistent" : "standard") << ", alpha " << alpha << ", "
              << (walls == PressureWall::bce ? "BCE" : "Neumann") << " walls): bulk particles " << o.bulk_particles
              << "  max |p - rho g (H-y)| / rho g (H-y) = " << o.max_relative_error << "  rms " << o.rms_relative_error
               << "  speed: max " << o.max_speed << ", bulk max " << o.bulk_max_speed << ", rms " << o.rms_speed << " m/s (sqrt(gH) = " << std::sqrt(g * H) << ")" << std::endl;
    return o;
  }

  /// Still water at rest for @p seconds (Δt = 2e-3 s, SPH/Wetted walls on): the largest fluid
  /// speed of any step and the final hydrostatic check.
  struct Rest
  {
    double           max_speed = 0;
    HydrostaticCheck last;
  };

  Rest stay_at_rest(const bool consistent, const double seconds,
                    const DensityCorrection form = EngineSettings().density_correction,
                    const bool conservative_gradient = false)
  {
    const Scene scene = twinflow::testing::water_tank(0.5, 0.6, 0.4);
    const double dx = 0.02;
    HostParticles<2> P;
    make_particles<2>(scene, dx, 3, 1000, P);
    SphParameters prm;
    prm.spacing            = dx;
    prm.consistent         = consistent; // the defaults: wetted walls
    prm.density_correction = form;
    EngineSettings s = make_engine_settings(scene, prm);
    s.conservative_gradient        = conservative_gradient; // with its partner (engine.h)
    s.shifting_velocity_correction = conservative_gradient;
    auto engine             = make_engine<2>("cpu", domain_box<2>(scene), s);
    engine->set_particles(P);
    Rest         rest;
    const int    steps = static_cast<int>(std::lround(seconds / 2e-3));
    for (int k = 0; k < steps; ++k)
    {
      const auto &r = engine->step(2e-3);
      EXPECT_TRUE(r.pressure.converged) << "step " << k;
      rest.max_speed = std::max(rest.max_speed, r.max_speed);
      if (!(r.max_speed < 1)) // diverged: no point in going on
        break;
    }
    engine->get_particles(P);
    rest.last = hydrostatic_check<2>(scene, dx, P, s.offsets_surface());
    std::cout << "at rest for " << seconds << " s (" << (consistent ? "consistent" : "standard")
              << "): max speed over the run " << rest.max_speed << " m/s (" << rest.max_speed / std::sqrt(9.8 * 0.4)
              << " sqrt(gH)); final bulk pressure error max " << rest.last.max_relative_error << ", rms "
              << rest.last.rms_relative_error << std::endl;
    return rest;
  }

  /// Issue 14, item 2: at rest, every fluid particle slower than 1e-3 sqrt(gH) at every step,
  /// and the bulk pressure within 1 % of hydrostatic at the end.
  void expect_at_rest(const Rest &rest)
  {
    EXPECT_LT(rest.max_speed, 1e-3 * std::sqrt(9.8 * 0.4));
    EXPECT_GT(rest.last.bulk_particles, 100u);
    EXPECT_LT(rest.last.max_relative_error, 0.01);
  }
} // namespace

TEST(StillWater, HydrostaticConsistent)
{
  const HydrostaticCheck o = still_water(true, 0.5, PressureWall::bce);
  EXPECT_GT(o.bulk_particles, 100u);
  EXPECT_LT(o.max_relative_error, 0.01);
  // at rest with the defaults (wetted walls): every particle slower than 1e-3 sqrt(gH), the
  // bound of issue 14 (measured 5.0e-5 m/s, bulk error 2.9e-5; with the defaults of before,
  // 0.96 % and a 0.1 sqrt(gH) jitter of the corners next to the walls)
  EXPECT_LT(o.max_speed, 1e-3 * std::sqrt(9.8 * 0.4));
}

TEST(StillWater, HydrostaticStandard)
{
  // Standard operators (Eq. 19–20, the pair-antisymmetric pressure force) in the paper's form of the
  // surface (density criterion alone, no shifting, no pair separation). Measured after 1 s: bulk
  // error max 2.2e-3 %, speed max 4.1e-5 m/s. Before the rows the surface truncates were assembled
  // consistent and the operators multiplied by the lattice factor (2026-12-07, doc/benchmarks.md
  // "Standard operators at rest"): 18.9 % and 0.12 m/s, the top layers jittering in a
  // compressed state, and a snapshot chaotic in the solver's round-off.
  const HydrostaticCheck o = still_water(false, 0.5, PressureWall::bce, true);
  EXPECT_GT(o.bulk_particles, 100u);
  EXPECT_LT(o.max_relative_error, 0.01);
  EXPECT_LT(o.max_speed, 1e-3 * std::sqrt(9.8 * 0.4));
}

// Walled still water at rest (issue 14, item 2), with SPH/Wetted walls (the default; Eq. 64 with ρ0, wetted
// wall markers mirror separation; engine_functors.inl). Without it the consistent run diverges
// at t = 2.44 s. The 2 s runs are quick; the 10 s runs (label full) are test_sph_still_water_10s.
TEST(StillWaterAtRest, ConsistentTwoSeconds) { expect_at_rest(stay_at_rest(true, 2)); }
// The 10 s runs (label full, test_sph_still_water_10s), both forms of the density-error
// correction. Measured 2026-12-06 with every wall marker wetted: velocity form 4.1e-4 m/s, bulk
// error 0.14 %; position form (the free-surface default) 4.0e-4 m/s, 0.28 %. Before, markers whose
// support held a free-surface particle (the contact line) did not hold the liquid: the wall-side
// particles of the top two rows drifted off the walls at a growing speed (4.2e-4 m/s at t = 8 s,
// 1.6 mm off the wall, second-row density 996 -> 970), and at t = 9.868 s two of them were
// flagged free surface for one step (rho = 0.95 rho0): a 0.013 m/s kick (position form; the
// velocity form passed at 5.6e-4 m/s, 0.54 %). A +-0.5-1 % hysteresis on the density criterion
// only delayed that flip by a step (the divergence criterion crosses with it).
TEST(StillWaterAtRest, DISABLED_ConsistentTenSeconds)
{
  expect_at_rest(stay_at_rest(true, 10, DensityCorrection::velocity));
}
TEST(StillWaterAtRest, DISABLED_PositionFormTenSeconds)
{
  expect_at_rest(stay_at_rest(true, 10, DensityCorrection::position));
}

// The standard operators with the scene defaults (the position form of the density-error
// correction, wetted walls, the surface offset). Measured 2026-12-07: 2 s 3.3e-4 m/s, bulk error
// 0.009 %; 10 s 6.3e-4 m/s (3.2e-4 sqrt(gH)), 0.23 % (a per-row scale: 1.0e-3 m/s, 0.30 %, and
// with the velocity form 1.7e-3 m/s, 0.085 %).
// Before: 0.79 m/s and 69 % at 2 s.
TEST(StillWaterAtRest, StandardTwoSeconds) { expect_at_rest(stay_at_rest(false, 2)); }
TEST(StillWaterAtRest, DISABLED_StandardTenSeconds) { expect_at_rest(stay_at_rest(false, 10)); }

// The experimental summation-by-parts gradient with shifting's velocity correction
// (EngineSettings::conservative_gradient, shifting_velocity_correction; doc/benchmarks.md
// "A summation-by-parts consistent gradient"): its free-surface rows are exact only for the plane
// Δx/2 above them along ∇p, so rest is what it must not lose. Measured 2026-12-07 with ω = V
// everywhere: 2 s 1.5e-4 m/s, bulk error 0.028 % (with the closure plane along the neighbours'
// centroid instead of ∇p: 9.1e-3 m/s at the contact line). With the free-surface rows' weights
// ω free (twenty-first session): 1.4e-4 m/s, bulk error 3.6e-6 rms, 29 s at 2 threads. Label full.
TEST(StillWaterAtRest, DISABLED_ConservativeGradientTwoSeconds)
{
  expect_at_rest(stay_at_rest(true, 2, EngineSettings().density_correction, true));
}
