#pragma once
/**
 * @file snapshots.h
 * Snapshots at given times (Scene/Snapshot times), shared by the FEM and the SPH: the file
 * name both use, so that scripts/plot_snapshots.py pairs them, and the schedule that says
 * when a snapshot is due.
 *
 * A snapshot of time s is written at the first step whose time t >= s (the step's state, its
 * file named after s); s = 0 is the initial state. Files: `<method dir>/snapshots/<prefix>_t<s
 * with 3 decimals>.csv`, e.g. `sph/snapshots/sph_t0.500.csv`, `fem/snapshots/fem_t0.500.csv`.
 */
#include <string>
#include <vector>

namespace twinflow::io
{
  /// "<prefix>_t<time, 3 decimals>.csv", e.g. snapshot_file_name("sph", 0.5) = "sph_t0.500.csv".
  std::string
  snapshot_file_name(const std::string &prefix, double time);

  /**
   * Which snapshot times are due. A run restarted at time t0 does not rewrite the
   * snapshots the run it continues has written: the times s <= t0 count as written.
   */
  class SnapshotSchedule
  {
  public:
    /// @p times in any order (duplicates ignored); @p start_time: the time of the run's
    /// first state (0, or the restart time); @p restart: true if that state was written
    /// by the run it continues (its snapshots at times <= start_time exist).
    SnapshotSchedule(std::vector<double> times, double start_time, bool restart);

    /// The snapshot times s <= @p t not written yet, ascending; they count as written from
    /// now on. Round-off: s counts as reached when t >= s (1 - 1e-9).
    std::vector<double>
    due(double t);

    /// The times not written yet, ascending.
    const std::vector<double> &
    pending() const;

  private:
    std::vector<double> remaining;
  };
} // namespace twinflow::io
