// Poiseuille flow in SPH (periodic in x, BCE walls at y = 0, H, body force): the steady
// profile u = f y (H − y) / (2ν) is approached with an error that falls with the spacing.
#include <twinflow/core/scene.h>
#include <twinflow/sph/particle_setup.h>
#include <twinflow/sph/sph_simulation.h>
#include <twinflow_sph/engine.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace twinflow;
using namespace twinflow::sph;

namespace
{
  constexpr double H = 0.1, rho = 1000, mu = 5.0, nu = mu / rho, u_max = 0.01, f = 8 * nu * u_max / (H * H);

  /// Relative L2 error of the steady SPH profile at spacing H / n.
  double profile_error(int n, bool consistent)
  {
    Scene scene;
    scene.dimension    = 2;
    scene.domain.lower = {{0, 0, 0}};
    scene.domain.upper = {{0.4 * H, H, 0}};
    scene.periodic     = {{true, false, false}};
    scene.fluids.push_back({"fluid", rho, mu});
    const double dx = H / n;
    HostParticles<2> P;
    make_particles<2>(scene, dx, 3, rho, P);
    scene.body_force = {{f, 0, 0}};
    SphParameters prm;
    prm.spacing          = dx;
    prm.consistent       = consistent;
    prm.solver_tolerance = 1e-10;
    const EngineSettings s = make_engine_settings(scene, prm);
    auto engine = make_engine<2>("cpu", domain_box<2>(scene), s);
    engine->set_particles(P);
    // slowest viscous mode decays like exp(−π²ν t / H²), e-folding time 0.2 s: 1.6 s of
    // implicit (Crank–Nicolson) steps of 0.02 s leave a transient below 5e-4
    for (int k = 0; k < 80; ++k)
      engine->step(0.02);
    engine->get_particles(P);
    double e2 = 0, u2 = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.kind[i] == ParticleKind::fluid)
      {
        const double y = P.x[i][1], exact = f * y * (H - y) / (2 * nu);
        e2 += (P.u[i][0] - exact) * (P.u[i][0] - exact);
        u2 += exact * exact;
      }
    const double e = std::sqrt(e2 / u2);
    std::cout << "SPH Poiseuille (" << (consistent ? "consistent" : "standard") << "): H/dx = " << n
              << "  relative L2 profile error " << e << std::endl;
    return e;
  }
} // namespace

TEST(PoiseuilleSph, ConvergesWithSpacingConsistent)
{
  const double e1 = profile_error(10, true), e2 = profile_error(20, true), e3 = profile_error(40, true);
  const double r1 = std::log2(e1 / e2), r2 = std::log2(e2 / e3);
  std::cout << "  observed orders " << r1 << ", " << r2 << std::endl;
  // measured: 11.5 %, 5.4 %, 2.6 % — first order, set by the BCE wall condition (Eq. 59–60:
  // the mirrored velocity places the no-slip point only approximately at the wall)
  EXPECT_LT(e3, 0.04);
  EXPECT_GT(r1, 0.8);
  EXPECT_GT(r2, 0.8);
}
