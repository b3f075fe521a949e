// Level set: the transports of φ (Eq. 7, NCLS) and θ (Eq. 8, VOF). Crank–Nicolson in time at
// the midpoint velocity, SUPG in space; the VOF adds residual-based shock capturing. Both are
// linear per step (GMRES + ILU).
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/level_set.h>
#include <twinflow/fem/vector_field_values.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include <cmath>

namespace twinflow::fem
{
  using namespace dealii;

  namespace
  {
    /// SUPG parameter of a Crank–Nicolson step: (4/τ² + 4|u|²/h²)^{-1/2}.
    double supg_tau(const double dt, const double speed, const double h)
    {
      return 1.0 / std::sqrt(4.0 / (dt * dt) + 4.0 * speed * speed / (h * h));
    }

    /// The Crank–Nicolson midpoint velocity (uⁿ + uⁿ⁺¹)/2 and its divergence at the quadrature
    /// points of a level-set cell (the same mesh, the velocity's DoFHandler).
    template <int dim>
    struct MidpointVelocity
    {
      MidpointVelocity(const NavierStokes<dim> &flow, const Quadrature<dim> &quad)
        : flow(flow)
        , fvu(flow.get_mapping(), flow.velocity_dof_handler().get_fe().base_element(0), quad,
              update_values | update_gradients)
        , velocity_values(flow.velocity_dof_handler().get_fe())
        , u(quad.size()), div(quad.size())
      {}

      /// Evaluate on @p cell; returns the velocity cell (for face values).
      typename DoFHandler<dim>::active_cell_iterator reinit(const typename DoFHandler<dim>::active_cell_iterator &cell)
      {
        const typename DoFHandler<dim>::active_cell_iterator vcell(&cell->get_triangulation(), cell->level(),
                                                                   cell->index(), &flow.velocity_dof_handler());
        fvu.reinit(vcell);
        flow.velocity_reader().gather(vcell, flow.velocity(), local);
        flow.velocity_reader().gather(vcell, flow.previous_velocity(), local_old);
        for (std::size_t i = 0; i < local.size(); ++i) // the midpoint's DoF values (linear)
          local[i] = 0.5 * (local[i] + local_old[i]);
        velocity_values.evaluate(fvu, local, u, &div);
        return vcell;
      }

      const NavierStokes<dim>    &flow;
      FEValues<dim>               fvu; ///< of the velocity's scalar base element
      const VectorFieldValues<dim> velocity_values;
      std::vector<Tensor<1, dim>> u; ///< the midpoint velocity
      std::vector<double>         div;
      std::vector<double>         local, local_old;
    };

    /// The midpoint velocity at the points of @p quad on every owned cell, from the table of
    /// the space when it holds this flow state (the second transport of a step), else computed.
    template <int dim>
    const typename LevelSetSpace<dim>::MidpointTable &midpoint_values(const LevelSetSpace<dim> &space,
                                                                      const NavierStokes<dim>  &flow,
                                                                      const Quadrature<dim>    &quad)
    {
      auto &table = space.midpoint_table();
      if (table.flow_state == flow.state_id() && table.n_points == quad.size())
        return table;
      const unsigned int nq      = quad.size();
      const std::size_t  n_cells = space.dof_handler().get_triangulation().n_active_cells();
      table.u.assign(n_cells * nq, Tensor<1, dim>());
      table.div.assign(n_cells * nq, 0.0);
      MidpointVelocity<dim> mid(flow, quad);
      for (const auto &cell : space.dof_handler().active_cell_iterators())
        if (cell->is_locally_owned())
        {
          mid.reinit(cell);
          const std::size_t first = cell->active_cell_index() * nq;
          std::copy(mid.u.begin(), mid.u.end(), table.u.begin() + first);
          std::copy(mid.div.begin(), mid.div.end(), table.div.begin() + first);
        }
      table.flow_state = flow.state_id();
      table.n_points   = nq;
      return table;
    }
  } // namespace

