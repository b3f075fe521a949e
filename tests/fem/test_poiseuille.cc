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

  template <int dim>
  class Parabola : public Function<dim>
  {
  public:
    Parabola() : Function<dim>(dim) {}
    double value(const Point<dim> &p, unsigned int c) const override
    {
      return c == 0 ? rho * f * p[1] * (H - p[1]) / (2 * mu) : 0.0;
    }
  };

  /// Plane Poiseuille flow between walls y = 0, H; periodic in x (and z in 3D).
  template <int dim>
  std::pair<double, double> poiseuille_errors(unsigned int refinements)
  {
    parallel::distributed::Triangulation<dim> tria(MPI_COMM_WORLD);
    std::vector<unsigned int> reps(dim, 1);
    reps[0] = 2;
    Point<dim> upper;
    for (unsigned int d = 0; d < dim; ++d)
      upper[d] = d == 0 ? 2.0 : H;
    GridGenerator::subdivided_hyper_rectangle(tria, reps, Point<dim>(), upper, true);
    std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>> faces;
    GridTools::collect_periodic_faces(tria, 0, 1, 0, faces);
    if (dim == 3)
      GridTools::collect_periodic_faces(tria, 4, 5, 2, faces);
    tria.add_periodicity(faces);
    tria.refine_global(refinements);

    ConstantMaterial<dim>  material(rho, mu);
    NavierStokesParameters prm;
    prm.scheme           = TimeScheme::bdf1;
    prm.linear_tolerance = 1e-14;
    NavierStokes<dim> ns(tria, prm, material);
    ns.set_periodic(0, 1, 0);
    if (dim == 3)
      ns.set_periodic(4, 5, 2);
    ns.set_dirichlet(2, std::make_shared<Functions::ZeroFunction<dim>>(dim));
    ns.set_dirichlet(3, std::make_shared<Functions::ZeroFunction<dim>>(dim));
    std::vector<double> g(dim, 0.0);
    g[0] = f;
    ns.set_acceleration(std::make_shared<Functions::ConstantFunction<dim>>(g));
    ns.setup();
    Functions::ZeroFunction<dim> zero_u(dim), zero_p(1);
    ns.initialize(zero_u, zero_p, 0.0);

    // Implicit viscous steps of size 0.5 contract the transient by ~1/(1 + dt π² ν) each.
    double change = 1;
    for (unsigned int k = 0; k < 200 && change > 1e-14; ++k)
      change = ns.step(0.5).velocity_change;

    Parabola<dim> exact;
    const auto    e     = ns.l2_errors(exact, zero_p);
    const double  u_max = rho * f * H * H / (8 * mu);
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      std::cout << "Poiseuille " << dim << "D: steps " << ns.n_steps() << "  DoFs "
                << ns.n_velocity_dofs() + ns.n_pressure_dofs() << "  |u - u_exact|_L2 / u_max = " << e.first / u_max
                << "  |p - p_exact|_L2 = " << e.second << std::endl;
    return {e.first / u_max, e.second};
  }
} // namespace

TEST(Poiseuille, SteadyProfileIsExactWithQ2In2D)
{
  const auto e = poiseuille_errors<2>(2);
  EXPECT_LT(e.first, 1e-8);
  EXPECT_LT(e.second, 1e-8 * rho * f * H);
}

TEST(Poiseuille, SteadyProfileIsExactWithQ2In3D)
{
  const auto e = poiseuille_errors<3>(1);
  EXPECT_LT(e.first, 1e-8);
  EXPECT_LT(e.second, 1e-8 * rho * f * H);
}
