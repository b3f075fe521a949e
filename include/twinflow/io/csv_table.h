#pragma once
/**
 * @file csv_table.h
 * Reading numeric CSV files: the monitor files written by CsvMonitor and the
 * reference data sets (files like martin_moyce_1952_front_n2.csv).
 *
 * Accepted format: lines whose first non-blank character is '#' and blank
 * lines are skipped; the first remaining line is the header (comma-separated
 * column names, optionally with a unit in brackets, `time [s]`); every further
 * line is a row of numbers with as many fields as the header.
 */
#include <cstddef>
#include <string>
#include <vector>

namespace twinflow::io
{
  /// A numeric table read from a CSV file, stored column by column.
  struct CsvTable
  {
    /// Column names without unit (`time` for a header field `time [s]`).
    std::vector<std::string> names;
    /// Units per column (the text in brackets, empty if none was given).
    std::vector<std::string> units;
    /// Header fields as written in the file (`time [s]`).
    std::vector<std::string> headers;
    /// `columns[c][r]`: value of column c in row r.
    std::vector<std::vector<double>> columns;

    /// Number of data rows.
    std::size_t
    n_rows() const;

    /// Number of columns.
    std::size_t
    n_columns() const;

    /// True if a column is called @p name (with or without unit, see column_index()).
    bool
    has_column(const std::string &name) const;

    /**
     * Index of the column called @p name; matches either the bare name
     * (`drag`) or the full header field (`drag [N]`).
     * Throws std::out_of_range if there is no such column.
     */
    std::size_t
    column_index(const std::string &name) const;

    /// The values of column @p name (see column_index()).
    const std::vector<double> &
    column(const std::string &name) const;
  };

  /**
   * Split a header field `name [unit]` into name and unit (both trimmed);
   * a field without brackets has an empty unit.
   */
  void
  split_name_and_unit(const std::string &field, std::string &name, std::string &unit);

  /**
   * Read the CSV file @p path (format described in the file comment).
   * Throws std::runtime_error if the file cannot be opened, has no header,
   * a row has the wrong number of fields or a field is not a number.
   * Not MPI-aware: every calling process reads the file.
   */
  CsvTable
  read_csv(const std::string &path);

  /// Rows of the monitor CSV @p path with time (first column) ≤ @p t: the monitors of the run
  /// a restart continues, read before the restarted run rewrites the file; empty if the file
  /// does not exist.
  std::vector<std::vector<double>>
  monitor_rows_until(const std::string &path, double t);
} // namespace twinflow::io
