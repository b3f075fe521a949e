#include <twinflow/core/errors.h>
#include <twinflow/sph/sph_simulation.h>
#include <twinflow_sph/engine.h>

#include <algorithm>
#include <array>

namespace twinflow::sph
{
  namespace
  {
    /// The entry values of `Density error correction`, in the order of DensityCorrection.
    constexpr std::array<const char *, 3> density_correction_names{{"velocity", "position", "auto"}};
  } // namespace

  bool StepReport::converged() const
  {
    return pressure.converged && velocity[0].converged && velocity[1].converged && velocity[2].converged;
  }

  void SphParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii;
    using Patterns::Tools::to_string;
    const SphParameters d; // the defaults: one place for each (the engine's in EngineSettings)
    prm.enter_subsection("SPH");
    prm.declare_entry("Backend", d.backend, Patterns::Selection("cpu|cuda"),
                      "Where the SPH kernels run: cpu (Thrust OpenMP) or cuda (needs a build with nvcc and a GPU).");
    prm.declare_entry("Particle spacing", to_string(d.spacing), Patterns::Double(0), "Initial inter-particle distance [m], > 0.");
    prm.declare_entry("Smoothing length ratio", to_string(d.h_over_dx), Patterns::Double(0.5, 3), "h / spacing (kernel support 2h).");
    prm.declare_entry("Operators", d.consistent ? "consistent" : "standard", Patterns::Selection("consistent|standard"),
                      "Discrete gradient/Laplacian: consistent (Eq. 22-26) or standard (Eq. 19-20; the kernel "
                      "operators multiplied by the lattice factor dim / tr G^{-1} of Eq. 24, exact on a regular lattice, and the "
                      "rows a free surface truncates assembled consistent, without which still water never rests).");
    prm.declare_entry("Alpha", to_string(d.alpha), Patterns::Double(0, 1),
                      "Weight of the density-invariance source in the pressure equation (Eq. 55/57).");
    prm.declare_entry("Density error correction", density_correction_names[static_cast<int>(d.density_correction)],
                      Patterns::Selection("auto|position|velocity"),
                      "Where the density-invariance source (weight Alpha) acts: position (the Alpha-blended pressure "
                      "moves the particles, the velocity is projected with Alpha = 0: the correction adds no kinetic "
                      "energy; one more solve per step, for the density-error part q = p_Alpha - p to 1e-2 of its "
                      "right-hand side), velocity (Eq. 55 as written), or auto: position "
                      "where the scene has a free surface, velocity otherwise (in a confined flow the velocity form "
                      "keeps particles out of small bodies).");
    prm.declare_entry("Wall pressure condition", d.neumann_walls ? "neumann" : "bce", Patterns::Selection("bce|neumann"),
                      "BCE markers' pressure rows: force balance (Eq. 64-65) or zero normal gradient (Eq. 66-67).");
    prm.declare_entry("Free-surface density ratio", to_string(d.free_surface_ratio), Patterns::Double(0, 1),
                      "Fluid particles with summation density below ratio * rho0 are free-surface particles (p = 0).");
    prm.declare_entry("Free-surface divergence ratio", to_string(d.free_surface_divergence_ratio), Patterns::Double(0, 1),
                      "Fluid particles whose position divergence div r is below ratio * dim are also free-surface "
                      "particles (catches the surface where BCE markers fill the density up, e.g. at walls; Lind et "
                      "al. 2012 use 1.5 in 2D); 0: density criterion only.");
    prm.declare_entry("Free-surface neighbour ratio", to_string(d.free_surface_neighbour_ratio), Patterns::Double(0, 1),
                      "Fluid particles with fewer neighbours (all kinds, itself included) than ratio * the count of "
                      "a full lattice support (21 in 2D, 57 in 3D at h = 1.2 dx) are also free-surface particles "
                      "(spray clusters, whose compression hides the density deficit); 0: off.");
    prm.declare_entry("Free-surface droplet ratio", to_string(d.free_surface_droplet_ratio), Patterns::Double(0, 1),
                      "Fluid particles with fewer fluid neighbours (itself excluded) than ratio * the count of a full "
                      "lattice support are droplets and free-surface particles (not next to a solid body). BCE markers "
                      "fill a droplet's support at a wall, so the other criteria see interior water, and the droplet "
                      "and the markers beside it would form a singular block of the pressure system. 0.15: 3.15 in "
                      "2D, 8.6 in 3D; a corner particle of a full tank has 7 / 16. 0: off.");
    prm.declare_entry("Particle shifting", to_string(d.shifting), Patterns::Double(0, 10),
                      "Coefficient A of Fickian particle shifting (dr = -A h |u| dt grad C, Lind et al. 2012); 0: off.");
    prm.declare_entry("Shifting velocity floor", to_string(d.shifting_velocity_floor), Patterns::Double(0),
                      "Speed scale of particle shifting: dr = -A h max(|u|, floor) dt grad C [m/s]. > 0: shifting also "
                      "acts at rest (damps the row-pairing mode of the consistent operators next to walls) and "
                      "particles next to the free surface are not shifted; 0: |u| (Lind et al. 2012).");
    prm.declare_entry("Minimum pair distance", to_string(d.min_pair_distance), Patterns::Double(0, 0.9),
                      "Fluid particles closer than this fraction of the spacing are pushed apart to it, along the "
                      "line joining them, after each step's free-surface detection (velocities unchanged; not next "
                      "to a solid body). Pairs form at the free surface: free-surface particles feel no pressure and "
                      "are not shifted, and a kernel's gradient vanishes at r = 0, so nothing else separates a pair "
                      "that has formed; a pair swept back into the water compresses its support by up to 20 % and "
                      "is kicked out by the density-invariance pressure. Water that keeps its volume has no pair "
                      "this close. 0: off.");
    prm.declare_entry("Limit pressure peaks", d.limit_pressure_peaks ? "true" : "false", Patterns::Bool(),
                      "Consistent operators: a fluid particle whose pressure is a strict local maximum (p > 0, above "
                      "every neighbour) or minimum (p < 0, below every neighbour) gets a zero pressure gradient, the "
                      "gradient of a smooth field at its extremum. Otherwise the one-sided consistent gradient of "
                      "such a particle at the edge of colliding splash sheets, or of a tear between separating "
                      "streams, ejects it (spray kicks). Not next to a solid.");
    prm.declare_entry("Energy-conserving pair", d.energy_conserving_pair ? "true" : "false", Patterns::Bool(),
                      "Consistent operators: the pressure gradient is rewritten, by the smallest change, as the "
                      "negative adjoint of the velocity divergence (a summation-by-parts pair, still exact for "
                      "linear fields), so the pressure does no work on the liquid but at the walls; particle "
                      "shifting then carries each shifted particle's velocity to its new position (u + dx.grad u). "
                      "A dam break then gains no energy at alpha = 0 and, at alpha > 0, only what the "
                      "density-error displacement gives back (Martin & Moyce, alpha = 1: 0.61 / 0.11 / 0.04 % at "
                      "a/10 / a/20 / a/40, against 4.75 / 2.14 / 1.25 % without). Costs a conjugate-gradient "
                      "solve for the pair's multipliers every step: 4.6 / 7.7 / 15 times the step without it at "
                      "a/10 / a/20 / a/40. CPU backend only (its coarse level is host code).");
    prm.declare_entry("Wetted walls", d.wetted_walls ? "true" : "false", Patterns::Bool(),
                      "Wall BCE markers hold the liquid that wets them: their force-balance "
                      "pressure (Eq. 64) uses rho0 instead of the fluid's summation density, and each wall "
                      "marker mirrors the fluid's motion away from the wall (up to |g| dt) as well as towards "
                      "it. Keeps still water in a walled tank at rest (without it the "
                      "tank diverges at t = 2.4 s).");
    prm.declare_entry("Free-surface offset", d.surface_offset ? "true" : "false", Patterns::Bool(),
                      "p = 0 lies half a spacing above the free-surface particles (the top "
                      "of the liquid they hold), so they carry p = dx/2 dp/dn from the liquid beneath, hydrostatic "
                      "at most, zero in free fall. false: p = 0 at their centres (the paper's form), which leaves the "
                      "whole pressure field rho |g| dx/2 low: a floating body sinks by dx/2.");
    prm.declare_entry("Time step", to_string(d.time_step), Patterns::Double(0), "Maximum time step [s], > 0.");
    prm.declare_entry("CFL number", to_string(d.cfl), Patterns::Double(0),
                      "dt <= CFL h / max(|u|_max, Monitors/Reference velocity); 0: fixed step.");
    prm.declare_entry("Solver tolerance", to_string(d.solver_tolerance), Patterns::Double(0, 1), "Relative residual of the BiCGStab solves.");
    prm.declare_entry("Pressure preconditioner", d.multigrid ? "multigrid" : "jacobi", Patterns::Selection("multigrid|jacobi"),
                      "Preconditioner of the pressure BiCGStab: multigrid (cell aggregation, iterations nearly "
                      "independent of the particle count) or jacobi.");
    prm.declare_entry("Density error relaxation",
                      d.relax_over_reference_step ? "reference step" : "step", Patterns::Selection("step|reference step"),
                      "Time over which the density-invariance source (Eq. 55/57) removes the density error: the "
                      "current step (the paper) or the reference step min(Time step, CFL h / Monitors/Reference "
                      "velocity), so that a CFL step shortened by a few fast particles does not stiffen it as 1/dt^2.");
    prm.declare_entry("Positive-definite Laplacian correction", to_string(d.positive_definite_laplacian), Patterns::Bool(),
                      "Consistent operators: a particle whose L_i is not positive definite, or next to a free "
                      "surface has an eigenvalue above 4 (a degenerate truncated support), gets the standard "
                      "Laplacian row (keeps the pressure rows elliptic and the viscous rows diffusive in "
                      "splashing flows).");
    prm.declare_entry("Max iterations", to_string(d.max_iterations), Patterns::Integer(1), "Iteration cap of the BiCGStab solves.");
    prm.declare_entry("Checkpoint interval", to_string(d.checkpoint_interval), Patterns::Double(0),
                      "Simulated time [s] between checkpoints of the particle state (<output>/sph/checkpoint.bin, "
                      "replaced each time); 0: none. A diverging run also leaves last_good_state.bin.");
    prm.declare_entry("Restart file", d.restart_file, Patterns::Anything(),
                      "Checkpoint to continue from (checkpoint.bin or last_good_state.bin of a run of the same scene "
                      "and spacing); empty: start at t = 0. Restarting into the same output directory continues its "
                      "monitors and particle series.");
    prm.leave_subsection();
  }

  void SphParameters::parse(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("SPH");
    backend   = prm.get("Backend");
    spacing   = prm.get_double("Particle spacing");
    require(spacing > 0, "SPH/Particle spacing", prm.get("Particle spacing"), "the spacing must be > 0");
    h_over_dx = prm.get_double("Smoothing length ratio");
    consistent    = prm.get("Operators") == "consistent";
    alpha         = prm.get_double("Alpha");
    const std::string correction = prm.get("Density error correction");
    density_correction = static_cast<DensityCorrection>(
      std::find(density_correction_names.begin(), density_correction_names.end(), correction) -
      density_correction_names.begin());
    neumann_walls = prm.get("Wall pressure condition") == "neumann";
    free_surface_ratio = prm.get_double("Free-surface density ratio");
    free_surface_divergence_ratio = prm.get_double("Free-surface divergence ratio");
    free_surface_neighbour_ratio  = prm.get_double("Free-surface neighbour ratio");
    free_surface_droplet_ratio    = prm.get_double("Free-surface droplet ratio");
    shifting           = prm.get_double("Particle shifting");
    shifting_velocity_floor = prm.get_double("Shifting velocity floor");
    wetted_walls            = prm.get_bool("Wetted walls");
    surface_offset          = prm.get_bool("Free-surface offset");
    min_pair_distance       = prm.get_double("Minimum pair distance");
    limit_pressure_peaks    = prm.get_bool("Limit pressure peaks");
    energy_conserving_pair  = prm.get_bool("Energy-conserving pair");
    require(!energy_conserving_pair || consistent, "SPH/Energy-conserving pair", "true",
            "the pair is built from the consistent gradient: it needs SPH/Operators = consistent");
    require(!energy_conserving_pair || backend == "cpu", "SPH/Energy-conserving pair", "true",
            "the pair needs SPH/Backend = cpu (its multipliers' coarse level is host code; block Jacobi alone, all "
            "the CUDA backend has, takes 16,000+ iterations on a column 100 particles wide)");
    time_step = prm.get_double("Time step");
    require(time_step > 0, "SPH/Time step", prm.get("Time step"), "the time step must be > 0");
    cfl              = prm.get_double("CFL number");
    solver_tolerance = prm.get_double("Solver tolerance");
    max_iterations   = prm.get_integer("Max iterations");
    multigrid        = prm.get("Pressure preconditioner") == "multigrid";
    relax_over_reference_step   = prm.get("Density error relaxation") == "reference step";
    positive_definite_laplacian = prm.get_bool("Positive-definite Laplacian correction");
    checkpoint_interval         = prm.get_double("Checkpoint interval");
    restart_file                = prm.get("Restart file");
    prm.leave_subsection();
    const auto b = available_backends();
    if (std::find(b.begin(), b.end(), backend) == b.end())
      throw InputError("invalid value for 'SPH/Backend' = '" + backend +
                       "': this build has no CUDA backend (nvcc was not found when it was configured); allowed: cpu");
  }
} // namespace twinflow::sph
