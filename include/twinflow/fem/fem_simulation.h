#pragma once
/**
 * @file fem_simulation.h
 * The Eulerian simulation composed from a Scene: it builds the mesh, the Navier–Stokes
 * solver and only the auxiliary physics the scene calls for, runs the time loop with
 * monitors, output, progress and a cost/accuracy summary.
 */
#include <twinflow/core/scene.h>
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/parameter_handler.h>

#include <map>
#include <string>
#include <vector>

namespace twinflow::fem
{
  /// Method parameters of the FEM solver (subsection "FEM").
  struct FemParameters
  {
    unsigned int           global_refinements = 0;
    double                 time_step          = 1e-2;   ///< fixed step, or the maximum with CFL control
    double                 cfl                = 0;      ///< > 0: dt = CFL h_min / |u|_max
    double                 steady_tolerance   = 0;      ///< > 0: stop when |du/dt|/|u| < tol
    std::vector<unsigned>  study_levels;                ///< refinement study (empty: single run)
    NavierStokesParameters navier_stokes;

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// What a run measured: final monitors, errors vs references and its cost.
  struct FemRunResult
  {
    unsigned int                  cells = 0, steps = 0;
    unsigned long long            dofs  = 0;
    double                        wall_time = 0, final_time = 0;
    std::map<std::string, double> monitors;
    std::map<std::string, double> relative_errors;
    std::vector<std::string>      active_physics;
  };

  /// Runs @p scene with the FEM on MPI_COMM_WORLD, writing into @p output_directory.
  template <int dim>
  FemRunResult run_fem(const Scene &scene, const FemParameters &parameters, const std::string &output_directory);

  /// Same with the dimension taken from the scene.
  FemRunResult run_fem_scene(const Scene &scene, const FemParameters &parameters, const std::string &output_directory);
} // namespace twinflow::fem
