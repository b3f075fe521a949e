#pragma once
// Scenes for FEM tests: a .prm text parsed exactly as the application parses a file.
#include <twinflow/core/scene.h>
#include <twinflow/fem/fem_simulation.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <utility>

namespace twinflow::testing
{
  /// Parses @p text (a scene file) into the scene and the FEM parameters.
  inline std::pair<Scene, fem::FemParameters> load_scene(const std::string &text)
  {
    dealii::ParameterHandler prm;
    declare_scene_parameters(prm);
    fem::FemParameters::declare(prm);
    prm.parse_input_from_string(text);
    fem::FemParameters f;
    f.parse(prm);
    return {parse_scene(prm, "test"), f};
  }

  /// Paper 4.1 (periodic channel, ρ = 20, μ = 0.1, body force 1, Re = 30) with an immersed
  /// disk (R = 0.05) at @p center on a box mesh of 5 × 2 cells refined twice, Q2/Q1, BDF2,
  /// dt = 0.01, ILU; monitors forces and energy, the body-fitted reference C_d = 1.62853.
  /// @p fem_entries go into subsection FEM (adaptation, steady tolerance, checkpoints ...).
  inline std::string periodic_cylinder_scene(double end_time, const std::string &fem_entries,
                                             const std::string &center = "0.5, 0.2")
  {
    return R"(
set Dimension = 2
subsection Scene
  set End time = )" + std::to_string(end_time) + R"(
end
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 1.0, 0.4
  set Periodic directions = x
end
subsection Fluids
  subsection Fluid 1
    set Density   = 20
    set Viscosity = 0.1
  end
end
subsection Forces
  set Body force = 1.0, 0
end
subsection Solids
  set Number of solids = 1
  subsection Solid 1
    set Center = )" + center + R"(
    set Radius = 0.05
  end
end
subsection Monitors
  set Monitors           = forces, energy
  set Reference velocity = 1.5
  set Reference length   = 0.1
end
subsection References
  set Drag coefficient = 1.62853
end
subsection FEM
  set Global refinements = 2
  set Time step          = 0.01
  subsection Navier-Stokes
    set Velocity preconditioner = ilu
  end
)" + fem_entries + "\nend\n";
  }

  /// FEM entries of a band adaptation from level @p min_level to @p max_level.
  inline std::string band_levels(unsigned int min_level, unsigned int max_level, const std::string &more = "")
  {
    return "subsection Mesh adaptation\n set Minimum level = " + std::to_string(min_level) +
           "\n set Maximum level = " + std::to_string(max_level) + "\n" + more + "end\n";
  }
} // namespace twinflow::testing
