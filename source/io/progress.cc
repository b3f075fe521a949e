/**
 * @file progress.cc
 * Implementation of ProgressReporter and format_duration().
 */
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/progress.h>

#include <cmath>
#include <cstdio>

namespace twinflow::io
{
  std::string
  format_duration(const double seconds)
  {
    if (!std::isfinite(seconds) || seconds < 0)
      return "--";
    char buf[48];
    if (seconds < 59.95)
      std::snprintf(buf, sizeof(buf), "%.1f s", seconds);
    else
      {
        const auto s = static_cast<long long>(std::llround(seconds));
        if (s < 3600)
          std::snprintf(buf, sizeof(buf), "%lldm %02llds", s / 60, s % 60);
        else if (s < 86400)
          std::snprintf(buf, sizeof(buf), "%lldh %02lldm", s / 3600, (s % 3600) / 60);
        else
          std::snprintf(buf, sizeof(buf), "%lldd %02lldh", s / 86400, (s % 86400) / 3600);
      }
    return buf;
  }

  ProgressReporter::ProgressReporter(const double  t_start,
                                     const double  t_end,
                                     std::ostream &out,
                                     const double  min_interval_seconds,
                                     MPI_Comm      comm)
    : t_start(t_start)
    , t_end(t_end)
    , out(out)
    , min_interval(min_interval_seconds)
    , writer(is_root_process(comm))
    , start(std::chrono::steady_clock::now())
    , last_t(t_start)
  {}

  ProgressReporter::ProgressReporter(const double  t_start,
                                     const double  t_end,
                                     std::ostream &out,
                                     MPI_Comm      comm,
                                     const double  min_interval_seconds)
    : ProgressReporter(t_start, t_end, out, min_interval_seconds, comm)
  {}

  double
  ProgressReporter::elapsed_seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::string
  ProgressReporter::format_line(const double        t,
                                const std::uint64_t step,
                                const std::string & extra) const
  {
    const double span     = t_end - t_start;
    const double fraction = span > 0 ? (t - t_start) / span : std::nan("");
    const double elapsed  = elapsed_seconds();
    const double eta =
      fraction > 0 ? elapsed * (1.0 - fraction) / fraction : std::nan(""); // NaN -> "--"

    // Fixed 4 decimals for times of order 1e-2 and above, else scientific.
    const bool small = std::abs(t_end) < 1e-2 && t_end != 0;
    char       buf[160];
    std::snprintf(buf,
                  sizeof(buf),
                  small ? "step %llu  t = %.4e / %g s" : "step %llu  t = %.4f / %g s",
                  static_cast<unsigned long long>(step),
                  t,
                  t_end);
    std::string line = buf;
    if (std::isfinite(fraction))
      {
        std::snprintf(buf, sizeof(buf), " (%.1f %%)", 100.0 * fraction);
        line += buf;
      }
    line += "  elapsed " + format_duration(elapsed) + "  ETA " + format_duration(eta);
    if (!extra.empty())
      line += "  " + extra;
    return line;
  }

  bool
  ProgressReporter::update(const double        t,
                           const std::uint64_t step,
                           const std::string & extra,
                           const bool          force)
  {
    last_t    = t;
    last_step = step;
    if (!writer)
      return false;
    const double now = elapsed_seconds();
    if (!force && now - last_print_time < min_interval)
      return false;
    last_print_time = now;
    out << format_line(t, step, extra) << std::endl;
    return true;
  }

  void
  ProgressReporter::finish(const std::string &extra)
  {
    if (finished)
      return;
    finished = true;
    if (!writer)
      return;
    char buf[96];
    std::snprintf(buf,
                  sizeof(buf),
                  "done: step %llu  t = %g s  wall time ",
                  static_cast<unsigned long long>(last_step),
                  last_t);
    out << buf << format_duration(elapsed_seconds());
    if (!extra.empty())
      out << "  " << extra;
    out << std::endl;
  }
} // namespace twinflow::io
