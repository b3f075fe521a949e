/**
 * @file csv_table.cc
 * Implementation of the CSV reader (read_csv()).
 */
#include <twinflow/io/csv_table.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace twinflow::io
{
  namespace
  {
    std::string
    trim(const std::string &s)
    {
      const char *ws    = " \t\r\n";
      const auto  begin = s.find_first_not_of(ws);
      if (begin == std::string::npos)
        return "";
      const auto end = s.find_last_not_of(ws);
      return s.substr(begin, end - begin + 1);
    }

    std::vector<std::string>
    split_fields(const std::string &line)
    {
      std::vector<std::string> fields;
      std::size_t              start = 0;
      while (true)
        {
          const auto comma = line.find(',', start);
          fields.push_back(trim(line.substr(start, comma - start)));
          if (comma == std::string::npos)
            break;
          start = comma + 1;
        }
      return fields;
    }

    double
    parse_number(const std::string &field, const std::string &path, std::size_t line_no)
    {
      const char *begin = field.c_str();
      char       *end   = nullptr;
      errno             = 0;
      const double v    = std::strtod(begin, &end);
      // ERANGE on underflow (denormals) is harmless; only reject unparsable text.
      if (field.empty() || end == begin || *end != '\0')
        throw std::runtime_error("read_csv: '" + path + "' line " + std::to_string(line_no) +
                                 ": '" + field + "' is not a number");
      return v;
    }
  } // namespace

  std::size_t
  CsvTable::n_rows() const
  {
    return columns.empty() ? 0 : columns.front().size();
  }

  std::size_t
  CsvTable::n_columns() const
  {
    return names.size();
  }

  bool
  CsvTable::has_column(const std::string &name) const
  {
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name || headers[c] == name)
        return true;
    return false;
  }

  std::size_t
  CsvTable::column_index(const std::string &name) const
  {
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name || headers[c] == name)
        return c;
    std::string available;
    for (const auto &h : headers)
      available += (available.empty() ? "" : ", ") + h;
    throw std::out_of_range("CsvTable: no column '" + name + "' (columns: " + available + ")");
  }

  const std::vector<double> &
  CsvTable::column(const std::string &name) const
  {
    return columns[column_index(name)];
  }

  void
  split_name_and_unit(const std::string &field, std::string &name, std::string &unit)
  {
    const std::string f     = trim(field);
    const auto        open  = f.rfind('[');
    const auto        close = f.rfind(']');
    if (open != std::string::npos && close != std::string::npos && open < close &&
        close == f.size() - 1)
      {
        name = trim(f.substr(0, open));
        unit = trim(f.substr(open + 1, close - open - 1));
      }
    else
      {
        name = f;
        unit.clear();
      }
  }

  CsvTable
  read_csv(const std::string &path)
  {
    std::ifstream in(path);
    if (!in)
      throw std::runtime_error("read_csv: cannot open '" + path + "'");

    CsvTable    table;
    bool        have_header = false;
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line))
      {
        ++line_no;
        const std::string t = trim(line);
        if (t.empty() || t.front() == '#')
          continue;
        const auto fields = split_fields(t);
        if (!have_header)
          {
            for (const auto &f : fields)
              {
                std::string name, unit;
                split_name_and_unit(f, name, unit);
                table.headers.push_back(f);
                table.names.push_back(name);
                table.units.push_back(unit);
              }
            table.columns.resize(fields.size());
            have_header = true;
            continue;
          }
        if (fields.size() != table.names.size())
          throw std::runtime_error("read_csv: '" + path + "' line " + std::to_string(line_no) +
                                   ": " + std::to_string(fields.size()) + " fields, header has " +
                                   std::to_string(table.names.size()));
        for (std::size_t c = 0; c < fields.size(); ++c)
          table.columns[c].push_back(parse_number(fields[c], path, line_no));
      }
    if (!have_header)
      throw std::runtime_error("read_csv: '" + path + "' has no header line");
    return table;
  }

  std::vector<std::vector<double>>
  monitor_rows_until(const std::string &path, const double t)
  {
    std::vector<std::vector<double>> rows;
    if (!std::ifstream(path))
      return rows;
    const CsvTable table = read_csv(path);
    for (std::size_t r = 0; r < table.n_rows(); ++r)
    {
      if (table.columns[0][r] > t * (1 + 1e-12))
        break;
      std::vector<double> row;
      for (const auto &c : table.columns)
        row.push_back(c[r]);
      rows.push_back(std::move(row));
    }
    return rows;
  }
} // namespace twinflow::io
