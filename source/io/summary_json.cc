/**
 * @file summary_json.cc
 * RunSummary::to_json() and RunSummary::write_json(); the schema is documented
 * in doc/summary_schema.md (keep both in sync).
 */
#include <twinflow/io/json_writer.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/summary.h>

#include <cmath>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace twinflow::io
{
  namespace
  {
    template <typename T>
    void
    optional_value(JsonWriter &json, const std::optional<T> &v)
    {
      if (v)
        json.value(*v);
      else
        json.null();
    }

    std::string
    utc_timestamp()
    {
      const std::time_t now = std::time(nullptr);
      std::tm           tm{};
      gmtime_r(&now, &tm);
      char buf[32];
      std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
      return buf;
    }
  } // namespace

  std::string
  RunSummary::to_json() const
  {
    std::ostringstream out;
    JsonWriter         json(out);
    const double       wall = wall_time();
    json.begin_object();
    json.key("schema");
    json.value("twinflow.run_summary");
    json.key("schema_version");
    json.value(1);
    json.key("created");
    json.value(utc_timestamp());
    json.key("method");
    json.value(method);
    json.key("dimension");
    json.value(dim);
    json.key("scene");
    json.value(scene);
    json.key("mpi_ranks");
    json.value(n_ranks);

    json.key("size");
    json.begin_object();
    json.key("cells");
    optional_value(json, cells);
    json.key("dofs");
    json.begin_object();
    for (const auto &[field, n] : dofs)
      {
        json.key(field);
        json.value(n);
      }
    json.end_object();
    json.key("dofs_total");
    optional_value(json, dofs.empty() ? std::nullopt : std::optional<std::uint64_t>(total_dofs()));
    json.key("particles");
    optional_value(json, particles);
    json.end_object();

    json.key("time_stepping");
    json.begin_object();
    json.key("steps");
    optional_value(json, steps);
    json.key("final_time_s");
    optional_value(json, final_time);
    json.end_object();

    json.key("cost");
    json.begin_object();
    json.key("wall_time_s");
    json.value(wall);
    json.key("wall_time_per_step_s");
    optional_value(json, steps && *steps > 0 ? std::optional<double>(wall / *steps) : std::nullopt);
    json.key("sections");
    json.begin_object();
    for (const auto &[name, section] : timers)
      {
        json.key(name);
        json.begin_object();
        json.key("wall_time_s");
        json.value(section.wall_seconds);
        json.key("calls");
        json.value(section.calls);
        json.key("fraction");
        json.value(wall > 0 ? section.wall_seconds / wall : std::nan(""));
        json.end_object();
      }
    json.end_object();
    json.end_object();

    json.key("monitors");
    json.begin_object();
    for (const auto &[name, value] : monitors)
      {
        json.key(name);
        json.value(value);
      }
    json.end_object();

    json.key("errors");
    json.begin_array();
    for (const auto &e : error_entries)
      {
        json.begin_object();
        json.key("quantity");
        json.value(e.quantity);
        json.key("measured");
        json.value(e.measured);
        json.key("reference");
        json.value(e.reference);
        json.key("relative_error");
        json.value(e.relative_error);
        json.key("tolerance");
        optional_value(json, e.tolerance);
        json.key("passed");
        json.value(e.passed());
        json.key("note");
        json.value(e.note);
        json.key("series");
        if (e.series)
          {
            const SeriesError &s = *e.series;
            json.begin_object();
            json.key("rms_error");
            json.value(s.rms_error);
            json.key("max_error");
            json.value(s.max_error);
            json.key("rms_relative_error");
            json.value(s.rms_relative_error);
            json.key("max_relative_error");
            json.value(s.max_relative_error);
            json.key("n_samples");
            json.value(s.n_samples);
            json.key("t_begin");
            json.value(s.t_begin);
            json.key("t_end");
            json.value(s.t_end);
            json.end_object();
          }
        else
          json.null();
        json.end_object();
      }
    json.end_array();
    json.key("all_within_tolerance");
    json.value(all_errors_within_tolerance());

    json.key("extra");
    json.begin_object();
    for (const auto &[key, v] : extras)
      {
        json.key(key);
        std::visit([&json](const auto &x) { json.value(x); }, v);
      }
    json.end_object();
    json.end_object();
    return out.str();
  }

  void
  RunSummary::write_json(const std::string &path) const
  {
    if (!writer)
      return;
    ensure_parent_directory(path);
    std::ofstream out(path, std::ios::out | std::ios::trunc);
    if (!out)
      throw std::runtime_error("RunSummary: cannot open '" + path + "' for writing");
    out << to_json();
    out.flush();
    if (!out)
      throw std::runtime_error("RunSummary: write to '" + path + "' failed");
  }
} // namespace twinflow::io