  template <int dim>
  void LevelSetField<dim>::solve_transport(const double dt, const bool conservative, const std::vector<double> *nu,
                                           TrilinosWrappers::MPI::Vector &result)
  {
    matrix = 0;
    TrilinosWrappers::MPI::Vector rhs;
    space.reinit_owned(rhs);
    const auto        &fe   = space.fe();
    const QGauss<dim>  quad(fe.degree + 2);
    const QGauss<dim - 1> face_quad(fe.degree + 2);
    const auto        &vdofs = flow.velocity_dof_handler();
    FEValues<dim>      fev(space.mapping(), fe, quad, update_values | update_gradients | update_JxW_values);
    const auto &mid = midpoint_values(space, flow, quad);
    FEFaceValues<dim>  ffv(space.mapping(), fe, face_quad, update_values | update_JxW_values | update_normal_vectors);
    FEFaceValues<dim>  ffu(flow.get_mapping(), vdofs.get_fe(), face_quad, update_values);
    const unsigned int n  = fe.n_dofs_per_cell();
    const unsigned int nq = quad.size();
    const FEValuesExtractors::Vector vel(0);
    FullMatrix<double> A(n, n);
    Vector<double>     b(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<Tensor<1, dim>> grad_old(nq), fu_new(face_quad.size()), fu_old(face_quad.size());
    std::vector<double> val_old(nq), fval_old(face_quad.size());
    std::vector<double> s(n), adv(n), pw(n), pa(n);
    std::vector<Tensor<1, dim>> ds(n);
    std::vector<double> local_old;
    const FEValuesExtractors::Scalar scalar(0);
    for (const auto &cell : space.dof_handler().active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      fev.reinit(cell);
      const std::size_t first = cell->active_cell_index() * nq;
      space.reader().gather(cell, current, local_old);
      fev[scalar].get_function_values_from_local_dof_values(local_old, val_old);
      fev[scalar].get_function_gradients_from_local_dof_values(local_old, grad_old);
      const double h     = space.cell_size(cell) / fe.degree;
      const double nu_K  = nu ? (*nu)[cell->active_cell_index()] : 0.0;
      A = 0;
      b = 0;
      for (unsigned int q = 0; q < nq; ++q)
      {
        const Tensor<1, dim> u   = mid.u[first + q];
        // θ (conservative): ∂θ/∂t + ∇·(θu) = 0. φ: ∂φ/∂t + u·∇φ + ½(∇·u)φ = 0, the skew-
        // symmetric form: ∇·u = 0 in the continuum, but the discrete u_h has a pointwise
        // divergence (next to no-slip walls), and the Galerkin u_h·∇φ then feeds ½∫(−∇·u_h)φ²
        // into φ: a node-to-node oscillation of φ along the top wall of the falling cylinder grew
        // to φ = 2.8 (the domain's diameter is 1.4) with water droplets on the ceiling. The
        // added term vanishes where φ = 0, so it does not move the interface.
        const double div = conservative ? mid.div[first + q] : 0.5 * mid.div[first + q];
        const double         tau = supg_tau(dt, u.norm(), h);
        const double         JxW = fev.JxW(q);
        for (unsigned int i = 0; i < n; ++i)
        {
          s[i]   = fev.shape_value(i, q);
          ds[i]  = fev.shape_grad(i, q);
          adv[i] = u * ds[i];
        }
        // Strong residual of the old state (explicit half of Crank–Nicolson).
        const double res_old = u * grad_old[q] + div * val_old[q];
        // Entry (i, j), with the test function w_i = s_i + τ u·∇s_i and b_j = ½(u·∇s_j + div s_j):
        //   φ (advective): w_i (s_j/Δt + b_j);
        //   θ (conservative, Galerkin part in divergence form −∫θ u·∇v): w_i s_j/Δt + (u·∇s_i)(τ b_j − ½ s_j);
        // plus ½ν_K ∇s_i·∇s_j: two rank-one updates per point (pw, pa below).
        for (unsigned int j = 0; j < n; ++j)
        {
          const double b = 0.5 * (adv[j] + div * s[j]);
          pw[j]          = conservative ? s[j] / dt : s[j] / dt + b;
          pa[j]          = conservative ? tau * b - 0.5 * s[j] : 0.0;
        }
        for (unsigned int i = 0; i < n; ++i)
        {
          const double w = s[i] + tau * adv[i], wx = w * JxW, ax = adv[i] * JxW;
          double      *row = &A(i, 0);
          if (conservative)
            for (unsigned int j = 0; j < n; ++j)
              row[j] += wx * pw[j] + ax * pa[j];
          else
            for (unsigned int j = 0; j < n; ++j)
              row[j] += wx * pw[j];
          if (nu_K != 0)
            for (unsigned int j = 0; j < n; ++j)
              row[j] += 0.5 * nu_K * (ds[i] * ds[j]) * JxW;
          double r = val_old[q] / dt * w - 0.5 * nu_K * (ds[i] * grad_old[q]);
          if (conservative)
            r += 0.5 * val_old[q] * adv[i] - tau * adv[i] * 0.5 * res_old;
          else
            r += -0.5 * res_old * w;
          b(i) += r * JxW;
        }
      }
      // Open boundaries of the conservative form: outflow carries θ away (implicit half),
      // inflow brings inflow_value.
      if (conservative && !open_boundaries.empty())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() && open_boundaries.count(cell->face(f)->boundary_id()))
          {
            ffv.reinit(cell, f);
            ffu.reinit(typename DoFHandler<dim>::active_cell_iterator(&cell->get_triangulation(), cell->level(),
                                                                      cell->index(), &vdofs),
                       f);
            ffu[vel].get_function_values(flow.velocity(), fu_new);
            ffu[vel].get_function_values(flow.previous_velocity(), fu_old);
            ffv.get_function_values(current, fval_old);
            for (unsigned int q = 0; q < face_quad.size(); ++q)
            {
              const double un = 0.5 * (fu_new[q] + fu_old[q]) * ffv.normal_vector(q);
              for (unsigned int i = 0; i < n; ++i)
              {
                const double vi = ffv.shape_value(i, q) * ffv.JxW(q);
                if (un > 0)
                {
                  for (unsigned int j = 0; j < n; ++j)
                    A(i, j) += 0.5 * un * ffv.shape_value(j, q) * vi;
                  b(i) -= 0.5 * un * fval_old[q] * vi;
                }
                else
                  b(i) -= un * inflow_value * vi;
              }
            }
          }
      if (!scatter.ready() || !scatter.add(cell, A, &b, &rhs))
      {
        cell->get_dof_indices(indices);
        space.constraints().distribute_local_to_global(A, b, indices, matrix, rhs);
      }
    }
    matrix.compress(VectorOperation::add);
    rhs.compress(VectorOperation::add);
    if (!scatter.ready())
      scatter.reinit(space.dof_handler(), space.constraints(), matrix, rhs);

    ilu.compute(matrix); // the symbolic factorisation is kept while the mesh is
    space.reinit_owned(result);
    space.reader().assign(result, current);
    space.constraints().set_zero(result);
    SolverControl control(1000, std::max(space.parameters().linear_tolerance * rhs.l2_norm(), 1e-300));
    SolverGMRES<TrilinosWrappers::MPI::Vector> gmres(control, SolverGMRES<TrilinosWrappers::MPI::Vector>::AdditionalData(50));
    solve_named(field_name + " transport", control, [&] { gmres.solve(matrix, result, rhs, ilu); });
    space.constraints().distribute(result);
    iterations += control.last_step();
  }

