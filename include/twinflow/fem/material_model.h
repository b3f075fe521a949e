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
   * Density given by an analytic function ρ(x,t) (with gradient), constant viscosity:
   * used by the variable-density manufactured solution (Guermond & Salgado 2009).
   * ∂ρ/∂t is taken by a centred difference of the function in time.
   */
  template <int dim>
  class FunctionMaterial : public MaterialModel<dim>
  {
  public:
    FunctionMaterial(std::shared_ptr<dealii::Function<dim>> density,
                     const double                           viscosity,
                     const double                           rho_min)
      : rho(std::move(density)), mu(viscosity), rho_min(rho_min)
    {}

    void evaluate(const typename dealii::Triangulation<dim>::active_cell_iterator &,
                  const std::vector<dealii::Point<dim>> &points,
                  double                                 time,
                  MaterialValues<dim>                   &values) const override
    {
      values.resize(points.size());
      const double eps = 1e-6;
      for (unsigned int q = 0; q < points.size(); ++q)
      {
        rho->set_time(time);
        values.density[q]          = rho->value(points[q]);
        values.density_gradient[q] = rho->gradient(points[q]);
        values.viscosity[q]        = mu;
        rho->set_time(time + eps);
        const double rp = rho->value(points[q]);
        rho->set_time(time - eps);
        const double rm = rho->value(points[q]);
        values.density_rate[q] = (rp - rm) / (2 * eps);
      }
      rho->set_time(time);
    }

    double minimum_density() const override { return rho_min; }

  private:
    std::shared_ptr<dealii::Function<dim>> rho;
    double                                 mu, rho_min;
  };
} // namespace twinflow::fem
