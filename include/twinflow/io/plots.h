#pragma once
/**
 * @file plots.h
 * PNG plots of the monitor CSV files of a run, drawn by
 * `scripts/plot_monitors.py` (Python 3 + matplotlib) at the end of a run, and of its
 * snapshots (`scripts/plot_snapshots.py`).
 *
 * The scripts are found through the compile definition TWINFLOW_SOURCE_DIR
 * (set for twinflow_lib in the top-level CMakeLists.txt) or, if set, the
 * environment variable TWINFLOW_SOURCE_DIR. The interpreter is
 * /usr/bin/python3 unless the environment variable TWINFLOW_PYTHON names
 * another one. Plotting is optional: a missing interpreter, matplotlib or
 * script gives a warning on std::cerr, never an exception.
 */
#include <mpi.h>

#include <string>
#include <vector>

namespace twinflow::io
{
  /**
   * Plot every monitor CSV in @p output_dir (and in its immediate
   * subdirectories, e.g. fem/ and sph/, drawn together with a legend) into
   * `<output_dir>/plots/<monitor>.png`. Runs on rank 0 of @p comm only (not
   * collective; other ranks return true at once). Returns false (after a
   * warning) if the plots could not be made.
   */
  bool
  make_plots(const std::string &output_dir, MPI_Comm comm = MPI_COMM_WORLD);

  /**
   * Like make_plots() for several directories (e.g. {"run/fem", "run/sph"};
   * same-named monitors are drawn on common axes, legend "FEM"/"SPH"), with extra
   * command-line arguments passed to the script (e.g. {"--reference",
   * "ref.csv", "--ref-x", "T", ...}; see `plot_monitors.py --help`).
   */
  bool
  make_monitor_plots(const std::vector<std::string> &directories,
             const std::vector<std::string> &extra_arguments = {},
             MPI_Comm                        comm            = MPI_COMM_WORLD);

  /**
   * Draw the snapshots of the run in @p run_dir (Scene/Snapshot times: the files
   * `fem/snapshots/fem_t<time>.csv` and `sph/snapshots/sph_t<time>.csv`) with
   * `scripts/plot_snapshots.py`: one `<run_dir>/plots/snapshot_t<time>.png` per time (FEM
   * water region above the SPH particles), with a JSON beside it listing what was drawn.
   * Rank 0 of @p comm only; false (after a warning) if the plots could not be made.
   */
  bool
  make_snapshot_plots(const std::string &run_dir, MPI_Comm comm = MPI_COMM_WORLD);

  /**
   * Write `<run_dir>/report.md` with `scripts/report.py`: the scene (@p scene_file, the
   * @p command_line that ran it), the active physics, the cost and accuracy tables and the
   * per-section times of every method's summary.json, and the plots and snapshots of
   * `<run_dir>/plots` inline. A run that stopped with an error passes its message as
   * @p stopped: the report then says so first and shows what was written up to the stop.
   * Rank 0 of @p comm only; false (after a warning) if it could not be written.
   */
  bool
  make_report(const std::string &run_dir,
              const std::string &scene_file,
              const std::string &command_line,
              MPI_Comm           comm    = MPI_COMM_WORLD,
              const std::string &stopped = "");

  /// Path of plot_monitors.py, or "" if it cannot be found.
  std::string
  plot_script_path();

  /// Path of scripts/@p name (found as plot_monitors.py is), or "" if it cannot be found.
  std::string
  script_path(const std::string &name);

  /// @p s quoted for a POSIX shell (single quotes).
  std::string
  shell_quote(const std::string &s);
} // namespace twinflow::io
