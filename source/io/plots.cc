/**
 * @file plots.cc
 * Implementation of make_plots() and make_snapshot_plots(): run scripts/plot_monitors.py and
 * scripts/plot_snapshots.py via std::system.
 */
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/plots.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace twinflow::io
{
  namespace
  {
    std::string
    python_interpreter()
    {
      const char *env = std::getenv("TWINFLOW_PYTHON");
      return env && *env ? std::string(env) : std::string("/usr/bin/python3");
    }

    void
    warn(const std::string &message)
    {
      std::cerr << "twinflow: warning: plots skipped: " << message << std::endl;
    }
  } // namespace

  std::string
  shell_quote(const std::string &s)
  {
    std::string r = "'";
    for (const char c : s)
      if (c == '\'')
        r += "'\\''";
      else
        r += c;
    return r + "'";
  }

  std::string
  plot_script_path()
  {
    return script_path("plot_monitors.py");
  }

  std::string
  script_path(const std::string &name)
  {
    std::vector<std::string> candidates;
    if (const char *env = std::getenv("TWINFLOW_SOURCE_DIR"); env && *env)
      candidates.emplace_back(env);
#ifdef TWINFLOW_SOURCE_DIR
    candidates.emplace_back(TWINFLOW_SOURCE_DIR);
#endif
    for (const auto &dir : candidates)
      {
        const auto script = std::filesystem::path(dir) / "scripts" / name;
        std::error_code ec;
        if (std::filesystem::is_regular_file(script, ec))
          return script.string();
      }
    return "";
  }

  namespace
  {
    /// Runs scripts/@p name with @p arguments (rank 0 of @p comm only); false after a warning
    /// if the script, the interpreter or matplotlib is missing or the script fails.
    bool
    run_plot_script(const std::string &name, const std::vector<std::string> &arguments, MPI_Comm comm)
    {
      if (!is_root_process(comm))
        return true;
      const std::string python = python_interpreter();
      const std::string script = script_path(name);
      if (script.empty())
        {
          warn("scripts/" + name + " not found (TWINFLOW_SOURCE_DIR not set or wrong)");
          return false;
        }
      const std::string probe = shell_quote(python) + " -c 'import matplotlib' >/dev/null 2>&1";
      if (std::system(probe.c_str()) != 0)
        {
          warn(python + " with matplotlib is not available (Debian: apt-get install "
                        "python3-matplotlib)");
          return false;
        }
      std::string command = shell_quote(python) + " " + shell_quote(script);
      for (const auto &a : arguments)
        command += " " + shell_quote(a);
      const int status = std::system(command.c_str());
      if (status != 0)
        {
          warn("'" + command + "' failed (status " + std::to_string(status) + ")");
          return false;
        }
      return true;
    }
  } // namespace

  bool
  make_monitor_plots(const std::vector<std::string> &directories,
             const std::vector<std::string> &extra_arguments,
             MPI_Comm                        comm)
  {
    std::vector<std::string> arguments(directories);
    arguments.insert(arguments.end(), extra_arguments.begin(), extra_arguments.end());
    return run_plot_script("plot_monitors.py", arguments, comm);
  }

  bool
  make_snapshot_plots(const std::string &run_dir, MPI_Comm comm)
  {
    return run_plot_script("plot_snapshots.py", {run_dir}, comm);
  }

  bool
  make_report(const std::string &run_dir,
              const std::string &scene_file,
              const std::string &command_line,
              MPI_Comm           comm,
              const std::string &stopped)
  {
    std::vector<std::string> arguments{run_dir, "--scene", scene_file, "--command", command_line};
    if (!stopped.empty())
      arguments.insert(arguments.end(), {"--stopped", stopped});
    return run_plot_script("report.py", arguments, comm);
  }

  bool
  make_plots(const std::string &output_dir, MPI_Comm comm)
  {
    return make_monitor_plots(std::vector<std::string>{output_dir}, {}, comm);
  }
} // namespace twinflow::io
