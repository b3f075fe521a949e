// Diagnostics of NavierStokes<dim>: forces, probes, errors, energy, output.
#pragma once
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/vector_tools.h>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  Tensor<1, dim> NavierStokes<dim>::boundary_force(const types::boundary_id id) const
  {
    TimerOutput::Scope scope(timer_output, "forces");
    // ψ_d = Σ_{i on boundary id, component d} φ_i equals e_d on the boundary and vanishes on
    // the others; F_d = −R(u, p; ψ_d) is the force the fluid exerts on that boundary.
    auto cached = force_dofs.find(id);
    if (cached == force_dofs.end())
      cached = force_dofs.emplace(id, DoFTools::extract_boundary_dofs(velocity_dofs, ComponentMask(), {id})).first;
    const IndexSet &on_body = cached->second;
    const QGauss<dim> quad(fe_velocity.degree + 1);
    FEValues<dim> fev(mapping, fe_velocity, quad,
                      update_values | update_gradients | update_JxW_values | update_quadrature_points);
    FEValues<dim> fep(mapping, fe_pressure, quad, update_values);
    const unsigned int n = fe_velocity.n_dofs_per_cell(), nq = quad.size();
    const FEValuesExtractors::Vector vel(0);
    std::vector<types::global_dof_index> indices(n);
    std::vector<Tensor<1, dim>> u(nq), uold(nq);
    std::vector<Tensor<2, dim>> grad_u(nq);
    std::vector<double>         p(nq);
    std::vector<Vector<double>> g_val(nq, Vector<double>(dim)), f_val(nq, Vector<double>(dim));
    MaterialValues<dim>         mat;
    const bool symmetric = prm.viscous_form == ViscousForm::symmetric;
    if (acceleration) acceleration->set_time(current_time);
    if (force_density) force_density->set_time(current_time);
    Tensor<1, dim> residual;
    for (const auto &cell : velocity_dofs.active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      cell->get_dof_indices(indices);
      bool touches = false;
      for (const auto i : indices)
        touches = touches || on_body.is_element(i);
      if (!touches)
        continue;
      fev.reinit(cell);
      const typename DoFHandler<dim>::active_cell_iterator pcell(&tria, cell->level(), cell->index(), &pressure_dofs);
      fep.reinit(pcell);
      fev[vel].get_function_values(u_n, u);
      fev[vel].get_function_values(u_nm1, uold);
      fev[vel].get_function_gradients(u_n, grad_u);
      fep.get_function_values(p_n, p);
      material.evaluate(cell, fev.get_quadrature_points(), current_time, mat);
      if (acceleration) acceleration->vector_value_list(fev.get_quadrature_points(), g_val);
      if (force_density) force_density->vector_value_list(fev.get_quadrature_points(), f_val);
      for (unsigned int q = 0; q < nq; ++q)
      {
        const double rho = mat.density[q], mu = mat.viscosity[q];
        Tensor<1, dim> momentum = rho * grad_u[q] * u[q]; // ρ (u·∇)u
        if (step_number > 0 && dt_last > 0)
          momentum += rho * (u[q] - uold[q]) / dt_last;
        for (unsigned int d = 0; d < dim; ++d)
        {
          if (acceleration) momentum[d] -= rho * g_val[q](d);
          if (force_density) momentum[d] -= f_val[q](d);
        }
        Tensor<2, dim> stress = mu * grad_u[q];
        if (symmetric)
          stress += mu * transpose(grad_u[q]);
        for (unsigned int d = 0; d < dim; ++d)
          stress[d][d] -= p[q];
        for (unsigned int i = 0; i < n; ++i)
        {
          if (!on_body.is_element(indices[i]))
            continue;
          const unsigned int c = fe_velocity.system_to_component_index(i).first;
          residual[c] += (momentum[c] * fev.shape_value(i, q) + stress[c] * fev.shape_grad(i, q)) * fev.JxW(q);
        }
      }
    }
    return -Utilities::MPI::sum(residual, comm);
  }

  template <int dim>
  double NavierStokes<dim>::pressure_at(const Point<dim> &point) const
  {
    double value = 0, count = 0;
    try
    {
      const auto found = GridTools::find_active_cell_around_point(mapping, pressure_dofs, point);
      if (found.first.state() == IteratorState::valid && found.first->is_locally_owned())
      {
        const Quadrature<dim> q(GeometryInfo<dim>::project_to_unit_cell(found.second));
        FEValues<dim>         fep(mapping, fe_pressure, q, update_values);
        fep.reinit(found.first);
        std::vector<double> v(1);
        fep.get_function_values(p_n, v);
        value = v[0];
        count = 1;
      }
    }
    catch (...)
    {
      // The point lies in the artificial part of this rank's mesh: another rank owns it.
    }
    value = Utilities::MPI::sum(value, comm);
    count = Utilities::MPI::sum(count, comm);
    AssertThrow(count > 0, ExcMessage("Pressure probe outside the domain."));
    return value / count;
  }

  template <int dim>
  std::pair<double, double> NavierStokes<dim>::l2_errors(const Function<dim> &u_exact,
                                                         const Function<dim> &p_exact) const
  {
    const_cast<Function<dim> &>(u_exact).set_time(current_time);
    const_cast<Function<dim> &>(p_exact).set_time(current_time);
    const QGauss<dim> quad(fe_velocity.degree + 2);
    Vector<double>    cellwise(tria.n_active_cells());
    VectorTools::integrate_difference(mapping, velocity_dofs, u_n, u_exact, cellwise, quad, VectorTools::L2_norm);
    const double eu = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
    VectorTools::integrate_difference(mapping, pressure_dofs, p_n, p_exact, cellwise, quad, VectorTools::L2_norm);
    double ep = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
    if (pressure_floating)
    {
      // Remove the mean of the error: ||e − c||² = ||e||² − c²|Ω| with c = ∫e/|Ω|.
      VectorTools::integrate_difference(mapping, pressure_dofs, p_n, p_exact, cellwise, quad, VectorTools::mean);
      const double integral = VectorTools::compute_global_error(tria, cellwise, VectorTools::mean);
      const double volume   = GridTools::volume(tria, mapping);
      ep = std::sqrt(std::max(0.0, ep * ep - integral * integral / volume));
    }
    return {eu, ep};
  }

  template <int dim>
  double NavierStokes<dim>::max_velocity() const
  {
    return u_n.linfty_norm();
  }

  template <int dim>
  double NavierStokes<dim>::kinetic_energy() const
  {
    const QGauss<dim> quad(fe_velocity.degree + 1);
    FEValues<dim> fev(mapping, fe_velocity, quad, update_values | update_JxW_values | update_quadrature_points);
    std::vector<Tensor<1, dim>> u(quad.size());
    MaterialValues<dim> mat;
    double e = 0;
    for (const auto &cell : velocity_dofs.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        fev.reinit(cell);
        fev[FEValuesExtractors::Vector(0)].get_function_values(u_n, u);
        material.evaluate(cell, fev.get_quadrature_points(), current_time, mat);
        for (unsigned int q = 0; q < quad.size(); ++q)
          e += 0.5 * mat.density[q] * u[q].norm_square() * fev.JxW(q);
      }
    return Utilities::MPI::sum(e, comm);
  }

  template <int dim>
  double NavierStokes<dim>::minimal_cell_diameter() const
  {
    return GridTools::minimal_cell_diameter(tria, mapping);
  }

  template <int dim>
  void NavierStokes<dim>::add_to_output(DataOut<dim> &data_out) const
  {
    std::vector<std::string> names(dim, "velocity");
    std::vector<DataComponentInterpretation::DataComponentInterpretation> interpretation(
      dim, DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(velocity_dofs, u_n, names, interpretation);
    data_out.add_data_vector(pressure_dofs, p_n, "pressure");
  }
} // namespace twinflow::fem
