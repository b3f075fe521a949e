#pragma once
// Shared pieces of the FEM flow verification tests: analytic solutions and small helpers.
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>

namespace twinflow::testing
{
  using namespace dealii;

  /// Taylor–Green vortex on [0, 2π]^2: u = (−cos x sin y, sin x cos y) e^{−2νt},
  /// p = −¼ (cos 2x + cos 2y) e^{−4νt} (ρ = 1).
  class TaylorGreenVelocity : public Function<2>
  {
  public:
    explicit TaylorGreenVelocity(double nu) : Function<2>(2), nu(nu) {}
    double value(const Point<2> &p, unsigned int c) const override
    {
      const double f = std::exp(-2 * nu * get_time());
      return c == 0 ? -std::cos(p[0]) * std::sin(p[1]) * f : std::sin(p[0]) * std::cos(p[1]) * f;
    }
    double nu;
  };

  class TaylorGreenPressure : public Function<2>
  {
  public:
    explicit TaylorGreenPressure(double nu) : Function<2>(1), nu(nu) {}
    double value(const Point<2> &p, unsigned int) const override
    {
      return -0.25 * (std::cos(2 * p[0]) + std::cos(2 * p[1])) * std::exp(-4 * nu * get_time());
    }
    double nu;
  };

  /// Doubly periodic square [0, L]^2 refined @p refinements times.
  inline void make_periodic_square(parallel::distributed::Triangulation<2> &tria, double L,
                                   unsigned int refinements)
  {
    GridGenerator::hyper_cube(tria, 0, L, true);
    std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<2>::cell_iterator>> faces;
    GridTools::collect_periodic_faces(tria, 0, 1, 0, faces);
    GridTools::collect_periodic_faces(tria, 2, 3, 1, faces);
    tria.add_periodicity(faces);
    tria.refine_global(refinements);
  }

  /// Smooth, boundary-preserving distortion of [0, L]^2 (x += a sin sin): removes the
  /// superconvergence of even-degree elements on uniform meshes, so rates are the generic ones.
  inline void distort_square(Triangulation<2> &tria, double L, double a = 0.12)
  {
    GridTools::transform(
      [L, a](const Point<2> &p) {
        const double k = 2 * numbers::PI / L;
        const double s = a * std::sin(k * p[0]) * std::sin(k * p[1]) / k;
        return Point<2>(p[0] + s, p[1] + 0.7 * s);
      },
      tria);
  }

  /// Copy of a (possibly ghosted) vector holding the locally owned entries only.
  template <int dim>
  TrilinosWrappers::MPI::Vector owned_copy(const DoFHandler<dim> &dofs, const TrilinosWrappers::MPI::Vector &v)
  {
    TrilinosWrappers::MPI::Vector r(dofs.locally_owned_dofs(), MPI_COMM_WORLD);
    r = v;
    return r;
  }

  /// L2 norm of a discrete field given by its locally owned DoF vector.
  template <int dim>
  double l2_norm(const Mapping<dim> &mapping, const DoFHandler<dim> &dofs, const TrilinosWrappers::MPI::Vector &owned)
  {
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dofs, relevant);
    TrilinosWrappers::MPI::Vector v(dofs.locally_owned_dofs(), relevant, MPI_COMM_WORLD);
    v = owned;
    Vector<double> cellwise(dofs.get_triangulation().n_active_cells());
    VectorTools::integrate_difference(mapping, dofs, v,
                                      Functions::ZeroFunction<dim>(dofs.get_fe().n_components()),
                                      cellwise, QGauss<dim>(dofs.get_fe().degree + 2), VectorTools::L2_norm);
    return VectorTools::compute_global_error(dofs.get_triangulation(), cellwise, VectorTools::L2_norm);
  }

  /// Observed order between consecutive errors with refinement ratio 2.
  inline double rate(double coarse, double fine) { return std::log2(coarse / fine); }
} // namespace twinflow::testing
