// run_fem<dim>: composes the FEM simulation from a Scene and runs it.
#pragma once
#include <twinflow/core/errors.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/fem/material_model.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/plots.h>
#include <twinflow/io/progress.h>
#include <twinflow/io/pvd_series.h>
#include <twinflow/io/summary.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>

#include <algorithm>
#include <cmath>
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
  } // namespace internal

  template <int dim>
  FemRunResult run_fem(const Scene &scene, const FemParameters &prm, const std::string &dir)
  {
    Timer              wall;
    MPI_Comm           comm = MPI_COMM_WORLD;
    ConditionalOStream pcout(std::cout, io::is_root_process(comm));
    FemRunResult       result;

    // ---- composition: only what the scene calls for -------------------------------------
    if (scene.has_free_surface())
      throw InputError("Fluids/Number of fluids = 2: the FEM two-phase module (conservative level set, "
                       "Algorithm 1) is not available yet; allowed with FEM now: 1 fluid.");
    const bool dfg_channel = scene.geometry == "channel with cylinder";
    const bool fitted      = dfg_channel || scene.geometry == "box with cylinder";
    if (scene.has_solids() && !fitted)
      throw InputError("Solids/Number of solids = " + std::to_string(scene.solids.size()) +
                       ": immersed solids (IBM, Eq. 15-16) are not available in the FEM yet; allowed now: "
                       "Domain/Geometry = channel with cylinder or box with cylinder (body-fitted cylinder) or "
                       "no solids.");
    result.active_physics.push_back("navier-stokes (single phase, constant density)");
    if (fitted)
      result.active_physics.push_back("body-fitted fixed cylinder");
    for (unsigned int d = 0; d < dim; ++d)
      if (scene.periodic[d])
        result.active_physics.push_back(std::string("periodic ") + "xyz"[d]);
    pcout << "FEM active physics: " << internal::join(result.active_physics, "; ")
          << "  (not built: level set, immersed boundary, rigid body, ANCF)" << std::endl;

    // ---- mesh --------------------------------------------------------------------------
    parallel::distributed::Triangulation<dim> tria(comm);
    std::array<types::boundary_id, 6> face_id{{0, 1, 2, 3, 4, 5}};
    types::boundary_id                body_id = numbers::invalid_boundary_id;
    if (dfg_channel)
    {
      GridGenerator::channel_with_cylinder(tria, 0.03, 2, 2.0, true);
      face_id = {{0, 1, 3, 3, 3, 3}};
      body_id = 2;
    }
    else if (fitted)
      body_id = internal::make_box_with_cylinder(tria, scene, face_id);
    else
    {
      Point<dim>                p1, p2;
      std::vector<unsigned int> reps(dim);
      double                    hmin = 1e300;
      for (unsigned int d = 0; d < dim; ++d)
      {
        p1[d] = scene.domain.lower[d];
        p2[d] = scene.domain.upper[d];
        hmin  = std::min(hmin, p2[d] - p1[d]);
      }
      for (unsigned int d = 0; d < dim; ++d)
        reps[d] = std::max(1u, static_cast<unsigned int>(std::lround((p2[d] - p1[d]) / hmin)));
      GridGenerator::subdivided_hyper_rectangle(tria, reps, p1, p2, true);
    }
    std::vector<GridTools::PeriodicFacePair<typename parallel::distributed::Triangulation<dim>::cell_iterator>> faces;
    for (unsigned int d = 0; d < dim; ++d)
      if (scene.periodic[d])
        GridTools::collect_periodic_faces(tria, face_id[2 * d], face_id[2 * d + 1], d, faces);
    if (!faces.empty())
      tria.add_periodicity(faces);
    tria.refine_global(prm.global_refinements);

    // ---- solver ------------------------------------------------------------------------
    const Fluid            &fluid = scene.fluids.front();
    ConstantMaterial<dim>   material(fluid.density, fluid.viscosity);
    NavierStokesParameters  nsp = prm.navier_stokes;
    if (nsp.mapping_degree == 0)
      nsp.mapping_degree = fitted ? nsp.velocity_degree : 1;
    NavierStokes<dim> ns(tria, nsp, material);

    std::shared_ptr<Function<dim>> inflow;
    bool                           periodic_set[3] = {false, false, false};
    for (unsigned int f = 0; f < 2 * dim; ++f)
    {
      const unsigned int axis = f / 2;
      switch (scene.boundary[f])
      {
        case BoundaryKind::no_slip:
          ns.set_dirichlet(face_id[f], std::make_shared<Functions::ZeroFunction<dim>>(dim));
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
            ns.set_periodic(face_id[2 * axis], face_id[2 * axis + 1], axis);
          periodic_set[axis] = true;
          break;
      }
    }
    if (fitted)
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
    ns.setup();
    // Initial state: the undisturbed inflow (if any) everywhere, hydrostatic pressure.
    Functions::ZeroFunction<dim>          zero(dim);
    internal::HydrostaticPressure<dim>    p0(fluid.density, scene.gravity);
    ns.initialize(inflow ? *inflow : static_cast<const Function<dim> &>(zero), p0, 0.0);

    result.cells = tria.n_global_active_cells();
    result.dofs  = ns.n_velocity_dofs() + ns.n_pressure_dofs();
    pcout << "FEM mesh: " << result.cells << " cells, " << ns.n_velocity_dofs() << " velocity + "
          << ns.n_pressure_dofs() << " pressure DoFs, Q" << nsp.velocity_degree << "/Q" << nsp.velocity_degree - 1
          << ", " << Utilities::MPI::n_mpi_processes(comm) << " MPI rank(s)" << std::endl;

    // ---- monitors ----------------------------------------------------------------------
    io::ensure_directory(dir);
    const double area = scene.reference_length * (dim == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 1.0);
    const double coefficient_scale = 2.0 / (fluid.density * scene.reference_velocity * scene.reference_velocity * area);
    std::unique_ptr<io::CsvMonitor> forces_csv, probes_csv, energy_csv;
    const bool want_forces = scene.monitors_contain("forces") && body_id != numbers::invalid_boundary_id;
    if (want_forces)
    {
      std::vector<std::string> cols{"time", "Fx", "Fy"}, units{"s", "N", "N"};
      if (dim == 3) { cols.push_back("Fz"); units.push_back("N"); }
      cols.insert(cols.end(), {"C_d", "C_l"});
      units.insert(units.end(), {"-", "-"});
      forces_csv = std::make_unique<io::CsvMonitor>(dir + "/forces.csv", cols, units, comm, "forces");
    }
    if (scene.monitors_contain("pressure probes"))
    {
      std::vector<std::string> cols{"time"}, units{"s"};
      for (unsigned int k = 0; k < scene.pressure_probes.size(); ++k)
      {
        cols.push_back("p" + std::to_string(k + 1));
        units.push_back("Pa");
      }
      if (scene.pressure_probes.size() >= 2) { cols.push_back("dp"); units.push_back("Pa"); }
      probes_csv = std::make_unique<io::CsvMonitor>(dir + "/pressure_probes.csv", cols, units, comm, "pressure probes");
    }
    if (scene.monitors_contain("energy"))
      energy_csv = std::make_unique<io::CsvMonitor>(dir + "/energy.csv",
                                                    std::vector<std::string>{"time", "kinetic energy", "divergence L2", "dt"},
                                                    std::vector<std::string>{"s", "J", "1/s", "s"}, comm, "energy");

    auto record = [&](double dt, double divergence) {
      const double t = ns.time();
      if (forces_csv)
      {
        const Tensor<1, dim> F = ns.boundary_force(body_id);
        std::vector<double>  row{t};
        for (unsigned int d = 0; d < dim; ++d)
          row.push_back(F[d]);
        row.push_back(coefficient_scale * F[0]);
        row.push_back(coefficient_scale * F[1]);
        forces_csv->append(row);
        result.monitors["C_d"] = coefficient_scale * F[0];
        result.monitors["C_l"] = coefficient_scale * F[1];
      }
      if (probes_csv)
      {
        std::vector<double> row{t};
        for (const auto &x : scene.pressure_probes)
        {
          Point<dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = x[d];
          row.push_back(ns.pressure_at(p));
          result.monitors["p" + std::to_string(row.size() - 1)] = row.back();
        }
        if (scene.pressure_probes.size() >= 2)
        {
          row.push_back(row[1] - row[2]);
          result.monitors["dp"] = row.back();
        }
        probes_csv->append(row);
      }
      if (energy_csv)
      {
        const double e = ns.kinetic_energy();
        energy_csv->append({t, e, divergence, dt});
        result.monitors["kinetic energy"] = e;
      }
    };

    // ---- output ------------------------------------------------------------------------
    io::PvdSeries pvd(dir, "solution", comm);
    unsigned int  output_count = 0;
    auto write_output = [&]() {
      DataOut<dim> data_out;
      data_out.attach_triangulation(tria);
      ns.add_to_output(data_out);
      Vector<float> subdomain(tria.n_active_cells());
      for (unsigned int i = 0; i < subdomain.size(); ++i)
        subdomain(i) = tria.locally_owned_subdomain();
      data_out.add_data_vector(subdomain, "subdomain");
      data_out.build_patches(ns.get_mapping(), nsp.velocity_degree, DataOut<dim>::curved_inner_cells);
      const std::string name = data_out.write_vtu_with_pvtu_record(dir + "/", "solution", output_count++, comm, 4);
      pvd.add(ns.time(), name);
    };

    // ---- time loop ---------------------------------------------------------------------
    const double     h_min = ns.minimal_cell_diameter();
    io::ProgressReporter progress(0.0, scene.end_time, std::cout, comm, 2.0);
    double           next_output = scene.output_interval;
    bool             steady      = false;
    if (scene.output_interval > 0)
      write_output();
    while (ns.time() < scene.end_time * (1 - 1e-12) && !steady)
    {
      double dt = prm.time_step;
      if (prm.cfl > 0)
        dt = std::min(dt, prm.cfl * h_min / std::max(ns.max_velocity(), 1e-12));
      dt = std::min(dt, scene.end_time - ns.time());
      const StepStatistics &st = ns.step(dt);
      if (!std::isfinite(st.divergence_l2) || !std::isfinite(st.velocity_change))
        throw std::runtime_error("FEM solution diverged at t = " + std::to_string(ns.time()) + " (step " +
                                 std::to_string(ns.n_steps()) + "): reduce FEM/Time step or FEM/CFL number. "
                                 "Monitors written so far are kept in " + dir);
      record(dt, st.divergence_l2);
      if (scene.output_interval > 0 && ns.time() >= next_output * (1 - 1e-9))
      {
        write_output();
        next_output += scene.output_interval;
      }
      const double umax = std::max(ns.max_velocity(), 1e-300);
      const double rate = st.velocity_change / (dt * umax);
      steady            = prm.steady_tolerance > 0 && ns.n_steps() > 2 && rate < prm.steady_tolerance;
      std::ostringstream extra;
      extra << "dt " << dt << "  its " << st.velocity_iterations << "/" << st.pressure_iterations
            << "  |du/dt|/|u| " << rate;
      progress.update(ns.time(), ns.n_steps(), extra.str());
    }
    progress.finish(steady ? "steady state reached" : "");
    if (scene.output_interval == 0)
      write_output();

    // ---- summary -----------------------------------------------------------------------
    result.steps      = ns.n_steps();
    result.final_time = ns.time();
    result.wall_time  = wall.wall_time();
    io::RunSummary summary(comm);
    summary.set_method("fem");
    summary.set_dimension(dim);
    summary.set_scene(scene.name);
    summary.set_cells(result.cells);
    summary.set_dofs("velocity", ns.n_velocity_dofs());
    summary.set_dofs("pressure", ns.n_pressure_dofs());
    summary.set_steps(result.steps);
    summary.set_final_time(result.final_time);
    summary.set_wall_time(result.wall_time);
    summary.set_timer_sections(ns.timer());
    summary.set_monitor_values(result.monitors);
    summary.set_extra("active physics", internal::join(result.active_physics, "; "));
    summary.set_extra("mpi ranks", Utilities::MPI::n_mpi_processes(comm));
    summary.set_extra("time per step [s]", result.wall_time / std::max(1u, result.steps));
    auto compare = [&](const char *name, const char *key, const std::optional<double> &ref) {
      if (ref && result.monitors.count(key))
      {
        summary.add_error(name, result.monitors[key], *ref);
        result.relative_errors[key] = std::abs(result.monitors[key] - *ref) / std::abs(*ref);
      }
    };
    compare("drag coefficient C_d", "C_d", scene.reference_drag);
    compare("lift coefficient C_l", "C_l", scene.reference_lift);
    compare("pressure difference", "dp", scene.reference_pressure_difference);
    summary.write_json(dir + "/summary.json");
    summary.print_table(std::cout);
    return result;
  }
} // namespace twinflow::fem
