// Rigid body alone (solids/rigid_body.h): free fall against the exact solution, torque-free
// rotation of an asymmetric body (energy and angular momentum over many periods), the measured
// order of the integrator, locked degrees of freedom, and the added-mass correction that keeps
// explicit coupling of a light body stable.
#include <twinflow/solids/coupling.h>
#include <twinflow/solids/rigid_body.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace twinflow::solids;

namespace
{
  RigidBody asymmetric_top(const DofMask &mask = DofMask::all())
  {
    MassProperties m;
    m.mass    = 2.0;
    m.inertia = Vector3(1.0, 2.0, 3.0).asDiagonal();
    RigidBodyState s;
    s.orientation = Quaternion(Eigen::AngleAxisd(0.3, Vector3(1, 2, 3).normalized()));
    RigidBody b(m, s, mask, Vector3::Zero());
    b.set_angular_velocity(Vector3(0.4, 2.0, 0.3)); // near the intermediate (unstable) axis: tumbling
    return b;
  }
} // namespace

TEST(RigidBody, FreeFallIsExact)
{
  const Vector3  g(0, -9.81, 0);
  RigidBodyState s;
  s.position = Vector3(0.5, 1.0, 0.1);
  s.velocity = Vector3(0.2, 1.5, 0);
  RigidBody body(MassProperties::cylinder(700, 0.12, 0.2), s, DofMask::all(), g);
  for (int n = 0; n < 100; ++n)
    body.advance(0.01, 3);
  const double  t     = 1.0;
  const Vector3 exact = s.position + s.velocity * t + 0.5 * g * t * t;
  EXPECT_NEAR(body.time(), t, 1e-12);
  EXPECT_LT((body.state().position - exact).norm(), 1e-12);
  EXPECT_LT((body.state().velocity - (s.velocity + g * t)).norm(), 1e-12);
  EXPECT_LT((body.acceleration() - g).norm(), 1e-12);
  // mechanical energy is kept
  const RigidBody start(MassProperties::cylinder(700, 0.12, 0.2), s, DofMask::all(), g);
  EXPECT_NEAR(body.kinetic_energy() + body.potential_energy(), start.kinetic_energy() + start.potential_energy(),
              1e-10 * start.kinetic_energy());
}

TEST(RigidBody, TorqueFreeRotationKeepsMomentumAndEnergy)
{
  RigidBody      body = asymmetric_top();
  const Vector3  L0   = body.state().angular_momentum;
  const double   E0   = body.kinetic_energy();
  // tumbling period ~ 2π/|ω| ≈ 3 s: 100 s is ~30 periods, 0.01 s steps
  double max_energy_error = 0, max_momentum_error = 0;
  for (int n = 0; n < 10000; ++n)
  {
    body.advance(0.01);
    max_energy_error   = std::max(max_energy_error, std::abs(body.kinetic_energy() - E0) / E0);
    max_momentum_error = std::max(max_momentum_error, (body.state().angular_momentum - L0).norm() / L0.norm());
    // L = I_w ω in world axes
    const Matrix3 R = body.rotation();
    ASSERT_LT((R * Vector3(1, 2, 3).asDiagonal() * R.transpose() * body.angular_velocity() - L0).norm(), 1e-9 * L0.norm());
  }
  std::printf("torque-free top, 30 periods, dt = 0.01: energy error %.3e, angular momentum error %.3e\n",
              max_energy_error, max_momentum_error);
  EXPECT_LT(max_energy_error, 1e-6);     // RK4: O(dt^4) per unit time
  EXPECT_LT(max_momentum_error, 1e-13);  // dL/dt = 0 is integrated exactly
  // it really tumbles: ω changes direction by a lot
  EXPECT_GT(std::abs(body.angular_velocity().normalized().dot(Vector3(0.4, 2.0, 0.3).normalized()) - 1), 1e-2);
}

TEST(RigidBody, IntegratorIsFourthOrder)
{
  auto run = [](double dt) {
    RigidBody b = asymmetric_top();
    const int n = static_cast<int>(std::lround(4.0 / dt));
    for (int k = 0; k < n; ++k)
      b.advance(dt);
    return b;
  };
  const RigidBody ref = run(0.4 / 512);
  std::vector<double> errors;
  for (const double dt : {0.4 / 8, 0.4 / 16, 0.4 / 32})
  {
    const RigidBody b = run(dt);
    errors.push_back((b.rotation() - ref.rotation()).norm());
  }
  for (std::size_t k = 1; k < errors.size(); ++k)
  {
    const double rate = std::log2(errors[k - 1] / errors[k]);
    std::printf("dt = %g: orientation error %.3e, rate %.2f\n", 0.4 / (8 << k), errors[k], rate);
    EXPECT_GT(rate, 3.7);
    EXPECT_LT(rate, 4.5);
  }
}

