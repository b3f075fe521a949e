// twinflow: run a scene (.prm) with the FEM and/or SPH solvers.
#include <twinflow/core/errors.h>
#include <twinflow/core/scene.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/plots.h>
#include <twinflow/sph/sph_simulation.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
  const char *usage = R"(twinflow — free-surface and fluid-solid flow, Eulerian (FEM) and Lagrangian (SPH)

usage:
  twinflow SCENE.prm [-o OUTPUT_DIR]   run a scene (mpirun -np N twinflow ... distributes the FEM)
  twinflow --print-parameters          print every parameter with its documentation and default
  twinflow --help                      this text

Results go to the scene's 'Output directory' (or OUTPUT_DIR): one folder per method with
ParaView files, CSV monitors, summary.json and PNG plots.
)";

  void declare_all(dealii::ParameterHandler &prm)
  {
    twinflow::declare_scene_parameters(prm);
    twinflow::fem::FemParameters::declare(prm);
    twinflow::sph::SphParameters::declare(prm);
  }

  /// deal.II's message of an exception without the stack trace.
  std::string message_of(const dealii::ExceptionBase &e)
  {
    std::ostringstream s;
    e.print_info(s);
    std::string m = s.str();
    while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
      m.pop_back();
    return m.erase(0, std::min(m.find_first_not_of(" \n"), m.size()));
  }

  int run(const std::string &file, const std::string &output_override)
  {
    using namespace twinflow;
    dealii::ParameterHandler prm;
    declare_all(prm);
    {
      std::ifstream in(file);
      if (!in)
        throw InputError("cannot open scene file '" + file + "' (no such file or not readable)");
    }
    try
    {
      prm.parse_input(file);
    }
    catch (const dealii::ExceptionBase &e)
    {
      throw InputError("in scene file '" + file + "': " + message_of(e) +
                       "\n(twinflow --print-parameters lists every subsection and entry with its allowed values)");
    }
    Scene scene = parse_scene(prm, file);
    fem::FemParameters fem_prm;
    fem_prm.parse(prm);
    if (!output_override.empty())
      scene.output_directory = output_override;
    sph::SphParameters sph_prm;
    sph_prm.parse(prm);

    const bool root = io::is_root_process(MPI_COMM_WORLD);
    if (root)
      std::cout << "twinflow: scene '" << scene.name << "' (" << scene.dimension << "D) from " << file << std::endl;
    const std::string dir = scene.output_directory + "/fem";
    if (scene.wants(Method::sph))
    {
      const std::string sph_dir = scene.output_directory + "/sph";
      sph::run_sph_scene(scene, sph_prm, sph_dir);
      if (!scene.wants(Method::fem))
      {
        io::make_plots(sph_dir);
        return 0;
      }
    }
    if (fem_prm.study_levels.empty())
    {
      fem::run_fem_scene(scene, fem_prm, dir);
      if (scene.wants(Method::sph))
        io::make_monitor_plots({dir, scene.output_directory + "/sph"});
      else
        io::make_plots(dir);
      return 0;
    }
    // Refinement study: each level in its own folder, one table of cost and accuracy.
    io::ensure_directory(dir);
    std::vector<std::string> cols{"level", "cells", "dofs", "steps", "wall time"}, units{"-", "-", "-", "-", "s"};
    for (const char *k : {"C_d", "C_l", "dp"})
    {
      cols.push_back(k);
      units.push_back("-");
      cols.push_back(std::string("error ") + k);
      units.push_back("-");
    }
    io::CsvMonitor table(dir + "/refinement_study.csv", cols, units, MPI_COMM_WORLD, "refinement study");
    for (const unsigned int level : fem_prm.study_levels)
    {
      fem_prm.global_refinements = level;
      const auto r = fem::run_fem_scene(scene, fem_prm, dir + "/level_" + std::to_string(level));
      std::vector<double> row{double(level), double(r.cells), double(r.dofs), double(r.steps), r.wall_time};
      for (const char *k : {"C_d", "C_l", "dp"})
      {
        row.push_back(r.monitors.count(k) ? r.monitors.at(k) : std::nan(""));
        row.push_back(r.relative_errors.count(k) ? r.relative_errors.at(k) : std::nan(""));
      }
      table.append(row);
    }
    if (root)
    {
      const std::string cmd = "/usr/bin/python3 " + io::shell_quote(std::string(TWINFLOW_SOURCE_DIR) + "/scripts/plot_study.py") +
                              " " + io::shell_quote(dir + "/refinement_study.csv");
      if (std::system(cmd.c_str()) != 0)
        std::cerr << "warning: could not plot the refinement study (python3 + matplotlib needed)" << std::endl;
    }
    return 0;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool root = twinflow::io::is_root_process(MPI_COMM_WORLD);
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string file, output;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    if (args[i] == "--help" || args[i] == "-h")
    {
      if (root) std::cout << usage;
      return 0;
    }
    if (args[i] == "--print-parameters")
    {
      dealii::ParameterHandler prm;
      declare_all(prm);
      if (root) prm.print_parameters(std::cout, dealii::ParameterHandler::PRM);
      return 0;
    }
    if (args[i] == "-o" && i + 1 < args.size())
      output = args[++i];
    else if (!args[i].empty() && args[i][0] == '-')
    {
      if (root) std::cerr << "twinflow: unknown option '" << args[i] << "'\n" << usage;
      return 1;
    }
    else
      file = args[i];
  }
  if (file.empty())
  {
    if (root) std::cerr << usage;
    return 1;
  }
  try
  {
    return run(file, output);
  }
  catch (const twinflow::InputError &e)
  {
    if (root) std::cerr << "twinflow: input error: " << e.what() << std::endl;
    return 1;
  }
  catch (const dealii::ExceptionBase &e)
  {
    if (root) std::cerr << "twinflow: error: " << message_of(e) << std::endl;
    return 2;
  }
  catch (const std::exception &e)
  {
    if (root) std::cerr << "twinflow: error: " << e.what() << std::endl;
    return 2;
  }
}
