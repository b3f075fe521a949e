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
} // namespace twinflow::testing
