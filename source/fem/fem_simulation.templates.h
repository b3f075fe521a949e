// FemSimulation<dim>: composition, mesh, adaptation and the time loop.
#pragma once
#include <optional>
#include <twinflow/core/errors.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/fem/material_model.h>
#include <twinflow/fem/linear_solve.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/progress.h>
#include <twinflow/io/pvd_series.h>
#include <twinflow/io/snapshots.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/error_estimator.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

namespace twinflow::fem
{
  using namespace dealii;

  namespace internal
  {
    /// Inflow through a face normal to @p axis: parabolic (product of 4 s(1−s) over the
    /// other directions, maximum U) or uniform U; directed into the domain.
    template <int dim>
    class InflowVelocity : public Function<dim>
    {
    public:
      InflowVelocity(const Scene &s, unsigned int axis, double sign)
        : Function<dim>(dim), scene(s), axis(axis), sign(sign)
      {}
      double value(const Point<dim> &p, const unsigned int c) const override
      {
        if (c != axis)
          return 0;
        double v = scene.inflow_velocity * sign;
        if (scene.inflow_profile == "parabolic")
          for (unsigned int d = 0; d < dim; ++d)
            if (d != axis)
            {
              const double lo = scene.domain.lower[d], hi = scene.domain.upper[d];
              v *= 4 * (p[d] - lo) * (hi - p[d]) / ((hi - lo) * (hi - lo));
            }
        return v;
      }

    private:
      const Scene &scene;
      unsigned int axis;
      double       sign;
    };

    /// Hydrostatic pressure ρ g·x of the (single) fluid: the initial pressure.
    template <int dim>
    class HydrostaticPressure : public Function<dim>
    {
    public:
      HydrostaticPressure(double rho, const std::array<double, 3> &g) : rho(rho), g(g) {}
      double value(const Point<dim> &p, unsigned int) const override
      {
        double v = 0;
        for (unsigned int d = 0; d < dim; ++d)
          v += rho * g[d] * p[d];
        return v;
      }

    private:
      double                rho;
      std::array<double, 3> g;
    };

    std::string join(const std::vector<std::string> &v, const std::string &sep);

    /// "box with cylinder": the scene's box around a body-fitted hole (Solid 1) from
    /// GridGenerator::plate_with_a_hole — a square of half-width a = min(2R, (R + d)/2)
    /// (d: distance from the centre to the nearest face) with transfinite cells around the
    /// polar-manifold hole, padded up to the box faces. Opposite faces get the same vertex
    /// layout, so periodic faces match. Colorized ids: x 0/1, y 2/3, hole 4 (returned).
    template <int dim>
    types::boundary_id make_box_with_cylinder(Triangulation<dim> &tria, const Scene &scene,
                                              std::array<types::boundary_id, 6> &face_id)
    {
      Assert(dim == 2, ExcNotImplemented()); // the scene parser allows 2D only
      const Solid &c = scene.solids.front();
      Point<dim>   center;
      double       d = 1e300;
      for (unsigned int k = 0; k < 2; ++k)
      {
        center[k] = c.center[k];
        d = std::min({d, c.center[k] - scene.domain.lower[k], scene.domain.upper[k] - c.center[k]});
      }
      const double a = std::min(2.0 * c.radius, 0.5 * (c.radius + d));
      GridGenerator::plate_with_a_hole(tria, c.radius, a, c.center[1] - a - scene.domain.lower[1],
                                       scene.domain.upper[1] - c.center[1] - a, c.center[0] - a - scene.domain.lower[0],
                                       scene.domain.upper[0] - c.center[0] - a, center, 0, 1, 1.0, 2, true);
      face_id = {{0, 1, 2, 3, 5, 6}};
      return 4;
    }

