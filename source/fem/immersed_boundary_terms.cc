// ImmersedBoundary<dim>: the Nitsche + penalty terms of Eq. 15-16 and the loads they imply.
#include <twinflow/fem/immersed_boundary.h>
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <cmath>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  ImmersedBoundary<dim>::ImmersedBoundary(const Scene &scene, const ImmersedBoundaryParameters &parameters)
    : prm(parameters)
  {
    const double span = dim == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 0.0;
    for (const auto &s : scene.solids)
      bodies.push_back(std::make_unique<ImmersedSolid<dim>>(s, span, dim == 3 && scene.periodic[2]));
  }

  template <int dim>
  double ImmersedBoundary<dim>::cell_size(const typename DoFHandler<dim>::active_cell_iterator &cell)
  {
    return cell->diameter() / std::sqrt(double(dim));
  }

  template <int dim>
  double ImmersedBoundary<dim>::distance(const Point<dim> &x, unsigned int &nearest) const
  {
    double best = std::numeric_limits<double>::max();
    nearest     = 0;
    for (unsigned int k = 0; k < bodies.size(); ++k)
    {
      const double d = bodies[k]->distance(x);
      if (d < best)
      {
        best    = d;
        nearest = k;
      }
    }
    return best;
  }

  template <int dim>
  bool ImmersedBoundary<dim>::acts_on(const typename DoFHandler<dim>::active_cell_iterator &cell) const
  {
    unsigned int k;
    const double eps = prm.interface_width * cell_size(cell);
    return distance(cell->center(), k) < 0.5 * cell->diameter() + eps;
  }

  template <int dim>
  void ImmersedBoundary<dim>::scale_fluid_fraction(const MomentumCell<dim> &c, std::vector<double> &fraction) const
  {
    const double eps = prm.interface_width * cell_size(c.cell);
    unsigned int k;
    for (unsigned int q = 0; q < fraction.size(); ++q)
      fraction[q] *= 1 - solid_fraction(distance(c.fe_values.quadrature_point(q), k), eps);
  }

  namespace
  {
    /// σ(u) n for a velocity gradient (μ = 1).
    template <int dim>
    Tensor<1, dim> stress_normal(const Tensor<2, dim> &grad_u, const Tensor<1, dim> &n, bool symmetric)
    {
      Tensor<1, dim> t = grad_u * n;
      if (symmetric)
        t += transpose(grad_u) * n;
      return t;
    }
  } // namespace

  template <int dim>
  void ImmersedBoundary<dim>::assemble(const MomentumCell<dim> &c, FullMatrix<double> &matrix, Vector<double> &rhs) const
  {
    last_time_step         = c.time_step;
    const FEValues<dim> &fev = c.fe_values;
    const double h   = cell_size(c.cell);
    const double eps = prm.interface_width * h;
    const unsigned int n = fev.get_fe().n_dofs_per_cell();
    std::vector<double>         sv(n), sn(n);
    std::vector<Tensor<1, dim>> sg(n);
    for (unsigned int q = 0; q < fev.n_quadrature_points; ++q)
    {
      const Point<dim> &x = fev.quadrature_point(q);
      unsigned int      k;
      const double      phi   = distance(x, k);
      const double      delta = smoothed_delta(phi, eps);
      const double      H     = solid_fraction(phi, eps); // 1 inside the solid
      if (delta == 0 && H == 0)
        continue;
      const double         mu      = c.material.viscosity[q], rho = c.material.density[q];
      const double         c_alpha = prm.nitsche_penalty * mu / h;
      const double         c_beta  = prm.volume_penalty * (rho / c.time_step + mu / (h * h));
      const Tensor<1, dim> n_f     = -bodies[k]->normal(x); // the fluid's outward normal
      const Tensor<1, dim> u_s     = bodies[k]->velocity(x);
      const double         JxW     = fev.JxW(q);
      const double         mass    = (delta * c_alpha + H * c_beta) * JxW;
      const double         nitsche = delta * mu * JxW;
      const bool           sym     = c.symmetric_stress;
      // Per shape function: value, gradient, ∇s·n; σ(φ_j)n·e_ci = δ_{ci cj} ∇s_j·n + [sym] ∂_ci s_j n_cj.
      for (unsigned int i = 0; i < n; ++i)
      {
        sv[i] = fev.shape_value(i, q);
        sg[i] = fev.shape_grad(i, q);
        sn[i] = sg[i] * n_f;
      }
      for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int ci = c.component[i];
        // σ(φ_i) n_f · u_s (adjoint-consistency term with the known u_s)
        double sigma_i_us = sn[i] * u_s[ci];
        if (sym)
          sigma_i_us += (sg[i] * u_s) * n_f[ci];
        rhs(i) += mass * u_s[ci] * sv[i] - nitsche * sigma_i_us;
        if (nitsche == 0)
        {
          for (unsigned int j = 0; j < n; ++j)
            if (c.component[j] == ci)
              matrix(i, j) += mass * sv[i] * sv[j];
          continue;
        }
        for (unsigned int j = 0; j < n; ++j)
        {
          const unsigned int cj = c.component[j];
          double a = 0;
          if (ci == cj)
            a = mass * sv[i] * sv[j] - nitsche * (sn[j] * sv[i] + sn[i] * sv[j]);
          if (sym)
            a -= nitsche * (sg[j][ci] * n_f[cj] * sv[i] + sg[i][cj] * n_f[ci] * sv[j]);
          matrix(i, j) += a;
        }
      }
    }
  }

  template <int dim>
  std::vector<SolidLoad<dim>> ImmersedBoundary<dim>::loads(const NavierStokes<dim> &flow) const
  {
    std::vector<SolidLoad<dim>> out(bodies.size());
    const auto &dofs = flow.velocity_dof_handler();
    const auto &fe   = dofs.get_fe();
    const QGauss<dim> quad(fe.degree + 1);
    FEValues<dim> fev(flow.get_mapping(), fe, quad, update_values | update_gradients | update_JxW_values | update_quadrature_points);
    const FEValuesExtractors::Vector vel(0);
    std::vector<Tensor<1, dim>> u(quad.size()), grad_increment(quad.size());
    std::vector<Tensor<2, dim>> grad_u(quad.size());
    MaterialValues<dim>         mat;
    const double tau = last_time_step > 0 ? last_time_step : std::numeric_limits<double>::max();
    // The reaction of the step's own terms: with the variable-density projection the momentum
    // step solved for ũ with p^n, and the correction u = ũ − τ/(α0ρ)∇φ is not a solution of
    // those terms (tested with u, C_β(u − u_s) would carry γ_β/α0 times the increment ∇φ: an
    // added mass of ~10–60 ρ V). The load is the reaction for ũ plus the increment's own
    // −∫ H_s ∇φ, so that the pressure part is −∫ H_s ∇p^{n+1}.
    const bool corrected = flow.velocity_corrected();
    const auto &pressure_dofs = flow.pressure_dof_handler();
    FEValues<dim> fep(flow.get_mapping(), pressure_dofs.get_fe(), quad, update_gradients);
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned() && acts_on(cell))
      {
        fev.reinit(cell);
        fev[vel].get_function_values(flow.momentum_velocity(), u);
        fev[vel].get_function_gradients(flow.momentum_velocity(), grad_u);
        if (corrected)
        {
          const typename DoFHandler<dim>::active_cell_iterator pcell(&dofs.get_triangulation(), cell->level(),
                                                                     cell->index(), &pressure_dofs);
          fep.reinit(pcell);
          fep.get_function_gradients(flow.pressure_increment(), grad_increment);
        }
        flow.material_model().evaluate(cell, fev.get_quadrature_points(), flow.time(), mat);
        const double h = cell_size(cell), eps = prm.interface_width * h;
        for (unsigned int q = 0; q < quad.size(); ++q)
        {
          const Point<dim> &x = fev.quadrature_point(q);
          unsigned int      k;
          const double      phi   = distance(x, k);
          const double      delta = smoothed_delta(phi, eps), H = solid_fraction(phi, eps);
          if (delta == 0 && H == 0)
            continue;
          const double mu = mat.viscosity[q], rho = mat.density[q];
          const double c_alpha = prm.nitsche_penalty * mu / h;
          const double c_beta  = prm.volume_penalty * (rho / tau + mu / (h * h));
          const Tensor<1, dim> n_f  = -bodies[k]->normal(x);
          const Tensor<1, dim> slip = u[q] - bodies[k]->velocity(x);
          const Tensor<1, dim> f =
            (delta * (-mu * stress_normal<dim>(grad_u[q], n_f, flow.symmetric_stress()) + c_alpha * slip) +
             H * (c_beta * slip - (corrected ? grad_increment[q] : Tensor<1, dim>()))) * fev.JxW(q);
          out[k].force += f;
          const Tensor<1, dim> r = x - bodies[k]->center();
          if constexpr (dim == 2)
            out[k].torque[2] += r[0] * f[1] - r[1] * f[0];
          else
            out[k].torque += cross_product_3d(r, f);
        }
      }
    const MPI_Comm comm = dofs.get_triangulation().get_communicator();
    for (auto &l : out)
    {
      l.force  = Utilities::MPI::sum(l.force, comm);
      l.torque = Utilities::MPI::sum(l.torque, comm);
    }
    return out;
  }

  template <int dim>
  std::pair<double, double> ImmersedBoundary<dim>::slip_errors(const NavierStokes<dim> &flow) const
  {
    const auto &dofs = flow.velocity_dof_handler();
    const auto &fe   = dofs.get_fe();
    const QGauss<dim> quad(fe.degree + 2);
    FEValues<dim> fev(flow.get_mapping(), fe, quad, update_values | update_JxW_values | update_quadrature_points);
    std::vector<Tensor<1, dim>> u(quad.size());
    double inside = 0, surface = 0;
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned() && acts_on(cell))
      {
        fev.reinit(cell);
        fev[FEValuesExtractors::Vector(0)].get_function_values(flow.velocity(), u);
        const double eps = prm.interface_width * cell_size(cell);
        for (unsigned int q = 0; q < quad.size(); ++q)
        {
          unsigned int k;
          const double phi  = distance(fev.quadrature_point(q), k);
          const double slip = (u[q] - bodies[k]->velocity(fev.quadrature_point(q))).norm_square();
          if (phi < 0)
            inside += slip * fev.JxW(q);
          surface += smoothed_delta(phi, eps) * slip * fev.JxW(q);
        }
      }
    const MPI_Comm comm = dofs.get_triangulation().get_communicator();
    return {std::sqrt(Utilities::MPI::sum(inside, comm)), std::sqrt(Utilities::MPI::sum(surface, comm))};
  }

  template class ImmersedBoundary<2>;
  template class ImmersedBoundary<3>;
} // namespace twinflow::fem
