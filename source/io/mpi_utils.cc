/**
 * @file mpi_utils.cc
 * Implementation of the MPI / file-system helpers of twinflow::io.
 */
#include <twinflow/io/mpi_utils.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace twinflow::io
{
  bool
  is_root_process(MPI_Comm comm)
  {
    int initialized = 0;
    int finalized   = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (!initialized || finalized)
      return true;
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    return rank == 0;
  }

  void
  ensure_directory(const std::string &dir)
  {
    if (dir.empty())
      return;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec && !std::filesystem::is_directory(dir))
      throw std::runtime_error("twinflow::io: cannot create directory '" + dir +
                               "': " + ec.message());
  }

  void
  ensure_parent_directory(const std::string &path)
  {
    ensure_directory(std::filesystem::path(path).parent_path().string());
  }
} // namespace twinflow::io
