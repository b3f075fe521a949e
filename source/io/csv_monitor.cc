/**
 * @file csv_monitor.cc
 * Implementation of CsvMonitor.
 */
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/mpi_utils.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace twinflow::io
{
  CsvMonitor::CsvMonitor(const std::string &             path,
                         const std::vector<std::string> &columns,
                         const std::vector<std::string> &units,
                         MPI_Comm                        comm,
                         const std::string &             name)
    : file_path(path)
    , monitor_name(name.empty() ? std::filesystem::path(path).stem().string() : name)
    , column_names(columns)
    , column_units(units.empty() ? std::vector<std::string>(columns.size()) : units)
    , writer(is_root_process(comm))
  {
    if (columns.empty())
      throw std::invalid_argument("CsvMonitor '" + path + "': no columns");
    if (column_units.size() != column_names.size())
      throw std::invalid_argument("CsvMonitor '" + path + "': " + std::to_string(units.size()) +
                                  " units for " + std::to_string(columns.size()) + " columns");
    for (const auto &c : column_names)
      if (c.empty() || c.find_first_of(",\n\r[]#") != std::string::npos)
        throw std::invalid_argument("CsvMonitor '" + path + "': invalid column name '" + c +
                                    "' (empty or containing one of , [ ] # newline)");
    for (const auto &u : column_units)
      if (u.find_first_of(",\n\r[]") != std::string::npos)
        throw std::invalid_argument("CsvMonitor '" + path + "': invalid unit '" + u + "'");
    if (monitor_name.find_first_of("\n\r") != std::string::npos)
      throw std::invalid_argument("CsvMonitor '" + path + "': name contains a newline");

    if (!writer)
      return;
    ensure_parent_directory(path);
    out = std::make_unique<std::ofstream>(path, std::ios::out | std::ios::trunc);
    if (!*out)
      throw std::runtime_error("CsvMonitor: cannot open '" + path + "' for writing");
    *out << "# twinflow monitor: " << monitor_name << '\n';
    for (std::size_t c = 0; c < column_names.size(); ++c)
      *out << (c ? "," : "") << header_field(column_names[c], column_units[c]);
    *out << '\n';
    out->flush();
  }

  void
  CsvMonitor::append(const std::vector<double> &row)
  {
    if (row.size() != column_names.size())
      throw std::invalid_argument("CsvMonitor '" + file_path + "': row of " +
                                  std::to_string(row.size()) + " values for " +
                                  std::to_string(column_names.size()) + " columns");
    ++rows;
    if (!writer)
      return;
    std::string line;
    char        buffer[40];
    for (std::size_t c = 0; c < row.size(); ++c)
      {
        std::snprintf(buffer, sizeof(buffer), "%.12e", row[c]);
        if (c)
          line += ',';
        line += buffer;
      }
    line += '\n';
    *out << line;
    out->flush();
    if (!*out)
      throw std::runtime_error("CsvMonitor: write to '" + file_path + "' failed");
  }

  void
  CsvMonitor::append(const double time, const std::vector<double> &values)
  {
    std::vector<double> row;
    row.reserve(values.size() + 1);
    row.push_back(time);
    row.insert(row.end(), values.begin(), values.end());
    append(row);
  }

  std::size_t
  CsvMonitor::n_columns() const
  {
    return column_names.size();
  }

  const std::vector<std::string> &
  CsvMonitor::columns() const
  {
    return column_names;
  }

  const std::vector<std::string> &
  CsvMonitor::units() const
  {
    return column_units;
  }

  const std::string &
  CsvMonitor::name() const
  {
    return monitor_name;
  }

  const std::string &
  CsvMonitor::path() const
  {
    return file_path;
  }

  bool
  CsvMonitor::is_writer() const
  {
    return writer;
  }

  std::size_t
  CsvMonitor::n_rows() const
  {
    return rows;
  }

  std::string
  CsvMonitor::header_field(const std::string &column, const std::string &unit)
  {
    return unit.empty() ? column : column + " [" + unit + "]";
  }
} // namespace twinflow::io
