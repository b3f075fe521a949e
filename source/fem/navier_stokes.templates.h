// Implementation of NavierStokes<dim>; instantiated in navier_stokes_2d.cc / _3d.cc.
#pragma once
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/navier_stokes.h>
#include <twinflow/fem/vector_field_values.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  NavierStokes<dim>::NavierStokes(parallel::distributed::Triangulation<dim> &tria,
                                  const NavierStokesParameters              &parameters,
                                  const MaterialModel<dim>                  &material)
    : comm(tria.get_communicator())
    , tria(tria)
    , prm(parameters)
    , material(material)
    , mapping(std::max(1u, parameters.mapping_degree))
    , fe_velocity(FE_Q<dim>(parameters.velocity_degree), dim)
    , fe_pressure(parameters.velocity_degree - 1)
    , velocity_dofs(tria)
    , pressure_dofs(tria)
    , timer_output(comm, silent_stream, TimerOutput::never,
                   TimerOutput::wall_times)
  {
    AssertThrow(parameters.velocity_degree >= 2,
                ExcMessage("Velocity degree must be >= 2 (Taylor-Hood Q_{k+1}/Q_k with k >= 1)."));
  }

  template <int dim>
  void NavierStokes<dim>::set_dirichlet(types::boundary_id id, std::shared_ptr<Function<dim>> u)
  {
    AssertThrow(u && u->n_components == dim, ExcMessage("Dirichlet velocity needs dim components."));
    dirichlet[id] = std::move(u);
  }

  template <int dim>
  void NavierStokes<dim>::set_slip(const types::boundary_id id, const unsigned int axis)
  {
    AssertThrow(axis < dim, ExcMessage("slip face: the normal axis must be < dim"));
    slip[id] = axis;
  }

  template <int dim>
  void NavierStokes<dim>::set_outflow(types::boundary_id id) { outflow.insert(id); }

  template <int dim>
  void NavierStokes<dim>::set_periodic(types::boundary_id b1, types::boundary_id b2, unsigned int d)
  {
    periodic.push_back({b1, b2, d});
  }

  template <int dim>
  void NavierStokes<dim>::set_acceleration(std::shared_ptr<Function<dim>> g) { acceleration = std::move(g); }

  template <int dim>
  void NavierStokes<dim>::set_force_density(std::shared_ptr<Function<dim>> f) { force_density = std::move(f); }

  template <int dim>
  void NavierStokes<dim>::make_velocity_constraints(const double t)
  {
    velocity_constraints.clear();
    velocity_constraints.reinit(velocity_relevant);
    DoFTools::make_hanging_node_constraints(velocity_dofs, velocity_constraints);
    for (const auto &pp : periodic)
      DoFTools::make_periodicity_constraints(velocity_dofs, pp.b1, pp.b2, pp.direction,
                                             velocity_constraints);
    for (const auto &[id, axis] : slip)
    {
      ComponentMask normal(dim, false);
      normal.set(axis, true);
      VectorTools::interpolate_boundary_values(mapping, velocity_dofs, id, Functions::ZeroFunction<dim>(dim),
                                               velocity_constraints, normal);
    }
    for (const auto &[id, fun] : dirichlet)
    {
      fun->set_time(t);
      VectorTools::interpolate_boundary_values(mapping, velocity_dofs, id, *fun, velocity_constraints);
    }
    velocity_constraints.close();
  }

  template <int dim>
  void NavierStokes<dim>::make_pressure_constraints()
  {
    pressure_constraints.clear();
    pressure_constraints.reinit(pressure_relevant);
    DoFTools::make_hanging_node_constraints(pressure_dofs, pressure_constraints);
    for (const auto &pp : periodic)
      DoFTools::make_periodicity_constraints(pressure_dofs, pp.b1, pp.b2, pp.direction,
                                             pressure_constraints);
    pressure_constraints.close();

    increment_constraints.clear();
    increment_constraints.reinit(pressure_relevant);
    increment_constraints.merge(pressure_constraints);
    for (const auto id : outflow)
      VectorTools::interpolate_boundary_values(mapping, pressure_dofs, id,
                                               Functions::ZeroFunction<dim>(), increment_constraints);
    pressure_floating = outflow.empty();
    if (pressure_floating)
    {
      // Pure Neumann problem for φ: pin the smallest unconstrained owned DoF (any rank).
      types::global_dof_index candidate = numbers::invalid_dof_index;
      for (const auto i : pressure_owned)
        if (!increment_constraints.is_constrained(i))
        {
          candidate = i;
          break;
        }
      const types::global_dof_index pin = Utilities::MPI::min(candidate, comm);
      AssertThrow(pin != numbers::invalid_dof_index, ExcMessage("No pressure DoF available to pin."));
      if (pressure_relevant.is_element(pin))
        increment_constraints.add_line(pin);
    }
    increment_constraints.close();
  }

  template <int dim>
  bool NavierStokes<dim>::use_component_blocks() const
  {
    return !symmetric_stress() && momentum_terms.empty() && slip.empty() && prm.velocity_preconditioner == "jacobi";
  }

  template <int dim>
  bool NavierStokes<dim>::number_velocity_by_components()
  {
    // The velocity DoF of component c at the node that is DoF s of component_dofs becomes
    // start + c n + (s − s0) on the rank that owns both (n of its nodes, from s0; start of its
    // velocity DoFs = dim s0): [x of its nodes | y of its nodes | ...], each in the scalar
    // (Cuthill–McKee) order. Both handlers give a DoF to the same rank (the same rule on the
    // same cells), which the checks below confirm before anything is renumbered.
    if (!component_dofs)
      component_dofs = std::make_unique<DoFHandler<dim>>(tria);
    component_dofs->distribute_dofs(fe_velocity.base_element(0));
    DoFRenumbering::Cuthill_McKee(*component_dofs);
    const IndexSet &vo = velocity_dofs.locally_owned_dofs(), &so = component_dofs->locally_owned_dofs();
    const types::global_dof_index n = so.n_elements();
    bool ok = vo.n_elements() == dim * n && vo.is_contiguous() && so.is_contiguous();
    const types::global_dof_index v0 = n > 0 ? vo.nth_index_in_set(0) : 0, s0 = n > 0 ? so.nth_index_in_set(0) : 0;
    ok = ok && v0 == dim * s0;
    std::vector<types::global_dof_index> new_numbers(vo.n_elements(), numbers::invalid_dof_index);
    const unsigned int n_cell = fe_velocity.n_dofs_per_cell();
    std::vector<types::global_dof_index> vi(n_cell), si(fe_velocity.base_element(0).n_dofs_per_cell());
    for (const auto &cell : velocity_dofs.active_cell_iterators())
      if (ok && cell->is_locally_owned())
      {
        cell->get_dof_indices(vi);
        typename DoFHandler<dim>::active_cell_iterator(&tria, cell->level(), cell->index(), component_dofs.get())
          ->get_dof_indices(si);
        for (unsigned int i = 0; i < n_cell && ok; ++i)
        {
          const auto [c, b] = fe_velocity.system_to_component_index(i);
          const bool owned  = vo.is_element(vi[i]);
          if (owned != so.is_element(si[b]))
            ok = false;
          else if (owned)
          {
            auto &number = new_numbers[vo.index_within_set(vi[i])];
            const types::global_dof_index wanted = v0 + c * n + (si[b] - s0);
            ok = number == numbers::invalid_dof_index || number == wanted;
            number = wanted;
          }
        }
      }
    for (const auto number : new_numbers)
      ok = ok && number != numbers::invalid_dof_index; // (s, c) ↦ number is one-to-one by construction
    if (Utilities::MPI::min(ok ? 1u : 0u, comm) == 0)
      return false;
    velocity_dofs.renumber_dofs(new_numbers);
    return true;
  }

  template <int dim>
  void NavierStokes<dim>::setup_dofs()
  {
    TimerOutput::Scope scope(timer_output, "setup");
    force_dofs.clear();
    cell_sizes.assign(tria.n_active_cells(), 0.0);
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        cell_sizes[cell->active_cell_index()] = cell->diameter() / std::sqrt(double(dim));
    velocity_dofs.distribute_dofs(fe_velocity);
    pressure_dofs.distribute_dofs(fe_pressure);
    component_blocks = use_component_blocks() && number_velocity_by_components();
    if (!component_blocks)
    {
      component_dofs.reset();
      DoFRenumbering::Cuthill_McKee(velocity_dofs);
    }
    DoFRenumbering::Cuthill_McKee(pressure_dofs);
    velocity_owned = velocity_dofs.locally_owned_dofs();
    pressure_owned = pressure_dofs.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(velocity_dofs, velocity_relevant);
    DoFTools::extract_locally_relevant_dofs(pressure_dofs, pressure_relevant);
    velocity_cells.reinit(velocity_dofs, velocity_owned, velocity_relevant, comm);
    velocity_scatter.clear();
    mass_scatter.clear();
    pressure_scatter.clear();
    step_density.clear();
    pressure_cells.reinit(pressure_dofs, pressure_owned, pressure_relevant, comm);

    make_velocity_constraints(current_time);
    make_pressure_constraints();

    // Only the symmetric stress 2με(u) couples two velocity components (momentum_term.h):
    // with μ∇u the momentum matrix has the same-component pattern, 1/dim of the entries of
    // the full one (fewer products in every Krylov iteration, less to assemble and zero). The
    // L²(ρ) mass of the variable-density correction never couples them.
    const auto velocity_pattern = [&](const bool couple_components, TrilinosWrappers::SparseMatrix &matrix) {
      Table<2, DoFTools::Coupling> coupling(dim, dim);
      for (unsigned int c = 0; c < dim; ++c)
        for (unsigned int d = 0; d < dim; ++d)
          coupling[c][d] = c == d || couple_components ? DoFTools::always : DoFTools::none;
      DynamicSparsityPattern dsp(velocity_relevant);
      DoFTools::make_sparsity_pattern(velocity_dofs, coupling, dsp, velocity_constraints, false);
      SparsityTools::distribute_sparsity_pattern(dsp, velocity_owned, comm, velocity_relevant);
      matrix.reinit(velocity_owned, velocity_owned, dsp, comm);
    };
    component_scatter.clear();
    component_mass_scatter.clear();
    rhs_scatter.clear();
    if (component_blocks)
    {
      // One component's constraints: hanging nodes, periodicity and the Dirichlet walls
      // (homogeneous: the values enter the right-hand side through the vector constraints).
      IndexSet component_relevant;
      DoFTools::extract_locally_relevant_dofs(*component_dofs, component_relevant);
      component_constraints.clear();
      component_constraints.reinit(component_relevant);
      DoFTools::make_hanging_node_constraints(*component_dofs, component_constraints);
      for (const auto &pp : periodic)
        DoFTools::make_periodicity_constraints(*component_dofs, pp.b1, pp.b2, pp.direction, component_constraints);
      for (const auto &entry : dirichlet)
        VectorTools::interpolate_boundary_values(mapping, *component_dofs, entry.first, Functions::ZeroFunction<dim>(),
                                                 component_constraints);
      component_constraints.close();
      DynamicSparsityPattern dsp(component_relevant);
      DoFTools::make_sparsity_pattern(*component_dofs, dsp, component_constraints, false);
      SparsityTools::distribute_sparsity_pattern(dsp, component_dofs->locally_owned_dofs(), comm, component_relevant);
      component_matrix.reinit(component_dofs->locally_owned_dofs(), component_dofs->locally_owned_dofs(), dsp, comm);
      if (prm.variable_projection)
        component_mass.reinit(component_matrix);
      velocity_matrix.clear();
      velocity_mass.clear();
    }
    else
    {
      component_matrix.clear();
      component_mass.clear();
      velocity_pattern(symmetric_stress(), velocity_matrix);
      if (prm.variable_projection)
      {
        if (symmetric_stress())
          velocity_pattern(false, velocity_mass);
        else
          velocity_mass.reinit(velocity_matrix); // the same pattern (its values are assembled per step)
      }
    }
    if (velocity_corrected())
      assemble_pressure_gradient();
    {
      DynamicSparsityPattern dsp(pressure_relevant);
      DoFTools::make_sparsity_pattern(pressure_dofs, dsp, increment_constraints, false);
      SparsityTools::distribute_sparsity_pattern(dsp, pressure_owned, comm, pressure_relevant);
      pressure_laplace.reinit(pressure_owned, pressure_owned, dsp, comm);
    }
    if (!(prm.variable_projection && !material.is_constant())) // else rebuilt every step
      assemble_pressure_laplacian();
    rebuild_velocity_preconditioner = true;
    pressure_amg_age                = std::numeric_limits<unsigned int>::max();
    velocity_jacobi.clear();
    velocity_ilu.clear();
    mass_jacobi.clear();

    ++state_counter;
    velocity_rhs.reinit(velocity_owned, comm);
    last_correction.reinit(velocity_owned, comm);
    pressure_rhs.reinit(pressure_owned, comm);
    for (auto *v : {&u_n, &u_nm1, &u_momentum})
      v->reinit(velocity_owned, velocity_relevant, comm);
    for (auto *v : {&p_n, &phi_n, &phi_nm1})
      v->reinit(pressure_owned, pressure_relevant, comm);
  }

  template <int dim>
  void NavierStokes<dim>::assemble_pressure_laplacian()
  {
    // Pressure-increment Laplacian: depends on the mesh only, rebuilt after each adaptation.
    const QGauss<dim>   quad(fe_pressure.degree + 1);
    FEValues<dim>       fev(mapping, fe_pressure, quad, update_gradients | update_JxW_values);
    const unsigned int  n = fe_pressure.n_dofs_per_cell();
    FullMatrix<double>  cell_matrix(n, n);
    std::vector<types::global_dof_index> indices(n);
    for (const auto &cell : pressure_dofs.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        fev.reinit(cell);
        cell_matrix = 0;
        for (unsigned int q = 0; q < quad.size(); ++q)
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              cell_matrix(i, j) += fev.shape_grad(i, q) * fev.shape_grad(j, q) * fev.JxW(q);
        cell->get_dof_indices(indices);
        increment_constraints.distribute_local_to_global(cell_matrix, indices, pressure_laplace);
      }
    pressure_laplace.compress(VectorOperation::add);
    initialize_pressure_amg();
  }

  template <int dim>
  void NavierStokes<dim>::assemble_pressure_gradient()
  {
    // Columns are not condensed: φ is the full, distributed increment.
    AffineConstraints<double>            no_constraints;
    const unsigned int                   nv = fe_velocity.n_dofs_per_cell(), np = fe_pressure.n_dofs_per_cell();
    std::vector<types::global_dof_index> vi(nv), pi(np);
    const auto pressure_cell = [&](const auto &cell) {
      return typename DoFHandler<dim>::active_cell_iterator(&tria, cell->level(), cell->index(), &pressure_dofs);
    };
    DynamicSparsityPattern dsp(velocity_dofs.n_dofs(), pressure_dofs.n_dofs(), velocity_relevant);
    for (const auto &cell : velocity_dofs.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        cell->get_dof_indices(vi);
        pressure_cell(cell)->get_dof_indices(pi);
        velocity_constraints.add_entries_local_to_global(vi, no_constraints, pi, dsp, false);
      }
    SparsityTools::distribute_sparsity_pattern(dsp, velocity_owned, comm, velocity_relevant);
    pressure_gradient.reinit(velocity_owned, pressure_owned, dsp, comm);

    const QGauss<dim>  quad(fe_velocity.degree + 1);
    FEValues<dim>      fev(mapping, fe_velocity, quad, update_values | update_JxW_values);
    FEValues<dim>      fep(mapping, fe_pressure, quad, update_gradients);
    FullMatrix<double> cell_matrix(nv, np);
    std::vector<unsigned int> comp(nv);
    for (unsigned int i = 0; i < nv; ++i)
      comp[i] = fe_velocity.system_to_component_index(i).first;
    for (const auto &cell : velocity_dofs.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        fev.reinit(cell);
        const auto pcell = pressure_cell(cell);
        fep.reinit(pcell);
        cell_matrix = 0;
        for (unsigned int q = 0; q < quad.size(); ++q)
          for (unsigned int i = 0; i < nv; ++i)
          {
            const double vi_JxW = fev.shape_value(i, q) * fev.JxW(q);
            for (unsigned int j = 0; j < np; ++j)
              cell_matrix(i, j) += fep.shape_grad(j, q)[comp[i]] * vi_JxW;
          }
        cell->get_dof_indices(vi);
        pcell->get_dof_indices(pi);
        velocity_constraints.distribute_local_to_global(cell_matrix, vi, no_constraints, pi, pressure_gradient);
      }
    pressure_gradient.compress(VectorOperation::add);
  }

  template <int dim>
  void NavierStokes<dim>::initialize_pressure_amg()
  {
    TrilinosWrappers::PreconditionAMG::AdditionalData amg;
    amg.elliptic              = true;
    amg.higher_order_elements = fe_pressure.degree > 1;
    amg.smoother_sweeps       = 2;
    amg.aggregation_threshold = 0.02;
    initialize_amg(pressure_amg, pressure_laplace, amg);
  }

  template <int dim>
  void NavierStokes<dim>::initialize(const Function<dim> &u0,
                                     const Function<dim> &p0,
                                     const double         t0,
                                     const Function<dim> *u_previous,
                                     const double         dt_previous)
  {
    current_time = t0;
    step_number  = 0;
    TrilinosWrappers::MPI::Vector tmp_u(velocity_owned, comm), tmp_p(pressure_owned, comm);
    const_cast<Function<dim> &>(u0).set_time(t0);
    const_cast<Function<dim> &>(p0).set_time(t0);
    VectorTools::interpolate(mapping, velocity_dofs, u0, tmp_u);
    make_velocity_constraints(t0);
    velocity_constraints.distribute(tmp_u);
    u_n = tmp_u;
    VectorTools::interpolate(mapping, pressure_dofs, p0, tmp_p);
    pressure_constraints.distribute(tmp_p);
    p_n = tmp_p;
    if (u_previous != nullptr)
    {
      AssertThrow(dt_previous > 0, ExcMessage("initialize: dt_previous must be > 0."));
      const_cast<Function<dim> *>(u_previous)->set_time(t0 - dt_previous);
      VectorTools::interpolate(mapping, velocity_dofs, *u_previous, tmp_u);
      velocity_constraints.distribute(tmp_u);
      u_nm1          = tmp_u;
      dt_last        = dt_previous;
      have_history   = true;
    }
    else
    {
      u_nm1        = u_n;
      have_history = false;
    }
    phi_n   = 0;
    phi_nm1 = 0;
    ++state_counter;
  }

  template <int dim>
  typename NavierStokes<dim>::BdfCoefficients NavierStokes<dim>::coefficients(const double dt) const
  {
    if (prm.scheme == TimeScheme::bdf1 || !have_history)
      return {1.0, -1.0, 0.0, 1.0, 0.0};
    const double w = dt / dt_last;
    return {(1 + 2 * w) / (1 + w), -(1 + w), w * w / (1 + w), 1 + w, -w};
  }

  template <int dim>
  const StepStatistics &NavierStokes<dim>::step(const double dt)
  {
    AssertThrow(dt > 0 && std::isfinite(dt), ExcMessage("Navier-Stokes step: time step must be positive."));
    const BdfCoefficients c = coefficients(dt);
    const double          t_new = current_time + dt;
    {
      TimerOutput::Scope scope(timer_output, "velocity assembly");
      // Walls at rest (every Dirichlet value a ZeroFunction) keep the constraints of the mesh.
      const bool fixed = std::all_of(dirichlet.begin(), dirichlet.end(), [](const auto &entry) {
        return dynamic_cast<const Functions::ZeroFunction<dim> *>(entry.second.get()) != nullptr;
      });
      if (!fixed)
        make_velocity_constraints(t_new);
      assemble_velocity_system(dt, c);
    }
    {
      TimerOutput::Scope scope(timer_output, "velocity solve");
      stats.velocity_iterations = solve_velocity(c);
    }
    {
      TimerOutput::Scope scope(timer_output, "pressure projection");
      stats.pressure_iterations = solve_pressure_increment(dt, c);
    }
    if (velocity_corrected())
      correct_velocity(dt, c);
    dt_before_last = dt_last;
    dt_last        = dt;
    current_time   = t_new;
    have_history   = true;
    ++step_number;
    ++state_counter;
    return stats;
  }

  template <int dim>
  typename NavierStokes<dim>::StepState NavierStokes<dim>::save_step() const
  {
    return {u_n, u_nm1, p_n, phi_n, phi_nm1, current_time, dt_last, dt_before_last, step_number, have_history};
  }

  template <int dim>
  void NavierStokes<dim>::restore_step(const StepState &s)
  {
    u_n            = s.u_n;
    u_nm1          = s.u_nm1;
    p_n            = s.p_n;
    phi_n          = s.phi_n;
    phi_nm1        = s.phi_nm1;
    current_time   = s.current_time;
    dt_last        = s.dt_last;
    dt_before_last = s.dt_before_last;
    step_number    = s.step_number;
    have_history   = s.have_history;
    ++state_counter;
  }
} // namespace twinflow::fem
