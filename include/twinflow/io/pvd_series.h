#pragma once
/**
 * @file pvd_series.h
 * A ParaView time series (`<basename>.pvd`) listing the output files of a run
 * with their simulated times; rewritten after every new record, so that it
 * can be opened in ParaView while the simulation is still running.
 *
 * @code
 * PvdSeries series("out/fem", "solution", mpi_comm);
 * const std::string pvtu = data_out.write_vtu_with_pvtu_record("out/fem/", "solution", step,
 *                                                              mpi_comm, 5);
 * series.add(t, pvtu);   // -> out/fem/solution.pvd
 * @endcode
 */
#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace twinflow::io
{
  /// Keeps (time, file) records and maintains the .pvd file (rank 0 writes).
  class PvdSeries
  {
  public:
    /**
     * @param output_dir directory of the .pvd file (created if missing);
     *        file names are stored relative to it.
     * @param basename   the file is `<output_dir>/<basename>.pvd`.
     * No file is written before the first add().
     */
    PvdSeries(const std::string &output_dir,
              const std::string &basename,
              MPI_Comm           comm = MPI_COMM_WORLD);

    /**
     * Add the output file @p filename for simulated time @p time and rewrite
     * the .pvd file (via a temporary file and rename, so a reader never sees
     * a half-written file). @p filename is stored relative to output_dir: a
     * path that is absolute or starts with output_dir is made relative;
     * anything else is taken as already relative to output_dir.
     */
    void
    add(double time, const std::string &filename);

    /// The records (time, file name relative to output_dir), in order of addition.
    const std::vector<std::pair<double, std::string>> &
    records() const;

    /// Path of the .pvd file.
    std::string
    pvd_path() const;

    /// Rewrite the .pvd file from the current records (rank 0 only).
    void
    write() const;

  private:
    std::string relative_to_output_dir(const std::string &filename) const;

    std::string                                 directory;
    std::string                                 base;
    bool                                        writer;
    std::vector<std::pair<double, std::string>> entries;
  };
} // namespace twinflow::io
