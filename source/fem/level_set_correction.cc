// Level set: redistancing (Eq. 14, steady state) and the mass correction (Eq. 12, Newton).
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/immersed_boundary.h>
#include <twinflow/fem/level_set.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <iterator>

namespace twinflow::fem
{
  using namespace dealii;

  // ---------------------------------------------------------------------------------------
  // Redistancing
  // ---------------------------------------------------------------------------------------
  template <int dim>
  void Redistancing<dim>::advance(const double dt)
  {
    // the surface moved at most this far (max_velocity is the largest component: |u| ≤ √dim of it)
    travel += std::sqrt(double(dim)) * ncls.carrier().max_velocity() * dt;
    ++steps;
    if (space.parameters().redistance && steps % space.parameters().redistancing_interval == 0)
      redistance();
  }

  template <int dim>
  void Redistancing<dim>::redistance()
  {
    TimerOutput::Scope scope(space.timer(), "redistancing");
    const auto        &phi = ncls.value();
    const auto        &fe  = space.fe();
    const unsigned int n   = fe.n_dofs_per_cell();
    const unsigned int m   = dim == 2 ? 4 : 3; // samples per direction in a cut cell
    // Samples packed as x (dim), unit normal (dim), patch radius.
    constexpr unsigned int stride = 2 * dim + 1;
    std::vector<double>    local;
    // Nodes of cut cells keep their zero level: they are only rescaled by the mean |∇φ| of
    // their cut cells (a common factor per cell leaves that cell's zero level where it is).
    TrilinosWrappers::MPI::Vector gradient_sum, cut_count;
    gradient_sum.reinit(space.owned(), space.relevant(), space.communicator(), true);
    cut_count.reinit(space.owned(), space.relevant(), space.communicator(), true);
    std::vector<types::global_dof_index> indices(n);
    std::vector<double>    values(n);
    double                 epsilon_min = std::numeric_limits<double>::max(), epsilon_cut = 0;
    const bool             far_only    = space.parameters().far_field_only; // cut cells keep their φ: no slopes
    // φ and ∇_ξφ at a reference point: Q1 in closed form (the DoFs are the vertices in
    // lexicographic order), other degrees through the element (FE_Q::shape_value evaluates
    // its polynomials afresh on every call: ~10^5 calls per step in the samples' Newton).
    const auto evaluate = [&](const Point<dim> &xi, double &val, Tensor<1, dim> &g) {
      val = 0;
      g   = Tensor<1, dim>();
      if (fe.degree == 1)
        for (unsigned int i = 0; i < n; ++i)
        {
          double         w = 1;
          Tensor<1, dim> dw;
          for (unsigned int e = 0; e < dim; ++e)
            dw[e] = 1;
          for (unsigned int d = 0; d < dim; ++d)
          {
            const bool   upper  = (i >> d) & 1u;
            const double factor = upper ? xi[d] : 1 - xi[d];
            w *= factor;
            for (unsigned int e = 0; e < dim; ++e)
              dw[e] *= e == d ? (upper ? 1.0 : -1.0) : factor;
          }
          val += values[i] * w;
          g += values[i] * dw;
        }
      else
        for (unsigned int i = 0; i < n; ++i)
        {
          val += values[i] * fe.shape_value(i, xi);
          g += values[i] * fe.shape_grad(i, xi);
        }
    };
    for (const auto &cell : space.dof_handler().active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      epsilon_min = std::min(epsilon_min, space.epsilon(cell));
      space.reader().gather(cell, phi, values);
      double lo = 1e300, hi = -1e300;
      for (unsigned int i = 0; i < n; ++i)
      {
        lo = std::min(lo, values[i]);
        hi = std::max(hi, values[i]);
      }
      if (lo > 0 || hi < 0)
        continue;
      epsilon_cut = std::max(epsilon_cut, space.epsilon(cell));
      cell->get_dof_indices(indices);
      // Parallelepiped cell (box meshes): x = v0 + J ξ.
      Tensor<2, dim> J;
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int e = 0; e < dim; ++e)
          J[e][d] = cell->vertex(1u << d)[e] - cell->vertex(0)[e];
      const Tensor<2, dim> JinvT = transpose(invert(J));
      const double         h     = space.cell_size(cell);
      {
        Point<dim> centre;
        for (unsigned int d = 0; d < dim; ++d)
          centre[d] = 0.5;
        Tensor<1, dim> g;
        double         unused;
        evaluate(centre, unused, g);
        const double slope = (JinvT * g).norm();
        for (unsigned int i = 0; i < n; ++i)
        {
          if (!far_only)
            gradient_sum[indices[i]] += slope;
          cut_count[indices[i]] += 1;
        }
      }
      for (unsigned int k = 0; k < Utilities::pow(m, dim); ++k)
      {
        Point<dim> xi;
        for (unsigned int d = 0, r = k; d < dim; ++d, r /= m)
          xi[d] = (r % m + 0.5) / m;
        double         val = 0;
        Tensor<1, dim> g;
        for (unsigned int it = 0; it < 10; ++it)
        {
          evaluate(xi, val, g);
          if (g.norm_square() == 0 || std::abs(val) < 1e-13 * h)
            break;
          xi -= val / g.norm_square() * g;
        }
        bool inside = std::abs(val) < 1e-9 * h && g.norm_square() > 0;
        for (unsigned int d = 0; d < dim; ++d)
          inside = inside && xi[d] >= -1e-10 && xi[d] <= 1 + 1e-10;
        if (!inside)
          continue;
        Point<dim> x = cell->vertex(0);
        x += J * xi;
        Tensor<1, dim> normal = JinvT * g;
        normal /= normal.norm();
        for (unsigned int d = 0; d < dim; ++d)
          local.push_back(x[d]);
        for (unsigned int d = 0; d < dim; ++d)
          local.push_back(normal[d]);
        local.push_back(0.75 * h / m);
      }
    }
    gradient_sum.compress(VectorOperation::add);
    cut_count.compress(VectorOperation::add);
    const double band = LevelSetParameters::far_field_band * Utilities::MPI::min(epsilon_min, space.communicator());
    // the near field (see the class documentation): every node on a full pass, else |φ| < B
    const double near  = near_field_band * Utilities::MPI::max(epsilon_cut, space.communicator());
    const bool   full  = !have_full || travel - travel_at_full >= 0.25 * near;
    // Every rank's samples on every rank: MPI_Allgatherv of the doubles (Utilities::MPI::
    // all_gather serialises each vector through boost, ~1 % of a dam-break step).
    const MPI_Comm   comm = space.communicator();
    const int        n_local = static_cast<int>(local.size());
    std::vector<int> counts(Utilities::MPI::n_mpi_processes(comm)), offsets(counts.size() + 1, 0);
    AssertThrowMPI(MPI_Allgather(&n_local, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
    std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
    std::vector<double> data(offsets.back());
    AssertThrowMPI(MPI_Allgatherv(local.data(), n_local, MPI_DOUBLE, data.data(), counts.data(), offsets.data(),
                                  MPI_DOUBLE, comm));
    std::vector<std::pair<Point<dim>, unsigned int>> leaves;
    samples = data.size() / stride;
    if (samples == 0)
      return; // no interface: nothing to measure distances to
    for (unsigned int s = 0; s < samples; ++s)
    {
      Point<dim> p;
      for (unsigned int d = 0; d < dim; ++d)
        p[d] = data[s * stride + d];
      leaves.emplace_back(p, s);
    }
    const auto tree = pack_rtree(leaves);

    // The node loop reads and writes by local index (owned vectors; the owned entries of φ
    // copied out of its ghosted storage): Epetra's global look-up per access cost ~1 ms a step.
    TrilinosWrappers::MPI::Vector next, phi_owned;
    space.reinit_owned(next);
    space.reinit_owned(phi_owned);
    space.reader().copy_owned(phi_owned, phi);
    const int n_owned = next.trilinos_vector().MyLength();
    AssertThrow(gradient_sum.trilinos_vector().MyLength() == n_owned && cut_count.trilinos_vector().MyLength() == n_owned,
                ExcMessage("Redistancing: the writable ghosted vectors are expected in the owned layout."));
    const double *phi_local = phi_owned.trilinos_vector()[0], *slope_sum = gradient_sum.trilinos_vector()[0],
                 *cuts      = cut_count.trilinos_vector()[0];
    double            *next_local = next.trilinos_vector()[0];
    const unsigned int k          = 1u << dim;
    std::vector<std::pair<Point<dim>, unsigned int>> nearest;
    for (const auto &[i, x] : space.support_points())
    {
      const auto   j   = space.owned().index_within_set(i);
      const double old = phi_local[j];
      if (far_only && (std::abs(old) < band || cuts[j] > 0)) // the band and the cut cells keep their φ
      {
        next_local[j] = old;
        continue;
      }
      if (cuts[j] > 0)
      {
        const double slope = slope_sum[j] / cuts[j];
        next_local[j]      = slope > 0 ? old / slope : old;
        continue;
      }
      if (!full && std::abs(old) >= near)
      {
        next_local[j] = old;
        continue;
      }
      nearest.clear();
      tree.query(boost::geometry::index::nearest(x, k), std::back_inserter(nearest));
      double d = std::numeric_limits<double>::max();
      for (const auto &[p, s] : nearest)
      {
        Tensor<1, dim> normal;
        for (unsigned int e = 0; e < dim; ++e)
          normal[e] = data[s * stride + dim + e];
        const Tensor<1, dim> r       = x - p;
        const double         along   = r * normal;
        const double         lateral = (r - along * normal).norm();
        d = std::min(d, lateral <= data[s * stride + 2 * dim] ? std::abs(along) : r.norm());
      }
      next_local[j] = old > 0 ? d : (old < 0 ? -d : 0.0);
    }
    ncls.set(next);
    if (full)
    {
      have_full      = true;
      travel_at_full = travel;
    }
  }

  template <int dim>
  void Redistancing<dim>::save_state(std::ostream &out) const
  {
    out.precision(17);
    out << "redistancing " << steps << ' ' << (have_full ? travel - travel_at_full : -1.0) << '\n';
  }

  template <int dim>
  void Redistancing<dim>::load_state(std::istream &in)
  {
    std::string tag;
    double      since_full = -1;
    in >> tag >> steps >> since_full;
    AssertThrow(in && tag == "redistancing",
                ExcMessage("checkpoint metadata: the redistancing line is missing or malformed (a checkpoint "
                           "written before 2026-12-06 cannot be restarted by this version)"));
    have_full      = since_full >= 0;
    travel_at_full = travel - since_full;
  }

  // ---------------------------------------------------------------------------------------
  // Solid interior drying

  template <int dim>
  void SolidInteriorDrying<dim>::advance(double)
  {
    TimerOutput::Scope            scope(space.timer(), "solid interior drying");
    const auto                   &phi = ncls.value();
    TrilinosWrappers::MPI::Vector next;
    space.reinit_owned(next);
    bool changed = false;
    for (const auto &[i, x] : space.support_points())
    {
      const double d = solid_distance(x);
      next[i]        = phi[i];
      if (d < 0 && phi[i] < -d)
      {
        next[i] = -d;
        changed = true;
      }
    }
    if (Utilities::MPI::logical_or(changed, space.communicator()))
    {
      next.compress(VectorOperation::insert);
      ncls.set(next);
    }
  }

  // ---------------------------------------------------------------------------------------
  // Mass correction
  // ---------------------------------------------------------------------------------------
  template <int dim>
  void MassCorrection<dim>::setup_dofs()
  {
    jacobian.reinit(space.owned(), space.owned(), space.sparsity(), space.communicator());
    jacobian_scatter.clear();
    space.reinit_ghosted(correction);
    amg_age = amg_lifetime; // a new mesh: a new hierarchy at the next correction
    domain  = 0;
  }

  template <int dim>
  void MassCorrection<dim>::advance(double)
  {
    if (space.parameters().mass_correction)
      correct();
  }

  template <int dim>
  void MassCorrection<dim>::correct()
  {
    TimerOutput::Scope scope(space.timer(), "mass correction");
    const auto        &prm  = space.parameters();
    const auto        &fe   = space.fe();
    const QGauss<dim>  quad = space.nonlinear_quadrature();
    FEValues<dim>      fev(space.mapping(), fe, quad, update_values | update_gradients | update_JxW_values);
    const unsigned int n  = fe.n_dofs_per_cell();
    const unsigned int nq = quad.size();
    FullMatrix<double> A(n, n), stiffness(n, n);
    Vector<double>     b(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<double>         phi_q(nq), theta_q(nq), u_q(nq);
    std::vector<Tensor<1, dim>> grad_u(nq);
    std::vector<double>         local, u_local;
    const FEValuesExtractors::Scalar scalar(0);
    const MPI_Comm comm = space.communicator();
    if (domain == 0) // once per mesh
    {
      for (const auto i : space.owned())
        domain += space.lumped_mass()[i];
      domain = Utilities::MPI::sum(domain, comm);
    }

    TrilinosWrappers::MPI::Vector u_owned, residual, delta;
    space.reinit_owned(u_owned);
    space.reinit_owned(residual);
    space.reinit_owned(delta);
    correction = 0;
    newton     = 0;
    ++amg_age;
    // After a full Newton step the residual is second order in u and the volume (the equation
    // tested with v = 1) is the only part the stopping test reads: it is met by a uniform shift
    // u ← u + c, which leaves the diffusion term κ∇u unchanged, by a scalar Newton on c over
    // the points of the band (H_ε(φ + u + c) differs from H_ε(φ + u) only where |φ + u| < ε + |c|).
    // Returns false when c would leave the band the points were taken from (then a full step).
    const auto shift_volume = [&]() -> bool {
      band.clear();
      double m0 = 0;
      for (const auto &cell : space.dof_handler().active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fev.reinit(cell);
        for (auto [v, out] : {std::pair{&ncls.value(), &phi_q}, {&vof.value(), &theta_q}, {&correction, &u_q}})
        {
          space.reader().gather(cell, *v, local);
          fev[scalar].get_function_values_from_local_dof_values(local, *out);
        }
        const double eps = space.epsilon(cell);
        for (unsigned int q = 0; q < nq; ++q)
        {
          const double s = phi_q[q] + u_q[q];
          m0 += (smoothed_heaviside(s, eps) - theta_q[q]) * fev.JxW(q);
          if (std::abs(s) < 2 * eps)
            band.push_back({s, eps, fev.JxW(q)});
        }
      }
      double mismatch = Utilities::MPI::sum(m0, comm);
      double c = 0, eps_min = std::numeric_limits<double>::max();
      for (const auto &b : band)
        eps_min = std::min(eps_min, b.eps);
      eps_min = Utilities::MPI::min(eps_min, comm);
      for (unsigned int k = 0; k < 20 && std::abs(mismatch) >= prm.correction_tolerance * domain; ++k)
      {
        double slope = 0;
        for (const auto &b : band)
          slope += smoothed_delta(b.s + c, b.eps) * b.JxW;
        slope = Utilities::MPI::sum(slope, comm);
        if (!(slope > 0))
          return false;
        c -= mismatch / slope;
        if (!(std::abs(c) < eps_min))
          return false;
        double m = 0;
        for (const auto &b : band)
          m += (smoothed_heaviside(b.s + c, b.eps) - smoothed_heaviside(b.s, b.eps)) * b.JxW;
        mismatch = Utilities::MPI::sum(m0 + m, comm);
      }
      if (std::abs(mismatch) >= prm.correction_tolerance * domain)
        return false;
      u_owned.add(c);
      space.constraints().distribute(u_owned); // a constant meets every (affine, weights summing to 1) constraint
      space.reader().assign(correction, u_owned);
      return true;
    };
    for (; newton < 25; ++newton)
    {
      // After a full Newton step the volume usually matches already or to second order: a
      // uniform shift finishes it without assembling a Jacobian (see shift_volume).
      if (newton > 0 && shift_volume())
        break;
      jacobian = 0;
      residual = 0;
      double mismatch        = 0;
      bool   stiffness_valid = false;
      for (const auto &cell : space.dof_handler().active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fev.reinit(cell);
        for (auto [v, out] : {std::pair{&ncls.value(), &phi_q}, {&vof.value(), &theta_q}})
        {
          space.reader().gather(cell, *v, local);
          fev[scalar].get_function_values_from_local_dof_values(local, *out);
        }
        space.reader().gather(cell, correction, u_local);
        fev[scalar].get_function_values_from_local_dof_values(u_local, u_q);
        const double eps   = space.epsilon(cell);
        const double kappa = prm.correction_diffusion * space.cell_size(cell);
        A = 0;
        b = 0;
        // Off the band |φ + u| < ε (δ_ε = 0 at every point) the Jacobian is κK: the stiffness
        // K_ij = ∫∇s_i·∇s_j, which a translated cell shares with the previous one (deal.II's
        // cell similarity), and the diffusion part of the residual is κ K u_K.
        bool in_band = false;
        for (unsigned int q = 0; q < nq && !in_band; ++q)
          in_band = std::abs(phi_q[q] + u_q[q]) < eps;
        if (!in_band)
        {
          if (!stiffness_valid || fev.get_cell_similarity() != CellSimilarity::translation)
          {
            stiffness = 0;
            for (unsigned int q = 0; q < nq; ++q)
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  stiffness(i, j) += fev.shape_grad(i, q) * fev.shape_grad(j, q) * fev.JxW(q);
            stiffness_valid = true;
          }
          for (unsigned int q = 0; q < nq; ++q)
          {
            const double r = smoothed_heaviside(phi_q[q] + u_q[q], eps) - theta_q[q];
            mismatch += r * fev.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              b(i) -= r * fev.shape_value(i, q) * fev.JxW(q);
          }
          A.add(kappa, stiffness);
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              b(i) -= A(i, j) * u_local[j];
        }
        else
        {
          stiffness_valid = false; // the next cell off the band computes K again
          fev[scalar].get_function_gradients_from_local_dof_values(u_local, grad_u);
        }
        for (unsigned int q = 0; in_band && q < nq; ++q)
        {
          const double JxW = fev.JxW(q);
          const double r   = smoothed_heaviside(phi_q[q] + u_q[q], eps) - theta_q[q];
          const double dH  = smoothed_delta(phi_q[q] + u_q[q], eps);
          mismatch += r * JxW;
          for (unsigned int i = 0; i < n; ++i)
          {
            const double         si  = fev.shape_value(i, q);
            const Tensor<1, dim> dsi = fev.shape_grad(i, q);
            b(i) -= (r * si + kappa * (grad_u[q] * dsi)) * JxW;
            for (unsigned int j = 0; j < n; ++j)
              A(i, j) += (dH * si * fev.shape_value(j, q) + kappa * (dsi * fev.shape_grad(j, q))) * JxW;
          }
        }
        cell->get_dof_indices(indices);
        if (!jacobian_scatter.ready() || !jacobian_scatter.add(cell, A, &b, &residual))
          space.constraints().distribute_local_to_global(A, b, indices, jacobian, residual);
      }
      jacobian.compress(VectorOperation::add);
      residual.compress(VectorOperation::add);
      if (!jacobian_scatter.ready())
        jacobian_scatter.reinit(space.dof_handler(), space.constraints(), jacobian, residual);
      mismatch = Utilities::MPI::sum(mismatch, comm);
      // The volume constraint (the equation tested with v = 1) is met once Newton has moved.
      if (newton == 0 && std::abs(mismatch) < prm.correction_tolerance * domain && residual.linfty_norm() == 0)
        break;
      if (newton == 0 && amg_age > amg_lifetime)
      {
        // Set up every amg_lifetime steps: the later Jacobians differ only through δ_ε(φ + u),
        // and CG still converges to the same tolerance with an older one's hierarchy.
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic              = true;
        data.higher_order_elements = fe.degree > 1;
        data.smoother_sweeps       = 2;
        initialize_amg(amg, jacobian, data);
        amg_age = 1;
      }
      delta = 0;
      // Inexact Newton (forcing term 1e-6, Eisenstat & Walker 1996): the step only has to bring
      // the residual to where the volume is met to second order; the uniform shift then makes
      // the volume exact (shift_volume), and a further full step converges at the rate 1e-6.
      // Solving to 1e-12 took 13 AMG-CG iterations per step for a change of u at 1e-6 of δ.
      SolverControl control(1000, std::max(1e-6 * residual.l2_norm(), 1e-300));
      SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
      solve_named("mass-correction Newton", control, [&] { cg.solve(jacobian, delta, residual, amg); });
      space.constraints().distribute(delta);
      u_owned += delta;
      space.reader().assign(correction, u_owned);
      if (delta.linfty_norm() < 1e-12 * std::pow(domain, 1.0 / dim))
      {
        ++newton;
        break;
      }
    }
    max_correction = u_owned.linfty_norm();
    TrilinosWrappers::MPI::Vector phi;
    space.reinit_owned(phi);
    space.reader().assign(phi, ncls.value());
    phi += u_owned;
    ncls.set(phi);
    TrilinosWrappers::MPI::Vector theta;
    space.reinit_ghosted(theta);
    space.project_heaviside(ncls.value(), theta);
    vof.set(theta);
  }

  template <int dim>
  void MassCorrection<dim>::add_to_output(DataOut<dim> &data_out) const
  {
    data_out.add_data_vector(space.dof_handler(), correction, "mass_correction");
  }

  template class Redistancing<2>;
  template class Redistancing<3>;
  template class SolidInteriorDrying<2>;
  template class SolidInteriorDrying<3>;
  template class MassCorrection<2>;
  template class MassCorrection<3>;
} // namespace twinflow::fem
