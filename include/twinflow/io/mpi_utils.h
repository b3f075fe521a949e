#pragma once
/**
 * @file mpi_utils.h
 * Tiny MPI helpers shared by the output classes of twinflow::io: which process
 * writes (rank 0 of the given communicator), usable also before MPI_Init or
 * after MPI_Finalize (then the calling process counts as the writer).
 */
#include <mpi.h>

#include <string>

namespace twinflow::io
{
  /**
   * True if the calling process is rank 0 of @p comm, or if MPI is not (or no
   * longer) initialised — a serial tool then writes its output normally.
   * Not collective.
   */
  bool
  is_root_process(MPI_Comm comm);

  /**
   * Create the directory @p dir (and its parents) if it does not exist.
   * An empty path is a no-op. Throws std::runtime_error on failure.
   * Not collective: call it on the writing process only.
   */
  void
  ensure_directory(const std::string &dir);

  /// Create the parent directory of the file @p path if needed (see ensure_directory()).
  void
  ensure_parent_directory(const std::string &path);
} // namespace twinflow::io
