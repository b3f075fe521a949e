#pragma once
/**
 * @file engine.h
 * Backend-neutral interface of the implicit SPH solver (Algorithm 2). No Thrust here:
 * the host side (source/sph) talks to either backend through plain std::vectors.
 */
#include <twinflow/geometry/vec.h>
#include <twinflow_sph/domain.h>
#include <twinflow_sph/solver_settings.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::sph
{

  /// Marker kinds.
  enum ParticleKind : int { fluid = 0, wall = 1, solid = 2 };

  enum class PressureWall { bce, neumann }; ///< Eq. 64–65 or Eq. 66–67

  /// How the density-invariance term of Eq. 55 (weight α) acts: `velocity`, Eq. 55 as written (the
  /// α-blended pressure corrects the velocity, which keeps the kick as kinetic energy: the Martin &
  /// Moyce energy rose 19 % at α = 1), or `position` (the α-blended pressure moves the particles,
  /// the velocity is projected with α = 0; one more, looser solve per step for q = p_α − p). `automatic`:
  /// position where the flow has a free surface, velocity otherwise.
  /// A free surface is where the velocity form feeds energy in (impacts, splash: doc/benchmarks.md,
  /// "SPH energy budget"); a confined flow has none, and there the α term acting on the velocity is
  /// what holds the particles out of a small body: the coarse periodic cylinder (a 16-marker
  /// cylinder, r = 2.5 Δx) diverges at t = 1.81 s with α = 0 and at 2.06 s with the position form,
  /// whose velocity projection is the α = 0 one. The standard operators' still water at rest is
  /// worse with the position form (bulk pressure error after 1 s 62 % against 16 %).
  enum class DensityCorrection { velocity, position, automatic };

  /// Preconditioner of the pressure solve: Jacobi or the cell-aggregation multigrid (multigrid.h).
  enum class PressurePreconditioner { jacobi, multigrid };

  /// Settings of the engine. Each member's initialiser is the one default of the setting: the
  /// scene parameters of subsection SPH (SphParameters, source/sph) take theirs from here.
  struct EngineSettings
  {
    double             spacing   = 0.02;  ///< initial inter-particle distance Δx
    double             h         = 0.024; ///< smoothing length (support 2h; scenes: ratio · Δx)
    double             rho0      = 1000;  ///< rest density
    double             mu        = 1e-3;  ///< dynamic viscosity
    bool               consistent = true; ///< consistent (Eq. 22–23) or standard (Eq. 19–20) operators
    double             alpha      = 0.5;  ///< blend of Eq. 55/57: density-invariance weight
    DensityCorrection  density_correction = DensityCorrection::automatic; ///< where the α term acts
    /// position form: relative tolerance of the density-error solve A q = b_α − b_0 (from q = 0;
    /// p_α = p + q moves the particles). q steers a displacement that the next step measures
    /// again, so 1e-2 suffices: the same energy, fronts and largest speeds as 1e-6 in half the
    /// iterations (doc/performance.md); the pressure solver's tolerance if that is looser
    double             density_correction_tolerance = 1e-2;
    PressureWall       pressure_wall = PressureWall::bce;
    double             free_surface_ratio = 0.95; ///< fluid with ρ_i < ratio ρ0 gets p = 0
    double             free_surface_divergence = 0; ///< … or with ∇·r_i below this (0: density only)
    double             free_surface_min_neighbours = 0; ///< … or with fewer neighbours, itself included (0: off)
    double             free_surface_min_fluid_neighbours = 0; ///< … or with fewer fluid neighbours, itself excluded (0: off)
    bool               free_surface = true;       ///< false: no p = 0 particles (confined flow)
    double             shifting     = 5;          ///< particle-shifting coefficient A (0: off)
    double             shifting_velocity_floor = 0; ///< D = A h max(|u_i|, this) Δt (0: |u_i|, the paper's form)
    /// fluid pairs closer than this fraction of Δx, one of them a free-surface particle, are
    /// pushed apart to it after the step's free-surface detection (PairSeparation; 0: off)
    double             min_pair_distance = 0.5;
    /// ∇p_i = 0 at a strict local pressure maximum (PeakGradientLimiter): consistent operators,
    /// and the standard operators' consistent rows at a free surface
    bool               limit_pressure_peaks = true;
    /// wall markers hold the liquid that wets them, Eq. 64 with ρ0 and the
    /// motion away from a wetted marker mirrored, up to |g| Δt, in the continuity source
    /// (ContinuityVelocity)
    bool               wetted_walls = true;
    /// with a free surface: p = 0 half a spacing beyond the free-surface
    /// particles, which carry p_s = Δx/2 ∂p/∂n (SurfacePressure), not at their centres
    bool               surface_offset = true;
    /// `SPH/Energy-conserving pair` (with shifting_velocity_correction): the consistent A^G made
    /// a summation-by-parts pair (make_gradient_conservative), its constraints relaxed by
    /// μ = conservative_regularisation on the rows with fewer than free_surface_min_neighbours
    /// entries, the weights ω of the rows near the free surface free. Still water rests, the
    /// α = 0 collapse gains no energy, and α > 0 gains only the density-error displacement's
    /// lift, a discretisation error (Martin & Moyce α = 1: 0.61 / 0.11 / 0.04 % at a/10 / a/20 /
    /// a/40). Each step costs a CG of ~40 (a/10) to ~70 (splash) iterations with the coarse space
    /// of the CPU backend: 4.6× (a/10) to 15× (a/40) the default step; block Jacobi alone (CUDA)
    /// needs 280 / 16,000+ (doc/benchmarks.md, "Where the α > 0 energy comes from").
    bool               conservative_gradient       = false;
    double             conservative_regularisation = 10;
    /// With conservative_gradient (`SPH/Energy-conserving pair`): a shifted particle's velocity
    /// is carried to its new position, u + (δx·∇)u (ShiftVelocity). Alone it gains 0.7-2.7 % on
    /// the coarse dam breaks and the splash scene runs away (doc/benchmarks.md).
    bool               shifting_velocity_correction = false;
    std::array<double, 3> acceleration{{0, 0, 0}}; ///< gravity + body force
    std::array<double, 3> gravity{{0, 0, 0}};      ///< g of Eq. 61/64
    SolverSettings     velocity_solver, pressure_solver;
    PressurePreconditioner pressure_preconditioner = PressurePreconditioner::multigrid;
    /// time over which the density-invariance term of Eq. 55/57 removes the density error:
    /// max(Δt, this); 0: Δt (the paper). A longer time keeps a CFL step shortened by a few fast
    /// particles from stiffening the correction as 1/Δt² (fast particle → small Δt → larger kicks)
    double             density_relaxation_time = 0;
    /// conditioning checks of the consistent corrections (CorrectionChecks): the engine keeps
    /// every pressure row elliptic (an operator on its own is exact by default)
    CorrectionChecks   correction_checks{true};
    /// face without BCE markers that fluid may cross (open top: 2 axis + 1 for the upper face of
    /// direction axis, 2 axis for the lower; −1: none): the last-resort clamp that keeps fluid
    /// inside the box skips it; the host removes the particles beyond (sph/open_boundary.h)
    int                open_face = -1;

    /// |g| of Eq. 61/64.
    double gravity_norm() const
    {
      return std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
    }

    /// Whether the free-surface particles carry the pressure of half a spacing (surface_offset).
    bool offsets_surface() const { return surface_offset && free_surface; }

    /// Whether the α term moves the particles (DensityCorrection::position, or `automatic` with a
    /// free surface); false when α = 0 (there is no α term).
    bool corrects_positions() const
    {
      return alpha > 0 && (density_correction == DensityCorrection::position ||
                           (density_correction == DensityCorrection::automatic && free_surface));
    }
  };

  /// Particles in host memory (structure of arrays).
  template <int dim>
  struct HostParticles
  {
    std::vector<geometry::Vec<dim>> x, u;
    std::vector<double>             p, rho;
    std::vector<int>                kind;
    std::vector<geometry::Vec<dim>> wall_velocity, wall_acceleration, normal; ///< BCE: u^p, a^p, n
    /// Index of the solid each `solid` marker belongs to (−1 for other kinds); empty: all
    /// solid markers form solid 0. Used for the per-solid fluid force (Engine::solid_force).
    std::vector<int>                body;
    std::size_t size() const { return x.size(); }

    /// Appends one particle; BCE velocity and acceleration start at zero.
    void add(const geometry::Vec<dim> &x_, const geometry::Vec<dim> &u_, const double p_, const double rho_,
             const int kind_ = ParticleKind::fluid, const geometry::Vec<dim> &normal_ = geometry::Vec<dim>::zero(),
             const int body_ = -1)
    {
      x.push_back(x_), u.push_back(u_), p.push_back(p_), rho.push_back(rho_), kind.push_back(kind_);
      wall_velocity.push_back(geometry::Vec<dim>::zero()), wall_acceleration.push_back(geometry::Vec<dim>::zero());
      normal.push_back(normal_), body.push_back(body_);
    }
  };

  /// Where the step's mechanical energy change (fluid kinetic + potential, J or J/m in 2D)
  /// came from: the sum of the members is the step's change of the total energy.
  struct EnergyBudget
  {
    double viscous    = 0; ///< ΔKE of the velocity prediction less the body force's work
    double body_force = 0; ///< work of gravity/body force over the prediction, m0 Δt a·(u^n + u*)/2
    double pressure   = 0; ///< ΔKE of the correction u* → u^{n+1} (and of the wall clamp)
    double potential  = 0; ///< ΔPE of the move x^n → x^n + Δt u^{n+1} (and of the wall clamp)
    double shifting   = 0; ///< ΔPE of particle shifting
    /// ΔPE of the density-error displacement −Δt²/ρ0 ∇q (the position form of the α term,
    /// DensityCorrection): the volume the α term gives back to compressed liquid lifts it
    double density_correction = 0;
  };

  /// What one step did (iterations, convergence, timings in seconds).
  struct StepReport
  {
    EnergyBudget budget;
    SolverResult velocity[3];
    /// the pressure phase: iterations of its solves (the position form: p and q), residual of p
    SolverResult pressure;
    int          free_surface_particles = 0;
    int          correction_fallbacks   = 0;
    double       max_speed              = 0;
    double       pressure_noise         = 0; ///< RMS of p_i − Shepard-averaged p over interior fluid [Pa]
    double       t_neighbors = 0, t_assembly = 0, t_velocity = 0, t_pressure = 0, t_update = 0;
    bool         converged() const;
  };

  /// Rigid motion of one solid's BCE markers over a step (Engine::move_solids), 3 components
  /// also in 2D: the markers of solid `body` go from x to to + R (x − from), their normals to
  /// R n; their expected velocity and acceleration (u^p, a^p of Eq. 59 and 61) become
  /// v + ω × r and a + α × r + ω × (ω × r) with r = x_new − to. `to` is also the point the
  /// torque of solid_torque() is taken about.
  struct MarkerMotion
  {
    int    body = 0;
    double from[3] = {0, 0, 0}, to[3] = {0, 0, 0};
    double rotation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double velocity[3] = {0, 0, 0}, angular_velocity[3] = {0, 0, 0};
    double acceleration[3] = {0, 0, 0}, angular_acceleration[3] = {0, 0, 0};
    /// Cross-section of the body in its x–y plane (all moving shapes are extrusions along z),
    /// for the last-resort no-penetration of fluid particles: 0 none, 1 round (half_size[0] =
    /// radius), 2 rectangle (half_size = half length, half thickness); `orientation`: body →
    /// world rotation at `to`.
    int    shape = 0;
    double half_size[2] = {0, 0};
    double orientation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  };

  template <int dim>
  class Engine
  {
  public:
    virtual ~Engine()                                         = default;
    virtual void              set_particles(const HostParticles<dim> &p) = 0;
    virtual void              get_particles(HostParticles<dim> &p) const = 0;
    virtual const StepReport &step(double dt)                 = 0;
    virtual double            max_fluid_speed() const         = 0;
    virtual std::size_t       n_neighbor_entries() const      = 0;
    virtual std::size_t       bytes_per_particle() const      = 0;
    virtual const char       *backend() const                 = 0;
    /// Fluid force on solid @p body (pressure + viscous, doc/equations.md "Forces on solids")
    /// from the last step (zero before the first step or if the solid has no markers).
    virtual std::array<double, 3> solid_force(int body) const = 0;
    /// Number of solids with markers (1 + the largest HostParticles::body index; 1 if body is
    /// empty and there are solid markers; 0 without solid markers).
    virtual int                   n_solids() const = 0;
    /// Fluid torque on solid @p body about the centre of its last MarkerMotion (the origin before
    /// any), from the last step; 3 components (2D: z only).
    virtual std::array<double, 3> solid_torque(int body) const = 0;
    /// Moves the markers of each listed solid rigidly and sets their wall velocity and
    /// acceleration (MarkerMotion); markers of other solids and walls are untouched. Fluid
    /// particles found inside a moved body's cross-section (closer than a quarter spacing to its
    /// surface) are put back on that offset and lose their velocity into the body, as the
    /// domain walls do (a fluid particle inside the BCE layers cannot be pushed out by them).
    virtual void                  move_solids(const std::vector<MarkerMotion> &motions) = 0;
  };

  /// Creates the engine of backend "cpu" or "cuda"; throws std::invalid_argument with
  /// a clear message if the backend is not part of this build.
  template <int dim>
  std::unique_ptr<Engine<dim>> make_engine(const std::string &backend, const DomainBox<dim> &box,
                                           const EngineSettings &settings);

  /// Backends compiled into this build ("cpu", and "cuda" when nvcc was found).
  std::vector<std::string> available_backends();
} // namespace twinflow::sph
