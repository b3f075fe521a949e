// Poiseuille flow driven by a body force, periodic in x: with Q2 velocity the steady
// parabola u = ρ f y (H − y) / (2μ) lies in the discrete space, so the steady discrete
// solution must reproduce it to solver precision.
#include "flow_fixtures.h"

#include <twinflow/fem/material_model.h>

#include <gtest/gtest.h>

using namespace dealii;
using namespace twinflow::fem;

namespace
{
  constexpr double rho = 2.0, mu = 0.5, f = 3.0, H = 1.0;

  class Parabola : public Function<2>
  {
  public:
    Parabola() : Function<2>(2) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      return c == 0 ? rho * f * p[1] * (H - p[1]) / (2 * mu) : 0.0;
    }
  };
} // namespace

TEST(Poiseuille, SteadyProfileIsExactWithQ2)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
  GridGenerator::subdivided_hyper_rectangle(tria, {2, 1}, Point<2>(0, 0), Point<2>(2, H), true);
  std::vector<GridTools::PeriodicFacePair<parallel::distributed::Triangulation<2>::cell_iterator>> faces;
  GridTools::collect_periodic_faces(tria, 0, 1, 0, faces);
  tria.add_periodicity(faces);
  tria.refine_global(2);

  ConstantMaterial<2>    material(rho, mu);
  NavierStokesParameters prm;
  prm.scheme           = TimeScheme::bdf1;
  prm.linear_tolerance = 1e-14;
  NavierStokes<2> ns(tria, prm, material);
  ns.set_periodic(0, 1, 0);
  ns.set_dirichlet(2, std::make_shared<Functions::ZeroFunction<2>>(2));
  ns.set_dirichlet(3, std::make_shared<Functions::ZeroFunction<2>>(2));
  ns.set_acceleration(std::make_shared<Functions::ConstantFunction<2>>(std::vector<double>{f, 0.0}));
  ns.setup();
  Functions::ZeroFunction<2> zero_u(2), zero_p(1);
  ns.initialize(zero_u, zero_p, 0.0);

  // Implicit viscous steps of size 0.5 contract the transient by ~1/(1 + dt π² ν) each.
  double change = 1;
  for (unsigned int k = 0; k < 200 && change > 1e-14; ++k)
    change = ns.step(0.5).velocity_change;

  Parabola exact;
  const auto   e     = ns.l2_errors(exact, zero_p);
  const double u_max = rho * f * H * H / (8 * mu);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "Poiseuille: steps " << ns.n_steps() << "  |u - u_exact|_L2 / u_max = " << e.first / u_max
              << "  |p - p_exact|_L2 = " << e.second << std::endl;
  EXPECT_LT(e.first / u_max, 1e-8);
  EXPECT_LT(e.second, 1e-8 * rho * f * H);
}
