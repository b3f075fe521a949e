// Variable-density manufactured solution of Guermond & Salgado (2009), unit disk:
//   ρ = 2 + x cos(sin t) + y sin(sin t),  u = (−y cos t, x cos t),  p = sin x sin y sin t,
// μ = 1, with the forcing f = ρ(∂_t u + u·∇u) + ∇p. ρ solves ∂_tρ + u·∇ρ = 0 exactly and is
// prescribed as a field, so this checks the variable-density projection scheme (Eq. 16 and
// the ρ_min pressure-increment problem) on its own: temporal self-convergence of BDF1/BDF2.
#include "flow_fixtures.h"

#include <twinflow/fem/material_model.h>

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <string>

using namespace dealii;
using namespace twinflow::fem;
using namespace twinflow::testing;

namespace
{
  class Density : public Function<2>
  {
  public:
    double value(const Point<2> &p, unsigned int = 0) const override
    {
      const double t = get_time();
      return 2 + p[0] * std::cos(std::sin(t)) + p[1] * std::sin(std::sin(t));
    }
    Tensor<1, 2> gradient(const Point<2> &, unsigned int = 0) const override
    {
      const double t = get_time();
      return Tensor<1, 2>({std::cos(std::sin(t)), std::sin(std::sin(t))});
    }
  };

  class Velocity : public Function<2>
  {
  public:
    Velocity() : Function<2>(2) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      const double t = get_time();
      return c == 0 ? -p[1] * std::cos(t) : p[0] * std::cos(t);
    }
  };

  class Pressure : public Function<2>
  {
  public:
    double value(const Point<2> &p, unsigned int = 0) const override
    {
      return std::sin(p[0]) * std::sin(p[1]) * std::sin(get_time());
    }
  };

  class Forcing : public Function<2>
  {
  public:
    Forcing() : Function<2>(2) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      const double t = get_time(), x = p[0], y = p[1];
      Density rho;
      rho.set_time(t);
      const double r  = rho.value(p);
      const double ct = std::cos(t), st = std::sin(t);
      return c == 0 ? r * (y * st - x * ct * ct) + std::cos(x) * std::sin(y) * st
                    : r * (-x * st - y * ct * ct) + std::sin(x) * std::cos(y) * st;
    }
  };

  /// The manufactured problem on @p tria with @p prm, started from the exact state and
  /// stepped @p n times by @p dt; @p inspect gets the solver and the exact u and p at the end.
  template <typename Inspect>
  void run_manufactured(parallel::distributed::Triangulation<2> &tria, const NavierStokesParameters &prm,
                        const double dt, const unsigned int n, Inspect inspect)
  {
    const bool          bdf2 = prm.scheme == TimeScheme::bdf2;
    FunctionMaterial<2> material(std::make_shared<Density>(), 1.0, 2 - std::sqrt(2.0), 0.0, bdf2 ? -dt : 0.0);
    NavierStokes<2>     ns(tria, prm, material);
    auto u = std::make_shared<Velocity>();
    ns.set_dirichlet(0, u);
    ns.set_force_density(std::make_shared<Forcing>());
    ns.setup();
    Pressure p;
    ns.initialize(*u, p, 0.0, bdf2 ? u.get() : nullptr, dt);
    for (unsigned int s = 0; s < n; ++s)
      ns.step(dt);
    inspect(ns, *u, p);
  }

  struct Outcome
  {
    TrilinosWrappers::MPI::Vector u, p;
    double                        eu, ep;
  };

  std::pair<double, double> self_convergence(TimeScheme scheme)
  {
    ConditionalOStream pout(std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0);
    std::vector<double>                        du, dp;
    std::vector<TrilinosWrappers::MPI::Vector> us, ps;
    for (unsigned int k = 0; k < 4; ++k)
    {
      parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
      GridGenerator::hyper_ball(tria);
      tria.refine_global(3);
      const unsigned int n  = 10u << k;
      const double       dt = 1.0 / n;
      NavierStokesParameters prm;
      prm.scheme           = scheme;
      prm.mapping_degree   = 2;
      prm.linear_tolerance = 1e-12;
      run_manufactured(tria, prm, dt, n, [&](const NavierStokes<2> &ns, const Velocity &u, const Pressure &p) {
        const auto e = ns.l2_errors(u, p);
        us.push_back(owned_copy(ns.velocity_dof_handler(), ns.velocity()));
        ps.push_back(owned_copy(ns.pressure_dof_handler(), ns.pressure()));
        if (k > 0)
        {
          TrilinosWrappers::MPI::Vector a(us[k]), b(ps[k]);
          a -= us[k - 1];
          b -= ps[k - 1];
          b.add(-b.mean_value());
          du.push_back(l2_norm(ns.get_mapping(), ns.velocity_dof_handler(), a));
          dp.push_back(l2_norm(ns.get_mapping(), ns.pressure_dof_handler(), b));
        }
        pout << "variable density " << (scheme == TimeScheme::bdf1 ? "BDF1" : "BDF2") << ": dt = " << dt
             << "  |u - u_exact| = " << e.first << "  |p - p_exact| = " << e.second;
        if (k > 0)
          pout << "  |u_dt - u_dt/2| = " << du.back() << "  |p_dt - p_dt/2| = " << dp.back();
        pout << std::endl;
      });
    }
    const double ru = rate(du[1], du[2]), rp = rate(dp[1], dp[2]);
    pout << "  temporal rates: velocity " << ru << "  pressure " << rp << std::endl;
    return {ru, rp};
  }
} // namespace

