#include <twinflow/io/mpi_utils.h>
#include <twinflow/sph/snapshot.h>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace twinflow::sph
{
  template <int dim>
  void write_snapshot(const std::string &path, const HostParticles<dim> &P, const double requested, const double time,
                      const std::size_t step)
  {
    io::ensure_parent_directory(path);
    std::ofstream f(path);
    if (!f)
      throw std::runtime_error("cannot write the SPH snapshot " + path);
    f.precision(10);
    f << "# twinflow SPH snapshot: requested t = " << requested << " s, written at t = " << time << " s (step "
      << step << ")\n# kind: 0 = fluid, 1 = wall (BCE) marker, 2 = solid marker\n";
    f << "x [m],y [m]" << (dim == 3 ? ",z [m]" : "") << ",speed [m/s],pressure [Pa],kind\n";
    for (std::size_t i = 0; i < P.size(); ++i)
    {
      double u2 = 0;
      for (int d = 0; d < dim; ++d)
      {
        f << P.x[i][d] << ",";
        u2 += P.u[i][d] * P.u[i][d];
      }
      f << std::sqrt(u2) << "," << P.p[i] << "," << P.kind[i] << "\n";
    }
    if (!f)
      throw std::runtime_error("writing the SPH snapshot " + path + " failed (disk full?)");
  }

  template void write_snapshot<2>(const std::string &, const HostParticles<2> &, double, double, std::size_t);
  template void write_snapshot<3>(const std::string &, const HostParticles<3> &, double, double, std::size_t);
} // namespace twinflow::sph
