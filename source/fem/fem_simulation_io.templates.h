// FemSimulation<dim>: monitors, output, checkpoints and the run summary.
#pragma once
#include <twinflow/core/errors.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/csv_table.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/pvd_series.h>
#include <twinflow/io/summary.h>
#include <twinflow/io/front_reference.h>
#include <twinflow/fem/linear_solve.h>

#include <deal.II/numerics/data_out.h>

#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  void FemSimulation<dim>::open_monitors()
  {
    io::ensure_directory(dir);
    // A restart continues the monitors of the run it restarts: their rows up to the restart
    // time are read before the files are rewritten (none for a fresh run or another directory).
    const bool   restarted = !prm.restart_file.empty();
    const double t0        = navier_stokes->time();
    auto open = [&](const std::string &file, const std::vector<std::string> &cols, const std::vector<std::string> &units,
                    const std::string &name) {
      // only the writing rank reads (the others would race with its rewrite; they write nothing)
      const auto carried = restarted && io::is_root_process(comm) ? io::monitor_rows_until(dir + "/" + file, t0)
                                                                  : std::vector<std::vector<double>>();
      auto       monitor = std::make_unique<io::CsvMonitor>(dir + "/" + file, cols, units, comm, name);
      for (const auto &row : carried)
        if (row.size() == cols.size())
          monitor->append(row);
      return monitor;
    };
    const Fluid &fluid = scene.fluids.front();
    const double area  = scene.reference_length * (dim == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 1.0);
    coefficient_scale  = 2.0 / (fluid.density * scene.reference_velocity * scene.reference_velocity * area);
    if (scene.monitors_contain("forces") && (body_id != numbers::invalid_boundary_id || ibm))
    {
      std::vector<std::string> cols{"time", "Fx", "Fy"}, units{"s", "N", "N"};
      if (dim == 3) { cols.push_back("Fz"); units.push_back("N"); }
      cols.insert(cols.end(), {"C_d", "C_l", "torque z"});
      units.insert(units.end(), {"-", "-", "N m"});
      forces_csv = open("forces.csv", cols, units, "forces");
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
      probes_csv = open("pressure_probes.csv", cols, units, "pressure probes");
    }
    if (ls_space)
    {
      // Free surface: the water's energies (as the SPH writes them) and the system's (both
      // phases); the front; the water volume and what the mass correction did.
      energy_csv = open("energy.csv",
                        {"time", "kinetic energy", "potential energy", "total energy", "system energy", "divergence L2",
                         "dt", "cells"},
                        {"s", "J", "J", "J", "J", "1/s", "s", "-"}, "energy");
      // max speed: in the water, as SPH's (no air there); max speed all phases: what the CFL sees
      front_csv  = open("front.csv", {"time", "x_front", "max speed", "x_foremost", "max speed all phases"},
                        {"s", "m", "m/s", "m", "m/s"}, "front");
      std::vector<std::string> cols{"time",           "water volume", "relative drift", "max correction",
                                    "newton iterations", "phi min",     "phi max"},
        units{"s", "m^dim", "-", "m", "-", "m", "m"};
      if (ibm)
      {
        // the level set's water inside the solids (their ghost region): not water the body displaces
        cols.push_back("water inside solids");
        units.push_back("m^dim");
      }
      volume_csv = open("volume.csv", cols, units, "volume");
    }
    else if (scene.monitors_contain("energy"))
      energy_csv = open("energy.csv", {"time", "kinetic energy", "divergence L2", "dt", "cells"},
                        {"s", "J", "1/s", "s", "-"}, "energy");
    if (coupling)
    {
      body_monitor = std::make_unique<io::BodyMonitor>(dir, *coupling, dim, scene.gravity, comm,
                                                       restarted ? t0 : -1.0);
      if (!restarted) // a restart carries the rows up to t0
        body_monitor->append(t0, body_loads);
    }
    pvd = std::make_unique<io::PvdSeries>(dir, "solution", comm);
    if (restarted && io::is_root_process(comm))
      std::cout << "FEM restart from " << prm.restart_file << ": t = " << t0 << " s, step " << navier_stokes->n_steps()
                << std::endl;
  }

  template <int dim>
  void FemSimulation<dim>::record(const double dt, const double divergence)
  {
    const NavierStokes<dim> &ns = *navier_stokes;
    const double             t  = ns.time();
    if (forces_csv)
    {
      Tensor<1, dim> F;
      double         torque = 0;
      if (ibm)
      {
        const auto loads = ibm->loads(ns);
        F      = loads.front().force;
        torque = loads.front().torque[2];
      }
      else
        F = ns.boundary_force(body_id);
      std::vector<double> row{t};
      for (unsigned int d = 0; d < dim; ++d)
        row.push_back(F[d]);
      row.push_back(coefficient_scale * F[0]);
      row.push_back(coefficient_scale * F[1]);
      row.push_back(torque);
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
    if (ls_space)
      record_free_surface(dt, divergence);
    else if (energy_csv)
    {
      const double e = ns.kinetic_energy();
      energy_csv->append({t, e, divergence, dt, double(tria.n_global_active_cells())});
      result.monitors["kinetic energy"] = e;
    }
  }

  template <int dim>
  void FemSimulation<dim>::write_output()
  {
    DataOut<dim> data_out;
    data_out.attach_triangulation(tria);
    for (const auto *p : physics)
      p->add_to_output(data_out);
    Vector<float> subdomain(tria.n_active_cells()), level(tria.n_active_cells()), solid(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
      {
        const auto i = cell->active_cell_index();
        subdomain(i) = tria.locally_owned_subdomain();
        level(i)     = cell->level();
        if (ibm)
        {
          double phi = 1e300;
          for (const auto &s : ibm->solids())
            phi = std::min(phi, s->distance(cell->center()));
          solid(i) = phi;
        }
      }
    data_out.add_data_vector(subdomain, "subdomain");
    data_out.add_data_vector(level, "level");
    if (ibm)
      data_out.add_data_vector(solid, "solid_distance");
    data_out.build_patches(navier_stokes->get_mapping(), prm.navier_stokes.velocity_degree,
                           DataOut<dim>::curved_inner_cells);
    // zlib's fastest level: the default (best compression) cost ~15 % of a 2D run's wall time
    DataOutBase::VtkFlags flags;
    flags.compression_level = DataOutBase::VtkFlags::best_speed;
    data_out.set_flags(flags);
    const std::string name = data_out.write_vtu_with_pvtu_record(dir + "/", "solution", output_count++, comm, 4);
    pvd->add(navier_stokes->time(), name);
  }

  template <int dim>
  void FemSimulation<dim>::write_checkpoint(const std::string &prefix)
  {
    for (auto *p : physics)
      p->prepare_transfer(true);
    tria.save(prefix + ".mesh");
    if (io::is_root_process(comm))
    {
      std::ofstream meta(prefix + ".meta");
      meta.precision(17);
      meta << "twinflow-fem-checkpoint 1 " << dim << ' ' << tria.n_global_active_cells() << '\n';
      if (coupling) // the rigid bodies and the loads they last moved under
      {
        coupling->save(meta);
        for (const auto &l : body_loads)
          meta << "load " << l.force.x() << ' ' << l.force.y() << ' ' << l.force.z() << ' ' << l.torque.x() << ' '
               << l.torque.y() << ' ' << l.torque.z() << '\n';
      }
      for (const auto *p : physics)
        p->save_state(meta);
      meta << "outputs " << output_count << ' ' << next_output << '\n';
      if (!meta)
        throw std::runtime_error("cannot write the checkpoint metadata " + prefix + ".meta");
    }
    MPI_Barrier(comm);
  }

  template <int dim>
  void FemSimulation<dim>::load_checkpoint(const std::string &prefix)
  {
    std::ifstream meta(prefix + ".meta"); // its presence was checked in compose()
    std::string tag;
    int         version = 0, file_dim = 0;
    unsigned long long cells = 0;
    meta >> tag >> version >> file_dim >> cells;
    if (tag != "twinflow-fem-checkpoint" || version != 1 || file_dim != dim)
      throw InputError("FEM/Restart file = '" + prefix + "': not a " + std::to_string(dim) +
                       "D twinflow FEM checkpoint (version 1)");
    if (coupling)
    {
      try
      {
        coupling->load(meta);
      }
      catch (const std::runtime_error &e)
      {
        throw InputError("FEM/Restart file = '" + prefix + "': " + e.what());
      }
      for (auto &l : body_loads)
      {
        meta >> tag >> l.force.x() >> l.force.y() >> l.force.z() >> l.torque.x() >> l.torque.y() >> l.torque.z();
        if (!meta || tag != "load")
          throw InputError("FEM/Restart file = '" + prefix + "': the bodies' loads are missing");
      }
      sync_solid_motion(); // the immersed solids where the bodies are, before the fields are set up
    }
    tria.load(prefix + ".mesh");
    if (tria.n_global_active_cells() != cells)
      throw InputError("FEM/Restart file = '" + prefix + "': the mesh does not match its metadata");
    for (auto *p : physics)
    {
      p->setup_dofs();
      p->finish_transfer(true);
      p->load_state(meta);
    }
    meta >> tag >> output_count >> next_output;
    if (!meta || tag != "outputs")
      throw InputError("FEM/Restart file = '" + prefix + "': the metadata is truncated");
    if (adaptation)
      adaptation->mark_adapted();
  }

  template <int dim>
  void FemSimulation<dim>::write_summary()
  {
    const NavierStokes<dim> &ns = *navier_stokes;
    result.monitors["max velocity"] = ns.max_velocity();
    if (ibm)
    {
      const auto [inside, surface] = ibm->slip_errors(ns);
      result.monitors["solid velocity L2"] = inside;
      result.monitors["surface slip L2"]   = surface;
    }
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
    summary.set_timer_sections(run_timer);
    if (ls_space)
    {
      summary.set_timer_sections(ls_space->timer());
      summary.set_dofs("level set", ls_space->n_dofs());
      summary.add_error("water volume drift (max over the run)", worst_volume_drift, 0.0, 1e-3,
                        "relative to the initial water volume int (1 - H_eps(phi))");
      summary.add_error("energy rise above the initial value (max over the run)", worst_energy_rise, 0.0, 5e-3,
                        "kinetic + potential energy of both phases; a dam break is dissipative");
      summary.add_error("level set |phi| / domain diameter (max over the run)", worst_phi_range, 0.0, 1.0,
                        "a distance in the domain is below its diameter; above it phi has run away");
    }
    if (ls_space)
      io::add_front_reference_errors(scene, front_time, front_position, summary, result.monitors);
    if (body_monitor)
    {
      body_monitor->summarise(summary, result.monitors);
      summary.set_extra("rigid-body RK4 sub-steps", double(coupling->substeps_taken()));
      summary.set_extra("rigid-body sub-steps touching a wall", double(coupling->contact_substeps()));
      summary.set_extra("rigid-body deepest wall penetration before projection [m]", coupling->max_contact_depth());
      summary.set_extra("coupling: Navier-Stokes solves per step",
                        coupling_steps > 0 ? double(coupling_solves) / coupling_steps : 0.0);
      summary.set_extra("coupling: steps not converged", double(coupling_unconverged));
    }
    summary.set_monitor_values(result.monitors);
    summary.set_extra("active physics", internal::join(result.active_physics, "; "));
    summary.set_extra("mpi ranks", Utilities::MPI::n_mpi_processes(comm));
    summary.set_extra("mesh adaptations", result.adaptations);
    summary.set_extra("time per step [s]", result.wall_time / std::max(1u, result.steps));
    for (const auto &[system, counts] : linear_solve_counts())
    {
      std::ostringstream line;
      line << std::fixed << std::setprecision(1) << double(counts.iterations) / std::max(1ul, counts.calls)
           << " per solve, " << std::setprecision(2) << double(counts.calls) / std::max(1u, result.steps)
           << " solves per step";
      summary.set_extra("Krylov iterations: " + system, line.str());
    }
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
  }
} // namespace twinflow::fem
