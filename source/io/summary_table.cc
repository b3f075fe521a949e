/**
 * @file summary_table.cc
 * RunSummary::print_table(): the human-readable cost / accuracy summary
 * printed at the end of a run.
 */
#include <twinflow/io/progress.h> // format_duration()
#include <twinflow/io/summary.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <variant>

namespace twinflow::io
{
  namespace
  {
    constexpr int width = 78;

    std::string
    rule(const std::string &title, const char fill = '-')
    {
      if (title.empty())
        return std::string(width, fill);
      const std::string t     = " " + title + " ";
      const int         left  = std::max(2, (width - static_cast<int>(t.size())) / 2);
      const int         right = std::max(2, width - left - static_cast<int>(t.size()));
      return std::string(left, fill) + t + std::string(right, fill);
    }

    template <typename... Args>
    std::string
    format(const char *fmt, Args... args)
    {
      char buf[512];
      std::snprintf(buf, sizeof(buf), fmt, args...);
      return buf;
    }

    std::string
    percent(const double v)
    {
      return std::isfinite(v) ? format("%.3g %%", 100.0 * v) : std::string("--");
    }

    std::string
    number(const double v)
    {
      return std::isfinite(v) ? format("%.6g", v) : std::string("--");
    }

    std::string
    upper(std::string s)
    {
      std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
      return s;
    }
  } // namespace

  void
  RunSummary::print_table(std::ostream &out) const
  {
    if (!writer)
      return;
    const double wall = wall_time();

    out << '\n' << rule("twinflow run summary", '=') << '\n';
    out << format("  method  %-6s  dimension %u  scene %s  MPI ranks %d\n",
                  method.empty() ? "?" : upper(method).c_str(),
                  dim,
                  scene.empty() ? "?" : scene.c_str(),
                  n_ranks);

    // problem size
    std::string size;
    if (cells)
      size += format("%llu cells", static_cast<unsigned long long>(*cells));
    if (!dofs.empty())
      {
        size += format("%s%llu dofs (", size.empty() ? "" : ", ",
                       static_cast<unsigned long long>(total_dofs()));
        for (std::size_t i = 0; i < dofs.size(); ++i)
          size += format("%s%s %llu", i ? ", " : "", dofs[i].first.c_str(),
                         static_cast<unsigned long long>(dofs[i].second));
        size += ")";
      }
    if (particles)
      size += format("%s%llu particles", size.empty() ? "" : ", ",
                     static_cast<unsigned long long>(*particles));
    if (!size.empty())
      out << "  size    " << size << '\n';

    // cost
    std::string cost = "wall time " + format_duration(wall) + format(" (%.4g s)", wall);
    if (steps)
      {
        cost += format(", %llu steps", static_cast<unsigned long long>(*steps));
        if (final_time)
          cost += format(" to t = %g s", *final_time);
        if (*steps > 0)
          {
            const double per_step = wall / static_cast<double>(*steps);
            cost += format(", %.4g ms/step", 1e3 * per_step);
            const double unknowns = !dofs.empty() ? static_cast<double>(total_dofs()) :
                                    particles     ? static_cast<double>(*particles) :
                                                    0.0;
            if (unknowns > 0)
              cost += format(", %.4g ns per step and %s", 1e9 * per_step / unknowns,
                             !dofs.empty() ? "dof" : "particle");
          }
      }
    out << "  cost    " << cost << '\n';

    if (!timers.empty())
      {
        out << rule("wall time by section") << '\n';
        out << format("  %-44s %10s %12s %7s\n", "section", "calls", "wall [s]", "share");
        auto sorted = timers;
        std::stable_sort(sorted.begin(), sorted.end(), [](const auto &a, const auto &b) {
          return a.second.wall_seconds > b.second.wall_seconds;
        });
        for (const auto &[name, s] : sorted)
          out << format("  %-44s %10llu %12.4g %7s\n", name.c_str(),
                        static_cast<unsigned long long>(s.calls), s.wall_seconds,
                        wall > 0 ? format("%.1f%%", 100.0 * s.wall_seconds / wall).c_str() : "--");
      }

    if (!monitors.empty())
      {
        out << rule("final monitor values") << '\n';
        for (const auto &[name, value] : monitors)
          out << format("  %-44s %s\n", name.c_str(), format("%.8g", value).c_str());
      }

    if (!error_entries.empty())
      {
        out << rule("accuracy against references") << '\n';
        out << format("  %-28s %11s %11s %10s %9s  %s\n", "quantity", "measured", "reference",
                      "rel. error", "tolerance", "status");
        for (const auto &e : error_entries)
          {
            const std::string measured =
              e.series ? "rms " + format("%.3g", e.measured) : number(e.measured);
            const std::string reference = e.series ? format("%zu pts", e.series->n_samples) :
                                                     number(e.reference);
            out << format("  %-28s %11s %11s %10s %9s  %s\n", e.quantity.c_str(), measured.c_str(),
                          reference.c_str(), percent(e.relative_error).c_str(),
                          e.tolerance ? percent(*e.tolerance).c_str() : "--",
                          !e.tolerance ? "info" : e.passed() ? "ok" : "FAILED");
            if (!e.note.empty())
              out << "      " << e.note << '\n';
          }
      }

    if (!extras.empty())
      {
        out << rule("other") << '\n';
        for (const auto &[key, v] : extras)
          {
            std::string text;
            if (const auto *d = std::get_if<double>(&v))
              text = format("%.8g", *d);
            else if (const auto *i = std::get_if<long long>(&v))
              text = std::to_string(*i);
            else if (const auto *b = std::get_if<bool>(&v))
              text = *b ? "true" : "false";
            else
              text = std::get<std::string>(v);
            out << format("  %-44s ", key.c_str()) << text << '\n';
          }
      }
    out << rule("", '=') << '\n' << std::flush;
  }
} // namespace twinflow::io