    /// Coarse cells of the box: as square as the extents allow (the IBM's ε and the
    /// adaptation bands are measured in cells). The cell size is the shortest extent / n
    /// for the smallest n ≤ 8 that divides every extent; otherwise the shortest extent.
    template <int dim>
    std::vector<unsigned int> box_subdivisions(const Scene &scene)
    {
      double shortest = 1e300;
      for (unsigned int d = 0; d < dim; ++d)
        shortest = std::min(shortest, scene.domain.upper[d] - scene.domain.lower[d]);
      for (unsigned int n = 1; n <= 8; ++n)
      {
        const double              h = shortest / n;
        std::vector<unsigned int> reps(dim);
        bool                      fits = true;
        for (unsigned int d = 0; d < dim; ++d)
        {
          const double m = (scene.domain.upper[d] - scene.domain.lower[d]) / h;
          reps[d]        = std::max(1u, static_cast<unsigned int>(std::lround(m)));
          fits           = fits && std::abs(m - reps[d]) < 1e-6 * m;
        }
        if (fits)
          return reps;
      }
      std::vector<unsigned int> reps(dim);
      for (unsigned int d = 0; d < dim; ++d)
        reps[d] = std::max(1u, static_cast<unsigned int>(std::lround((scene.domain.upper[d] - scene.domain.lower[d]) / shortest)));
      return reps;
    }
  } // namespace internal

  template <int dim>
  FemSimulation<dim>::FemSimulation(const Scene &s, const FemParameters &p, const std::string &d, MPI_Comm c)
    : scene(s)
    , prm(p)
    , dir(d)
    , comm(c)
    , tria(comm)
    , body_id(numbers::invalid_boundary_id)
  {
    compose();
  }

  template <int dim>
  FemSimulation<dim>::~FemSimulation() = default;

