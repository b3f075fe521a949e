// NavierStokes<dim>: the projection half of a step: the pressure increment (Eq. 16 or its
// variable-density form) and the velocity correction. Included after navier_stokes.templates.h.
#pragma once
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/navier_stokes.h>
#include <twinflow/fem/vector_field_values.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include <cmath>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  unsigned int NavierStokes<dim>::solve_pressure_increment(const double dt, const BdfCoefficients &c)
  {
    // Constant ρ or Guermond–Salgado (χ = ρ_min): −Δφ = −(α0 χ/τ) ∇·ũ with the Laplacian of
    // the mesh. A density carried by the flow (two phases, up to 1000:1): the variable-
    // coefficient form −∇·(ρ̄⁻¹∇φ) = −(α0/τ) ∇·ũ, rebuilt every step, so that the pressure
    // changes where the fluid is heavy (with χ = ρ_air the water's pressure would adapt at
    // ρ_air/ρ_water of the rate it needs and the light side of the interface run away).
    const bool variable = velocity_corrected();
    pressure_rhs = 0;
    const QGauss<dim>  quad(fe_velocity.degree + 1);
    FEValues<dim>      fes(mapping, fe_velocity.base_element(0), quad, update_gradients); // ∇·u from the scalar functions
    const VectorFieldValues<dim> velocity_values(fe_velocity);
    FEValues<dim>      fep(mapping, fe_pressure, quad, update_values | update_gradients | update_JxW_values);
    const unsigned int n = fe_pressure.n_dofs_per_cell();
    Vector<double>     cell_rhs(n);
    FullMatrix<double> cell_matrix(n, n), stiffness(n, n);
    bool               stiffness_valid = false;
    std::vector<double> div_u(quad.size());
    std::vector<double> local_u;
    std::vector<types::global_dof_index> indices(n);
    // ρ^{n+1} at the same points was evaluated by this step's momentum assembly (same
    // quadrature, same level set): no second evaluation of the material.
    AssertThrow(!variable || step_density.size() == tria.n_active_cells() * quad.size(),
                ExcMessage("Navier-Stokes: the variable-density projection needs the densities of this step's "
                           "momentum assembly."));
    const double factor = variable ? -c.a0 / dt : -c.a0 * material.minimum_density() / dt;
    if (variable)
      pressure_laplace = 0;
    double div_sq = 0;
    for (const auto &cell : pressure_dofs.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        fep.reinit(cell);
        const typename DoFHandler<dim>::active_cell_iterator vcell(&tria, cell->level(), cell->index(), &velocity_dofs);
        fes.reinit(vcell);
        velocity_cells.gather(vcell, u_n, local_u);
        velocity_values.divergence(fes, local_u, div_u);
        cell_rhs    = 0;
        cell_matrix = 0;
        const double *density = variable ? &step_density[cell->active_cell_index() * quad.size()] : nullptr;
        for (unsigned int q = 0; q < quad.size(); ++q)
        {
          div_sq += div_u[q] * div_u[q] * fep.JxW(q);
          for (unsigned int i = 0; i < n; ++i)
            cell_rhs(i) += factor * div_u[q] * fep.shape_value(i, q) * fep.JxW(q);
        }
        // ρ̄ of a cell is one value (the two-phase material's cell mean): K_ab/ρ̄ with the
        // stiffness K, which a translated cell shares with the previous one (cell similarity)
        bool uniform = variable;
        for (unsigned int q = 1; q < quad.size() && uniform; ++q)
          uniform = density[q] == density[0];
        if (uniform && (!stiffness_valid || fep.get_cell_similarity() != CellSimilarity::translation))
        {
          stiffness = 0;
          for (unsigned int q = 0; q < quad.size(); ++q)
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                stiffness(i, j) += fep.shape_grad(i, q) * fep.shape_grad(j, q) * fep.JxW(q);
        }
        stiffness_valid = uniform;
        if (uniform)
          cell_matrix.add(1.0 / density[0], stiffness);
        else if (variable)
          for (unsigned int q = 0; q < quad.size(); ++q)
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                cell_matrix(i, j) += fep.shape_grad(i, q) * fep.shape_grad(j, q) / density[q] * fep.JxW(q);
        if (variable)
        {
          if (!pressure_scatter.ready() || !pressure_scatter.add(cell, cell_matrix, &cell_rhs, &pressure_rhs))
          {
            cell->get_dof_indices(indices);
            increment_constraints.distribute_local_to_global(cell_matrix, cell_rhs, indices, pressure_laplace, pressure_rhs);
          }
        }
        else
        {
          cell->get_dof_indices(indices);
          increment_constraints.distribute_local_to_global(cell_rhs, indices, pressure_rhs);
        }
      }
    pressure_rhs.compress(VectorOperation::add);
    if (variable)
    {
      pressure_laplace.compress(VectorOperation::add);
      if (!pressure_scatter.ready())
        pressure_scatter.reinit(pressure_dofs, increment_constraints, pressure_laplace, pressure_rhs);
      // Set up every pressure_amg_interval steps: in between the interface has moved by less
      // than a cell, and the hierarchy of a step ago still preconditions the new matrix
      // (dam break: 9.0 → 9.2 iterations at n = 2, a third of this section saved; n = 10
      // costs more iterations than it saves). Its fine level applies the current matrix.
      if (pressure_amg_age >= prm.pressure_amg_interval - 1)
      {
        initialize_pressure_amg();
        pressure_amg_age = 0;
      }
      else
        ++pressure_amg_age;
    }
    stats.divergence_l2 = std::sqrt(Utilities::MPI::sum(div_sq, comm));

    // The last increment is the guess (the increments of consecutive steps differ by O(τ)).
    TrilinosWrappers::MPI::Vector phi(pressure_owned, comm);
    pressure_cells.copy_owned(phi, phi_n);
    increment_constraints.set_zero(phi);
    const double  target = std::max(prm.linear_tolerance * pressure_rhs.l2_norm(), 1e-300);
    const std::string system = "Navier-Stokes pressure increment";
    const bool    reused = variable && pressure_amg_age > 0;
    // A reused AMG gets 3× the iterations of the last fresh one (+10); past that, a fresh one
    // solves from the same guess (a jump of the interface across a cell, a violent splash).
    SolverControl control(reused ? 3 * fresh_pressure_iterations + 10 : 5000, target);
    SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
    bool solved = reused && try_solve_named(system, control, [&] { cg.solve(pressure_laplace, phi, pressure_rhs, pressure_amg); });
    if (!solved)
    {
      if (reused)
      {
        initialize_pressure_amg();
        pressure_amg_age = 0;
        pressure_cells.copy_owned(phi, phi_n);
        increment_constraints.set_zero(phi);
        control.set_max_steps(5000);
      }
      solve_named(system, control, [&] { cg.solve(pressure_laplace, phi, pressure_rhs, pressure_amg); });
      if (variable)
        fresh_pressure_iterations = control.last_step();
    }
    increment_constraints.distribute(phi);

    TrilinosWrappers::MPI::Vector p(pressure_owned, comm);
    pressure_cells.copy_owned(p, p_n);
    p += phi;
    phi_nm1 = phi_n;
    pressure_cells.update_ghosted(phi_n, phi);
    pressure_cells.update_ghosted(p_n, p);
    return control.last_step();
  }

  template <int dim>
  void NavierStokes<dim>::correct_velocity(const double dt, const BdfCoefficients &c)
  {
    // u^{n+1} = ũ − (τ/α0) δ with M_ρ δ = (∇φ, v): the L²(ρ^{n+1}) projection of
    // ũ − τ/(α0 ρ) ∇φ, with M_ρ assembled beside the momentum matrix (same ρ^{n+1}).
    TimerOutput::Scope scope(timer_output, "velocity correction");
    // (∇φ, v) = G φ: one product with the matrix of the mesh instead of a cell loop
    TrilinosWrappers::MPI::Vector phi(pressure_owned, comm);
    pressure_cells.copy_owned(phi, phi_n); // the increment just solved for
    pressure_gradient.vmult(velocity_rhs, phi);
    // The last step's correction is the guess (δ follows the increment ∇φ, smooth in time).
    TrilinosWrappers::MPI::Vector &delta = last_correction; // sized by setup_dofs()
    mass_jacobi.compute(component_blocks ? component_mass : velocity_mass);
    SolverControl control(2000, std::max(prm.correction_tolerance * velocity_rhs.l2_norm(), 1e-300));
    SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
    solve_named("Navier-Stokes velocity correction", control, [&] {
      if (component_blocks)
        cg.solve(ComponentBlockMatrix(component_mass, dim), delta, velocity_rhs, mass_jacobi);
      else
        cg.solve(velocity_mass, delta, velocity_rhs, mass_jacobi);
    });
    if (!momentum_terms.empty())
      u_momentum = u_n;
    TrilinosWrappers::MPI::Vector x(velocity_owned, comm);
    velocity_cells.copy_owned(x, u_n);
    x.add(-dt / c.a0, delta);
    velocity_constraints.distribute(x);
    velocity_cells.update_ghosted(u_n, x);
  }
} // namespace twinflow::fem
