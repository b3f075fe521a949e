#include <twinflow/core/errors.h>
#include <twinflow/fem/fem_simulation.h>

#include <deal.II/base/utilities.h>

namespace twinflow::fem
{
  void FemParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii;
    prm.enter_subsection("FEM");
    prm.declare_entry("Global refinements", "0", Patterns::Integer(0, 12),
                      "Uniform refinements of the scene's coarse mesh.");
    prm.declare_entry("Time step", "0.01", Patterns::Double(0),
                      "Time step [s] (the maximum one when CFL control is on); must be > 0.");
    prm.declare_entry("CFL number", "0", Patterns::Double(0),
                      "> 0: the step is CFL * h_min / max|u|, capped by 'Time step'; 0: fixed step.");
    prm.declare_entry("Steady-state tolerance", "0", Patterns::Double(0),
                      "> 0: stop before the end time once max|u^{n+1}-u^n| / (dt max|u|) falls below it.");
    prm.declare_entry("Checkpoint interval", "0", Patterns::Double(0),
                      "> 0: write a checkpoint (mesh, every field, time-step history) every this many simulated "
                      "seconds into <output>/fem/checkpoint.*; 0: none.");
    prm.declare_entry("Coupling iterations", "1", Patterns::Integer(1, 100),
                      "Rigid bodies: 1 = explicit co-simulation (the last step's loads, with Soeding's added-mass "
                      "correction); n > 1 = up to n Navier-Stokes solves per step with Aitken-relaxed loads until "
                      "they agree (implicit coupling: light bodies, rho_s < rho_w, need it).");
    prm.declare_entry("Coupling tolerance", "1e-3", Patterns::Double(1e-12, 1),
                      "Sub-iterations end when |loads - guess| <= this * max(|loads|, sum of body weights).");
    prm.declare_entry("Restart file", "", Patterns::Anything(),
                      "Checkpoint prefix to continue from (e.g. output/scene/fem/checkpoint); empty: start at t = 0. "
                      "The scene and the FEM discretisation must be those that wrote it.");
    prm.enter_subsection("Navier-Stokes");
    NavierStokesParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Mesh adaptation");
    MeshAdaptationParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Immersed boundary");
    ImmersedBoundaryParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Level set");
    LevelSetParameters::declare(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void FemParameters::parse(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("FEM");
    global_refinements = prm.get_integer("Global refinements");
    time_step          = prm.get_double("Time step");
    require(time_step > 0, "FEM/Time step", prm.get("Time step"), "the time step must be > 0");
    cfl              = prm.get_double("CFL number");
    steady_tolerance = prm.get_double("Steady-state tolerance");
    checkpoint_interval = prm.get_double("Checkpoint interval");
    restart_file        = prm.get("Restart file");
    coupling_iterations = prm.get_integer("Coupling iterations");
    coupling_tolerance  = prm.get_double("Coupling tolerance");
    prm.enter_subsection("Navier-Stokes");
    navier_stokes.parse(prm);
    prm.leave_subsection();
    prm.enter_subsection("Mesh adaptation");
    adaptation.parse(prm);
    prm.leave_subsection();
    prm.enter_subsection("Immersed boundary");
    immersed_boundary.parse(prm);
    prm.leave_subsection();
    prm.enter_subsection("Level set");
    level_set.parse(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void check_fem_scene(const Scene &scene, const FemParameters &parameters)
  {
    // Composition alone: refuses what the FEM cannot build, allocates no mesh or DoFs.
    if (scene.dimension == 2)
      FemSimulation<2> check(scene, parameters, "");
    else
      FemSimulation<3> check(scene, parameters, "");
  }

  FemRunResult run_fem_scene(const Scene &scene, const FemParameters &parameters, const std::string &dir)
  {
    return scene.dimension == 2 ? run_fem<2>(scene, parameters, dir) : run_fem<3>(scene, parameters, dir);
  }
} // namespace twinflow::fem

namespace twinflow::fem::internal
{
  std::string join(const std::vector<std::string> &v, const std::string &sep)
  {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i)
      s += (i ? sep : "") + v[i];
    return s;
  }
} // namespace twinflow::fem::internal
