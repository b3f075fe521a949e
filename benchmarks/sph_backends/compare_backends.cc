// CPU against CUDA backend of the same SPH kernels (sph_gpu/src/*.inl), without deal.II so that
// it runs on a GPU machine that has only the CUDA toolkit: a Martin & Moyce dam break (column
// a × 2a, n² = 2, in a closed 5a × 3a tank, three BCE layers), every engine default of the
// SPH subsection (consistent operators, shifting, three surface criteria, wetted walls).
//
//   sph_backend_compare SPACING_OVER_A STEPS [cpu|cuda|both]
//
// Prints, per backend, the wall time per step, per 1000 steps and per particle-step, and the
// final kinetic energy and largest speed; with `both`, the largest position difference between
// the backends after STEPS steps (the CPU uses OpenMP with OMP_NUM_THREADS threads).
#include <twinflow_sph/engine.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

namespace twinflow::sph
{
  namespace cpu
  {
    template <int dim>
    std::unique_ptr<Engine<dim>> create_engine(const DomainBox<dim> &, const EngineSettings &);
  }
  namespace cuda
  {
    template <int dim>
    std::unique_ptr<Engine<dim>> create_engine(const DomainBox<dim> &, const EngineSettings &);
  }
} // namespace twinflow::sph

using namespace twinflow;
using namespace twinflow::sph;

namespace
{
  constexpr double a = 0.1, rho0 = 1000, g = 9.8;

  struct Setup
  {
    DomainBox<2>     box;
    EngineSettings   s;
    HostParticles<2> P;
    std::size_t      fluid = 0;
  };

  Setup make_setup(const double dx)
  {
    Setup S;
    const double W = 5 * a, H = 3 * a;
    S.box.lower    = geometry::Vec<2>{{0.0, 0.0}};
    S.box.upper    = geometry::Vec<2>{{W, H}};
    S.box.periodic[0] = S.box.periodic[1] = false;
    const int nx = static_cast<int>(std::lround(W / dx)), ny = static_cast<int>(std::lround(H / dx)), layers = 3;
    for (int j = -layers; j < ny + layers; ++j)
      for (int i = -layers; i < nx + layers; ++i)
      {
        const geometry::Vec<2> x{{(i + 0.5) * dx, (j + 0.5) * dx}};
        const bool inside = i >= 0 && i < nx && j >= 0 && j < ny;
        if (inside && !(x[0] < a && x[1] < 2 * a))
          continue; // air
        if (inside)
        {
          S.P.add(x, geometry::Vec<2>::zero(), rho0 * g * (2 * a - x[1]), rho0);
          ++S.fluid;
          continue;
        }
        geometry::Vec<2> n{{i < 0 ? 1.0 : (i >= nx ? -1.0 : 0.0), j < 0 ? 1.0 : (j >= ny ? -1.0 : 0.0)}};
        const double     len = std::sqrt(n[0] * n[0] + n[1] * n[1]);
        n[0] /= len, n[1] /= len; // into the tank
        S.P.add(x, geometry::Vec<2>::zero(), 0.0, rho0, ParticleKind::wall, n);
      }
    EngineSettings &s = S.s; // the SPH subsection's defaults (source/sph/sph_simulation.cc)
    s.spacing                     = dx;
    s.h                           = 1.2 * dx;
    s.rho0                        = rho0;
    s.mu                          = 1e-3;
    s.free_surface_divergence     = 0.6 * 2;
    s.free_surface_min_neighbours = 0.6 * 21;
    s.acceleration                = {{0.0, -g, 0.0}};
    s.gravity                     = {{0.0, -g, 0.0}};
    s.velocity_solver = s.pressure_solver = {2000, 1e-8};
    s.density_relaxation_time     = std::min(1e-3, 0.2 * s.h / std::sqrt(2 * g * 2 * a));
    return S;
  }

  struct Result
  {
    HostParticles<2> P;
    double           seconds = 0, kinetic = 0, max_speed = 0, t = 0;
    long             pressure_iterations = 0;
    double           t_neighbors = 0, t_assembly = 0, t_velocity = 0, t_pressure = 0, t_update = 0;
  };

