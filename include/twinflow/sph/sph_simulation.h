#pragma once
/**
 * @file sph_simulation.h
 * The Lagrangian simulation composed from a Scene: particles on a lattice in the initial
 * fluid region, BCE wall markers (Eq. 59–65) from the domain's no-slip faces and from the
 * solids' signed distances, the implicit SPH engine (Algorithm 2) on the chosen backend,
 * monitors, ParaView output and a cost/accuracy summary. No CUDA or Thrust in this header.
 */
#include <twinflow/core/scene.h>
#include <twinflow_sph/engine.h>

#include <deal.II/base/parameter_handler.h>

#include <map>
#include <string>
#include <vector>

namespace twinflow::sph
{
  /// Method parameters of the SPH solver (subsection "SPH"). Each member holds the default of
  /// its entry (declare() prints it); an entry that sets an engine setting takes the default of
  /// EngineSettings (engine.h).
  struct SphParameters
  {
    std::string backend       = "cpu";
    double      spacing       = EngineSettings().spacing; ///< Δx
    double      h_over_dx     = 1.2;                      ///< smoothing length / spacing
    bool        consistent    = EngineSettings().consistent;
    double      alpha         = EngineSettings().alpha;
    DensityCorrection density_correction = EngineSettings().density_correction;
    bool        neumann_walls = EngineSettings().pressure_wall == PressureWall::neumann;
    double      free_surface_ratio = EngineSettings().free_surface_ratio;
    double      free_surface_divergence_ratio = 0.6;    ///< surface also where div r < ratio · dim (0: off)
    double      free_surface_neighbour_ratio  = 0.6;    ///< … or fewer neighbours than ratio · a full lattice support (0: off)
    /// … or, a droplet, fewer fluid neighbours than ratio · a full lattice support (0: off)
    double      free_surface_droplet_ratio    = 0.15;
    double      shifting      = EngineSettings().shifting; ///< particle-shifting coefficient (0: off)
    double      shifting_velocity_floor = EngineSettings().shifting_velocity_floor; ///< shifting speed scale max(|u_i|, floor) [m/s]
    bool        wetted_walls = EngineSettings().wetted_walls; ///< EngineSettings::wetted_walls
    bool        surface_offset = EngineSettings().surface_offset; ///< EngineSettings::surface_offset
    double      min_pair_distance = EngineSettings().min_pair_distance; ///< EngineSettings::min_pair_distance
    bool        limit_pressure_peaks = EngineSettings().limit_pressure_peaks; ///< EngineSettings::limit_pressure_peaks
    /// EngineSettings::conservative_gradient together with shifting_velocity_correction
    bool        energy_conserving_pair = EngineSettings().conservative_gradient;
    double      time_step     = 1e-3;   ///< maximum step
    double      cfl           = 0.2;    ///< dt ≤ CFL h / max(|u|, U_ref)
    double      solver_tolerance = SolverSettings().tolerance;
    int         max_iterations   = SolverSettings().max_iterations;
    /// pressure preconditioner: multigrid (else Jacobi)
    bool        multigrid = EngineSettings().pressure_preconditioner == PressurePreconditioner::multigrid;
    /// L_i = I where L_i is not SPD
    bool        positive_definite_laplacian = EngineSettings().correction_checks.positive_definite_laplacian;
    bool        relax_over_reference_step   = true;  ///< density error removed over Δt_ref, not Δt
    double      checkpoint_interval = 0;  ///< simulated time between checkpoints (0: none)
    std::string restart_file;             ///< checkpoint to continue from (empty: fresh start)

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  struct SphRunResult
  {
    std::size_t                   fluid_particles = 0, markers = 0, steps = 0;
    std::size_t                   removed_particles = 0; ///< fluid particles that left through an open top
    double                        wall_time = 0, final_time = 0;
    std::map<std::string, double> monitors;
    std::map<std::string, double> timings;   ///< seconds per phase (neighbours, assembly, solves, output)
    std::vector<std::string>      active_physics;
  };

  /// Neighbour count of a particle in a full lattice support (itself included): lattice points
  /// closer than 2h to a lattice point, 21 in 2D and 57 in 3D for h = 1.2 Δx.
  int full_support_count(int dim, double h_over_dx);

  /// The engine settings a scene and its SPH parameters call for (one place for the mapping).
  EngineSettings make_engine_settings(const Scene &scene, const SphParameters &parameters);

  /// Runs @p scene with SPH (on MPI rank 0 of MPI_COMM_WORLD), writing into @p dir.
  SphRunResult run_sph_scene(const Scene &scene, const SphParameters &parameters, const std::string &dir);
} // namespace twinflow::sph
