// Implicit SPH engine (Algorithm 2) — the single source of both backends.
#include <twinflow_sph/engine.h>
#include <twinflow_sph/linear_solver.h>
#include <twinflow_sph/multigrid.h>
#include <twinflow_sph/neighbor_search.h>
#include <twinflow_sph/operators.h>

#include "engine_functors.inl"
#include "confined_pressure.inl"
#include "solid_force.inl"

#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/equal.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/gather.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/reduce.h>
#include <thrust/transform.h>
#include <thrust/functional.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace detail
  {
    template <int dim>
    struct ExtractComponent
    {
      int c;
      TWINFLOW_HD double operator()(const Vec<dim> &v) const { return v[c]; }
    };
    template <int dim>
    struct SetComponent
    {
      const double *src;
      Vec<dim>     *dst;
      int           c;
      TWINFLOW_HD void operator()(int i) const { dst[i][c] = src[i]; }
    };

    class Stopwatch
    {
    public:
      Stopwatch() : t0(std::chrono::steady_clock::now()) {}
      double lap()
      {
        const auto t1 = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(t1 - t0).count();
        t0 = t1;
        return s;
      }
    private:
      std::chrono::steady_clock::time_point t0;
    };
  } // namespace detail

  template <int dim>
  class BackendEngine : public Engine<dim>
  {
  public:
    BackendEngine(const DomainBox<dim> &box, const EngineSettings &s)
      : box(box), settings(s), W(s.h), search(box, 2.0 * s.h)
    {
      double vol = 1;
      for (int d = 0; d < dim; ++d)
        vol *= s.spacing;
      m0 = s.rho0 * vol;
      if (!s.consistent)
        standard_scale = lattice_scale<dim>(W, s.spacing);
    }

    void set_particles(const HostParticles<dim> &p) override
    {
      n = static_cast<int>(p.size());
      x.assign(p.x.begin(), p.x.end());
      x_start.resize(p.x.size());
      u.assign(p.u.begin(), p.u.end());
      pressure.assign(p.p.begin(), p.p.end());
      kind.assign(p.kind.begin(), p.kind.end());
      wall_velocity.assign(p.wall_velocity.begin(), p.wall_velocity.end());
      wall_acceleration.assign(p.wall_acceleration.begin(), p.wall_acceleration.end());
      normal.assign(p.normal.begin(), p.normal.end());
      setup_solids(p);
      rho.resize(n);
      support.resize(n);
      surface.resize(n);
      V.resize(n);
      rhs.resize(n);
      tmp.resize(n);
      comp.resize(n);
      div_u.resize(n);
      for (int d = 0; d < dim; ++d)
        grad_p[d].resize(n);
      // Confined flows: the pressure is defined up to a constant. A pinned particle becomes a
      // point source of the residual incompatibility (divergence of the periodic cylinder
      // benchmark), so by default nothing is pinned: the right-hand side is made compatible
      // (make_confined_rhs_compatible) and the system regular (regularise_confined_pressure_matrix).
      pinned = -1;
      if (!settings.free_surface && pin_confined_pressure)
        for (int i = 0; i < n; ++i)
          if (p.kind[i] == ParticleKind::fluid)
          {
            pinned = i;
            break;
          }
    }

    void get_particles(HostParticles<dim> &p) const override
    {
      p.x.resize(n);
      p.u.resize(n);
      p.p.resize(n);
      p.rho.resize(n);
      p.kind.resize(n);
      thrust::copy(x.begin(), x.end(), p.x.begin());
      thrust::copy(u.begin(), u.end(), p.u.begin());
      thrust::copy(pressure.begin(), pressure.end(), p.p.begin());
      thrust::copy(rho.begin(), rho.end(), p.rho.begin());
      thrust::copy(kind.begin(), kind.end(), p.kind.begin());
      // the markers' state, which moving solids change (so that set_particles(get_particles) is the identity)
      p.wall_velocity.resize(n);
      p.wall_acceleration.resize(n);
      p.normal.resize(n);
      thrust::copy(wall_velocity.begin(), wall_velocity.end(), p.wall_velocity.begin());
      thrust::copy(wall_acceleration.begin(), wall_acceleration.end(), p.wall_acceleration.begin());
      thrust::copy(normal.begin(), normal.end(), p.normal.begin());
      p.body.resize(body.size());
      thrust::copy(body.begin(), body.end(), p.body.begin());
    }

    void move_solids(const std::vector<MarkerMotion> &motions) override
    {
      if (motions.empty())
        return;
      for (const MarkerMotion &m : motions)
        if (m.body >= 0 && m.body < solids)
          for (int d = 0; d < 3; ++d)
            torque_centres[m.body][d] = m.to[d];
      device_motions.assign(motions.begin(), motions.end()); // a few bodies: no reallocation after the first
      const detail::MotionsView moved{ptr(device_motions), static_cast<int>(motions.size())};
      detail::MoveMarkers<dim>  move;
      move.p                 = particles();
      move.motions           = moved;
      move.x                 = ptr(x);
      move.normal            = ptr(normal);
      move.wall_velocity     = ptr(wall_velocity);
      move.wall_acceleration = ptr(wall_acceleration);
      for_each_particle(move);
      detail::KeepOutOfSolids<dim> keep_out;
      keep_out.p       = particles();
      keep_out.motions = moved;
      keep_out.margin  = 0.25 * settings.spacing;
      keep_out.x       = ptr(x);
      keep_out.u       = ptr(u);
      for_each_particle(keep_out);
    }

    /// One step of Algorithm 2; each phase is timed into the StepReport.
    const StepReport &step(const double dt) override
    {
      detail::Stopwatch clock;
      report = StepReport();
      search.build(x, nl);
      report.t_neighbors = clock.lap();
      compute_density_and_free_surface();
      const double separation_pe = separate_close_pairs(); // density and flags again if it moved any
      assemble_operators_and_velocity_matrix(dt);
      report.t_assembly = clock.lap();
      u_old.resize(n);
      thrust::copy(exec, u.begin(), u.end(), u_old.begin());
      const double ke0 = fluid_energy(u, false), pe0 = fluid_energy(x, true);
      predict_velocity(dt);
      const double ke1 = fluid_energy(u, false);
      report.budget.body_force = body_force_work(dt);
      report.budget.viscous    = ke1 - ke0 - report.budget.body_force;
      report.t_velocity = clock.lap();
      solve_pressure(dt);
      report.pressure_noise = pressure_noise();
      report.t_pressure     = clock.lap();
      correct_and_move(dt);
      report.max_speed = max_fluid_speed();
      report.budget.pressure = fluid_energy(u, false) - ke1;
      // the shifting's and the pair separation's potential-energy changes (positions only)
      report.budget.shifting  = (settings.shifting > 0 ? fluid_energy(x, true) - pe_moved : 0.0) + separation_pe;
      report.budget.potential = (settings.shifting > 0 ? pe_moved : fluid_energy(x, true)) - pe0 -
                                report.budget.density_correction; // correct_and_move() booked it
      report.t_update  = clock.lap();
      return report;
    }

    /// Σ over fluid particles of ½ m0 |f_i|² (potential: false) or −m0 g·f_i (true).
    double fluid_energy(const dvec<Vec<dim>> &f, const bool potential) const
    {
      detail::FluidEnergy<dim> e;
      e.p         = particles();
      e.u         = ptr(f);
      e.x         = ptr(f);
      e.m0        = m0;
      e.potential = potential;
      for (int d = 0; d < dim; ++d)
        e.g[d] = settings.gravity[d];
      const thrust::counting_iterator<int> first(0);
      return thrust::transform_reduce(exec, first, first + n, e, 0.0, thrust::plus<double>());
    }

    /// ΔPE of the density-error displacement −Δt²/ρ0 ∇q (EnergyBudget::density_correction).
    double displacement_energy(const double dt) const
    {
      detail::DisplacementEnergy<dim> e;
      e.p      = particles();
      e.grad_q = components(grad_q);
      e.scale  = dt * dt / settings.rho0;
      e.m0     = m0;
      for (int d = 0; d < dim; ++d)
        e.g[d] = settings.gravity[d];
      const thrust::counting_iterator<int> first(0);
      return thrust::transform_reduce(exec, first, first + n, e, 0.0, thrust::plus<double>());
    }

    /// Work of the body force over the velocity prediction (EnergyBudget::body_force).
    double body_force_work(const double dt) const
    {
      detail::BodyForceWork<dim> w;
      w.p     = particles();
      w.u_old = ptr(u_old);
      w.m0    = m0;
      w.dt    = dt;
      for (int d = 0; d < dim; ++d)
        w.a[d] = settings.acceleration[d];
      const thrust::counting_iterator<int> first(0);
      return thrust::transform_reduce(exec, first, first + n, w, 0.0, thrust::plus<double>());
    }

    double max_fluid_speed() const override
    {
      const thrust::counting_iterator<int> first(0);
      return thrust::transform_reduce(exec, first, first + n, detail::FluidSpeed<dim>{particles()}, 0.0,
                                      thrust::maximum<double>());
    }

    std::size_t n_neighbor_entries() const override { return nl.n_entries(); }

    std::size_t bytes_per_particle() const override
    {
      if (n == 0)
        return 0;
      const std::size_t per_entry = sizeof(int) + sizeof(double) * (dim + 2); // index, A^G, A^L, system
      const std::size_t per_particle =
        sizeof(Vec<dim>) * 5 + sizeof(double) * (8 + dim) + sizeof(int) * 3 + 2 * sizeof(Tensor2<dim>);
      const std::size_t krylov = 9 * sizeof(double); // BiCGStab work vectors (linear_solver.inl)
      return per_particle + krylov + per_entry * nl.n_entries() / n + multigrid.memory_bytes() / n;
    }

    const char *backend() const override { return backend_name(); }

    std::array<double, 3> solid_force(const int b) const override
    {
      return b >= 0 && b < static_cast<int>(forces.size()) ? forces[b] : std::array<double, 3>{{0, 0, 0}};
    }

    int n_solids() const override { return solids; }

    std::array<double, 3> solid_torque(const int b) const override
    {
      return b >= 0 && b < static_cast<int>(torques.size()) ? torques[b] : std::array<double, 3>{{0, 0, 0}};
    }

  private:
    /// Algorithm 2, step 1: volumes (Eq. 17), summation density, the BCE markers' fluid
    /// support (Eq. 60–65) and the free-surface particles.
    void compute_density_and_free_surface()
    {
      compute_volumes<dim>(x, nl, box, W, V);
      detail::DensityAndSupport<dim> f;
      f.p                    = particles();
      f.nb                   = neighbors(x);
      f.m0                   = m0;
      f.rho0                 = settings.rho0;
      f.ratio                = settings.free_surface_ratio;
      f.divergence_threshold = settings.free_surface_divergence;
      f.min_neighbours       = settings.free_surface_min_neighbours;
      f.min_fluid_neighbours = settings.free_surface_min_fluid_neighbours;
      f.free_surface         = settings.free_surface;
      f.rho                  = ptr(rho);
      f.support              = ptr(support);
      f.surface              = ptr(surface);
      for_each_particle(f);
      report.free_surface_particles = thrust::reduce(exec, surface.begin(), surface.end(), 0);
    }

    /// Algorithm 2, step 1: the corrections G, L (Eq. 24–26), the operators A^G, A^L and the
    /// matrix of the velocity system (Eq. 56, 62–63), shared by its components.
    void assemble_operators_and_velocity_matrix(const double dt)
    {
      // A BCE marker with no fluid in its support has known rows (ReducedSystem) and no row of
      // A^G, A^L is read: its corrections and operator rows are skipped (~40 % of a dam break's
      // particles at the start).
      operator_rows.resize(n);
      for_each_particle(detail::NeedsOperatorRow<dim>{particles(), ptr(operator_rows)});
      if (settings.consistent)
        report.correction_fallbacks = compute_corrections<dim>(x, V, nl, box, W, G, L, settings.correction_checks,
                                                               settings.free_surface ? &surface : nullptr, &operator_rows);
      else if (settings.free_surface)
      {
        // Standard operators: the rows a free surface truncates are consistent rows (one-sided,
        // the standard gradient there carries about half of ρg and the surface layers never rest;
        // doc/benchmarks.md "Standard operators at rest").
        corrected_rows.resize(n);
        for_each_particle(detail::TruncatedBySurface<dim>{particles(), neighbors(x), ptr(corrected_rows)});
        report.correction_fallbacks = compute_corrections<dim>(x, V, nl, box, W, G, L, settings.correction_checks,
                                                               &surface, &corrected_rows);
      }
      assemble_operators<dim>(x, V, nl, box, W, settings.consistent ? OperatorKind::consistent : OperatorKind::standard,
                              G, L, A, &operator_rows, standard_surface_rows(), standard_scale);
      if (settings.consistent && settings.conservative_gradient) // experimental (operators.h)
        make_gradient_conservative<dim>(x, V, nl, box, W, G, kind, settings.free_surface ? &surface : nullptr, A,
                                        conservative_work, settings.offsets_surface() ? 0.5 * settings.spacing : 0.0,
                                        grad_p, settings.conservative_regularisation,
                                        settings.free_surface_min_neighbours, 1e-8, 2000);
      values.resize(nl.n_entries());
      detail::VelocityMatrix<dim> m;
      m.p       = particles();
      m.nb      = neighbors(x);
      m.A       = operators();
      m.inv_dt  = 1.0 / dt;
      m.half_nu = 0.5 * (settings.mu / settings.rho0);
      m.values  = ptr(values);
      for_each_particle(m);
    }

    /// Algorithm 2, step 2: velocity prediction u*, Eq. 56, one solve per component with the
    /// same matrix. First the fluid velocity at t^n extrapolated to the markers (the approach
    /// velocity of ContinuityVelocity).
    void predict_velocity(const double dt)
    {
      u_approach.resize(n);
      detail::ExtrapolateToMarkers<dim> extrapolate;
      extrapolate.p   = particles();
      extrapolate.nb  = neighbors(x);
      extrapolate.out = ptr(u_approach);
      for_each_particle(extrapolate);
      detail::VelocityRhs<dim> r;
      r.p       = particles();
      r.lap_u   = ptr(tmp);
      r.inv_dt  = 1.0 / dt;
      r.half_nu = 0.5 * (settings.mu / settings.rho0);
      r.rhs     = ptr(rhs);
      reduced.build(nl.offsets, nl.indices, values); // without the markers' prescribed rows
      for (int c = 0; c < dim; ++c)
      {
        thrust::transform(exec, u.begin(), u.end(), comp.begin(), detail::ExtractComponent<dim>{c});
        spmv(nl.offsets, nl.indices, A.laplacian, comp, tmp);
        r.c = c;
        r.f = settings.acceleration[c];
        for_each_particle(r);
        report.velocity[c] = reduced.solve(rhs, comp, settings.velocity_solver);
        for_each_particle(detail::SetComponent<dim>{ptr(comp), ptr(u), c});
      }
    }

    /// ∇·u* (Eq. 41) of the continuity velocity (ContinuityVelocity; Neumann walls: u*).
    void compute_velocity_divergence(const double dt)
    {
      u_cont.resize(n);
      if (settings.pressure_wall == PressureWall::neumann)
        thrust::copy(exec, u.begin(), u.end(), u_cont.begin()); // Chorin: mirrored wall velocity, ∂p/∂n = 0
      else
      {
        detail::ContinuityVelocity<dim> cont;
        cont.p        = particles();
        cont.nb       = neighbors(x);
        cont.wetted_walls = settings.wetted_walls;
        cont.max_separation = settings.gravity_norm() * dt;
        cont.approach = ptr(u_approach);
        cont.out      = ptr(u_cont);
        for_each_particle(cont);
      }
      thrust::fill(exec, div_u.begin(), div_u.end(), 0.0);
      for (int c = 0; c < dim; ++c)
      {
        thrust::transform(exec, u_cont.begin(), u_cont.end(), comp.begin(), detail::ExtractComponent<dim>{c});
        spmv(nl.offsets, nl.indices, A.gradient[c], comp, tmp);
        thrust::transform(exec, div_u.begin(), div_u.end(), tmp.begin(), div_u.begin(), thrust::plus<double>());
      }
    }

    /// Algorithm 2, step 3: the pressure Poisson equation, Eq. 53/55/57 for fluid, p = 0 on
    /// the free surface, Eq. 64–65 or 66–67 for the BCE markers; confined flows made solvable.
    void solve_pressure(const double dt)
    {
      compute_velocity_divergence(dt);
      const bool                  neumann = settings.pressure_wall == PressureWall::neumann;
      detail::PressureMatrix<dim> m;
      m.p        = particles();
      m.nb       = neighbors(x);
      m.A        = operators();
      m.inv_rho0 = 1.0 / settings.rho0;
      m.neumann  = neumann;
      m.pinned   = pinned;
      m.values   = ptr(values);
      for_each_particle(m);
      regularise_confined_pressure_matrix(); // confined flows only
      detail::PressureRhs<dim> r;
      r.p     = particles();
      r.nb    = neighbors(x);
      r.div_u = ptr(div_u);
      r.dt    = dt;
      r.rho0  = settings.rho0;
      r.alpha = settings.alpha;
      for (int d = 0; d < dim; ++d)
        r.g[d] = settings.gravity[d];
      r.relaxation_time = std::max(dt, settings.density_relaxation_time);
      r.neumann         = neumann;
      r.rest_density_markers = settings.wetted_walls;
      r.pinned          = pinned;
      r.rhs             = ptr(rhs);
      if (settings.offsets_surface())
        r.surface_pressure = compute_surface_pressure();
      for_each_particle(r);
      make_confined_rhs_compatible(); // confined flows only
      // The free-surface rows and the dry markers' rows are known (p = p_s, p = 0): the solve runs
      // over the other rows only (ReducedSystem), and so does the multigrid.
      reduced.build(nl.offsets, nl.indices, values);
      const bool multigrid_on = settings.pressure_preconditioner == PressurePreconditioner::multigrid;
      if (multigrid_on && reduced.size() > 0)
      {
        x_reduced.resize(reduced.size());
        thrust::gather(exec, reduced.kept().begin(), reduced.kept().end(), x.begin(), x_reduced.begin());
        multigrid.setup(x_reduced, box, 2.0 * settings.h, reduced.offsets(), reduced.indices(), reduced.values());
      }
      auto solve_with = [&](dvec<double> &solution, const SolverSettings &solver) {
        return reduced.solve(rhs, solution, solver, multigrid_on ? &multigrid : nullptr);
      };
      auto solve = [&](dvec<double> &solution) { return solve_with(solution, settings.pressure_solver); };
      position_correction = settings.corrects_positions();
      if (!position_correction)
      {
        report.pressure = solve(pressure);
        remove_confined_pressure_level(); // confined flows only
        return;
      }
      // The α-blended pressure p_α (Eq. 55) moves the particles; their velocity is projected with
      // α = 0 (Eq. 52), so the density-error correction displaces particles without giving them
      // kinetic energy. p_α = p + q with A q = b_α − b_0 (the system is linear in α).
      rhs_alpha.resize(n);
      thrust::copy(exec, rhs.begin(), rhs.end(), rhs_alpha.begin());
      r.alpha = 0;
      for_each_particle(r);
      make_confined_rhs_compatible();
      report.pressure = solve(pressure);
      thrust::transform(exec, rhs_alpha.begin(), rhs_alpha.end(), rhs.begin(), rhs.begin(), thrust::minus<double>());
      // q only steers the density-error displacement, which the next step measures again: from
      // zero to a relative 1e-2 it takes ~7 iterations where p takes ~14 (doc/performance.md)
      density_q.resize(n);
      thrust::fill(exec, density_q.begin(), density_q.end(), 0.0);
      SolverSettings q_solver = settings.pressure_solver;
      q_solver.tolerance      = std::max(q_solver.tolerance, settings.density_correction_tolerance);
      const SolverResult q    = solve_with(density_q, q_solver);
      report.pressure.converged = report.pressure.converged && q.converged;
      report.pressure.iterations += q.iterations;
      remove_confined_pressure_level(); // confined flows only
    }

    /// p of the free-surface rows: half a spacing of liquid above them (SurfacePressure), from
    /// the last step's pressure differentiated at this step's positions (a restart has both).
    /// grad_p holds ∇p^n until correct_and_move() overwrites it with ∇p^{n+1}.
    const double *compute_surface_pressure()
    {
      for (int d = 0; d < dim; ++d)
        spmv(nl.offsets, nl.indices, A.gradient[d], pressure, grad_p[d]);
      surface_pressure.resize(n);
      detail::SurfacePressure<dim> sp;
      sp.p      = particles();
      sp.nb     = neighbors(x);
      sp.grad_p = components(grad_p);
      sp.d      = 0.5 * settings.spacing;
      sp.p_max  = settings.rho0 * settings.gravity_norm() * sp.d;
      sp.out    = ptr(surface_pressure);
      for_each_particle(sp);
      return ptr(surface_pressure);
    }

    /// Diagnostics: RMS of p_i minus its Shepard average over the interior fluid particles.
    double pressure_noise() const
    {
      const thrust::counting_iterator<int> first(0), last(n);
      const int interior = thrust::transform_reduce(exec, first, last, detail::InteriorFluid<dim>{particles()}, 0,
                                                    thrust::plus<int>());
      detail::PressureNoise<dim> noise;
      noise.p           = particles();
      noise.nb          = neighbors(x);
      const double sum2 = thrust::transform_reduce(exec, first, last, noise, 0.0, thrust::plus<double>());
      return interior > 0 ? std::sqrt(sum2 / interior) : 0.0;
    }

    /// Algorithm 2, step 4: ∇p^{n+1}, the forces on the solids, the correction u^{n+1} = u* −
    /// Δt/ρ0 ∇p (Eq. 58), the position update and particle shifting.
    void correct_and_move(const double dt)
    {
      for (int d = 0; d < dim; ++d)
        spmv(nl.offsets, nl.indices, A.gradient[d], pressure, grad_p[d]);
      if (settings.limit_pressure_peaks && (settings.consistent || settings.free_surface))
      {
        detail::PeakGradientLimiter<dim> lim;
        lim.p  = particles();
        lim.nb = neighbors(x);
        lim.rows = settings.consistent ? nullptr : ptr(corrected_rows); // standard: its consistent rows
        for (int d = 0; d < dim; ++d)
          lim.grad_p[d] = ptr(grad_p[d]);
        for_each_particle(lim);
      }
      if (!settings.consistent)
      {
        detail::PairwisePressureGradient<dim> pg;
        pg.p  = particles();
        pg.nb = neighbors(x);
        pg.A  = operators();
        pg.corrected = standard_surface_rows() ? ptr(corrected_rows) : nullptr;
        for (int d = 0; d < dim; ++d)
          pg.grad_p[d] = ptr(grad_p[d]);
        for_each_particle(pg);
      }
      compute_solid_forces(dt); // needs u*, p^{n+1}, ∇p and the step's positions: before the move
      if (settings.shifting > 0)
        thrust::copy(exec, x.begin(), x.end(), x_start.begin());
      if (position_correction)
      {
        // q = p_α − p: moves the particles, x^{n+1} = x^n + Δt u^{n+1} − Δt²/ρ0 ∇q, not their velocity
        for (int d = 0; d < dim; ++d)
          spmv(nl.offsets, nl.indices, A.gradient[d], density_q, grad_q[d]);
        if (!settings.consistent)
        {
          detail::PairwisePressureGradient<dim> pg;
          pg.p  = particles();
          pg.p.pressure = ptr(density_q);
          pg.nb = neighbors(x);
          pg.A  = operators();
          pg.corrected = standard_surface_rows() ? ptr(corrected_rows) : nullptr;
          for (int d = 0; d < dim; ++d)
            pg.grad_p[d] = ptr(grad_q[d]);
          for_each_particle(pg);
        }
      }
      report.budget.density_correction = position_correction ? displacement_energy(dt) : 0.0;
      detail::CorrectAndMove<dim> cm;
      cm.p         = particles();
      cm.grad_p    = components(grad_p);
      if (position_correction)
        cm.grad_q = components(grad_q);
      cm.box       = box;
      cm.dt        = dt;
      cm.inv_rho0  = 1.0 / settings.rho0;
      cm.margin    = 0.25 * settings.spacing;
      cm.open_face = settings.open_face;
      cm.x         = ptr(x);
      cm.u         = ptr(u);
      for_each_particle(cm);
      if (settings.shifting > 0)
      {
        pe_moved = fluid_energy(x, true);
        shift_particles(dt);
        if (settings.shifting_velocity_correction) // experimental (engine.h)
        {
          detail::ShiftVelocity<dim> sv;
          sv.p     = particles();
          sv.nb    = neighbors(x_start);
          sv.A     = operators();
          sv.moved = ptr(shift_moved);
          u_cont.resize(n); // scratch: free until the next step's ContinuityVelocity
          sv.out = ptr(u_cont);
          for_each_particle(sv);
          thrust::copy(exec, u_cont.begin(), u_cont.end(), u.begin());
        }
      }
    }

    /// Pushes fluid pairs closer than settings.min_pair_distance Δx apart (PairSeparation), after
    /// the neighbour search and this step's free-surface flags (from the step's own positions: a
    /// checkpoint restarts bit-exactly); if it moved any particle, the volumes, densities and
    /// flags are computed again for the moved positions (the moves, ≤ ¼ Δx for the default ½ Δx,
    /// stay within the list's reach). Returns the change of potential energy, booked with the
    /// shifting's.
    double separate_close_pairs()
    {
      if (!(settings.min_pair_distance > 0) || n == 0)
        return 0.0;
      x_start.resize(n);
      thrust::copy(exec, x.begin(), x.end(), x_start.begin());
      detail::PairSeparation<dim> sep;
      sep.p            = particles();
      sep.nb           = neighbors(x_start);
      sep.min_distance = settings.min_pair_distance * settings.spacing;
      sep.x            = ptr(x);
      for_each_particle(sep);
      const bool moved = !thrust::equal(exec, x.begin(), x.end(), x_start.begin(), detail::SamePosition<dim>());
      if (!moved)
        return 0.0;
      compute_density_and_free_surface();
      return fluid_energy(x, true) - fluid_energy(x_start, true);
    }

    /// Fickian particle shifting (ShiftingDisplacement) from the step's start positions.
    void shift_particles(const double dt)
    {
      detail::ShiftingDisplacement<dim> shift;
      shift.p           = particles();
      shift.nb          = neighbors(x_start);
      shift.coefficient = settings.shifting;
      shift.dt          = dt;
      shift.max_shift   = 0.1 * settings.spacing;
      shift.u_min       = settings.shifting_velocity_floor;
      shift.x           = ptr(x);
      if (settings.shifting_velocity_correction)
      {
        shift_moved.resize(n);
        shift.moved = ptr(shift_moved);
      }
      for_each_particle(shift);
    }

    /// Runs the per-particle functor f(i) for i = 0 … n − 1 on the backend.
    template <typename F>
    void for_each_particle(const F &f) const
    {
      thrust::for_each(exec, thrust::counting_iterator<int>(0), thrust::counting_iterator<int>(n), f);
    }

    /// The particle state as the kernels read it.
    ParticleView<dim> particles() const
    {
      ParticleView<dim> p;
      p.x                 = ptr(x);
      p.u                 = ptr(u);
      p.kind              = ptr(kind);
      p.surface           = ptr(surface);
      p.body              = body.empty() ? nullptr : ptr(body);
      p.V                 = ptr(V);
      p.rho               = ptr(rho);
      p.support           = ptr(support);
      p.pressure          = ptr(pressure);
      p.wall_velocity     = ptr(wall_velocity);
      p.wall_acceleration = ptr(wall_acceleration);
      p.normal            = ptr(normal);
      return p;
    }

    /// The step's neighbour list with the positions it was built for.
    NeighborView<dim> neighbors(const dvec<Vec<dim>> &positions) const
    {
      return neighbor_view(positions, nl, box, W);
    }

    OperatorView<dim> operators() const
    {
      OperatorView<dim> view;
      view.gradient  = components(A.gradient);
      view.laplacian = ptr(A.laplacian);
      return view;
    }

    static Components<dim> components(const dvec<double> (&f)[dim])
    {
      Components<dim> c;
      for (int d = 0; d < dim; ++d)
        c.c[d] = ptr(f[d]);
      return c;
    }

    /// A confined flow (no free surface) has a pure-Neumann pressure problem, solvable only
    /// if Σ_F V_i rhs_i = 0; the one-sided density term of Eq. 55 and the non-symmetric
    /// operators break that, and pinning one particle then turns the defect into a point
    /// source there (pressure spike, divergence). Removing the volume-weighted mean of the
    /// fluid rows restores compatibility; pressure is defined up to a constant anyway.
    void make_confined_rhs_compatible()
    {
      if (settings.free_surface)
        return;
      for_each_particle(detail::ShiftConfinedFluidRows<dim>{particles(), pinned, fluid_mean(rhs), ptr(rhs)});
    }

    /// Σ_F V_i f_i / Σ_F V_i over the fluid particles (not the pin); 0 without fluid.
    double fluid_mean(const dvec<double> &f) const
    {
      const thrust::counting_iterator<int> first(0), last(n);
      const double volume = thrust::transform_reduce(
        exec, first, last, detail::ConfinedFluidRowWeight<dim>{particles(), nullptr, pinned}, 0.0, thrust::plus<double>());
      const double integral = thrust::transform_reduce(
        exec, first, last, detail::ConfinedFluidRowWeight<dim>{particles(), ptr(f), pinned}, 0.0, thrust::plus<double>());
      return volume > 0 ? integral / volume : 0.0;
    }

    /// Confined flows: the pressure is defined up to a constant (a uniform shift of every
    /// particle's pressure, markers included, leaves every fluid and BCE row unchanged up to the
    /// −ε regularisation below). Its volume-weighted fluid mean is removed after each solve, so
    /// that the level the regularised system drifts to (the incompatibility over ε) does not
    /// accumulate in the warm start: the periodic cylinder's pressure solve needed 25 → 43
    /// iterations within 0.01 s and then diverged (residual 1e145) at t = 1.4 s without it.
    void remove_confined_pressure_level()
    {
      if (settings.free_surface)
        return;
      for_each_particle(detail::ShiftAll{fluid_mean(pressure), ptr(pressure)});
    }

    /// Confined flows: the fluid rows' diagonal gets −ε, ε = 1e-6 / (ρ0 h²) — about 1e-5 of
    /// the smallest physical eigenvalue of (1/ρ0) A^L in a unit domain — which makes the
    /// singular pure-Neumann system regular without a pinned particle; what is left of the
    /// incompatibility goes into a uniform pressure level that no gradient sees.
    void regularise_confined_pressure_matrix()
    {
      if (settings.free_surface)
        return;
      detail::ShiftFluidDiagonal<dim> shift;
      shift.p       = particles();
      shift.nb      = neighbors(x);
      shift.epsilon = 1e-6 / (settings.rho0 * settings.h * settings.h);
      shift.values  = ptr(values);
      for_each_particle(shift);
    }

    void setup_solids(const HostParticles<dim> &p)
    {
      solids = 0;
      for (std::size_t i = 0; i < p.kind.size(); ++i)
        if (p.kind[i] == ParticleKind::solid)
          solids = std::max(solids, p.body.empty() ? 1 : p.body[i] + 1);
      body.assign(p.body.begin(), p.body.end());
      forces.assign(solids, std::array<double, 3>{{0, 0, 0}});
      torques.assign(solids, std::array<double, 3>{{0, 0, 0}});
      torque_centres.resize(solids, std::array<double, 3>{{0, 0, 0}}); // kept across set_particles
    }

    /// Fluid force on each solid (doc/equations.md "Forces on solids"): one reduction for the
    /// reference pressure p̄_s of its wetted markers, one for the pair sum (SolidForce).
    void compute_solid_forces(const double dt)
    {
      const thrust::counting_iterator<int> first(0), last(n);
      const ParticleView<dim>              state = particles();
      for (int b = 0; b < solids; ++b)
      {
        const int wetted = thrust::transform_reduce(exec, first, last, detail::IsSolidMarkerWithFluid<dim>{state, b}, 0,
                                                    thrust::plus<int>());
        const double p_sum = thrust::transform_reduce(exec, first, last, detail::SolidMarkerPressure<dim>{state, b},
                                                      0.0, thrust::plus<double>());
        // p̄_s removes the discrete error of the pressure level over a closed wetted surface (its
        // exact integral is zero there): for confined flows (arbitrary level) and bodies fully
        // under water. A body that pierces the free surface (a marker sees a p = 0 particle) has an
        // open wetted surface on which the absolute level acts: no reference then.
        const int pierces = thrust::transform_reduce(
          exec, first, last, detail::MarkerMeetsFreeSurface<dim>{state, neighbors(x), b}, 0, thrust::plus<int>());
        detail::SolidForce<dim> sf;
        sf.p        = state;
        sf.nb       = neighbors(x);
        sf.grad_p   = components(grad_p);
        sf.mu       = settings.mu;
        sf.dt       = dt;
        sf.inv_rho0 = 1.0 / settings.rho0;
        sf.p_ref    = pierces > 0 || wetted == 0 ? 0.0 : p_sum / wetted;
        sf.target   = b;
        const Vec<dim> F = thrust::transform_reduce(exec, first, last, sf, Vec<dim>::zero(), detail::VecPlus<dim>());
        forces[b] = {{0, 0, 0}};
        for (int d = 0; d < dim; ++d)
          forces[b][d] = F[d];
        detail::SolidTorque<dim> st{sf, {torque_centres[b][0], torque_centres[b][1], torque_centres[b][2]}};
        const Vec<3> T = thrust::transform_reduce(exec, first, last, st, Vec<3>::zero(), detail::VecPlus<3>());
        torques[b] = {{T[0], T[1], T[2]}};
      }
    }

    DomainBox<dim>     box;
    EngineSettings     settings;
    CubicSpline<dim>   W;
    NeighborSearch<dim> search;
    NeighborList       nl;
    OperatorMatrices<dim> A;
    CellMultigrid<dim> multigrid;
    ReducedSystem      reduced;   ///< the velocity's, then the pressure's system without its known rows
    dvec<Vec<dim>>     x_reduced; ///< positions of the pressure system's kept rows (the multigrid's cells)
    dvec<Tensor2<dim>> G, L;
    dvec<Vec<dim>>     shift_moved; ///< the shift of each particle (shifting_velocity_correction)
    dvec<Vec<dim>>     x, x_start, u, u_old, u_cont, u_approach, wall_velocity, wall_acceleration, normal;
    dvec<double>       pressure, surface_pressure, rhs_alpha, density_q, grad_q[dim], rho, support, V, rhs, tmp, comp, div_u, values, grad_p[dim];
    dvec<int>          kind, surface, body;
    dvec<int>          operator_rows; ///< NeedsOperatorRow of each particle, this step
    ConservativeGradientWork<dim> conservative_work;
    dvec<int>          corrected_rows; ///< standard operators: TruncatedBySurface, this step
    double             standard_scale = 1.0; ///< standard operators: lattice_scale of the setup lattice

    /// The standard operators' consistent rows at a free surface (null: consistent operators, or
    /// no free surface).
    const dvec<int> *standard_surface_rows() const
    {
      return !settings.consistent && settings.free_surface ? &corrected_rows : nullptr;
    }
    std::vector<std::array<double, 3>> forces, torques; ///< per solid, from the last step
    std::vector<std::array<double, 3>> torque_centres;  ///< per solid: `to` of its last MarkerMotion
    dvec<MarkerMotion>                 device_motions;  ///< move_solids' motions on the device
    int                solids = 0;
    static constexpr bool pin_confined_pressure = false;
    double             m0 = 0, pe_moved = 0; ///< pe_moved: potential energy before the shift
    int                n = 0, pinned = -1;
    bool               position_correction = false;
    StepReport         report;
  };

  template <int dim>
  std::unique_ptr<Engine<dim>> create_engine(const DomainBox<dim> &box, const EngineSettings &settings)
  {
    try
    {
      dvec<int> probe(1); // fails here if the backend's device is unusable (e.g. no GPU)
    }
    catch (const std::exception &e)
    {
      throw std::runtime_error(std::string("SPH backend '") + backend_name() +
                               "' cannot allocate device memory (no usable device?): " + e.what());
    }
    return std::make_unique<BackendEngine<dim>>(box, settings);
  }

  template std::unique_ptr<Engine<2>> create_engine<2>(const DomainBox<2> &, const EngineSettings &);
  template std::unique_ptr<Engine<3>> create_engine<3>(const DomainBox<3> &, const EngineSettings &);
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
