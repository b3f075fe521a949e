#include <twinflow/sph/particle_setup.h>

#include <twinflow/core/errors.h>
#include <twinflow/io/body_monitor.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/csv_table.h>
#include <twinflow/io/front_reference.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/particle_output.h>
#include <twinflow/io/progress.h>
#include <twinflow/io/snapshots.h>
#include <twinflow/io/pvd_series.h>
#include <twinflow/io/summary.h>
#include <twinflow/sph/checkpoint.h>
#include <twinflow/sph/front.h>
#include <twinflow/sph/hydrostatic_check.h>
#include <twinflow/sph/open_boundary.h>
#include <twinflow/sph/snapshot.h>
#include <twinflow/sph/sph_simulation.h>
#include <twinflow/solids/coupling.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <fstream>
#include <iostream>
#include <sstream>
#include <utility>

namespace twinflow::sph
{
  namespace
  {
    template <int dim>
    SphRunResult run(const Scene &scene, const SphParameters &prm, const std::string &dir)
    {
      dealii::Timer wall;
      SphRunResult  result;
      if (scene.has_solids())
        for (const auto &s : scene.solids)
          if (s.motion == SolidMotion::elastic)
            throw InputError("Solids/" + s.name + "/Motion = elastic: elastic solids are not available in SPH yet; "
                             "allowed: fixed, rigid");
      if (scene.has_moving_solids() && !prm.restart_file.empty())
        throw InputError("SPH/Restart file = " + prm.restart_file +
                         ": a restart does not carry the rigid bodies' state yet; run scenes with moving solids from t = 0");
      const Fluid &fluid = scene.fluids.front();
      const double h     = prm.h_over_dx * prm.spacing;
      const int    layers = static_cast<int>(std::ceil(2.0 * h / prm.spacing - 1e-9));

      HostParticles<dim> P;
      result.fluid_particles = make_particles<dim>(scene, prm.spacing, layers, fluid.density, P);
      result.markers         = P.size() - result.fluid_particles;
      if (scene.reference_hydrostatic && hydrostatic_check<dim>(scene, prm.spacing, P, false).bulk_particles == 0)
        throw InputError("SPH/Particle spacing = " + std::to_string(prm.spacing) +
                         ": no fluid particle lies more than " + std::to_string(int(hydrostatic_bulk_margin)) +
                         " spacings below the surface and from the walls, so References/Hydrostatic pressure has "
                         "nothing to measure; reduce the spacing");

      // Restart: the checkpoint replaces the generated particles' state (checkpoint.h).
      const bool     restart = !prm.restart_file.empty();
      const OpenFace open    = open_face(scene); // fluid leaving through it is removed
      RunPosition    start;
      if (restart)
        start = read_checkpoint<dim>(prm.restart_file, prm.spacing, P, open.active());
      const EngineSettings s = make_engine_settings(scene, prm);
      auto engine = make_engine<dim>(prm.backend, domain_box<dim>(scene), s);
      engine->set_particles(P);

      result.active_physics.push_back("implicit SPH (Algorithm 2, " + std::string(prm.consistent ? "consistent" : "standard") +
                                      " operators" + (s.conservative_gradient ? " made an energy-conserving pair" : "") +
                                      ", " + engine->backend() + " backend)");
      // Moving solids: rigid bodies co-simulated with the fluid (solids/coupling.h, Fig. 1).
      std::optional<solids::CoSimulation> coupling;
      if (scene.has_moving_solids())
        coupling.emplace(scene);
      if (coupling)
        for (const std::string &line : coupling->describe())
          result.active_physics.push_back(line + ", moving BCE markers");
      result.active_physics.push_back(std::to_string(layers) + " BCE layers (" +
                                      (prm.neumann_walls ? "Neumann pressure rows" : "force-balance pressure rows") + ")");
      if (open.active())
        result.active_physics.push_back("open " + open.name + " (outflow): no BCE markers there; fluid particles "
                                        "leaving through it are removed");
      if (s.alpha > 0)
      {
        std::ostringstream de;
        de << "density error (alpha = " << s.alpha << ") corrected through the "
           << (s.corrects_positions() ? "positions" : "velocity");
        result.active_physics.push_back(de.str());
      }
      if (s.free_surface)
      {
        std::ostringstream fs;
        fs << "free surface (" << (s.offsets_surface() ? "p = 0 half a spacing above" : "p = 0 at")
           << " the particles where rho < " << prm.free_surface_ratio << " rho0";
        if (s.free_surface_divergence > 0)
          fs << ", div r < " << s.free_surface_divergence;
        if (s.free_surface_min_neighbours > 0)
          fs << ", fewer than " << s.free_surface_min_neighbours << " neighbours";
        if (s.free_surface_min_fluid_neighbours > 0)
          fs << ", droplets of fewer than " << s.free_surface_min_fluid_neighbours << " fluid neighbours";
        result.active_physics.push_back(fs.str() + ")");
      }
      std::cout << "SPH active physics: ";
      for (std::size_t k = 0; k < result.active_physics.size(); ++k)
        std::cout << (k ? "; " : "") << result.active_physics[k];
      std::cout << "\nSPH particles: " << result.fluid_particles << " fluid + " << result.markers
                << " BCE markers, spacing " << prm.spacing << " m, h = " << h << " m" << std::endl;

      io::ensure_directory(dir);
      MPI_Comm self = MPI_COMM_SELF;
      if (restart)
        std::cout << "SPH restart from " << prm.restart_file << ": t = " << start.time << " s, step " << start.steps
                  << std::endl;
      // A restart continues the monitors of the run it restarts: their rows up to the restart
      // time are read before the files are rewritten (empty for a fresh run or another directory).
      auto carried = [&](const std::string &file) {
        return restart ? io::monitor_rows_until(dir + "/" + file, start.time) : std::vector<std::vector<double>>();
      };
      const auto energy_rows = carried("energy.csv"), front_rows = carried("front.csv"),
                 solver_rows = carried("solver.csv"), budget_rows = carried("energy_budget.csv");
      io::CsvMonitor energy(dir + "/energy.csv", {"time", "kinetic energy", "potential energy", "total energy"},
                            {"s", "J", "J", "J"}, self, "energy");
      // x_front: leading edge of the connected water (sph/front.h); x_foremost: of any particle,
      // spray included
      io::CsvMonitor front(dir + "/front.csv", {"time", "x_front", "max speed", "x_foremost"}, {"s", "m", "m/s", "m"},
                           self, "front");
      io::CsvMonitor solver(dir + "/solver.csv",
                            {"time", "dt", "velocity iterations", "pressure iterations", "pressure residual", "free-surface particles",
                             "pressure noise"},
                            {"s", "s", "-", "-", "-", "-", "Pa"}, self, "solver");
      // Where the mechanical energy change came from, summed from t = 0 (EnergyBudget): the six
      // columns add up to the change of the total energy in energy.csv.
      io::CsvMonitor energy_budget(dir + "/energy_budget.csv",
                                   {"time", "viscous", "body force work", "pressure correction", "potential of the move",
                                    "shifting", "density-error displacement"},
                                   {"s", "J", "J", "J", "J", "J", "J"}, self, "energy budget");
      for (const auto &row : budget_rows)
        energy_budget.append(row);
      double noise_sum = 0, noise_time = 0; // time average of the pressure noise
      // the largest rise of the total energy above its initial value, relative to |E0| (a restart
      // continues it from the carried rows; E0 is the run's first row)
      double energy0 = std::nan(""), worst_energy_rise = 0;
      auto   track_energy = [&](const double e) {
        if (std::isnan(energy0))
          energy0 = e;
        if (energy0 != 0)
          worst_energy_rise = std::max(worst_energy_rise, (e - energy0) / std::abs(energy0));
      };
      for (const auto &row : energy_rows)
      {
        energy.append(row);
        track_energy(row[3]);
      }
      for (const auto &row : solver_rows)
      {
        solver.append(row);
        noise_sum += row[6] * row[1], noise_time += row[1];
      }
      std::vector<double> front_t, front_x;
      for (const auto &row : front_rows)
      {
        front.append(row);
        front_t.push_back(row[0]);
        front_x.push_back(row[1]);
      }
      // Fluid force on each solid (engine, doc/equations.md "Forces on solids"); columns as the
      // FEM's forces monitor so that both overlay in one plot. Solid 1: forces.csv, others
      // forces_<name>.csv. C = 2F / (rho U^2 A), A = Reference length (x depth in 3D).
      std::vector<std::unique_ptr<io::CsvMonitor>> forces_csv;
      std::vector<double>                          force_t, drag_series, lift_series;
      const double area = scene.reference_length * (dim == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 1.0);
      const double coefficient_scale =
        2.0 / (fluid.density * scene.reference_velocity * scene.reference_velocity * area);
      if (scene.has_solids() && scene.monitors_contain("forces"))
        for (std::size_t b = 0; b < scene.solids.size(); ++b)
        {
          std::vector<std::string> cols{"time", "Fx", "Fy"}, units{"s", "N", "N"};
          if (dim == 3) { cols.push_back("Fz"); units.push_back("N"); }
          cols.insert(cols.end(), {"C_d", "C_l"});
          units.insert(units.end(), {"-", "-"});
          const std::string file = b == 0 ? "forces.csv" : "forces_" + scene.solids[b].name + ".csv";
          const auto        rows = carried(file);
          forces_csv.push_back(std::make_unique<io::CsvMonitor>(dir + "/" + file, cols, units, self, "forces"));
          for (const auto &row : rows)
          {
            forces_csv.back()->append(row);
            if (b == 0 && row[0] > 0) // as monitors(): the series starts with the first step
            {
              force_t.push_back(row[0]);
              drag_series.push_back(row[1 + dim]);
              lift_series.push_back(row[2 + dim]);
            }
          }
        }
      std::optional<io::BodyMonitor> body_monitor;
      std::vector<solids::BodyLoad>  loads(coupling ? coupling->n_bodies() : 0);
      if (coupling)
      {
        body_monitor.emplace(dir, *coupling, dim, scene.gravity, self);
        body_monitor->append(0, loads);
      }
      // Rigid motion of body b's markers from pose `from` to `to` with the rigid velocity field of `to`.
      auto marker_motion = [&](std::size_t b, const solids::BodyKinematics &from, const solids::BodyKinematics &to) {
        MarkerMotion m;
        m.body                  = coupling->solid_index(b);
        const solids::Matrix3 R = to.rotation * from.rotation.transpose();
        for (int a = 0; a < 3; ++a)
        {
          m.from[a] = from.position[a], m.to[a] = to.position[a];
          m.velocity[a] = to.velocity[a], m.angular_velocity[a] = to.angular_velocity[a];
          m.acceleration[a] = to.acceleration[a], m.angular_acceleration[a] = to.angular_acceleration[a];
          for (int c = 0; c < 3; ++c)
            m.rotation[a][c] = R(a, c), m.orientation[a][c] = to.rotation(a, c);
        }
        const Solid &sb = scene.solids[m.body];
        const bool   round = sb.shape == "disk" || sb.shape == "cylinder";
        m.shape            = round ? 1 : 2;
        m.half_size[0]     = round ? sb.radius : 0.5 * sb.length;
        m.half_size[1]     = round ? sb.radius : 0.5 * sb.thickness;
        return m;
      };
      io::PvdSeries       pvd(dir, "particles", self);
      std::vector<double> output_times = start.output_times;
      for (std::size_t k = 0; k < output_times.size(); ++k)
        pvd.add(output_times[k], "particles_" + std::to_string(k) + ".vtu");
      double        m0 = fluid.density;
      for (int d = 0; d < dim; ++d)
        m0 *= prm.spacing;

      auto monitors = [&](double t, double dt, const StepReport *r) {
        engine->get_particles(P);
        double ek = 0, ep = 0;
        for (std::size_t i = 0; i < P.size(); ++i)
          if (P.kind[i] == ParticleKind::fluid)
          {
            double u2 = 0, gx = 0;
            for (int d = 0; d < dim; ++d)
            {
              u2 += P.u[i][d] * P.u[i][d];
              gx += scene.gravity[d] * P.x[i][d];
            }
            ek += 0.5 * m0 * u2;
            ep -= m0 * gx;
          }
        const double xf = surge_front(P, prm.spacing);
        energy.append({t, ek, ep, ek + ep});
        track_energy(ek + ep);
        front.append({t, xf, engine->max_fluid_speed(), foremost_particle(P, prm.spacing)});
        front_t.push_back(t);
        front_x.push_back(xf);
        for (std::size_t b = 0; b < forces_csv.size(); ++b)
        {
          const std::array<double, 3> F = engine->solid_force(static_cast<int>(b));
          std::vector<double>         row{t};
          for (int d = 0; d < dim; ++d)
            row.push_back(F[d]);
          row.push_back(coefficient_scale * F[0]);
          row.push_back(coefficient_scale * F[1]);
          forces_csv[b]->append(row);
          if (b == 0 && r)
          {
            force_t.push_back(t);
            drag_series.push_back(coefficient_scale * F[0]);
            lift_series.push_back(coefficient_scale * F[1]);
          }
        }
        if (r)
        {
          solver.append({t, dt, double(r->velocity[0].iterations), double(r->pressure.iterations), r->pressure.residual,
                         double(r->free_surface_particles), r->pressure_noise});
          noise_sum += r->pressure_noise * dt, noise_time += dt;
          // relative to the hydrostatic pressure scale ρ0 |g| L_ref (or ρ0 U_ref² without gravity)
          const double g2    = scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                               scene.gravity[2] * scene.gravity[2];
          const double scale = fluid.density * (g2 > 0 ? std::sqrt(g2) * scene.reference_length
                                                      : scene.reference_velocity * scene.reference_velocity);
          result.monitors["pressure noise (time-averaged rms) / rho g L_ref"] = noise_sum / noise_time / scale;
        }
        result.monitors["kinetic energy"] = ek;
        result.monitors["total energy"]   = ek + ep;
        result.monitors["x_front"]        = xf;
      };
      auto write = [&](double t) {
        io::ParticleOutput<dim> out;
        std::vector<double> xs, us;
        for (std::size_t i = 0; i < P.size(); ++i)
          for (int d = 0; d < dim; ++d)
          {
            xs.push_back(P.x[i][d]);
            us.push_back(P.u[i][d]);
          }
        out.set_positions_flat(xs);
        out.add_vector_flat("velocity", us);
        out.add_scalar("pressure", P.p);
        out.add_scalar("density", P.rho);
        out.add_scalar("kind", P.kind);
        out.set_time(t, output_times.size());
        const std::string name = "particles_" + std::to_string(output_times.size()) + ".vtu";
        out.write_vtu(dir + "/" + name);
        pvd.add(t, name);
        output_times.push_back(t);
      };

      // Scene/Snapshot times (io/snapshots.h): P holds the state monitors() just read.
      io::SnapshotSchedule snapshots(scene.snapshot_times, start.time, restart);
      auto snapshot = [&](double t) {
        for (const double s : snapshots.due(t))
          write_snapshot<dim>(dir + "/snapshots/" + io::snapshot_file_name("sph", s), P, s, t, result.steps);
      };

      if (!restart)
      {
        energy_budget.append({0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
        monitors(0, 0, nullptr);
        snapshot(0);
        write(0);
      }
      io::ProgressReporter progress(start.time, scene.end_time, std::cout, self, 2.0);
      double t = start.time, t_output = 0;
      double next_output = restart ? start.next_output : scene.output_interval;
      result.steps       = start.steps;
      EnergyBudget budget = start.budget; // summed over the run, checkpointed with it
      const double checkpoint_interval = prm.checkpoint_interval;
      double       next_checkpoint     = t + checkpoint_interval;
      auto checkpoint = [&](const std::string &file, double time, std::size_t steps) {
        write_checkpoint<dim>(dir + "/" + file, P, prm.spacing, RunPosition{time, steps, next_output, output_times, budget});
      };
      const double u_ref = scene.reference_velocity;
      while (t < scene.end_time * (1 - 1e-12))
      {
        double dt = prm.time_step;
        if (prm.cfl > 0)
          dt = std::min(dt, prm.cfl * h / std::max({engine->max_fluid_speed(), coupling ? coupling->max_surface_speed() : 0.0, u_ref}));
        // Over the last (at most 10) steps, spread the remaining time evenly instead of ending
        // on a sliver step: the pressure of a step scales with its dt (the density-invariance
        // source, Eq. 55/57, goes as 1/dt^2), so a last step of a fraction of dt leaves a wrong
        // final pressure (still water, dx = 0.01: bulk error 47 % instead of 0.5 %). Only the
        // end is touched: the Martin-Moyce a/20 run with consistent operators diverges when
        // every step is evenly spread (doc/benchmarks.md "SPH: spacing and operator study").
        const double remaining = scene.end_time - t;
        dt = remaining <= 10 * dt ? remaining / std::ceil(remaining / dt * (1 - 1e-9)) : std::min(dt, remaining);
        // Co-simulation (Fig. 1): the bodies advance under the fluid's load of the last step; the
        // fluid step then sees their new velocity and acceleration at the markers' current
        // positions (as a fluid particle, a marker moves with its end-of-step velocity), and the
        // markers move to the bodies' new pose after it.
        std::vector<solids::BodyKinematics> pose_before;
        if (coupling)
        {
          std::vector<MarkerMotion> motions;
          for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
            pose_before.push_back(coupling->kinematics(b));
          coupling->advance(dt, loads);
          coupling->check_clear_of_walls(scene);
          for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
          {
            solids::BodyKinematics velocities_only = coupling->kinematics(b);
            velocities_only.position = pose_before[b].position;
            velocities_only.rotation = pose_before[b].rotation;
            motions.push_back(marker_motion(b, pose_before[b], velocities_only));
          }
          engine->move_solids(motions);
        }
        const StepReport &r = engine->step(dt);
        if (coupling)
        {
          std::vector<MarkerMotion> motions;
          for (std::size_t b = 0; b < coupling->n_bodies(); ++b)
          {
            const std::array<double, 3> F = engine->solid_force(coupling->solid_index(b));
            const std::array<double, 3> T = engine->solid_torque(coupling->solid_index(b));
            loads[b].force  = solids::Vector3(F[0], F[1], F[2]);
            loads[b].torque = solids::Vector3(T[0], T[1], T[2]);
            motions.push_back(marker_motion(b, pose_before[b], coupling->kinematics(b)));
          }
          engine->move_solids(motions);
        }
        t += dt;
        ++result.steps;
        result.timings["neighbour search"] += r.t_neighbors;
        result.timings["assembly"] += r.t_assembly;
        result.timings["velocity solve"] += r.t_velocity;
        result.timings["pressure solve"] += r.t_pressure;
        result.timings["correction and update"] += r.t_update;
        if (!std::isfinite(r.max_speed) || !std::isfinite(r.pressure.residual) ||
            (!r.pressure.converged && r.pressure.residual > 1e-1) || dt < 1e-10 * scene.end_time ||
            r.max_speed > 50 * u_ref)
        {
          // Keep the last good state for diagnosis (P still holds the previous step), also as a
          // checkpoint to restart from (e.g. with a smaller time step or other settings).
          checkpoint("last_good_state.bin", t - dt, result.steps - 1);
          std::ofstream dump(dir + "/last_good_state.csv");
          dump << "# twinflow: SPH particles at the last step before divergence\nx,y,z,u,v,w,p,rho,kind\n";
          for (std::size_t i = 0; i < P.size(); ++i)
          {
            for (int d = 0; d < 3; ++d)
              dump << (d < dim ? P.x[i][d] : 0.0) << ",";
            for (int d = 0; d < 3; ++d)
              dump << (d < dim ? P.u[i][d] : 0.0) << ",";
            dump << P.p[i] << "," << P.rho[i] << "," << P.kind[i] << "\n";
          }
          throw std::runtime_error("SPH solution diverged at t = " + std::to_string(t) + " (step " +
                                   std::to_string(result.steps) + "; pressure residual " + std::to_string(r.pressure.residual) +
                                   ", max speed " + std::to_string(r.max_speed) +
                                   " m/s): reduce SPH/Time step or CFL number. Monitors so far and the last good "
                                   "particle state (last_good_state.csv, and last_good_state.bin to restart from) are in " +
                                   dir);
        }
        // where the mechanical energy change came from, summed over the run (EnergyBudget)
        budget.viscous += r.budget.viscous;
        budget.body_force += r.budget.body_force;
        budget.pressure += r.budget.pressure;
        budget.potential += r.budget.potential;
        budget.shifting += r.budget.shifting;
        budget.density_correction += r.budget.density_correction;
        energy_budget.append({t, budget.viscous, budget.body_force, budget.pressure, budget.potential, budget.shifting,
                              budget.density_correction});
        if (open.active())
        {
          engine->get_particles(P);
          if (remove_beyond(open, P) > 0)
            engine->set_particles(P);
        }
        dealii::Timer out_timer;
        monitors(t, dt, &r);
        if (body_monitor)
          body_monitor->append(t, loads);
        snapshot(t);
        if (scene.output_interval > 0 && t >= next_output * (1 - 1e-9))
        {
          write(t);
          next_output += scene.output_interval;
        }
        if (checkpoint_interval > 0 && t >= next_checkpoint * (1 - 1e-9))
        {
          checkpoint("checkpoint.bin", t, result.steps);
          next_checkpoint += checkpoint_interval;
        }
        t_output += out_timer.wall_time();
        std::ostringstream extra;
        extra << "dt " << dt << "  its " << r.velocity[0].iterations << "/" << r.pressure.iterations << "  |u|max "
              << r.max_speed << "  surface " << r.free_surface_particles;
        progress.update(t, result.steps, extra.str());
      }
      progress.finish();
      if (scene.output_interval == 0)
        write(t);
      result.timings["monitors and output"] = t_output;
      result.wall_time  = wall.wall_time();
      result.final_time = t;

      io::RunSummary summary(self);
      summary.set_method("sph");
      summary.set_dimension(dim);
      summary.set_scene(scene.name);
      summary.set_particles(P.size());
      summary.set_steps(result.steps);
      summary.set_final_time(t);
      summary.set_wall_time(result.wall_time);
      for (const auto &[k, v] : result.timings)
        summary.set_timer_section(k, v, result.steps - start.steps);
      io::add_front_reference_errors(scene, front_t, front_x, summary, result.monitors);
      // where the mechanical energy change came from, summed over the run (EnergyBudget)
      result.monitors["energy budget: viscous [J]"]               = budget.viscous;
      result.monitors["energy budget: body force work [J]"]       = budget.body_force;
      result.monitors["energy budget: pressure correction [J]"]   = budget.pressure;
      result.monitors["energy budget: potential of the move [J]"] = budget.potential;
      result.monitors["energy budget: shifting [J]"]              = budget.shifting;
      result.monitors["energy budget: density-error displacement [J]"] = budget.density_correction;
      result.monitors["energy rise (max)"] = worst_energy_rise;
      // A free surface under gravity in fixed walls, with no body force, moving body or outflow,
      // is dissipative: its energy must never rise (the FEM reports the same quantity)
      bool dissipative = s.free_surface && s.gravity_norm() > 0 && !coupling && !open.active();
      for (int d = 0; d < dim; ++d)
        dissipative = dissipative && scene.body_force[d] == 0;
      if (dissipative)
        summary.add_error("energy rise above the initial value (max over the run)", worst_energy_rise, 0.0, 5e-3,
                          "fluid kinetic + potential energy; a free-surface flow in fixed walls is dissipative");
      if (scene.reference_hydrostatic)
      {
        // Fluid at rest: final bulk pressure against rho |g| (H_0 - y) (hydrostatic_check.h).
        engine->get_particles(P);
        const bool             offset = s.offsets_surface();
        const HydrostaticCheck c      = hydrostatic_check<dim>(scene, prm.spacing, P, offset);
        summary.add_error("hydrostatic bulk pressure (RMS relative error)", c.rms_relative_error, 0.0, 0.01,
                          std::string("final bulk pressure against rho |g| (") + (offset ? "H" : "H - dx/2") +
                            " - y) over " + std::to_string(c.bulk_particles) +
                            " particles more than " + std::to_string(int(hydrostatic_bulk_margin)) +
                            " spacings below the surface and from the walls; reference 0 = exact");
        result.monitors["hydrostatic max relative error"] = c.max_relative_error;
        result.monitors["hydrostatic rms relative error"] = c.rms_relative_error;
        result.monitors["bulk max speed"]                 = c.bulk_max_speed;
        result.monitors["fluid rms speed"]                = c.rms_speed;
        summary.set_extra("hydrostatic bulk particles", c.bulk_particles);
      }
      if (!force_t.empty())
      {
        // Steady coefficients: time averages over the last quarter of the run (the particle
        // force fluctuates step to step; the average is what converges to the steady value).
        double cd = 0, cl = 0, cd2 = 0;
        int    count = 0;
        for (std::size_t k = 0; k < force_t.size(); ++k)
          if (force_t[k] >= 0.75 * t)
          {
            cd += drag_series[k];
            cl += lift_series[k];
            cd2 += drag_series[k] * drag_series[k];
            ++count;
          }
        cd /= count;
        cl /= count;
        result.monitors["C_d"]             = cd;
        result.monitors["C_l"]             = cl;
        result.monitors["C_d (last step)"] = drag_series.back();
        summary.set_extra("C_d standard deviation (last quarter)", std::sqrt(std::max(0.0, cd2 / count - cd * cd)));
        if (scene.reference_drag)
          summary.add_error("drag coefficient C_d", cd, *scene.reference_drag, std::nullopt,
                            "SPH: mean over the last quarter of the run");
        if (scene.reference_lift)
          summary.add_error("lift coefficient C_l", cl, *scene.reference_lift, std::nullopt,
                            "SPH: mean over the last quarter of the run");
      }
      if (body_monitor)
      {
        body_monitor->summarise(summary, result.monitors);
        summary.set_extra("rigid-body RK4 sub-steps", double(coupling->substeps_taken()));
        summary.set_extra("rigid-body sub-steps touching a wall", double(coupling->contact_substeps()));
        summary.set_extra("rigid-body deepest wall penetration before projection [m]", coupling->max_contact_depth());
      }
      summary.set_monitor_values(result.monitors);
      {
        std::string physics;
        for (const auto &p : result.active_physics)
          physics += (physics.empty() ? "" : "; ") + p;
        summary.set_extra("active physics", physics);
      }
      summary.set_extra("fluid particles", result.fluid_particles);
      summary.set_extra("BCE markers", result.markers);
      if (open.active())
      {
        result.removed_particles =
          result.fluid_particles - std::count(P.kind.begin(), P.kind.end(), int(ParticleKind::fluid));
        summary.set_extra("fluid particles removed at the open " + open.name, result.removed_particles);
      }
      summary.set_extra("backend", std::string(engine->backend()));
      if (restart) // wall time, steps per second and timers cover the restarted part only
        summary.set_extra("restarted from time [s]", start.time);
      summary.set_extra("neighbour entries per particle", double(engine->n_neighbor_entries()) / P.size());
      summary.set_extra("memory per particle [B]", engine->bytes_per_particle());
      summary.set_extra("particle-steps per second", double(P.size()) * (result.steps - start.steps) / result.wall_time);
      summary.write_json(dir + "/summary.json");
      summary.print_table(std::cout);
      return result;
    }
  } // namespace

  /// Lattice points (spacing 1) closer than 2 h/Δx to the origin, the origin included.
  int full_support_count(const int dim, const double h_over_dx)
  {
    const double r2 = 4 * h_over_dx * h_over_dx;
    const int    m  = static_cast<int>(std::ceil(2 * h_over_dx));
    int          count = 0;
    for (int i = -m; i <= m; ++i)
      for (int j = -m; j <= m; ++j)
        for (int k = (dim == 3 ? -m : 0); k <= (dim == 3 ? m : 0); ++k)
          count += i * i + j * j + k * k < r2 ? 1 : 0;
    return count;
  }

  EngineSettings make_engine_settings(const Scene &scene, const SphParameters &prm)
  {
    const Fluid   &fluid = scene.fluids.front();
    EngineSettings s;
    s.spacing            = prm.spacing;
    s.h                  = prm.h_over_dx * prm.spacing;
    s.rho0               = fluid.density;
    s.mu                 = fluid.viscosity;
    s.consistent         = prm.consistent;
    s.alpha              = prm.alpha;
    s.density_correction = prm.density_correction;
    s.pressure_wall      = prm.neumann_walls ? PressureWall::neumann : PressureWall::bce;
    s.free_surface_ratio = prm.free_surface_ratio;
    s.free_surface_divergence = prm.free_surface_divergence_ratio * scene.dimension;
    s.free_surface_min_neighbours = prm.free_surface_neighbour_ratio * full_support_count(scene.dimension, s.h / s.spacing);
    // A droplet: fewer fluid neighbours than `Free-surface droplet ratio` (0.15) of a full
    // support (2D 3.15 of 21, 3D 8.6 of 57). No particle of a continuous body of water has so few: a corner particle of a full
    // tank has 7 (2D) / 16 (3D) others. Without it a droplet against a wall, whose support
    // BCE markers fill up, is an interior particle, and the markers beside it and it form a
    // block of the pressure system with no p = 0 row (singular: the paper's dam break at
    // Δx = H/80 and CFL 0.5 stopped at t = 1.43 s on two particles caught in a top corner).
    s.free_surface_min_fluid_neighbours = prm.free_surface_droplet_ratio * full_support_count(scene.dimension, s.h / s.spacing);
    s.free_surface       = scene.fluid_region.has_value();
    s.open_face          = open_face(scene).face;
    s.shifting           = prm.shifting;
    s.shifting_velocity_floor = prm.shifting_velocity_floor;
    s.min_pair_distance       = prm.min_pair_distance;
    s.limit_pressure_peaks    = prm.limit_pressure_peaks;
    s.wetted_walls            = prm.wetted_walls;
    s.conservative_gradient        = prm.energy_conserving_pair;
    s.shifting_velocity_correction = prm.energy_conserving_pair;
    s.surface_offset          = prm.surface_offset;
    for (int d = 0; d < 3; ++d)
    {
      s.acceleration[d] = scene.gravity[d] + scene.body_force[d];
      s.gravity[d]      = scene.gravity[d];
    }
    s.velocity_solver = {prm.max_iterations, prm.solver_tolerance};
    s.pressure_solver = {prm.max_iterations, prm.solver_tolerance};
    s.pressure_preconditioner = prm.multigrid ? PressurePreconditioner::multigrid : PressurePreconditioner::jacobi;
    s.correction_checks.positive_definite_laplacian = prm.positive_definite_laplacian;
    if (prm.relax_over_reference_step) // the step the run takes while no particle is faster than U_ref
      s.density_relaxation_time =
        prm.cfl > 0 ? std::min(prm.time_step, prm.cfl * s.h / scene.reference_velocity) : prm.time_step;
    return s;
  }

  SphRunResult run_sph_scene(const Scene &scene, const SphParameters &prm, const std::string &dir)
  {
    // SPH neglects the second (air) phase of a two-fluid scene: fluid 1 is simulated.
    SphRunResult r;
    if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      r = scene.dimension == 2 ? run<2>(scene, prm, dir) : run<3>(scene, prm, dir);
    MPI_Barrier(MPI_COMM_WORLD);
    return r;
  }
} // namespace twinflow::sph
