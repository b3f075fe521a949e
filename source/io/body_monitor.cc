#include <twinflow/io/body_monitor.h>
#include <twinflow/io/csv_table.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/summary.h>

#include <algorithm>
#include <cmath>

namespace twinflow::io
{
  BodyMonitor::BodyMonitor(const std::string &dir, const solids::CoSimulation &bodies, const int dim_,
                           const std::array<double, 3> &gravity, MPI_Comm comm, const double restart_time)
    : co(bodies), dim(dim_), g(gravity[0], gravity[1], gravity[2])
  {
    for (std::size_t b = 0; b < co.n_bodies(); ++b)
    {
      std::vector<std::string> cols{"time", "x", "y"}, units{"s", "m", "m"};
      if (dim == 3)
        cols.insert(cols.end(), {"z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz", "Fx", "Fy", "Fz",
                                 "Tx", "Ty", "Tz"}),
          units.insert(units.end(), {"m", "-", "-", "-", "-", "m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s", "N", "N",
                                     "N", "N m", "N m", "N m"});
      else
        cols.insert(cols.end(), {"angle", "vx", "vy", "wz", "Fx", "Fy", "Tz"}),
          units.insert(units.end(), {"rad", "m/s", "m/s", "rad/s", "N", "N", "N m"});
      cols.insert(cols.end(), {"kinetic energy", "potential energy"});
      units.insert(units.end(), {"J", "J"});
      const std::string path = dir + "/body_" + co.name(b) + ".csv";
      // a restart keeps the rows up to its time; only the writing rank reads (the others
      // would race with its rewrite)
      const auto carried = restart_time >= 0 && is_root_process(comm) ? monitor_rows_until(path, restart_time)
                                                                       : std::vector<std::vector<double>>();
      files.push_back(std::make_unique<CsvMonitor>(path, cols, units, comm, "body"));
      lift.emplace_back();
      const std::size_t fx = std::find(cols.begin(), cols.end(), "Fx") - cols.begin();
      for (const auto &row : carried)
        if (row.size() == cols.size())
        {
          files[b]->append(row);
          if (b == 0)
            times.push_back(row[0]);
          const solids::Vector3 F(row[fx], row[fx + 1], dim == 3 ? row[fx + 2] : 0.0);
          lift[b].push_back(g.norm() > 0 ? -F.dot(g.normalized()) : 0.0);
        }
    }
  }

  void BodyMonitor::append(const double t, const std::vector<solids::BodyLoad> &loads)
  {
    times.push_back(t);
    for (std::size_t b = 0; b < co.n_bodies(); ++b)
    {
      const solids::RigidBody &body = co.body(b);
      const auto              &s    = body.state();
      const solids::Vector3    w    = body.angular_velocity();
      const solids::BodyLoad   load = b < loads.size() ? loads[b] : solids::BodyLoad();
      std::vector<double>      row{t, s.position.x(), s.position.y()};
      if (dim == 3)
        row.insert(row.end(), {s.position.z(), s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z(),
                               s.velocity.x(), s.velocity.y(), s.velocity.z(), w.x(), w.y(), w.z(), load.force.x(),
                               load.force.y(), load.force.z(), load.torque.x(), load.torque.y(), load.torque.z()});
      else
      {
        const solids::Matrix3 R = body.rotation();
        row.insert(row.end(), {std::atan2(R(1, 0), R(0, 0)), s.velocity.x(), s.velocity.y(), w.z(), load.force.x(),
                               load.force.y(), load.torque.z()});
      }
      row.insert(row.end(), {body.kinetic_energy(), body.potential_energy()});
      files[b]->append(row);
      lift[b].push_back(g.norm() > 0 ? -load.force.dot(g.normalized()) : 0.0);
    }
  }

  void BodyMonitor::summarise(RunSummary &summary, std::map<std::string, double> &monitors) const
  {
    if (times.empty())
      return;
    const double t_end = times.back();
    for (std::size_t b = 0; b < co.n_bodies(); ++b)
    {
      const solids::RigidBody &body = co.body(b);
      const std::string        key  = "body " + co.name(b);
      monitors[key + " final x"]    = body.state().position.x();
      monitors[key + " final y"]    = body.state().position.y();
      if (dim == 3)
        monitors[key + " final z"] = body.state().position.z();
      if (g.norm() == 0)
        continue;
      double sum = 0;
      int    count = 0;
      for (std::size_t k = 0; k < times.size(); ++k)
        if (times[k] >= 0.75 * t_end && times[k] > 0)
          sum += lift[b][k], ++count;
      if (count == 0)
        continue;
      const double mean = sum / count;
      monitors[key + " mean vertical fluid force (last quarter)"] = mean;
      summary.add_error(key + ": vertical fluid force against the weight m|g|", mean, body.mass_properties().mass * g.norm(),
                        std::nullopt,
                        "mean over the last quarter of the run; a body floating at rest carries exactly its weight");
    }
  }
} // namespace twinflow::io