  template <int dim>
  std::vector<double> LevelSetField<dim>::shock_capturing(const double dt,
                                                          const TrilinosWrappers::MPI::Vector &provisional_owned) const
  {
    TrilinosWrappers::MPI::Vector provisional;
    space.reinit_ghosted(provisional);
    space.reader().assign(provisional, provisional_owned);
    const auto        &fe = space.fe();
    const QGauss<dim>  quad(fe.degree + 1);
    FEValues<dim>      fev(space.mapping(), fe, quad, update_values | update_gradients);
    MidpointVelocity<dim> mid(flow, quad);
    const unsigned int nq = quad.size();
    std::vector<Tensor<1, dim>> g_new(nq), g_old(nq);
    std::vector<double> v_new(nq), v_old(nq);
    const auto &tria = space.dof_handler().get_triangulation();
    std::vector<double> nu(tria.n_active_cells(), 0.0);
    const double c = space.parameters().shock_capturing;
    for (const auto &cell : space.dof_handler().active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      fev.reinit(cell);
      mid.reinit(cell);
      fev.get_function_values(provisional, v_new);
      fev.get_function_values(current, v_old);
      fev.get_function_gradients(provisional, g_new);
      fev.get_function_gradients(current, g_old);
      const double h = space.cell_size(cell) / fe.degree;
      double       ratio = 0, speed = 0;
      for (unsigned int q = 0; q < nq; ++q)
      {
        const Tensor<1, dim> u = mid.u[q], g = 0.5 * (g_new[q] + g_old[q]);
        const double R = (v_new[q] - v_old[q]) / dt + u * g + 0.5 * (v_new[q] + v_old[q]) * mid.div[q];
        ratio = std::max(ratio, std::abs(R) / std::max(g.norm(), 1e-8 / h));
        speed = std::max(speed, u.norm());
      }
      nu[cell->active_cell_index()] = std::min(c * h * ratio, 0.5 * h * speed);
    }
    return nu;
  }