  template <int dim>
  void FemSimulation<dim>::compose()
  {
    body_fitted = scene.geometry == "channel with cylinder" || scene.geometry == "box with cylinder";
    for (const auto &s : scene.solids)
      if (s.motion == SolidMotion::elastic)
        throw InputError("Solids/" + s.name + "/Motion = elastic: elastic solids (ANCF) are not available in the "
                         "FEM yet; allowed now: fixed, rigid");
    if (scene.has_moving_solids() && (scene.geometry != "box"))
      throw InputError("Domain/Geometry = " + scene.geometry + ": a rigid (moving) solid needs the immersed boundary "
                       "of the 'box' geometry; the body-fitted geometries hold a fixed cylinder");
    const bool free_surface = scene.has_free_surface();
    if (free_surface)
      compose_free_surface(); // the level-set space and the two-phase material
    else
      material = std::make_unique<ConstantMaterial<dim>>(scene.fluids.front().density, scene.fluids.front().viscosity);
    NavierStokesParameters nsp = prm.navier_stokes;
    if (nsp.mapping_degree == 0)
      nsp.mapping_degree = body_fitted ? nsp.velocity_degree : 1;
    navier_stokes = std::make_unique<NavierStokes<dim>>(tria, nsp, *material);
    if (free_surface)
    {
      // Algorithm 1 in the order of the list: Navier–Stokes, NCLS, VOF, redistancing, mass
      // correction; the space first (it distributes the level-set DoFs).
      std::set<types::boundary_id> open;
      for (unsigned int f = 0; f < 2 * dim; ++f)
        if (scene.boundary[f] == BoundaryKind::outflow)
          open.insert(face_id[f]);
      ncls       = std::make_unique<NclsTransport<dim>>(*ls_space, *navier_stokes);
      vof        = std::make_unique<VofTransport<dim>>(*ls_space, *navier_stokes, open);
      redistance = std::make_unique<Redistancing<dim>>(*ls_space, *ncls);
      correction = std::make_unique<MassCorrection<dim>>(*ls_space, *ncls, *vof);
      static_cast<TwoPhaseMaterial<dim> &>(*material).attach(*ncls);
      ls_space->attach(*ncls);
      physics = {ls_space.get(), navier_stokes.get(), ncls.get(), vof.get(), redistance.get(), correction.get()};
    }
    else
      physics.push_back(navier_stokes.get());

    std::vector<std::string> &active = result.active_physics;
    std::vector<std::string>  idle{"ANCF"};
    if (free_surface)
    {
      active.push_back("navier-stokes (two phases, variable density)");
      active.push_back("level set (Q" + std::to_string(prm.level_set.degree) + ": NCLS, VOF, " +
                       (prm.level_set.redistance ? (prm.level_set.far_field_only ? "far-field redistancing, " : "redistancing, ") : "") +
                       (prm.level_set.mass_correction ? "mass correction" : "no mass correction") + ")");
    }
    else
    {
      active.push_back("navier-stokes (single phase, constant density)");
      idle.insert(idle.begin(), "level set");
    }
    if (body_fitted)
      active.push_back("body-fitted fixed cylinder");
    if (scene.has_solids() && !body_fitted)
    {
      ibm = std::make_unique<ImmersedBoundary<dim>>(scene, prm.immersed_boundary);
      navier_stokes->add_momentum_term(*ibm);
      const auto moving = std::count_if(scene.solids.begin(), scene.solids.end(),
                                        [](const Solid &b) { return b.motion == SolidMotion::rigid; });
      active.push_back("immersed boundary (Nitsche + penalty, " + std::to_string(scene.solids.size() - moving) +
                       " fixed and " + std::to_string(moving) + " moving solid(s))");
    }
    else
      idle.insert(idle.begin(), "immersed boundary");
    if (scene.has_moving_solids())
    {
      coupling = std::make_unique<solids::CoSimulation>(scene);
      body_loads.assign(coupling->n_bodies(), solids::BodyLoad());
      for (const std::string &line : coupling->describe())
        active.push_back(line + ", the IBM's phi_s and u_s follow it" +
                         (prm.coupling_iterations > 1
                            ? "; implicit coupling: up to " + std::to_string(prm.coupling_iterations) +
                                " Navier-Stokes solves per step with Aitken-relaxed loads"
                            : std::string("; explicit (FEM/Coupling iterations = 1): light bodies need more")));
    }
    else
      idle.insert(idle.begin(), "rigid body");
    if (free_surface && coupling && prm.level_set.dry_moving_solids)
    {
      // after the transports (Algorithm 1: NCLS, VOF, then drying, redistancing, mass correction)
      std::vector<unsigned int> moving;
      for (unsigned int k = 0; k < scene.solids.size(); ++k)
        if (scene.solids[k].motion == SolidMotion::rigid)
          moving.push_back(k);
      drying = std::make_unique<SolidInteriorDrying<dim>>(*ls_space, *ncls, [this, moving](const Point<dim> &x) {
        double d = std::numeric_limits<double>::max();
        for (const unsigned int k : moving)
          d = std::min(d, ibm->solids()[k]->distance(x));
        return d;
      });
      physics.insert(std::find(physics.begin(), physics.end(), vof.get()) + 1, drying.get());
      active.push_back("solid interior drying (phi = max(phi, -phi_s) inside the moving solids)");
    }
    else if (free_surface)
      idle.insert(idle.begin(), "solid interior drying");
    const bool interfaces = ibm != nullptr || free_surface;
    if (ibm && prm.adaptation.enabled() && prm.immersed_boundary.interface_width > prm.adaptation.band_width)
      throw InputError("FEM/Mesh adaptation/Band width = " + std::to_string(prm.adaptation.band_width) +
                       ": the band must cover the smoothed solid interface (FEM/Immersed boundary/Interface width = " +
                       std::to_string(prm.immersed_boundary.interface_width) + " cells)");
    if (!prm.restart_file.empty() && !(std::ifstream(prm.restart_file + ".meta") && std::ifstream(prm.restart_file + ".mesh")))
      throw InputError("FEM/Restart file = '" + prm.restart_file + "': cannot open " + prm.restart_file + ".meta and " +
                       prm.restart_file + ".mesh (write them with FEM/Checkpoint interval > 0; give the prefix "
                       "without extension)");
    if (prm.adaptation.enabled() && (interfaces || prm.adaptation.kelly_threshold > 0))
      active.push_back(std::string("mesh adaptation (levels ") + std::to_string(prm.adaptation.minimum_level) + "-" +
                       std::to_string(prm.adaptation.maximum_level) + (ibm ? ", band at phi_s = 0" : "") + (free_surface ? ", band at phi = 0" : "") +
                       (prm.adaptation.kelly_threshold > 0 ? ", Kelly" : "") + ")");
    else
      idle.insert(idle.begin(), "mesh adaptation");
    for (unsigned int d = 0; d < dim; ++d)
      if (scene.periodic[d])
        active.push_back(std::string("periodic ") + "xyz"[d]);
    ConditionalOStream pcout(std::cout, io::is_root_process(comm));
    pcout << "FEM active physics: " << internal::join(active, "; ") << "  (not built: " << internal::join(idle, ", ")
          << ")" << std::endl;
  }