TEST(VariableDensity, GuermondSalgadoBDF1)
{
  const auto r = self_convergence(TimeScheme::bdf1);
  EXPECT_GE(r.first, 0.9);
  EXPECT_GE(r.second, 0.9 - 0.4); // pressure of first-order projection: at least ~1/2 (GS 2009)
}

TEST(VariableDensity, GuermondSalgadoBDF2)
{
  const auto r = self_convergence(TimeScheme::bdf2);
  EXPECT_GE(r.first, 1.8);
  EXPECT_GE(r.second, 1.4); // pressure of the standard incremental form: ≥ 3/2 (GS 2009)
}

// The component-block solve (Jacobi: the momentum matrix and the correction's L²(ρ) mass as
// diag(S, S) with S stored and read once) against the vector matrices (SSOR) on the same
// discrete problem: hanging nodes (one quadrant refined once more), the inhomogeneous rotating
// wall, the variable-density projection with its velocity correction. Both solve to 1e-12, so
// the results agree far below the discretisation error; a wrong block (a missed constraint or
// inhomogeneity, a swapped component) would differ at the size of the error itself.
TEST(VariableDensity, ComponentBlocksSolveTheVectorSystem)
{
  ConditionalOStream pout(std::cout, Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0);
  std::map<std::string, std::array<double, 4>> result;
  for (const std::string kind : {"jacobi", "ssor"})
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
    GridGenerator::hyper_ball(tria);
    tria.refine_global(2);
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && cell->center()[0] > 0 && cell->center()[1] > 0)
        cell->set_refine_flag();
    tria.execute_coarsening_and_refinement();
    NavierStokesParameters prm;
    prm.mapping_degree          = 2;
    prm.linear_tolerance        = 1e-12;
    prm.variable_projection     = true;
    prm.velocity_preconditioner = kind;
    prm.correction_tolerance    = 1e-12;
    run_manufactured(tria, prm, 0.05, 10, [&](const NavierStokes<2> &ns, const Velocity &u, const Pressure &p) {
      EXPECT_TRUE(ns.velocity_corrected());
      EXPECT_EQ(ns.solves_component_blocks(), kind == "jacobi");
      const auto e = ns.l2_errors(u, p);
      result[kind] = {{e.first, e.second, ns.kinetic_energy(), ns.max_velocity()}};
      pout << "component blocks " << (kind == "jacobi" ? "on " : "off") << ": |u - u_exact| = " << e.first
           << "  |p - p_exact| = " << e.second << "  kinetic energy = " << ns.kinetic_energy()
           << "  max |u| = " << ns.max_velocity() << std::endl;
    });
  }
  for (unsigned int k = 0; k < 4; ++k)
    EXPECT_NEAR(result["jacobi"][k], result["ssor"][k], 1e-7 * std::abs(result["ssor"][k])) << "quantity " << k;
}

// The variable-density pressure AMG set up every third step (applied to the two later
// matrices) against one set up every step: the same discrete solution to the solver
// tolerance. The reuse changes only the preconditioner, never the system.
TEST(VariableDensity, ReusedPressureAmgSolvesTheSameSystem)
{
  std::map<unsigned int, std::array<double, 3>> result;
  for (const unsigned int interval : {1u, 3u})
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
    GridGenerator::hyper_ball(tria);
    tria.refine_global(3);
    NavierStokesParameters prm;
    prm.mapping_degree        = 2;
    prm.linear_tolerance      = 1e-12;
    prm.correction_tolerance  = 1e-12;
    prm.variable_projection   = true;
    prm.pressure_amg_interval = interval;
    run_manufactured(tria, prm, 0.05, 9, [&](const NavierStokes<2> &ns, const Velocity &u, const Pressure &p) {
      const auto e = ns.l2_errors(u, p);
      result[interval] = {{e.first, e.second, ns.kinetic_energy()}};
    });
  }
  for (unsigned int k = 0; k < 3; ++k)
    EXPECT_NEAR(result[3][k], result[1][k], 1e-7 * std::abs(result[1][k])) << "quantity " << k;
}
