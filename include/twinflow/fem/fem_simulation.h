#pragma once
/**
 * @file fem_simulation.h
 * The Eulerian simulation composed from a Scene (DESIGN.md "FEM structure"): FemSimulation
 * owns the mesh, the physics the scene calls for (Navier–Stokes always; the immersed
 * boundary for solids on a box mesh; mesh adaptation when asked), the monitors and the
 * time loop; every field physics follows the FieldPhysics life cycle (field_physics.h).
 */
#include <twinflow/core/scene.h>
#include <twinflow/fem/immersed_boundary.h>
#include <twinflow/fem/level_set.h>
#include <twinflow/fem/mesh_adaptation.h>
#include <twinflow/fem/navier_stokes.h>
#include <twinflow/io/body_monitor.h>
#include <twinflow/solids/coupling.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::io
{
  class CsvMonitor;
  class SnapshotSchedule;
  class PvdSeries;
} // namespace twinflow::io

namespace twinflow::fem
{
  /// Method parameters of the FEM solver (subsection "FEM").
  struct FemParameters
  {
    unsigned int               global_refinements = 0;
    double                     time_step          = 1e-2; ///< fixed step, or the maximum with CFL control
    double                     cfl                = 0;    ///< > 0: dt = CFL h_min / |u|_max
    double                     steady_tolerance   = 0;    ///< > 0: stop when |du/dt|/|u| < tol
    double                     checkpoint_interval = 0;   ///< > 0: checkpoint every this many seconds
    unsigned int               coupling_iterations = 1;   ///< rigid bodies: 1 explicit, > 1 Aitken sub-iterations
    double                     coupling_tolerance  = 1e-3; ///< relative load residual that ends them
    std::string                restart_file;              ///< checkpoint to continue from (empty: none)
    NavierStokesParameters     navier_stokes;
    MeshAdaptationParameters   adaptation;
    ImmersedBoundaryParameters immersed_boundary;
    LevelSetParameters         level_set;

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// What a run measured: final monitors, errors vs references and its cost.
  struct FemRunResult
  {
    unsigned int                  cells = 0, steps = 0, adaptations = 0;
    unsigned long long            dofs  = 0;
    double                        wall_time = 0, final_time = 0;
    std::map<std::string, double> monitors;
    std::map<std::string, double> relative_errors;
    std::vector<std::string>      active_physics;
  };

  template <int dim>
  class FemSimulation
  {
  public:
    /// Composes the simulation (nothing is computed yet); runs on the ranks of @p comm.
    FemSimulation(const Scene &scene, const FemParameters &parameters, const std::string &output_directory,
                  MPI_Comm comm = MPI_COMM_WORLD);
    ~FemSimulation();

    /// Builds the mesh and the state (or loads the restart file) and runs to the end time.
    FemRunResult run();

    /// Mesh, initial refinement and initial state (run() calls it; tests may call it alone).
    void setup();
    /// One adaptation of the mesh to the registered interfaces, all fields transferred.
    void adapt_mesh();
    /// Writes a checkpoint (mesh + every field + scalars) under @p prefix.
    void write_checkpoint(const std::string &prefix);

    const NavierStokes<dim>                               &flow() const { return *navier_stokes; }
    NavierStokes<dim>                                     &flow() { return *navier_stokes; }
    const dealii::parallel::distributed::Triangulation<dim> &mesh() const { return tria; }
    const ImmersedBoundary<dim>                           *immersed_boundary() const { return ibm.get(); }
    const MeshAdaptation<dim>                             *mesh_adaptation() const { return adaptation.get(); }
    /// The free surface (null without one): space, φ transport, θ transport, corrections.
    const LevelSetSpace<dim>                              *level_set_space() const { return ls_space.get(); }
    const NclsTransport<dim>                              *level_set() const { return ncls.get(); }
    const VofTransport<dim>                               *volume_fraction() const { return vof.get(); }
    Redistancing<dim>                                     *redistancing() { return redistance.get(); }
    const SolidInteriorDrying<dim>                        *solid_drying() const { return drying.get(); }
    MassCorrection<dim>                                   *mass_correction() { return correction.get(); }
    /// Water volume, fronts and energies now (collective; free surface only).
    FreeSurfaceMeasures                                    free_surface_measures() const;
    /// The physics in the order they advance.
    const std::vector<FieldPhysics<dim> *>                &physics_list() const { return physics; }
    const std::vector<std::string>                        &active_physics() const { return result.active_physics; }