  template <int dim>
  void FemSimulation<dim>::make_coarse_mesh()
  {
    if (scene.geometry == "channel with cylinder")
    {
      GridGenerator::channel_with_cylinder(tria, 0.03, 2, 2.0, true);
      face_id = {{0, 1, 3, 3, 3, 3}};
      body_id = 2;
    }
    else if (scene.geometry == "box with cylinder")
      body_id = internal::make_box_with_cylinder(tria, scene, face_id);
    else
    {
      Point<dim> p1, p2;
      for (unsigned int d = 0; d < dim; ++d)
      {
        p1[d] = scene.domain.lower[d];
        p2[d] = scene.domain.upper[d];
      }
      GridGenerator::subdivided_hyper_rectangle(tria, internal::box_subdivisions<dim>(scene), p1, p2, true);
    }
    std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>> faces;
    for (unsigned int d = 0; d < dim; ++d)
      if (scene.periodic[d])
        GridTools::collect_periodic_faces(tria, face_id[2 * d], face_id[2 * d + 1], d, faces);
    if (!faces.empty())
      tria.add_periodicity(faces);
  }

  template <int dim>
  void FemSimulation<dim>::set_boundary_conditions()
  {
    NavierStokes<dim> &ns = *navier_stokes;
    bool periodic_set[3] = {false, false, false};
    for (unsigned int f = 0; f < 2 * dim; ++f)
    {
      const unsigned int axis = f / 2;
      switch (scene.boundary[f])
      {
        case BoundaryKind::no_slip:
          ns.set_dirichlet(face_id[f], std::make_shared<Functions::ZeroFunction<dim>>(dim));
          break;
        case BoundaryKind::slip:
          ns.set_slip(face_id[f], axis);
          break;
        case BoundaryKind::inflow:
          inflow = std::make_shared<internal::InflowVelocity<dim>>(scene, axis, f % 2 == 0 ? 1.0 : -1.0);
          ns.set_dirichlet(face_id[f], inflow);
          break;
        case BoundaryKind::outflow:
          ns.set_outflow(face_id[f]);
          break;
        case BoundaryKind::periodic:
          if (!periodic_set[axis])
          {
            ns.set_periodic(face_id[2 * axis], face_id[2 * axis + 1], axis);
            if (ls_space)
              ls_space->set_periodic(face_id[2 * axis], face_id[2 * axis + 1], axis);
          }
          periodic_set[axis] = true;
          break;
      }
    }
    if (body_fitted)
      ns.set_dirichlet(body_id, std::make_shared<Functions::ZeroFunction<dim>>(dim));
    std::vector<double> accel(dim);
    bool                any_accel = false;
    for (unsigned int d = 0; d < dim; ++d)
    {
      accel[d]  = scene.gravity[d] + scene.body_force[d];
      any_accel = any_accel || accel[d] != 0;
    }
    if (any_accel)
      ns.set_acceleration(std::make_shared<Functions::ConstantFunction<dim>>(accel));
  }

  template <int dim>
  void FemSimulation<dim>::refine_initial_mesh()
  {
    tria.refine_global(prm.global_refinements);
    if (!adaptation)
      return;
    // No field exists yet: refine towards the interfaces until the marking settles.
    for (unsigned int k = 0; k <= prm.adaptation.maximum_level + 1; ++k)
    {
      if (!adaptation->mark(nullptr))
        break;
      tria.execute_coarsening_and_refinement();
    }
    adaptation->mark_adapted();
  }

