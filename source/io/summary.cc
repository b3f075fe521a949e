/**
 * @file summary.cc
 * Implementation of RunSummary: collection of the data. JSON output is in
 * summary_json.cc, the text table in summary_table.cc.
 */
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/summary.h>

#include <deal.II/base/timer.h>

#include <cmath>
#include <stdexcept>

namespace twinflow::io
{
  namespace
  {
    template <typename Value>
    void
    set_in_order(std::vector<std::pair<std::string, Value>> &list,
                 const std::string &                         key,
                 Value                                       value)
    {
      for (auto &entry : list)
        if (entry.first == key)
          {
            entry.second = std::move(value);
            return;
          }
      list.emplace_back(key, std::move(value));
    }
  } // namespace

  bool
  ErrorEntry::passed() const
  {
    return !tolerance || relative_error <= *tolerance; // NaN compares false
  }

  RunSummary::RunSummary(MPI_Comm comm)
    : writer(is_root_process(comm))
    , start(std::chrono::steady_clock::now())
  {
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (initialized && !finalized)
      MPI_Comm_size(comm, &n_ranks);
  }

  void
  RunSummary::set_method(const std::string &m)
  {
    method = m;
  }

  void
  RunSummary::set_dimension(const unsigned int d)
  {
    dim = d;
  }

  void
  RunSummary::set_scene(const std::string &s)
  {
    scene = s;
  }

  void
  RunSummary::set_cells(const std::uint64_t n)
  {
    cells = n;
  }

  void
  RunSummary::set_dofs(const std::string &field, const std::uint64_t n)
  {
    set_in_order(dofs, field, n);
  }

  void
  RunSummary::set_particles(const std::uint64_t n)
  {
    particles = n;
  }

  void
  RunSummary::set_steps(const std::uint64_t n)
  {
    steps = n;
  }

  void
  RunSummary::set_final_time(const double t)
  {
    final_time = t;
  }

  void
  RunSummary::set_wall_time(const double seconds)
  {
    wall_seconds = seconds;
  }

  void
  RunSummary::set_timer_sections(const dealii::TimerOutput &timer)
  {
    const auto wall  = timer.get_summary_data(dealii::TimerOutput::total_wall_time);
    const auto calls = timer.get_summary_data(dealii::TimerOutput::n_calls);
    for (const auto &[name, seconds] : wall)
      {
        const auto c = calls.find(name);
        set_timer_section(name,
                          seconds,
                          c == calls.end() ? 0 : static_cast<std::uint64_t>(std::llround(c->second)));
      }
  }

  void
  RunSummary::set_timer_section(const std::string &name,
                                const double       seconds,
                                const std::uint64_t n_calls)
  {
    set_in_order(timers, name, TimerSection{seconds, n_calls});
  }

  void
  RunSummary::set_monitor_value(const std::string &name, const double value)
  {
    set_in_order(monitors, name, value);
  }

  void
  RunSummary::set_monitor_values(const std::map<std::string, double> &values)
  {
    for (const auto &[name, value] : values)
      set_monitor_value(name, value);
  }

  void
  RunSummary::add_error(const std::string &   quantity,
                        const double          measured,
                        const double          reference,
                        std::optional<double> tolerance,
                        const std::string &   note)
  {
    ErrorEntry e;
    e.quantity       = quantity;
    e.measured       = measured;
    e.reference      = reference;
    e.relative_error = reference != 0 ? std::abs(measured - reference) / std::abs(reference) :
                                        std::abs(measured);
    e.tolerance      = tolerance;
    e.note           = note;
    add_error(e);
  }

  void
  RunSummary::add_series_error(const std::string &   quantity,
                               const SeriesError &   error,
                               std::optional<double> tolerance,
                               const std::string &   note)
  {
    ErrorEntry e;
    e.quantity       = quantity;
    e.measured       = error.rms_error;
    e.reference      = std::nan("");
    e.relative_error = error.rms_relative_error;
    e.tolerance      = tolerance;
    e.note           = note;
    e.series         = error;
    add_error(e);
  }

  void
  RunSummary::add_error(const ErrorEntry &entry)
  {
    error_entries.push_back(entry);
  }

  bool
  RunSummary::all_errors_within_tolerance() const
  {
    for (const auto &e : error_entries)
      if (!e.passed())
        return false;
    return true;
  }

  void
  RunSummary::set_extra(const std::string &key, const double value)
  {
    set_extra_value(key, value);
  }

  void
  RunSummary::set_extra(const std::string &key, const bool value)
  {
    set_extra_value(key, value);
  }

  void
  RunSummary::set_extra(const std::string &key, const std::string &value)
  {
    set_extra_value(key, value);
  }

  void
  RunSummary::set_extra(const std::string &key, const char *value)
  {
    set_extra_value(key, std::string(value ? value : ""));
  }

  void
  RunSummary::set_extra_value(const std::string &key, ExtraValue value)
  {
    set_in_order(extras, key, std::move(value));
  }

  std::uint64_t
  RunSummary::total_dofs() const
  {
    std::uint64_t n = 0;
    for (const auto &d : dofs)
      n += d.second;
    return n;
  }

  double
  RunSummary::wall_time() const
  {
    if (wall_seconds)
      return *wall_seconds;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  const std::vector<ErrorEntry> &
  RunSummary::errors() const
  {
    return error_entries;
  }

} // namespace twinflow::io
