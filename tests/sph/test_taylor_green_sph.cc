// Taylor–Green vortex in SPH (Algorithm 2, both directions periodic, no walls, no free
// surface): u = U sin(kx) cos(ky), v = −U cos(kx) sin(ky) decays like exp(−2νk²t), so the
// kinetic energy decays at the rate 4νk². The rate fitted to log KE(t) approaches it as the
// spacing falls, for the consistent (Eq. 22–23) and the standard (Eq. 19–20) operators.
#include <twinflow_sph/engine.h>

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <iostream>

using namespace twinflow;
using namespace twinflow::sph;

namespace
{
  // Re = U / (νk) ≈ 3.2. The particles follow the flow: at a hyperbolic stagnation point
  // the lattice stretches by exp(∫ kU e^{−2νk²t} dt), 1.7 by t = 0.1 here. With ν = 0.02 until
  // t = 0.2 (stretch 2.4) the spacing along the stretching direction exceeds the support
  // 2h = 2.4Δx, the correction tensors of the consistent operators degenerate and the run
  // diverges (measured at 32² and 64², with or without shifting); the standard ones survive.
  constexpr double pi = 3.14159265358979323846, k = 2 * pi, U = 1, rho0 = 1, nu = 0.05, end_time = 0.1;
  // One fixed step for all spacings: the approximate projection (A^L ≠ A^G A^G) removes a
  // little kinetic energy per step, so with a CFL-scaled step the rate error stalls near 1 %
  // (more steps on finer lattices); with a fixed step it falls with the spacing.
  constexpr int steps = 20;

  struct Decay
  {
    double rate = 0;          ///< fitted −d log KE / dt
    double rate_error = 0;    ///< |rate − 4νk²| / 4νk²
    double velocity_error = 0;///< relative L2 error of u against the exact field at t_end
    int    max_pressure_iterations = 0;
    bool   converged = true;
    double seconds = 0;
  };

  /// Runs the vortex on an n × n lattice of the unit square until end_time.
  Decay taylor_green(const int n, const bool consistent)
  {
    const auto   start = std::chrono::steady_clock::now();
    const double dx    = 1.0 / n;
    DomainBox<2> box;
    for (int d = 0; d < 2; ++d)
    {
      box.lower[d]    = 0;
      box.upper[d]    = 1;
      box.periodic[d] = true;
    }
    HostParticles<2> P;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
      {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
        P.add({{x, y}}, {{U * std::sin(k * x) * std::cos(k * y), -U * std::cos(k * x) * std::sin(k * y)}},
              0.25 * rho0 * U * U * (std::cos(2 * k * x) + std::cos(2 * k * y)), rho0);
      }
    EngineSettings s;
    s.spacing      = dx;
    s.h            = 1.2 * dx;
    s.rho0         = rho0;
    s.mu           = nu * rho0;
    s.consistent   = consistent;
    s.free_surface = false;
    s.velocity_solver = {2000, 1e-8};
    s.pressure_solver = {2000, 1e-8};
    auto engine = make_engine<2>("cpu", box, s);
    engine->set_particles(P);

    const double dt = end_time / steps; // CFL U dt / h = 0.27 on the finest lattice (64²)
    auto kinetic = [&]() {
      engine->get_particles(P);
      double e = 0;
      for (const auto &v : P.u)
        e += 0.5 * (v[0] * v[0] + v[1] * v[1]);
      return e * rho0 * dx * dx;
    };
    // least-squares fit of log KE = a − rate t over all steps
    double st = 0, sl = 0, stt = 0, stl = 0;
    int    m = 0;
    auto   sample = [&](const double t) {
      const double l = std::log(kinetic());
      st += t, sl += l, stt += t * t, stl += t * l, ++m;
    };
    Decay out;
    sample(0);
    for (int step = 1; step <= steps; ++step)
    {
      const StepReport &r = engine->step(dt);
      out.converged       = out.converged && r.pressure.converged;
      out.max_pressure_iterations = std::max(out.max_pressure_iterations, r.pressure.iterations);
      sample(step * dt);
    }
    out.rate       = -(m * stl - st * sl) / (m * stt - st * st);
    const double exact_rate = 4 * nu * k * k;
    out.rate_error = std::abs(out.rate - exact_rate) / exact_rate;

    engine->get_particles(P);
    const double decay = std::exp(-2 * nu * k * k * end_time);
    double       e2 = 0, u2 = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
    {
      const double x = P.x[i][0], y = P.x[i][1];
      const double ue = U * decay * std::sin(k * x) * std::cos(k * y), ve = -U * decay * std::cos(k * x) * std::sin(k * y);
      e2 += (P.u[i][0] - ue) * (P.u[i][0] - ue) + (P.u[i][1] - ve) * (P.u[i][1] - ve);
      u2 += ue * ue + ve * ve;
    }
    out.velocity_error = std::sqrt(e2 / u2);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "Taylor-Green SPH (" << (consistent ? "consistent" : "standard") << "): " << n << "^2 particles, "
              << steps << " steps: KE decay rate " << out.rate << " (exact " << exact_rate << ", error "
              << out.rate_error << "), velocity L2 error " << out.velocity_error << ", max pressure iterations "
              << out.max_pressure_iterations << ", " << out.seconds << " s" << std::endl;
    return out;
  }

  /// Rate errors at 16², 32², 64²; prints the observed orders.
  std::array<Decay, 3> series(const bool consistent)
  {
    const std::array<Decay, 3> d{{taylor_green(16, consistent), taylor_green(32, consistent), taylor_green(64, consistent)}};
    std::cout << "  observed orders of the rate error " << std::log2(d[0].rate_error / d[1].rate_error) << ", "
              << std::log2(d[1].rate_error / d[2].rate_error) << std::endl;
    for (const Decay &x : d)
      EXPECT_TRUE(x.converged);
    return d;
  }
} // namespace

namespace
{
  /// The decay-rate error falls at each refinement and the finest lattice is within bounds.
  void expect_converging(const bool consistent, const double rate_tolerance, const double velocity_tolerance)
  {
    const auto d = series(consistent);
    EXPECT_LT(d[1].rate_error, d[0].rate_error);
    EXPECT_LT(d[2].rate_error, d[1].rate_error);
    EXPECT_LT(d[2].rate_error, rate_tolerance);
    EXPECT_LT(d[2].velocity_error, velocity_tolerance);
  }
} // namespace

TEST(TaylorGreenSph, DecayRateConsistent)
{
  // measured: rate errors 3.7 %, 1.2 %, 0.56 % (orders 1.6, 1.1); velocity L2 errors 4.7 %, 3.5 %, 3.2 %
  expect_converging(true, 0.015, 0.06);
}

TEST(TaylorGreenSph, DecayRateStandard)
{
  // measured: rate errors 4.3 %, 1.3 %, 0.53 % (orders 1.7, 1.3); velocity L2 errors 11.0 %, 7.5 %,
  // 5.7 %. Before the operators were multiplied by the lattice factor (2026-12-07): 4.6 %, 2.0 %,
  // 1.3 % (orders 1.2, 0.58) and 6.2 %, 4.9 %, 4.6 %: the exact projection on the lattice decays
  // the vortex at the right rate, and its velocity error is larger (doc/benchmarks.md).
  expect_converging(false, 0.03, 0.08);
}
