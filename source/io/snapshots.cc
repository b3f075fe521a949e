/**
 * @file snapshots.cc
 * Implementation of snapshot_file_name() and SnapshotSchedule (snapshots.h).
 */
#include <twinflow/io/snapshots.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace twinflow::io
{
  namespace
  {
    bool
    reached(const double s, const double t)
    {
      return t >= s * (1 - 1e-9);
    }
  } // namespace

  std::string
  snapshot_file_name(const std::string &prefix, const double time)
  {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "_t%.3f.csv", time);
    return prefix + buffer;
  }

  SnapshotSchedule::SnapshotSchedule(std::vector<double> times, const double start_time, const bool restart)
    : remaining(std::move(times))
  {
    std::sort(remaining.begin(), remaining.end());
    remaining.erase(std::unique(remaining.begin(), remaining.end()), remaining.end());
    if (restart)
      remaining.erase(std::remove_if(remaining.begin(), remaining.end(),
                                     [&](const double s) { return reached(s, start_time); }),
                      remaining.end());
  }

  std::vector<double>
  SnapshotSchedule::due(const double t)
  {
    const auto end = std::find_if(remaining.begin(), remaining.end(), [&](const double s) { return !reached(s, t); });
    std::vector<double> now(remaining.begin(), end);
    remaining.erase(remaining.begin(), end);
    return now;
  }

  const std::vector<double> &
  SnapshotSchedule::pending() const
  {
    return remaining;
  }
} // namespace twinflow::io
