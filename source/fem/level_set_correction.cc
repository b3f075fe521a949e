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
  namespace
  {
    /// dst = src for two matrices built from the same sparsity pattern and maps (the rows'
    /// storage is then the same): a copy of the values, without the graph.
    void copy_values(const TrilinosWrappers::SparseMatrix &src, TrilinosWrappers::SparseMatrix &dst)
    {
      const Epetra_CrsMatrix &a = src.trilinos_matrix();
      Epetra_CrsMatrix       &b = const_cast<Epetra_CrsMatrix &>(dst.trilinos_matrix());
      AssertThrow(a.NumMyRows() == b.NumMyRows() && a.NumMyNonzeros() == b.NumMyNonzeros(),
                  ExcMessage("copy_values: the matrices do not share one sparsity pattern."));
      for (int row = 0; row < a.NumMyRows(); ++row)
      {
        int     na = 0, nb = 0, *ca = nullptr, *cb = nullptr;
        double *va = nullptr, *vb = nullptr;
        a.ExtractMyRowView(row, na, va, ca);
        b.ExtractMyRowView(row, nb, vb, cb);
        Assert(na == nb && std::equal(ca, ca + na, cb), ExcInternalError());
        std::copy(va, va + na, vb);
      }
    }
  } // namespace

  template <int dim>
  void MassCorrection<dim>::setup_dofs()
  {
    jacobian.reinit(space.owned(), space.owned(), space.sparsity(), space.communicator());
    jacobian_scatter.clear();
    space.reinit_ghosted(correction);
    amg_age = amg_lifetime; // a new mesh: a new hierarchy at the next correction
    domain  = 0;
    points_ready = false; // the points and the diffusion matrix at the next correction
  }

  template <int dim>
  void MassCorrection<dim>::advance(double)
  {
    if (space.parameters().mass_correction)
      correct();
  }

  template <int dim>
  void MassCorrection<dim>::setup_points()
  {
    const auto        &fe   = space.fe();
    const QGauss<dim>  quad = space.nonlinear_quadrature();
    FEValues<dim>      fev(space.mapping(), fe, quad, update_gradients | update_JxW_values);
    const unsigned int n = fe.n_dofs_per_cell(), nq = quad.size();
    points.cells.clear(), points.eps.clear(), points.JxW.clear();
    points.shape = reference_shape_values(fe, quad);
    diffusion.reinit(space.owned(), space.owned(), space.sparsity(), space.communicator());
    FullMatrix<double>                   stiffness(n, n);
    std::vector<types::global_dof_index> indices(n);
    for (const auto &cell : space.dof_handler().active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      fev.reinit(cell);
      points.cells.push_back(cell);
      points.eps.push_back(space.epsilon(cell));
      const double kappa = space.parameters().correction_diffusion * space.cell_size(cell);
      stiffness          = 0;
      for (unsigned int q = 0; q < nq; ++q)
      {
        points.JxW.push_back(fev.JxW(q));
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            stiffness(i, j) += kappa * (fev.shape_grad(i, q) * fev.shape_grad(j, q)) * fev.JxW(q);
      }
      cell->get_dof_indices(indices);
      space.constraints().distribute_local_to_global(stiffness, indices, diffusion);
    }
    diffusion.compress(VectorOperation::add);
    TrilinosWrappers::MPI::Vector owned_layout; // the rows' places in an owned vector of the space
    space.reinit_owned(owned_layout);
    jacobian_scatter.reinit(space.dof_handler(), space.constraints(), jacobian, owned_layout);
  }

  template <int dim>
  void MassCorrection<dim>::correct()
  {
    TimerOutput::Scope scope(space.timer(), "mass correction");
    const auto        &prm = space.parameters();
    const unsigned int n   = space.fe().n_dofs_per_cell();
    const MPI_Comm     comm = space.communicator();
    if (!points_ready) // once per mesh
    {
      points_ready = true;
      setup_points();
      for (const auto i : space.owned())
        domain += space.lumped_mass()[i];
      domain = Utilities::MPI::sum(domain, comm);
    }
    const unsigned int nq = points.shape.n();
    FullMatrix<double> A(n, n);
    Vector<double>     b(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<double>                  u_q(nq), local, u_local;
    // φ and θ at the points: fixed through the correction
    points.phi.resize(points.JxW.size());
    points.theta.resize(points.JxW.size());
    for (std::size_t k = 0; k < points.cells.size(); ++k)
    {
      points.evaluate(space.reader(), k, ncls.value(), local, u_q);
      std::copy(u_q.begin(), u_q.end(), points.phi.begin() + k * nq);
      points.evaluate(space.reader(), k, vof.value(), local, u_q);
      std::copy(u_q.begin(), u_q.end(), points.theta.begin() + k * nq);
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
      for (std::size_t k = 0; k < points.cells.size(); ++k)
      {
        const double eps = points.eps[k];
        points.evaluate(space.reader(), k, correction, u_local, u_q);
        for (unsigned int q = 0, p = k * nq; q < nq; ++q, ++p)
        {
          const double s = points.phi[p] + u_q[q];
          m0 += (smoothed_heaviside(s, eps) - points.theta[p]) * points.JxW[p];
          if (std::abs(s) < 2 * eps)
            band.push_back({s, eps, points.JxW[p]});
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
      // The Jacobian κK + ∫δ_ε(φ + u) ψ_i ψ_j: the mesh's diffusion (setup_points) plus the
      // mass of the band |φ + u| < ε, the only cells assembled; the residual
      // −∫(H_ε(φ + u) − θ) ψ_i − κ(Ku)_i, whose diffusion part vanishes on the first iteration (u = 0).
      copy_values(diffusion, jacobian);
      if (newton == 0)
        residual = 0;
      else
      {
        diffusion.vmult(residual, u_owned);
        residual *= -1;
        space.constraints().set_zero(residual);
      }
      double mismatch = 0;
      for (std::size_t k = 0; k < points.cells.size(); ++k)
      {
        const auto  &cell = points.cells[k];
        const double eps  = points.eps[k];
        if (newton == 0)
          std::fill(u_q.begin(), u_q.end(), 0.0);
        else
          points.evaluate(space.reader(), k, correction, u_local, u_q);
        b            = 0;
        bool in_band = false;
        for (unsigned int q = 0, p = k * nq; q < nq; ++q, ++p)
        {
          const double s = points.phi[p] + u_q[q];
          const double r = (smoothed_heaviside(s, eps) - points.theta[p]) * points.JxW[p];
          mismatch += r;
          for (unsigned int i = 0; i < n; ++i)
            b(i) -= r * points.shape(i, q);
          in_band = in_band || std::abs(s) < eps;
        }
        if (in_band)
        {
          A = 0;
          for (unsigned int q = 0, p = k * nq; q < nq; ++q, ++p)
          {
            const double dH = smoothed_delta(points.phi[p] + u_q[q], eps) * points.JxW[p];
            for (unsigned int i = 0; i < n && dH != 0; ++i)
              for (unsigned int j = 0; j < n; ++j)
                A(i, j) += dH * points.shape(i, q) * points.shape(j, q);
          }
          if (!jacobian_scatter.add(cell, A, &b, &residual))
          {
            cell->get_dof_indices(indices);
            space.constraints().distribute_local_to_global(A, b, indices, jacobian, residual);
          }
        }
        else if (!jacobian_scatter.add_vector(cell, b, residual))
        {
          cell->get_dof_indices(indices);
          space.constraints().distribute_local_to_global(b, indices, residual);
        }
      }
      jacobian.compress(VectorOperation::add);
      residual.compress(VectorOperation::add);
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
        data.higher_order_elements = space.fe().degree > 1;
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
    // θ = the L² projection of H_ε(φ + u), its moments at the cached points (φ + u there is
    // the corrected φ at the points: both are linear in the nodal values)
    TrilinosWrappers::MPI::Vector moments, theta;
    space.reinit_owned(moments);
    space.reinit_ghosted(theta);
    Vector<double> cell_moments(n);
    for (std::size_t k = 0; k < points.cells.size(); ++k)
    {
      const double eps = points.eps[k];
      points.evaluate(space.reader(), k, correction, u_local, u_q);
      cell_moments = 0;
      for (unsigned int q = 0, p = k * nq; q < nq; ++q, ++p)
      {
        const double h = smoothed_heaviside(points.phi[p] + u_q[q], eps) * points.JxW[p];
        for (unsigned int i = 0; i < n; ++i)
          cell_moments(i) += h * points.shape(i, q);
      }
      if (!jacobian_scatter.add_vector(points.cells[k], cell_moments, moments))
      {
        points.cells[k]->get_dof_indices(indices);
        space.constraints().distribute_local_to_global(cell_moments, indices, moments);
      }
    }
    moments.compress(VectorOperation::add);
    space.project_moments(moments, theta);
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