  template <int dim>
  void FemSimulation<dim>::setup()
  {
    make_coarse_mesh();
    set_boundary_conditions();
    if (prm.adaptation.enabled() && (ibm || ls_space || prm.adaptation.kelly_threshold > 0))
    {
      adaptation = std::make_unique<MeshAdaptation<dim>>(tria, prm.adaptation);
      if (ibm)
        for (auto &s : ibm->solids())
          adaptation->register_interface(*s);
      if (ls_space)
        adaptation->register_interface(*ls_space);
    }
    if (!prm.restart_file.empty())
    {
      load_checkpoint(prm.restart_file);
      return;
    }
    refine_initial_mesh();
    for (auto *p : physics)
      p->setup_dofs();
    // Initial state: the undisturbed inflow (if any) everywhere, hydrostatic pressure.
    Functions::ZeroFunction<dim>                   zero(dim);
    std::unique_ptr<Function<dim>>                 p0;
    if (ls_space)
    {
      // ε of the finest cells (those at the interface).
      const double h = navier_stokes->minimal_cell_diameter() / std::sqrt(double(dim));
      p0 = std::make_unique<internal::TwoPhaseHydrostatic<dim>>(scene, two_fluids, vertical_axis, initial_water_distance,
                                                                prm.level_set.interface_width * h);
      initialize_free_surface();
    }
    else
      p0 = std::make_unique<internal::HydrostaticPressure<dim>>(scene.fluids.front().density, scene.gravity);
    navier_stokes->initialize(inflow ? *inflow : static_cast<const Function<dim> &>(zero), *p0, 0.0);
  }

  template <int dim>
  void FemSimulation<dim>::adapt_mesh()
  {
    if (!adaptation)
      return;
    std::unique_ptr<Vector<float>> indicator;
    if (prm.adaptation.kelly_threshold > 0)
    {
      indicator = std::make_unique<Vector<float>>(tria.n_active_cells());
      const auto &dofs = navier_stokes->velocity_dof_handler();
      KellyErrorEstimator<dim>::estimate(navier_stokes->get_mapping(), dofs, QGauss<dim - 1>(dofs.get_fe().degree + 1),
                                         {}, navier_stokes->velocity(), *indicator);
    }
    if (!adaptation->mark(indicator.get()))
    {
      adaptation->mark_adapted();
      return;
    }
    for (auto *p : physics)
      p->prepare_transfer(false);
    tria.execute_coarsening_and_refinement();
    for (auto *p : physics)
    {
      p->setup_dofs();
      p->finish_transfer(false);
    }
    adaptation->mark_adapted();
    ++result.adaptations;
    h_min = navier_stokes->minimal_cell_diameter();
  }

  template <int dim>
  double FemSimulation<dim>::next_time_step() const
  {
    double dt = prm.time_step;
    if (prm.cfl > 0)
      dt = std::min(dt, prm.cfl * h_min / std::max({navier_stokes->max_velocity(), coupling ? coupling->max_surface_speed() : 0.0, 1e-12}));
    return std::min(dt, scene.end_time - navier_stokes->time());
  }