TEST(RigidBody, LockedDegreesOfFreedomStayPut)
{
  RigidBodyState s;
  s.position = Vector3(0.3, 0.4, 0.05);
  RigidBody body(MassProperties::box(500, 0.2, 0.1, 0.3), s, DofMask::parse_locked("x", 2), Vector3(0, -9.8, 0));
  body.set_load(Vector3(3, 1, 7), Vector3(0.2, -0.5, 0.1));
  for (int n = 0; n < 50; ++n)
    body.advance(0.01, 2);
  EXPECT_DOUBLE_EQ(body.state().position.x(), 0.3);
  EXPECT_DOUBLE_EQ(body.state().position.z(), 0.05);
  EXPECT_LT(body.state().position.y(), 0.4); // falls: 1 N up against 0.003·500·9.8 N down
  const Vector3 w = body.angular_velocity();
  EXPECT_EQ(w.x(), 0.0);
  EXPECT_EQ(w.y(), 0.0);
  // rz alone: α = τ_z / I_zz exactly
  const double Izz = 500 * 0.2 * 0.1 * 0.3 * (0.04 + 0.01) / 12;
  EXPECT_NEAR(w.z(), 0.1 / Izz * 0.5, 1e-9 * std::abs(w.z()));
  // the rotation stays about z
  EXPECT_NEAR((body.rotation() * Vector3::UnitZ() - Vector3::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(RigidBody, BadInputIsRefused)
{
  EXPECT_THROW(DofMask::parse_locked("x, q", 3), std::invalid_argument);
  EXPECT_THROW(DofMask::parse_locked("rx", 2), std::invalid_argument);
  EXPECT_THROW(DofMask::parse_locked("z", 2), std::invalid_argument);
  EXPECT_NO_THROW(DofMask::parse_locked(" x , rz ", 2));
  MassProperties zero = MassProperties::cylinder(0, 0.1, 1);
  EXPECT_THROW(RigidBody(zero, RigidBodyState(), DofMask::all(), Vector3::Zero()), std::invalid_argument);
  RigidBody b(MassProperties::ball(1000, 0.1), RigidBodyState(), DofMask::all(), Vector3::Zero());
  EXPECT_THROW(b.set_load(Vector3(NAN, 0, 0), Vector3::Zero()), std::runtime_error);
  EXPECT_THROW(b.advance(-1), std::invalid_argument);
}

// A model of explicit co-simulation: the fluid answers the body's last acceleration with the
// added-mass force −M a (plus buoyancy B), lagged by one step as the fluid step after the solid
// step provides it. For M > m this diverges; Söding's correction with m_a ≥ (M − m)/2 is stable
// and keeps the equilibrium (the body settles where the load balances its weight).
TEST(RigidBody, AddedMassCorrectionStabilisesExplicitCoupling)
{
  const double rho_s = 300, rho_w = 1000, r = 0.1; // the stability suite's light body, 2D disk
  const MassProperties mp = MassProperties::cylinder(rho_s, r, 1.0);
  const double M = rho_w * M_PI * r * r;           // added mass of a submerged disk
  const double g = 9.81, k = 2 * rho_w * g * r;    // hydrostatic stiffness of a floating disk (half-submerged)
  const double y0 = 0.02; // released 2 cm above its equilibrium
  struct Run
  {
    double max_excursion = 0, period = 0;
  };
  auto simulate = [&](double ma) {
    RigidBodyState s;
    s.position = Vector3(0, y0, 0);
    RigidBody body(mp, s, DofMask::parse_locked("x, rz", 2), Vector3(0, -g, 0));
    body.set_added_mass(ma, 0);
    Run    run;
    double last_crossing = -1, y_old = y0;
    int    crossings = 0;
    for (int n = 0; n < 3000; ++n)
    {
      const double y = body.state().position.y();
      // buoyancy balancing the weight at y = 0 plus the hydrostatic spring, and the added mass
      const double F = mp.mass * g - k * y - M * body.acceleration().y();
      body.set_load(Vector3(0, F, 0), Vector3::Zero());
      body.advance(1e-3, 5);
      const double y_new = body.state().position.y();
      run.max_excursion  = std::max(run.max_excursion, std::abs(y_new));
      if (!std::isfinite(y_new) || run.max_excursion > 1)
      {
        run.max_excursion = 1e300;
        return run;
      }
      if (y_old > 0 && y_new <= 0) // downward zero crossings: one per period
      {
        const double tc = body.time() - 1e-3 * y_new / (y_new - y_old);
        if (last_crossing >= 0)
          run.period += tc - last_crossing, ++crossings;
        last_crossing = tc;
      }
      y_old = y_new;
    }
    run.period = crossings ? run.period / crossings : 0;
    return run;
  };
  const double exact_period = 2 * M_PI * std::sqrt((mp.mass + M) / k);
  const Run    explicit_run = simulate(0), corrected = simulate(M), partial = simulate(0.6 * M);
  std::printf("rho_s/rho_w = 0.3, released %g m off equilibrium: explicit coupling excursion %.3g m; with m_a = M: "
              "%.4f m, period %.4f s (exact %.4f s); with m_a = 0.6 M: %.4f m\n",
              y0, explicit_run.max_excursion, corrected.max_excursion, corrected.period, exact_period,
              partial.max_excursion);
  EXPECT_GT(explicit_run.max_excursion, 1.0); // the added-mass instability
  // with the correction: the undamped oscillation of amplitude y0, growing only by the one-step
  // lag of the spring load (energy gain at the rate ω²Δt/2 of a forward-lagged spring) …
  const double lag_growth = std::exp(0.5 * 4 * M_PI * M_PI / (exact_period * exact_period) * 1e-3 * 3.0);
  EXPECT_LT(corrected.max_excursion, 1.01 * lag_growth * y0);
  EXPECT_LT(partial.max_excursion, 1.01 * lag_growth * y0); // any m_a > (M − m)/2 is stable
  // … with the period of the body and its added mass on the hydrostatic spring
  EXPECT_NEAR(corrected.period, exact_period, 0.01 * exact_period);
}

// The implicit coupling the FEM uses for light bodies (solids::LoadRelaxation): the same
// disk of rho_s = 0.3 rho_w on the hydrostatic spring with the added mass M = 3.3 m, now with
// no added-mass correction. Each step is repeated with Aitken-relaxed loads until the "fluid"
// load F = m g - k y - M a of the moved body agrees with the one it moved under. Explicit
// coupling (one pass) diverges; the sub-iterations converge in every step and give the
// oscillation of the body with its added mass: amplitude kept, period 2 pi sqrt((m + M)/k).
TEST(CoSimulation, AitkenSubIterationsMakeLightBodyCouplingImplicit)
{
  const double rho_s = 300, rho_w = 1000, r = 0.1, g = 9.81, dt = 1e-3, y0 = 0.02;
  const MassProperties mp = MassProperties::cylinder(rho_s, r, 1.0);
  const double M = rho_w * M_PI * r * r, k = 2 * rho_w * g * r;
  auto run = [&](int max_iterations, double &period, double &mean_iterations, int &unconverged) {
    RigidBodyState s;
    s.position = Vector3(0, y0, 0);
    RigidBody      body(mp, s, DofMask::parse_locked("x, rz", 2), Vector3(0, -g, 0));
    LoadRelaxation relax(max_iterations, 1e-10);
    std::vector<BodyLoad> loads(1);
    loads[0].force = Vector3(0, mp.mass * g - k * y0, 0);
    double excursion = 0, last_crossing = -1, y_old = y0, sum_periods = 0;
    int    crossings = 0, total_iterations = 0;
    unconverged = 0;
    const int steps = 3000;
    for (int n = 0; n < steps; ++n)
    {
      const RigidBody start = body;
      relax.start(loads, {r}, mp.mass * g);
      for (;;)
      {
        body = start;
        body.set_load(relax.guess()[0].force, Vector3::Zero());
        body.advance(dt, 5);
        loads[0].force = Vector3(0, mp.mass * g - k * body.state().position.y() - M * body.acceleration().y(), 0);
        if (relax.update(loads))
          break;
      }
      total_iterations += relax.iterations();
      unconverged += relax.converged() ? 0 : 1;
      const double y_new = body.state().position.y();
      excursion          = std::max(excursion, std::abs(y_new));
      if (!std::isfinite(y_new) || excursion > 1)
        return 1e300;
      if (y_old > 0 && y_new <= 0)
      {
        const double tc = body.time() - dt * y_new / (y_new - y_old);
        if (last_crossing >= 0)
          sum_periods += tc - last_crossing, ++crossings;
        last_crossing = tc;
      }
      y_old = y_new;
    }
    period          = crossings ? sum_periods / crossings : 0;
    mean_iterations = double(total_iterations) / steps;
    return excursion;
  };
  double period = 0, iterations = 0;
  int    unconverged = 0;
  const double explicit_excursion = run(1, period, iterations, unconverged);
  const double implicit_excursion = run(30, period, iterations, unconverged);
  const double exact_period       = 2 * M_PI * std::sqrt((mp.mass + M) / k);
  std::printf("rho_s/rho_w = 0.3, no added-mass correction: explicit excursion %.3g m; Aitken sub-iterations: "
              "%.4f m, %.2f load evaluations per step, %d steps unconverged, period %.4f s (exact %.4f s)\n",
              explicit_excursion, implicit_excursion, iterations, unconverged, period, exact_period);
  EXPECT_GT(explicit_excursion, 1.0);
  EXPECT_EQ(unconverged, 0);
  EXPECT_LT(iterations, 10.0);
  EXPECT_LT(implicit_excursion, 1.01 * y0); // the implicit oscillation neither grows …
  EXPECT_GT(implicit_excursion, 0.99 * y0); // … nor is damped by the iteration
  EXPECT_NEAR(period, exact_period, 0.01 * exact_period);
}

TEST(CoSimulation, LoadRelaxationRefusesBadSettings)
{
  EXPECT_THROW(LoadRelaxation(0, 1e-3), std::invalid_argument);
  EXPECT_THROW(LoadRelaxation(5, 0), std::invalid_argument);
  EXPECT_THROW(LoadRelaxation(5, 1e-3, 1.5), std::invalid_argument);
}

TEST(RigidBody, MassProperties)
{
  const MassProperties c = MassProperties::cylinder(700, 0.12, 0.2);
  EXPECT_NEAR(c.mass * 9.81, 700 * M_PI * 0.0144 * 0.2 * 9.81, 1e-9);
  EXPECT_NEAR(c.mass * 9.8, 62.07, 0.01); // the falling cylinder's weight of BENCHMARKS.md
  EXPECT_NEAR(c.inertia(2, 2), 0.5 * c.mass * 0.0144, 1e-12);
}

// Wall contact (coupling.h): bodies in an empty tank (no fluid load) against its walls.
namespace
{
  twinflow::Scene contact_tank(const std::string &shape, const double restitution, const double friction)
  {
    twinflow::Scene s;
    s.dimension           = 2;
    s.domain.lower        = {{0, 0, 0}};
    s.domain.upper        = {{1, 1, 0}};
    s.gravity             = {{0, -9.81, 0}};
    s.solid_substeps      = 10;
    s.contact_restitution = restitution;
    s.contact_friction    = friction;
    twinflow::Solid b;
    b.name      = "body";
    b.shape     = shape;
    b.radius    = 0.1;
    b.length    = 0.3;
    b.thickness = 0.1;
    b.motion    = twinflow::SolidMotion::rigid;
    b.density   = 500;
    b.center    = {{0.5, 0.5, 0}};
    s.solids.push_back(b);
    return s;
  }

  double energy(const CoSimulation &c) { return c.body(0).kinetic_energy() + c.body(0).potential_energy(); }

  /// Advances @p steps fluid steps of @p dt with no fluid load; returns the largest energy rise
  /// over the initial value and checks no wall is crossed by more than one sub-step's fall.
  double run_in_air(CoSimulation &c, const twinflow::Scene &s, const int steps, const double dt)
  {
    const double e0 = energy(c);
    double       rise = 0;
    for (int n = 0; n < steps; ++n)
    {
      c.advance(dt, std::vector<BodyLoad>(1));
      c.check_clear_of_walls(s);
      rise = std::max(rise, energy(c) - e0);
    }
    return rise;
  }
} // namespace

TEST(WallContact, InelasticDiskComesToRestOnTheFloor)
{
  twinflow::Scene s = contact_tank("disk", 0.0, 0.0);
  CoSimulation    c(s);
  const double    e0 = energy(c);
  const double    rise = run_in_air(c, s, 1000, 2e-3); // falls 0.4 m in 0.29 s, then rests
  const Vector3   x = c.body(0).state().position, v = c.body(0).state().velocity;
  EXPECT_NEAR(x.y(), 0.1, 1e-9);               // on the floor, not in it
  EXPECT_NEAR(x.x(), 0.5, 1e-12);              // a frictionless vertical impact
  EXPECT_LT(v.norm(), 1e-12);                  // at rest
  EXPECT_NEAR(c.body(0).acceleration().y(), 0, 1e-9); // the fluid sees a body at rest
  EXPECT_LE(rise, 1e-9 * std::abs(e0) + 1e-12); // a contact never adds energy
  EXPECT_GT(c.contact_substeps(), 0u);
}

TEST(WallContact, RestitutionSetsTheRebound)
{
  // dropped from 0.4 m above the floor: the impact speed is sqrt(2 g 0.4) = 2.80 m/s, the first
  // rebound climbs e² 0.4 m
  for (const double e : {0.5, 0.9})
  {
    twinflow::Scene s = contact_tank("disk", e, 0.0);
    CoSimulation    c(s);
    double          apex = 0, lowest = 1;
    bool            bounced = false;
    for (int n = 0; n < 2000 && !(bounced && c.body(0).state().velocity.y() < 0); ++n)
    {
      c.advance(1e-3, std::vector<BodyLoad>(1));
      const double y = c.body(0).state().position.y();
      lowest         = std::min(lowest, y);
      if (c.body(0).state().velocity.y() > 0)
        bounced = true;
      if (bounced)
        apex = std::max(apex, y);
    }
    EXPECT_GE(lowest, 0.1 - 1e-12);
    // the impact falls within a sub-step (0.1 ms, 0.3 mm of travel): the apex to 1 %
    EXPECT_NEAR((apex - 0.1) / 0.4, e * e, 0.01 * e * e) << "e = " << e;
  }
}

TEST(WallContact, FrictionTurnsSlidingIntoRolling)
{
  // a disk on the floor sliding at v0 without spin: friction μ m g decelerates it and spins it
  // up until it rolls, at v0 / (1 + I / (m R²)) = 2 v0 / 3 (a solid disk), after t = v0 / (3 μ g)
  const double    v0 = 1.0, mu = 0.3, g = 9.81;
  twinflow::Scene s = contact_tank("disk", 0.0, mu);
  s.solids[0].center           = {{0.2, 0.1, 0}};
  s.solids[0].initial_velocity = {{v0, 0, 0}};
  CoSimulation c(s);
  const double t_roll = v0 / (3 * mu * g), dt = 1e-3;
  const int    steps  = int(std::round(1.5 * t_roll / dt));
  const double e0     = energy(c);
  for (int n = 0; n < steps; ++n)
  {
    c.advance(dt, std::vector<BodyLoad>(1));
    EXPECT_LE(energy(c), e0 + 1e-9);
  }
  const Vector3 v = c.body(0).state().velocity, w = c.body(0).angular_velocity();
  EXPECT_NEAR(v.x(), 2 * v0 / 3, 1e-3 * v0);
  EXPECT_NEAR(-w.z() * 0.1, v.x(), 1e-3 * v0); // rolling: v = −ω_z R
  EXPECT_NEAR(c.body(0).state().position.y(), 0.1, 1e-9);
}

TEST(WallContact, TiltedBoxSettlesOnTheFloorWithoutGainingEnergy)
{
  // a 0.3 x 0.1 box dropped tilted by 0.5 rad lands on a corner, rotates and comes to rest on a
  // face: every corner above the floor (to the sub-step's fall), no energy gained at any step
  twinflow::Scene s = contact_tank("box", 0.0, 0.5);
  s.solids[0].angle = 0.5;
  CoSimulation c(s);
  const double e0   = energy(c);
  const double rise = run_in_air(c, s, 3000, 1e-3);
  EXPECT_LE(rise, 1e-9 * std::abs(e0) + 1e-12);
  const Matrix3 R = c.body(0).rotation();
  double        lowest = 1;
  for (const double a : {-0.15, 0.15})
    for (const double b : {-0.05, 0.05})
      lowest = std::min(lowest, (c.body(0).state().position + R * Vector3(a, b, 0)).y());
  EXPECT_NEAR(lowest, 0.0, 1e-6);
  EXPECT_LT(c.body(0).kinetic_energy(), 1e-6 * std::abs(e0)); // at rest
  EXPECT_NEAR(c.body(0).state().position.y(), 0.05, 1e-3);     // on its long face
}

TEST(WallContact, OffStopsTheRunAtTheWall)
{
  twinflow::Scene s = contact_tank("disk", 0.0, 0.0);
  s.wall_contact    = false;
  CoSimulation c(s);
  EXPECT_THROW(run_in_air(c, s, 1000, 2e-3), std::runtime_error);
  s.contact_restitution = 1.5;
  EXPECT_THROW(CoSimulation bad(s), std::invalid_argument);
}
