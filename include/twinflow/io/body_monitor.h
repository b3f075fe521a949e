#pragma once
/**
 * @file body_monitor.h
 * Time series of the moving bodies of a co-simulation (solids/coupling.h), shared by both
 * fluid methods: one CSV per body, `body_<name>.csv`, with the centre, the orientation (2D: the
 * angle about z; 3D: the unit quaternion), velocity, angular velocity, the fluid's force and
 * torque, and the body's kinetic and potential energy. Also what the run summary reports of a
 * body: the time-averaged fluid force over the last quarter of the run against the weight.
 */
#include <twinflow/io/csv_monitor.h>
#include <twinflow/solids/coupling.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::io
{
  class RunSummary;

  class BodyMonitor
  {
  public:
    /// Opens one CSV per body of @p bodies in @p dir (rank 0 of @p comm writes); @p gravity: the
    /// scene's g (3 components), whose opposite is "vertical".
    /// @p restart_time >= 0: a restarted run; the files' rows up to it are kept (and count in
    /// the summary).
    BodyMonitor(const std::string &dir, const solids::CoSimulation &bodies, int dim, const std::array<double, 3> &gravity,
                MPI_Comm comm, double restart_time = -1.0);

    /// One row per body at time @p t with the fluid @p loads of that step.
    void append(double t, const std::vector<solids::BodyLoad> &loads);

    /// Adds, per body free to move along gravity, the mean fluid force along −g over the last
    /// quarter of the run against the weight m|g| (what floating equilibrium must reach), and the
    /// final position, to @p summary and @p monitors.
    void summarise(RunSummary &summary, std::map<std::string, double> &monitors) const;

  private:
    const solids::CoSimulation              &co;
    int                                      dim;
    solids::Vector3                          g;
    std::vector<std::unique_ptr<CsvMonitor>> files;
    std::vector<double>                      times;
    std::vector<std::vector<double>>         lift; ///< per body: fluid force along −g
  };
} // namespace twinflow::io