  template <int dim>
  void FemSimulation<dim>::advance_flow_and_bodies(const double dt)
  {
    if (!coupling)
    {
      navier_stokes->advance(dt);
      return;
    }
    ++coupling_steps;
    // Explicit coupling is the first pass of the iteration; only sub-iterations need the
    // state at the start of the step to return to.
    const bool iterate = prm.coupling_iterations > 1;
    std::optional<solids::CoSimulation>                  bodies_at_start;
    std::optional<typename NavierStokes<dim>::StepState> flow_at_start;
    std::vector<double>                                  extents;
    for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
      extents.push_back(coupling->body_extent(b));
    if (iterate)
    {
      bodies_at_start = *coupling;
      flow_at_start   = navier_stokes->save_step();
    }
    const double g = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                               scene.gravity[2] * scene.gravity[2]);
    solids::LoadRelaxation relaxation(prm.coupling_iterations, prm.coupling_tolerance);
    relaxation.start(body_loads, extents, coupling->weight_scale(g));
    for (;;)
    {
      advance_bodies(dt, relaxation.guess());
      navier_stokes->advance(dt);
      ++coupling_solves;
      record_body_loads();
      if (relaxation.update(body_loads))
        break;
      *coupling = *bodies_at_start;
      navier_stokes->restore_step(*flow_at_start);
    }
    if (iterate && !relaxation.converged())
      ++coupling_unconverged;
    if (body_monitor)
      body_monitor->append(navier_stokes->time(), body_loads);
  }

  template <int dim>
  void FemSimulation<dim>::advance_bodies(const double dt, const std::vector<solids::BodyLoad> &loads)
  {
    coupling->advance(dt, loads);
    coupling->check_clear_of_walls(scene);
    sync_solid_motion();
  }

  template <int dim>
  void FemSimulation<dim>::sync_solid_motion()
  {
    for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
    {
      const solids::BodyKinematics k = coupling->kinematics(b);
      Point<dim>                   c;
      Tensor<2, dim>               R;
      Tensor<1, dim>               v;
      Tensor<1, 3>                 w;
      for (unsigned int i = 0; i < dim; ++i)
      {
        c[i] = k.position[i];
        v[i] = k.velocity[i];
        for (unsigned int j = 0; j < dim; ++j)
          R[i][j] = k.rotation(i, j);
      }
      for (unsigned int i = 0; i < 3; ++i)
        w[i] = k.angular_velocity[i];
      ibm->solids()[coupling->solid_index(b)]->set_motion(c, R, v, w);
    }
  }

  template <int dim>
  void FemSimulation<dim>::record_body_loads()
  {
    if (!coupling)
      return;
    const auto loads = ibm->loads(*navier_stokes); // torque about each solid's current centre
    for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
    {
      const SolidLoad<dim> &l = loads[coupling->solid_index(b)];
      body_loads[b]           = solids::BodyLoad();
      for (unsigned int d = 0; d < dim; ++d)
        body_loads[b].force[d] = l.force[d];
      for (unsigned int d = 0; d < 3; ++d)
        body_loads[b].torque[d] = l.torque[d];
      if (!body_loads[b].force.allFinite() || !body_loads[b].torque.allFinite())
        throw std::runtime_error("FEM solution diverged at t = " + std::to_string(navier_stokes->time()) +
                                 ": the fluid load on body '" + coupling->name(b) + "' is not finite; reduce FEM/Time "
                                 "step or FEM/CFL number. Monitors written so far are kept in " + dir);
    }
  }

  template <int dim>
  double FemSimulation<dim>::bodies_energy() const
  {
    double e = 0;
    if (coupling)
      for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
        e += coupling->body(b).kinetic_energy() + coupling->body(b).potential_energy();
    return e;
  }

  template <int dim>
  FemRunResult FemSimulation<dim>::run()
  {
    Timer wall;
    linear_solve_counts().clear(); // this run's Krylov iterations, for the summary
    setup();
    h_min = navier_stokes->minimal_cell_diameter(); // for the CFL step; updated on adaptation
    NavierStokes<dim> &ns = *navier_stokes;
    ConditionalOStream pcout(std::cout, io::is_root_process(comm));
    pcout << "FEM mesh: " << tria.n_global_active_cells() << " cells (levels " << tria.n_global_levels() - 1
          << " max), " << ns.n_velocity_dofs() << " velocity + " << ns.n_pressure_dofs() << " pressure DoFs, Q"
          << prm.navier_stokes.velocity_degree << "/Q" << prm.navier_stokes.velocity_degree - 1 << ", "
          << Utilities::MPI::n_mpi_processes(comm) << " MPI rank(s)" << std::endl;
    open_monitors();
    const double t0 = ns.time();
    io::ProgressReporter progress(t0, scene.end_time, std::cout, comm, 2.0);
    bool steady = false;
    if (scene.output_interval > 0 && ns.n_steps() == 0)
    {
      TimerOutput::Scope scope(run_timer, "output");
      write_output();
    }
    if (ls_space && ns.n_steps() == 0)
      record_free_surface(0, 0);
    if (ls_space && !scene.snapshot_times.empty())
    {
      snapshots = std::make_unique<io::SnapshotSchedule>(scene.snapshot_times, t0, !prm.restart_file.empty());
      for (const double s : snapshots->due(t0))
        write_snapshot(s);
    }
    if (prm.checkpoint_interval > 0)
      next_checkpoint = (std::floor(t0 / prm.checkpoint_interval + 1e-9) + 1) * prm.checkpoint_interval;
    while (ns.time() < scene.end_time * (1 - 1e-12) && !steady)
    {
      const double dt = next_time_step();
      if (dt < 1e-6 * prm.time_step && scene.end_time - ns.time() > 1e-6 * prm.time_step)
        throw std::runtime_error("FEM solution diverged at t = " + std::to_string(ns.time()) + " (step " +
                                 std::to_string(ns.n_steps()) + "): the CFL step fell to " + std::to_string(dt) +
                                 " s (max |u| = " + std::to_string(ns.max_velocity()) +
                                 " m/s); reduce FEM/CFL number or refine. Monitors written so far are kept in " + dir);
      for (auto *p : physics)
        if (p == navier_stokes.get())
          advance_flow_and_bodies(dt); // Fig. 1: the bodies move under the loads; φ_s, u_s follow
        else
          p->advance(dt);
      if (ls_space)
        ls_space->add_travel(ns.max_velocity() * dt); // the surface moved at most this far
      const StepStatistics &st = ns.statistics();
      if (!std::isfinite(st.divergence_l2) || !std::isfinite(st.velocity_change))
        throw std::runtime_error("FEM solution diverged at t = " + std::to_string(ns.time()) + " (step " +
                                 std::to_string(ns.n_steps()) + "): reduce FEM/Time step or FEM/CFL number. "
                                 "Monitors written so far are kept in " + dir);
      {
        TimerOutput::Scope scope(run_timer, "monitors");
        record(dt, st.divergence_l2);
      }
      if (snapshots)
        for (const double s : snapshots->due(ns.time()))
        {
          TimerOutput::Scope scope(run_timer, "output");
          write_snapshot(s);
        }
      if (scene.output_interval > 0 && ns.time() >= next_output * (1 - 1e-9))
      {
        TimerOutput::Scope scope(run_timer, "output");
        write_output();
        next_output += scene.output_interval;
      }
      if (adaptation && adaptation->due(ns.n_steps()))
        adapt_mesh();
      // Last in the step: a restart continues with exactly the state the next step sees.
      if (prm.checkpoint_interval > 0 && ns.time() >= next_checkpoint * (1 - 1e-9))
      {
        TimerOutput::Scope scope(run_timer, "output");
        write_checkpoint(dir + "/checkpoint");
        next_checkpoint += prm.checkpoint_interval;
      }
      const double rate = st.velocity_change / (dt * std::max(ns.max_velocity(), 1e-300));
      steady = prm.steady_tolerance > 0 && ns.n_steps() > 2 && rate < prm.steady_tolerance;
      std::ostringstream extra;
      extra << "dt " << dt << "  its " << st.velocity_iterations << "/" << st.pressure_iterations << "  |du/dt|/|u| "
            << rate;
      if (adaptation)
        extra << "  cells " << tria.n_global_active_cells();
      if (ls_space)
        extra << "  volume drift " << result.monitors["water volume drift (max)"];
      progress.update(ns.time(), ns.n_steps(), extra.str());
    }
    progress.finish(steady ? "steady state reached" : "");
    if (scene.output_interval == 0)
    {
      TimerOutput::Scope scope(run_timer, "output");
      write_output();
    }
    result.steps      = ns.n_steps();
    result.final_time = ns.time();
    result.wall_time  = wall.wall_time();
    result.cells      = tria.n_global_active_cells();
    result.dofs       = ns.n_velocity_dofs() + ns.n_pressure_dofs();
    write_summary();
    return result;
  }
} // namespace twinflow::fem
