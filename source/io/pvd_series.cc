/**
 * @file pvd_series.cc
 * Implementation of PvdSeries on top of dealii::DataOutBase::write_pvd_record().
 */
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/pvd_series.h>

#include <deal.II/base/data_out_base.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace twinflow::io
{
  namespace fs = std::filesystem;

  PvdSeries::PvdSeries(const std::string &output_dir, const std::string &basename, MPI_Comm comm)
    : directory(output_dir.empty() ? std::string(".") : output_dir)
    , base(basename)
    , writer(is_root_process(comm))
  {
    if (basename.empty() || basename.find('/') != std::string::npos)
      throw std::invalid_argument("PvdSeries: invalid basename '" + basename + "'");
    if (writer)
      ensure_directory(directory);
  }

  std::string
  PvdSeries::relative_to_output_dir(const std::string &filename) const
  {
    const fs::path file = fs::path(filename).lexically_normal();
    if (file.is_absolute())
      return file.lexically_relative(fs::absolute(directory).lexically_normal()).generic_string();

    // does `file` start with the components of output_dir (e.g. "out/fem/x.vtu")?
    std::vector<fs::path> dir_parts, file_parts;
    for (const auto &part : fs::path(directory).lexically_normal())
      if (!part.empty() && part != ".")
        dir_parts.push_back(part);
    for (const auto &part : file)
      file_parts.push_back(part);
    if (!dir_parts.empty() && file_parts.size() > dir_parts.size() &&
        std::equal(dir_parts.begin(), dir_parts.end(), file_parts.begin()))
      {
        fs::path rest;
        for (std::size_t i = dir_parts.size(); i < file_parts.size(); ++i)
          rest /= file_parts[i];
        return rest.generic_string();
      }
    return file.generic_string();
  }

  void
  PvdSeries::add(const double time, const std::string &filename)
  {
    entries.emplace_back(time, relative_to_output_dir(filename));
    write();
  }

  const std::vector<std::pair<double, std::string>> &
  PvdSeries::records() const
  {
    return entries;
  }

  std::string
  PvdSeries::pvd_path() const
  {
    return (fs::path(directory) / (base + ".pvd")).string();
  }

  void
  PvdSeries::write() const
  {
    if (!writer)
      return;
    const std::string path = pvd_path();
    const std::string tmp  = path + ".tmp";
    {
      std::ofstream out(tmp, std::ios::out | std::ios::trunc);
      if (!out)
        throw std::runtime_error("PvdSeries: cannot open '" + tmp + "' for writing");
      dealii::DataOutBase::write_pvd_record(out, entries);
      out.flush();
      if (!out)
        throw std::runtime_error("PvdSeries: write to '" + tmp + "' failed");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec)
      throw std::runtime_error("PvdSeries: cannot rename '" + tmp + "' to '" + path +
                               "': " + ec.message());
  }
} // namespace twinflow::io