  private:
    void compose();
    void make_coarse_mesh();
    void set_boundary_conditions();
    void refine_initial_mesh();
    void load_checkpoint(const std::string &prefix);
    double next_time_step() const;
    void open_monitors();
    void compose_free_surface();
    void initialize_free_surface();
    void record(double dt, double divergence);
    void record_free_surface(double dt, double divergence);
    /// Nodal x, y(, z), φ of the level set into <dir>/snapshots/fem_t<time>.csv (root writes).
    void write_snapshot(double time) const;
    void write_output();
    void write_summary();

    const Scene                                         scene;
    const FemParameters                                 prm;
    const std::string                                   dir;
    MPI_Comm                                            comm;
    dealii::parallel::distributed::Triangulation<dim>   tria;
    std::array<dealii::types::boundary_id, 6>           face_id{{0, 1, 2, 3, 4, 5}};
    dealii::types::boundary_id                          body_id;
    bool                                                body_fitted = false;
    std::unique_ptr<MaterialModel<dim>>                 material;
    std::unique_ptr<NavierStokes<dim>>                  navier_stokes;
    std::unique_ptr<ImmersedBoundary<dim>>              ibm;
    std::unique_ptr<MeshAdaptation<dim>>                adaptation;
    std::unique_ptr<LevelSetSpace<dim>>                 ls_space;
    std::unique_ptr<NclsTransport<dim>>                 ncls;
    std::unique_ptr<VofTransport<dim>>                  vof;
    std::unique_ptr<Redistancing<dim>>                  redistance;
    std::unique_ptr<SolidInteriorDrying<dim>>           drying; ///< moving solids with a free surface
    std::unique_ptr<MassCorrection<dim>>                correction;
    /// moving solids: rigid bodies co-simulated through the IBM (solids/coupling.h)
    std::unique_ptr<solids::CoSimulation>               coupling;
    std::vector<solids::BodyLoad>                       body_loads; ///< fluid loads of the last step
    std::unique_ptr<io::BodyMonitor>                    body_monitor;
    /// Moves the immersed solids to where the rigid bodies are (after a body step or a restart).
    void sync_solid_motion();
    /// Moves the bodies over @p dt under @p loads; the IBM's φ_s, u_s follow.
    void advance_bodies(double dt, const std::vector<solids::BodyLoad> &loads);
    /// Navier–Stokes and the bodies over one step: explicit (the last step's loads), or with
    /// FEM/Coupling iterations > 1 repeated with Aitken-relaxed loads until they agree.
    void advance_flow_and_bodies(double dt);
    std::size_t coupling_steps = 0, coupling_solves = 0, coupling_unconverged = 0;
    void record_body_loads();
    double bodies_energy() const;
    std::shared_ptr<dealii::Function<dim>>              initial_water_distance;
    TwoFluids                                           two_fluids;
    unsigned int                                        vertical_axis = 1;
    std::vector<FieldPhysics<dim> *>                    physics;
    std::shared_ptr<dealii::Function<dim>>              inflow;

    std::unique_ptr<io::CsvMonitor> forces_csv, probes_csv, energy_csv, front_csv, volume_csv;
    /// Free-surface history for the summary: initial volume and energy, worst drift and rise.
    double initial_volume = 0, initial_energy = 0, worst_volume_drift = 0, worst_energy_rise = 0;
    /// max over the run of max|φ| / domain_diameter (volume.csv has φ's range per record)
    double worst_phi_range = 0, domain_diameter = 1;
    std::vector<double> front_time, front_position;
    std::unique_ptr<io::SnapshotSchedule> snapshots;
    std::unique_ptr<io::PvdSeries>  pvd;
    unsigned int                    output_count = 0;
    double                          next_output = 0, next_checkpoint = 0, coefficient_scale = 0;
    double                          h_min = 0; ///< smallest cell diameter of the current mesh
    FemRunResult                    result;
    /// The run's own work beside the physics (monitors every step, VTU/snapshot/checkpoint
    /// output), reported with the sub-solvers' sections in the summary.
    dealii::ConditionalOStream      silent{std::cout, false};
    mutable dealii::TimerOutput     run_timer{silent, dealii::TimerOutput::never, dealii::TimerOutput::wall_times};
  };

  /// Runs @p scene with the FEM on MPI_COMM_WORLD, writing into @p output_directory.
  template <int dim>
  FemRunResult run_fem(const Scene &scene, const FemParameters &parameters, const std::string &output_directory)
  {
    return FemSimulation<dim>(scene, parameters, output_directory).run();
  }

  /// Composes the FEM simulation of @p scene without running it: throws the input errors a
  /// run would throw before its first step (used by `twinflow --check`).
  void check_fem_scene(const Scene &scene, const FemParameters &parameters);

  /// Same with the dimension taken from the scene.
  FemRunResult run_fem_scene(const Scene &scene, const FemParameters &parameters, const std::string &output_directory);
} // namespace twinflow::fem