  Result run(const std::string &backend, const double dx, const int steps)
  {
    Setup S = make_setup(dx);
    auto  engine = backend == "cpu" ? cpu::create_engine<2>(S.box, S.s) : cuda::create_engine<2>(S.box, S.s);
    engine->set_particles(S.P);
    const double u_ref = std::sqrt(2 * g * 2 * a);
    Result       r;
    double       umax = 0;
    const auto   start = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k)
    {
      const double dt = std::min(1e-3, 0.2 * S.s.h / std::max(umax, u_ref));
      const auto  &rep = engine->step(dt);
      if (!(rep.pressure.converged && rep.velocity[0].converged && rep.velocity[1].converged) ||
          !(rep.max_speed < 100 * u_ref))
      {
        std::printf("%s: step %d did not converge or diverged (max speed %g)\n", backend.c_str(), k, rep.max_speed);
        std::exit(2);
      }
      umax = rep.max_speed;
      r.pressure_iterations += rep.pressure.iterations;
      r.t_neighbors += rep.t_neighbors, r.t_assembly += rep.t_assembly, r.t_velocity += rep.t_velocity;
      r.t_pressure += rep.t_pressure, r.t_update += rep.t_update;
      r.t += dt;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    engine->get_particles(r.P);
    for (std::size_t i = 0; i < r.P.size(); ++i)
      if (r.P.kind[i] == ParticleKind::fluid)
      {
        const double v2 = r.P.u[i][0] * r.P.u[i][0] + r.P.u[i][1] * r.P.u[i][1];
        r.kinetic += 0.5 * rho0 * dx * dx * v2;
        r.max_speed = std::max(r.max_speed, std::sqrt(v2));
      }
    std::printf("%-4s  %zu particles (%zu fluid), %d steps to t = %.4f s: %.3f s, %.2f ms/step, %.1f s per 1000 steps, "
                "%.1f s per simulated second, %.1f ns per particle-step, mean pressure iterations %.1f; "
                "kinetic energy %.6e J/m, largest speed %.4f m/s\n",
                backend.c_str(), S.P.size(), S.fluid, steps, r.t, r.seconds, 1e3 * r.seconds / steps,
                1e3 * r.seconds / steps, r.seconds / r.t, 1e9 * r.seconds / (double(steps) * S.P.size()),
                double(r.pressure_iterations) / steps, r.kinetic, r.max_speed);
    std::printf("      split per step [ms]: neighbour search %.2f, assembly %.2f, velocity solve %.2f, pressure solve "
                "%.2f (%.3f per iteration), correction and update %.2f\n",
                1e3 * r.t_neighbors / steps, 1e3 * r.t_assembly / steps, 1e3 * r.t_velocity / steps,
                1e3 * r.t_pressure / steps, 1e3 * r.t_pressure / std::max<long>(1, r.pressure_iterations),
                1e3 * r.t_update / steps);
    return r;
  }
} // namespace

int main(int argc, char **argv)
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: %s SPACING_OVER_A STEPS [cpu|cuda|both]\n", argv[0]);
    return 1;
  }
  const double      dx      = a / std::atof(argv[1]);
  const int         steps   = std::atoi(argv[2]);
  const std::string which   = argc > 3 ? argv[3] : "both";
  if (!(dx > 0) || steps < 1 || (which != "cpu" && which != "cuda" && which != "both"))
  {
    std::fprintf(stderr, "SPACING_OVER_A must be > 0, STEPS >= 1, backend cpu, cuda or both\n");
    return 1;
  }
  if (which != "both")
  {
    run(which, dx, steps);
    return 0;
  }
  const Result c = run("cpu", dx, steps), d = run("cuda", dx, steps);
  double       dmax = 0;
  for (std::size_t i = 0; i < c.P.size(); ++i)
    dmax = std::max(dmax, std::hypot(c.P.x[i][0] - d.P.x[i][0], c.P.x[i][1] - d.P.x[i][1]));
  std::printf("cpu vs cuda: largest position difference %.3e m (%.3e spacings), kinetic energy %.3e relative, "
              "speed-up %.1fx\n",
              dmax, dmax / dx, std::abs(c.kinetic - d.kinetic) / c.kinetic, c.seconds / d.seconds);
  return 0;
}
