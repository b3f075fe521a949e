#pragma once
/**
 * @file material_model.h
 * Density and viscosity fields ρ(x,t), μ(x,t) as the Navier–Stokes solver sees them.
 *
 * The solver never asks *why* the density varies: a single fluid gives constants, the
 * two-phase module evaluates Eq. 9–10 of the paper from the level set, a verification
 * scene prescribes an analytic field. All of them implement this interface.
 */
#include <deal.II/base/function.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

namespace twinflow::fem
{
  /// Material values at the quadrature points of one cell.
  template <int dim>
  struct MaterialValues
  {
    std::vector<double>                  density;            ///< ρ^{n+1}
    std::vector<double>                  viscosity;          ///< μ^{n+1}
    std::vector<double>                  density_previous;   ///< ρ^n (the step before)
    std::vector<double>                  density_older;      ///< ρ^{n−1}

    void resize(const unsigned int n)
    {
      density.resize(n);
      viscosity.resize(n);
      density_previous.resize(n);
      density_older.resize(n);
    }
  };

  /**
   * Interface of a material (density/viscosity) field. Evaluated cell by cell at the
   * quadrature points the solver hands over, at the time of the new step.
   */
  template <int dim>
  class MaterialModel
  {
  public:
    virtual ~MaterialModel() = default;

    /// Fill @p values at @p points (real coordinates) of @p cell at time @p time.
    virtual void evaluate(const typename dealii::Triangulation<dim>::active_cell_iterator &cell,
                          const std::vector<dealii::Point<dim>> &points,
                          double                                 time,
                          MaterialValues<dim>                   &values) const = 0;

    /// Lower bound of ρ over the domain and all times: χ = ρ_min of the projection step.
    virtual double minimum_density() const = 0;

    /// True if ρ and μ are constants: the solver then skips the variable-density terms.
    virtual bool is_constant() const { return false; }

  };

  /// One fluid: constant ρ and μ.
  template <int dim>
  class ConstantMaterial : public MaterialModel<dim>
  {
  public:
    ConstantMaterial(const double density, const double viscosity)
      : rho(density), mu(viscosity)
    {}

    void evaluate(const typename dealii::Triangulation<dim>::active_cell_iterator &,
                  const std::vector<dealii::Point<dim>> &points,
                  double,
                  MaterialValues<dim> &values) const override
    {
      values.resize(points.size());
      std::fill(values.density.begin(), values.density.end(), rho);
      std::fill(values.viscosity.begin(), values.viscosity.end(), mu);
      std::fill(values.density_previous.begin(), values.density_previous.end(), rho);
      std::fill(values.density_older.begin(), values.density_older.end(), rho);
    }

    double minimum_density() const override { return rho; }
    bool   is_constant() const override { return true; }

  private:
    double rho, mu;
  };

  /**
   * Density given by an analytic function ρ(x,t), constant viscosity: used by the variable-
   * density manufactured solution (Guermond & Salgado 2009). The earlier densities ρ^n, ρ^{n−1}
   * are the function at the two time levels evaluated before (the solver asks for t^{n+1} in
   * increasing steps; the first levels are @p start_time and @p before_start, the time of the
   * initial history a BDF2 start is given).
   */
  template <int dim>
  class FunctionMaterial : public MaterialModel<dim>
  {
  public:
    FunctionMaterial(std::shared_ptr<dealii::Function<dim>> density,
                     const double                           viscosity,
                     const double                           rho_min,
                     const double                           start_time  = 0,
                     const double                           before_start = 0)
      : rho(std::move(density)), mu(viscosity), rho_min(rho_min), levels{{start_time, before_start, before_start}}
    {}

    void evaluate(const typename dealii::Triangulation<dim>::active_cell_iterator &,
                  const std::vector<dealii::Point<dim>> &points,
                  double                                 time,
                  MaterialValues<dim>                   &values) const override
    {
      if (time > levels[0] + 1e-12 * std::max(1.0, std::abs(time)))
        levels = {{time, levels[0], levels[1]}};
      const double previous = levels[1], older = levels[2];
      values.resize(points.size());
      for (unsigned int q = 0; q < points.size(); ++q)
      {
        rho->set_time(time);
        values.density[q]   = rho->value(points[q]);
        values.viscosity[q] = mu;
        rho->set_time(previous);
        values.density_previous[q] = rho->value(points[q]);
        rho->set_time(older);
        values.density_older[q] = rho->value(points[q]);
      }
      rho->set_time(time);
    }

    double minimum_density() const override { return rho_min; }

  private:
    std::shared_ptr<dealii::Function<dim>> rho;
    double                                 mu, rho_min;
    mutable std::array<double, 3>          levels; ///< t^{n+1}, t^n, t^{n−1} seen so far
  };
} // namespace twinflow::fem
