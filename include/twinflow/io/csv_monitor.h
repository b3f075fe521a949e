#pragma once
/**
 * @file csv_monitor.h
 * Time series of scalar monitor quantities (drag, front position, kinetic
 * energy, ...) written as CSV, one row per call of CsvMonitor::append().
 *
 * File layout (read back by read_csv(), plotted by scripts/plot_monitors.py):
 * @code
 * # twinflow monitor: forces
 * time [s],drag [N],lift [N]
 * 0.000000000000e+00,1.234567890123e+00,-4.000000000000e-03
 * @endcode
 * Only rank 0 of the communicator opens and writes the file; on the other
 * ranks every member function is a cheap no-op, so all ranks can call them.
 */
#include <twinflow/io/csv_table.h> // read_csv(), for the readers of monitor files

#include <mpi.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::io
{
  /// Writer of one monitor CSV file.
  class CsvMonitor
  {
  public:
    /**
     * Create (truncate) the file @p path, creating its directory if needed,
     * and write the two header lines.
     * @param columns column names, e.g. {"time", "drag"}; by convention the
     *        first column is the time. Names must not contain ',' or newlines.
     * @param units   one unit per column ({"s", "N"}), "" for dimensionless
     *        columns (no brackets are then written); may be empty altogether.
     * @param comm    only its rank 0 writes.
     * @param name    monitor name for the comment line; default: the file
     *        name without directory and extension.
     * Throws std::invalid_argument on inconsistent arguments (on every rank)
     * and std::runtime_error if rank 0 cannot open the file.
     */
    CsvMonitor(const std::string &             path,
               const std::vector<std::string> &columns,
               const std::vector<std::string> &units = {},
               MPI_Comm                        comm  = MPI_COMM_WORLD,
               const std::string &             name  = "");

    /**
     * Write one row (one value per column) in full precision (%.12e) and flush.
     * Throws std::invalid_argument if @p row has the wrong size (on every rank).
     */
    void
    append(const std::vector<double> &row);

    /// Convenience: append({time, values...}).
    void
    append(double time, const std::vector<double> &values);

    /// Number of columns (including the time column).
    std::size_t
    n_columns() const;

    /// Column names as given to the constructor.
    const std::vector<std::string> &
    columns() const;

    /// Units as given to the constructor (empty strings if none were given).
    const std::vector<std::string> &
    units() const;

    /// The monitor name written in the first line.
    const std::string &
    name() const;

    /// Path of the file.
    const std::string &
    path() const;

    /// True on the process that writes (rank 0).
    bool
    is_writer() const;

    /// Number of rows appended so far (counted on every rank).
    std::size_t
    n_rows() const;

    /// The header field of one column: `name [unit]`, or `name` if the unit is empty.
    static std::string
    header_field(const std::string &column, const std::string &unit);

  private:
    std::string                    file_path;
    std::string                    monitor_name;
    std::vector<std::string>       column_names;
    std::vector<std::string>       column_units;
    bool                           writer;
    std::size_t                    rows = 0;
    std::unique_ptr<std::ofstream> out;
  };
} // namespace twinflow::io
