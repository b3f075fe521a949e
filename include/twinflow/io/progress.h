#pragma once
/**
 * @file progress.h
 * Throttled progress lines for long time loops:
 * @code
 * step 120  t = 0.3400 / 2.5 s (13.6 %)  elapsed 12.1 s  ETA 1m 17s  dt = 2e-3, 12 GMRES its
 * @endcode
 * Only rank 0 of the communicator prints.
 */
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace twinflow::io
{
  /**
   * A duration in compact human form: "12.1 s" below a minute, "1m 17s"
   * below an hour, "2h 03m" below a day, "3d 04h" beyond; "--" if negative
   * or not finite.
   */
  std::string
  format_duration(double seconds);

  /// Prints the progress of a simulation from t_start to t_end at most every few seconds.
  class ProgressReporter
  {
  public:
    /**
     * @param t_start, t_end simulated time interval (t_end > t_start for a
     *        meaningful percentage and ETA)
     * @param out            stream printed to (on rank 0 of @p comm)
     * @param min_interval_seconds minimum wall time between two lines; 0
     *        prints on every update()
     * The wall clock for "elapsed" and "ETA" starts at construction.
     */
    ProgressReporter(double        t_start,
                     double        t_end,
                     std::ostream &out,
                     double        min_interval_seconds = 2.0,
                     MPI_Comm      comm                 = MPI_COMM_WORLD);

    /// Same, with the communicator before the interval.
    ProgressReporter(double        t_start,
                     double        t_end,
                     std::ostream &out,
                     MPI_Comm      comm,
                     double        min_interval_seconds = 2.0);

    /**
     * Report that step @p step reached time @p t. Prints a line if at least
     * min_interval_seconds passed since the last line (or since construction),
     * or if @p force is true. Returns true if a line was printed on this
     * process. @p extra is appended to the line (e.g. solver statistics).
     */
    bool
    update(double t, std::uint64_t step, const std::string &extra = "", bool force = false);

    /**
     * Print the final line `done: step N  t = ... s  wall time ...` with the
     * values of the last update(). Only the first call prints.
     */
    void
    finish(const std::string &extra = "");

    /// The line update() would print now (on every rank; for tests and logs).
    std::string
    format_line(double t, std::uint64_t step, const std::string &extra) const;

    /// Wall time since construction [s].
    double
    elapsed_seconds() const;

  private:
    double                                t_start, t_end;
    std::ostream &                        out;
    double                                min_interval;
    bool                                  writer;
    std::chrono::steady_clock::time_point start;
    double                                last_print_time = 0.0; ///< seconds since start
    double                                last_t;
    std::uint64_t                         last_step = 0;
    bool                                  finished  = false;
  };
} // namespace twinflow::io