  template <int dim>
  void NclsTransport<dim>::advance(const double dt)
  {
    TimerOutput::Scope scope(this->space.timer(), "NCLS");
    this->iterations = 0;
    TrilinosWrappers::MPI::Vector next;
    this->solve_transport(dt, false, nullptr, next);
    if (this->space.parameters().shock_capturing > 0)
    {
      // Residual-based shock capturing as for θ: SUPG alone leaves crosswind wiggles that cut
      // zero far from Γ (islands of water) at corners of under-resolved shapes.
      const std::vector<double> nu = this->shock_capturing(dt, next);
      this->solve_transport(dt, false, &nu, next);
    }
    this->push(next, dt);
  }

  template <int dim>
  VofTransport<dim>::VofTransport(LevelSetSpace<dim> &space, const NavierStokes<dim> &flow,
                                  const std::set<types::boundary_id> &open)
    : LevelSetField<dim>(space, flow, "theta")
  {
    this->open_boundaries = open;
    this->inflow_value    = 1.0; // air enters through open boundaries
    this->conserved_by_transfer = true;
  }

  template <int dim>
  void VofTransport<dim>::advance(const double dt)
  {
    TimerOutput::Scope scope(this->space.timer(), "VOF");
    this->iterations = 0;
    TrilinosWrappers::MPI::Vector provisional, next;
    this->solve_transport(dt, true, nullptr, provisional);
    std::vector<double> nu;
    if (this->space.parameters().shock_capturing > 0)
    {
      nu = this->shock_capturing(dt, provisional);
      this->solve_transport(dt, true, &nu, next);
    }
    else
      next = provisional;
    this->push(next, dt);
  }

  template class NclsTransport<2>;
  template class NclsTransport<3>;
  template class VofTransport<2>;
  template class VofTransport<3>;
} // namespace twinflow::fem

namespace twinflow::fem
{
  template void LevelSetField<2>::solve_transport(double, bool, const std::vector<double> *,
                                                  dealii::TrilinosWrappers::MPI::Vector &);
  template void LevelSetField<3>::solve_transport(double, bool, const std::vector<double> *,
                                                  dealii::TrilinosWrappers::MPI::Vector &);
  template std::vector<double> LevelSetField<2>::shock_capturing(double, const dealii::TrilinosWrappers::MPI::Vector &) const;
  template std::vector<double> LevelSetField<3>::shock_capturing(double, const dealii::TrilinosWrappers::MPI::Vector &) const;
} // namespace twinflow::fem
