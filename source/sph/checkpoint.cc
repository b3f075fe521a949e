#include <twinflow/core/errors.h>
#include <twinflow/sph/checkpoint.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

namespace twinflow::sph
{
  namespace
  {
    constexpr char magic[8] = {'T', 'W', 'S', 'P', 'H', 'C', 'K', '3'};

    template <typename T>
    void put(std::ofstream &f, const T *data, const std::size_t count)
    {
      f.write(reinterpret_cast<const char *>(data), static_cast<std::streamsize>(sizeof(T) * count));
    }

    template <typename T>
    void put(std::ofstream &f, const T &value)
    {
      put(f, &value, 1);
    }

    /// Reads from a checkpoint; a short file is an InputError naming it.
    struct Reader
    {
      std::ifstream      f;
      const std::string &path;

      template <typename T>
      void get(T *data, const std::size_t count)
      {
        f.read(reinterpret_cast<char *>(data), static_cast<std::streamsize>(sizeof(T) * count));
        if (!f)
          throw InputError("SPH/Restart file = '" + path + "': the file ends early (truncated checkpoint)");
      }

      template <typename T>
      T get()
      {
        T value;
        get(&value, 1);
        return value;
      }
    };
  } // namespace

  template <int dim>
  void write_checkpoint(const std::string &path, const HostParticles<dim> &P, const double spacing, const RunPosition &pos)
  {
    const std::string tmp = path + ".tmp";
    {
      std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
      if (!f)
        throw std::runtime_error("cannot write the checkpoint " + tmp);
      const std::uint64_t n = P.size(), n_outputs = pos.output_times.size(), steps = pos.steps;
      const std::int32_t  d = dim;
      put(f, magic, sizeof(magic));
      put(f, d);
      put(f, n);
      put(f, spacing);
      put(f, pos.time);
      put(f, steps);
      put(f, pos.next_output);
      put(f, n_outputs);
      put(f, pos.output_times.data(), pos.output_times.size());
      const double budget[6] = {pos.budget.viscous,   pos.budget.body_force, pos.budget.pressure,
                                pos.budget.potential, pos.budget.shifting,   pos.budget.density_correction};
      put(f, budget, 6);
      put(f, P.x.data(), P.size());
      put(f, P.u.data(), P.size());
      put(f, P.p.data(), P.size());
      put(f, P.rho.data(), P.size());
      std::vector<std::int32_t> kinds(P.kind.begin(), P.kind.end());
      put(f, kinds.data(), kinds.size());
      if (!f)
        throw std::runtime_error("writing the checkpoint " + tmp + " failed (disk full?)");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw std::runtime_error("cannot rename the checkpoint " + tmp + " to " + path);
  }

  namespace
  {
    /// A checkpoint with fewer particles than the scene generates (fluid removed at an open
    /// top, open_boundary.h): its markers must be the scene's, in the same order; @p P becomes
    /// the checkpoint's particle set (kinds, and each marker's wall velocity, acceleration,
    /// normal and body from the scene; a fluid particle's are the generated defaults).
    template <int dim>
    void align_with_markers(const std::string &entry, const std::vector<std::int32_t> &kinds, HostParticles<dim> &P)
    {
      HostParticles<dim> a;
      std::size_t        g = 0; // next generated particle
      for (std::size_t j = 0; j < kinds.size(); ++j)
      {
        if (kinds[j] == ParticleKind::fluid)
        {
          a.add(P.x[0], P.u[0], 0, 0); // x, u, p, rho replaced by the checkpoint's
          continue;
        }
        while (g < P.size() && P.kind[g] == ParticleKind::fluid)
          ++g;
        if (g == P.size() || P.kind[g] != kinds[j])
          throw InputError(entry + ": particle " + std::to_string(j) + " is of another kind than in the scene (wall " +
                           "or solid markers differ); restart with the scene that wrote it");
        a.add(P.x[g], P.u[g], 0, 0, P.kind[g], P.normal[g], P.body[g]);
        a.wall_velocity.back() = P.wall_velocity[g], a.wall_acceleration.back() = P.wall_acceleration[g];
        ++g;
      }
      for (; g < P.size(); ++g)
        if (P.kind[g] != ParticleKind::fluid)
          throw InputError(entry + ": the checkpoint lacks wall or solid markers of the scene; restart with the "
                           "scene that wrote it");
      P = std::move(a);
    }
  } // namespace

  template <int dim>
  RunPosition read_checkpoint(const std::string &path, const double spacing, HostParticles<dim> &P,
                              const bool fluid_may_leave)
  {
    Reader r{std::ifstream(path, std::ios::binary), path};
    const std::string entry = "SPH/Restart file = '" + path + "'";
    if (!r.f)
      throw InputError(entry + ": cannot open the file (a checkpoint.bin written by a run with SPH/Checkpoint interval > 0)");
    char m[sizeof(magic)];
    r.get(m, sizeof(m));
    if (std::memcmp(m, magic, sizeof(magic)) != 0)
      throw InputError(entry + ": not a Twinflow SPH checkpoint of this version (allowed: a checkpoint.bin written by SPH/Checkpoint interval of this build)");
    const auto d = r.get<std::int32_t>();
    if (d != dim)
      throw InputError(entry + ": the checkpoint is " + std::to_string(d) + "D, the scene " + std::to_string(dim) + "D");
    const auto   n = r.get<std::uint64_t>();
    const double h = r.get<double>();
    if (std::abs(h - spacing) > 1e-12 * spacing)
      throw InputError(entry + ": written with SPH/Particle spacing = " + std::to_string(h) + ", the scene has " +
                       std::to_string(spacing) + "; restart with the scene that wrote it");
    if (n != P.size() && !(fluid_may_leave && n < P.size()))
      throw InputError(entry + ": the checkpoint has " + std::to_string(n) + " particles, the scene generates " +
                       std::to_string(P.size()) + "; restart with the scene that wrote it");
    RunPosition pos;
    pos.time        = r.get<double>();
    pos.steps       = r.get<std::uint64_t>();
    pos.next_output = r.get<double>();
    pos.output_times.resize(r.get<std::uint64_t>());
    r.get(pos.output_times.data(), pos.output_times.size());
    double budget[6];
    r.get(budget, 6);
    pos.budget = EnergyBudget{budget[0], budget[1], budget[2], budget[3], budget[4], budget[5]};
    HostParticles<dim> c;
    c.x.resize(n), c.u.resize(n), c.p.resize(n), c.rho.resize(n);
    std::vector<std::int32_t> kinds(n);
    r.get(c.x.data(), n);
    r.get(c.u.data(), n);
    r.get(c.p.data(), n);
    r.get(c.rho.data(), n);
    r.get(kinds.data(), n);
    if (n == P.size())
    {
      for (std::size_t i = 0; i < n; ++i)
        if (kinds[i] != P.kind[i])
          throw InputError(entry + ": particle " + std::to_string(i) + " is of another kind than in the scene (fluid, " +
                           "wall or solid markers differ); restart with the scene that wrote it");
    }
    else
      align_with_markers(entry, kinds, P); // fluid particles left through the open top
    P.x = std::move(c.x), P.u = std::move(c.u), P.p = std::move(c.p), P.rho = std::move(c.rho);
    return pos;
  }

  template void        write_checkpoint<2>(const std::string &, const HostParticles<2> &, double, const RunPosition &);
  template void        write_checkpoint<3>(const std::string &, const HostParticles<3> &, double, const RunPosition &);
  template RunPosition read_checkpoint<2>(const std::string &, double, HostParticles<2> &, bool);
  template RunPosition read_checkpoint<3>(const std::string &, double, HostParticles<3> &, bool);
} // namespace twinflow::sph
