#pragma once
/**
 * @file summary.h
 * Machine- and human-readable summary of one run (FEM or SPH): problem size,
 * cost (wall time, per-section timings), final monitor values and errors
 * against reference data. Written as JSON (schema: doc/summary_schema.md)
 * and printed as a table at the end of a run.
 */
#include <twinflow/io/reference_data.h>

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace dealii
{
  class TimerOutput;
}

namespace twinflow::io
{
  /// One comparison of a simulated quantity with a reference value or curve.
  struct ErrorEntry
  {
    std::string quantity;       ///< e.g. "front position x(t)" or "Strouhal number"
    double      measured  = 0;  ///< simulated value (series: RMS error, see below)
    double      reference = 0;  ///< reference value (series: NaN, written as null)
    double      relative_error = 0;
    std::optional<double>      tolerance; ///< accepted relative error, if any
    std::string                note;      ///< free text (source of the reference, ...)
    std::optional<SeriesError> series;    ///< set for time-series comparisons

    /// True without tolerance; otherwise relative_error <= tolerance (NaN fails).
    bool
    passed() const;
  };

  /// Collects the facts of a run and writes them (rank 0 only).
  class RunSummary
  {
  public:
    /// Value of a free-form extra entry.
    using ExtraValue = std::variant<double, long long, bool, std::string>;

    /// Starts the wall-clock measurement (see set_wall_time()); only rank 0 of @p comm writes.
    explicit RunSummary(MPI_Comm comm = MPI_COMM_WORLD);

    /// @name Identification of the run
    /// @{
    void
    set_method(const std::string &method); ///< "fem" or "sph"
    void
    set_dimension(unsigned int dim);
    void
    set_scene(const std::string &scene);
    /// @}

    /// @name Problem size and cost
    /// @{
    void
    set_cells(std::uint64_t n_active_cells);
    /// Degrees of freedom of one field ("velocity", "pressure", "level set", ...).
    void
    set_dofs(const std::string &field, std::uint64_t n_dofs);
    void
    set_particles(std::uint64_t n_particles);
    void
    set_steps(std::uint64_t n_steps);
    /// Simulated end time [s].
    void
    set_final_time(double t);
    /// Total wall time [s]; if never called, the time since construction is used.
    void
    set_wall_time(double seconds);
    /// Wall time and call count of every section of @p timer (values of this process).
    void
    set_timer_sections(const dealii::TimerOutput &timer);
    /// One timed section by hand (for code that does not use dealii::TimerOutput).
    void
    set_timer_section(const std::string &name, double wall_seconds, std::uint64_t n_calls = 0);
    /// @}

    /// @name Results
    /// @{
    void
    set_monitor_value(const std::string &name, double value);
    void
    set_monitor_values(const std::map<std::string, double> &values);
    /**
     * Compare a scalar with a reference: relative error |m - r| / |r|
     * (absolute error |m| if r == 0).
     */
    void
    add_error(const std::string &        quantity,
              double                     measured,
              double                     reference,
              std::optional<double>      tolerance = std::nullopt,
              const std::string &        note      = "");
    /// A time-series comparison (compare_series()); relative error = rms_relative_error.
    void
    add_series_error(const std::string &   quantity,
                     const SeriesError &   error,
                     std::optional<double> tolerance = std::nullopt,
                     const std::string &   note      = "");
    void
    add_error(const ErrorEntry &entry);
    /// True if every error entry with a tolerance passed.
    bool
    all_errors_within_tolerance() const;
    /// @}

    /// @name Free-form extra entries (replaced if the key exists; kept in insertion order)
    /// @{
    void
    set_extra(const std::string &key, double value);
    void
    set_extra(const std::string &key, bool value);
    void
    set_extra(const std::string &key, const std::string &value);
    void
    set_extra(const std::string &key, const char *value);
    template <typename Int,
              std::enable_if_t<std::is_integral_v<Int> && !std::is_same_v<Int, bool>, int> = 0>
    void
    set_extra(const std::string &key, const Int value)
    {
      set_extra_value(key, static_cast<long long>(value));
    }
    /// @}

    /// The summary as pretty-printed JSON text (on every rank).
    std::string
    to_json() const;
    /// Write to_json() to @p path (rank 0 only; creates the directory).
    void
    write_json(const std::string &path) const;
    /// Human-readable cost / accuracy table (rank 0 only; other ranks print nothing).
    void
    print_table(std::ostream &out) const;

    /// Total wall time [s]: set_wall_time() value or time since construction.
    double
    wall_time() const;
    const std::vector<ErrorEntry> &
    errors() const;

  private:
    struct TimerSection
    {
      double        wall_seconds = 0;
      std::uint64_t calls        = 0;
    };

    void
    set_extra_value(const std::string &key, ExtraValue value);
    std::uint64_t
    total_dofs() const;

    bool                                               writer;
    int                                                n_ranks = 1;
    std::chrono::steady_clock::time_point              start;
    std::string                                        method, scene;
    unsigned int                                       dim = 0;
    std::optional<std::uint64_t>                       cells, particles, steps;
    std::vector<std::pair<std::string, std::uint64_t>> dofs;
    std::optional<double>                              final_time, wall_seconds;
    std::vector<std::pair<std::string, TimerSection>>  timers;
    std::vector<std::pair<std::string, double>>        monitors;
    std::vector<ErrorEntry>                            error_entries;
    std::vector<std::pair<std::string, ExtraValue>>    extras;
  };
} // namespace twinflow::io
