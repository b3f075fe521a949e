#pragma once
/**
 * @file momentum_term.h
 * Terms that other physics add to the velocity step of the projection (Eq. 16): the
 * immersed boundary's Nitsche and penalty terms now, surface tension or porous drag later.
 *
 * NavierStokes assembles, per cell and quadrature point, its own terms (inertia,
 * convection, viscosity, body force) weighted by a *fluid fraction* w(x) ∈ [0, 1] and the
 * pressure gradient ∇p^# unweighted; every registered MomentumTerm may lower w (the IBM sets
 * w = 1 − H_ε(φ_s)) and adds its own cell matrix and right-hand side. The Navier–Stokes
 * loop therefore never asks which physics is present.
 */
#include <twinflow/fem/material_model.h>

#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace twinflow::fem
{
  /// What a momentum term sees of one cell of the velocity assembly.
  template <int dim>
  struct MomentumCell
  {
    const typename dealii::DoFHandler<dim>::active_cell_iterator &cell;
    /// Velocity FE values (values, gradients, JxW, quadrature points).
    const dealii::FEValues<dim> &fe_values;
    /// Component of each local shape function.
    const std::vector<unsigned int> &component;
    /// Extrapolated velocity u* at the quadrature points.
    const std::vector<dealii::Tensor<1, dim>> &u_star;
    /// ρ, μ at the quadrature points (time t^{n+1}).
    const MaterialValues<dim> &material;
    /// Viscous stress of a velocity gradient: 2με(u) (symmetric form) or μ∇u (Laplacian).
    bool   symmetric_stress;
    double time;      ///< t^{n+1}
    double time_step; ///< τ
  };

  template <int dim>
  class MomentumTerm
  {
  public:
    virtual ~MomentumTerm() = default;

    virtual std::string name() const = 0;

    /// Whether the term has anything to add on @p cell (cheap test; cells where it returns
    /// false are skipped entirely).
    virtual bool acts_on(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell) const = 0;

    /// Multiply @p fraction (one value per quadrature point, 1 in the fluid) by the share of
    /// the fluid's inertia, convection, viscosity and body force that remains at each point.
    virtual void scale_fluid_fraction(const MomentumCell<dim> & /*cell*/, std::vector<double> & /*fraction*/) const {}

    /// Add the term's contribution (implicit in u^{n+1}) to the cell matrix and right-hand side.
    /// With the Laplacian stress μ∇u (MomentumCell::symmetric_stress false) the momentum
    /// matrix holds no entries between two different velocity components: a term may couple
    /// components only under the symmetric stress (the sum into the matrix refuses a nonzero
    /// outside its sparsity).
    virtual void assemble(const MomentumCell<dim> &cell,
                          dealii::FullMatrix<double> &matrix,
                          dealii::Vector<double>     &rhs) const = 0;
  };
} // namespace twinflow::fem
