#pragma once
/**
 * @file navier_stokes.h
 * Variable-density incompressible Navier–Stokes by the incremental projection of
 * Guermond & Salgado (2009) — Eq. 16 of the paper and the pressure-increment Poisson
 * problem with ρ_min that follows it.
 *
 * One step t^n → t^{n+1} (BDF1 or variable-step BDF2, coefficients α0, α1, α2):
 *  1. velocity: ρ(α0 ũ + α1 u^n + α2 u^{n-1})/τ + ρ (u*·∇)ũ + ½[∂_tρ + ∇·(ρu*)] ũ
 *                − ∇·(2με(ũ)) + ∇p^# = ρ g + f,   p^# = p^n + (4/3 φ^n − 1/3 φ^{n-1} | φ^n);
 *  2. pressure increment: −Δφ^{n+1} = −(α0 ρ_min/τ) ∇·ũ  (φ = 0 on outflow, ∂_nφ = 0 elsewhere);
 *  3. pressure update: p^{n+1} = p^n + φ^{n+1}.
 * Taylor–Hood Q_{k+1}/Q_k on a parallel::distributed::Triangulation, Trilinos vectors,
 * AMG-preconditioned GMRES (velocity) and CG (pressure increment).
 */
#include <twinflow/fem/cell_dof_reader.h>
#include <twinflow/fem/cell_scatter.h>
#include <twinflow/fem/field_physics.h>
#include <twinflow/fem/material_model.h>
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/momentum_term.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/data_out.h>

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::fem
{
  enum class TimeScheme { bdf1, bdf2 };
  enum class ViscousForm { laplacian, symmetric };

  /// Numerical parameters of the flow solver (subsection "FEM/Navier-Stokes").
  struct NavierStokesParameters
  {
    unsigned int velocity_degree  = 2;   ///< k+1 of Q_{k+1}/Q_k
    unsigned int mapping_degree   = 1;
    TimeScheme   scheme           = TimeScheme::bdf2;
    ViscousForm  viscous_form     = ViscousForm::laplacian;
    double       linear_tolerance = 1e-10; ///< relative residual of every Krylov solve but the correction's
    double       correction_tolerance = 1e-6; ///< relative residual of the velocity correction's CG
    unsigned int amg_rebuild_interval = 1; ///< velocity preconditioner rebuilt every n steps
    unsigned int pressure_amg_interval = 2; ///< variable-density pressure AMG set up every n steps
    std::string  velocity_preconditioner = "amg"; ///< amg | ilu | ssor | jacobi
    double       streamline_diffusion = 0;      ///< c of c τ_K ρ (u*·∇u)(u*·∇v); 0: Galerkin
    bool         variable_projection  = false;  ///< −∇·(ρ⁻¹∇φ) instead of −χΔφ, χ = ρ_min

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// Statistics of the last step (for progress lines and summaries).
  struct StepStatistics
  {
    unsigned int velocity_iterations = 0;
    unsigned int pressure_iterations = 0;
    double       divergence_l2       = 0;
    double       velocity_change     = 0; ///< max |u^{n+1} − u^n| over the DoFs
  };

  template <int dim>
  class NavierStokes : public FieldPhysics<dim>
  {
  public:
    NavierStokes(dealii::parallel::distributed::Triangulation<dim> &tria,
                 const NavierStokesParameters                      &parameters,
                 const MaterialModel<dim>                          &material);

    /// Velocity prescribed on boundary @p id (a zero function = no slip).
    void set_dirichlet(dealii::types::boundary_id id, std::shared_ptr<dealii::Function<dim>> u);
    /// Free slip on the axis-aligned face @p id whose normal is @p axis: u_axis = 0, no shear.
    void set_slip(dealii::types::boundary_id id, unsigned int axis);
    /// Do-nothing outflow (μ∇u − pI)n = 0 on @p id; φ = 0 there.
    void set_outflow(dealii::types::boundary_id id);
    /// Periodic pair of boundaries in @p direction (the triangulation must already
    /// have the matching periodicity added).
    void set_periodic(dealii::types::boundary_id b1, dealii::types::boundary_id b2, unsigned int direction);
    /// Body acceleration g(x,t) (gravity, driving force per unit mass): enters as ρ g.
    void set_acceleration(std::shared_ptr<dealii::Function<dim>> g);
    /// Force density f(x,t) (per unit volume, not multiplied by ρ).
    void set_force_density(std::shared_ptr<dealii::Function<dim>> f);

    /// Extra terms of the velocity step (IBM, ...): see momentum_term.h. Register before
    /// the first step; the term must outlive the solver.
    void add_momentum_term(const MomentumTerm<dim> &term) { momentum_terms.push_back(&term); }

    // ---- FieldPhysics life cycle ----------------------------------------------------------
    std::string name() const override { return "navier-stokes"; }
    /// Distribute DoFs, build constraints, sparsity, the pressure Laplacian and its AMG on the
    /// current mesh; (re)size the state vectors. Called again after every adaptation.
    void setup_dofs() override;
    /// Same as setup_dofs() (kept for the verification tests).
    void setup() { setup_dofs(); }
    /// u^n, u^{n-1} and p^n, φ^n, φ^{n-1} go through parallel::distributed::SolutionTransfer.
    void prepare_transfer(bool serialization) override;
    void finish_transfer(bool serialization) override;
    void advance(double dt) override { step(dt); }
    void save_state(std::ostream &out) const override;
    void load_state(std::istream &in) override;
    dealii::types::global_dof_index n_dofs() const override { return n_velocity_dofs() + n_pressure_dofs(); }

    /// Initial state at @p t0. If @p u_previous is given (the velocity at t0 − dt_previous),
    /// BDF2 starts with a second-order step; otherwise the first step is BDF1.
    void initialize(const dealii::Function<dim> &u0,
                    const dealii::Function<dim> &p0,
                    double                       t0,
                    const dealii::Function<dim> *u_previous  = nullptr,
                    double                       dt_previous = 0);

    /// Advance one step of size @p dt.
    const StepStatistics &step(double dt);

    /// Everything step() changes: repeating a step from a StepState (coupling sub-iterations)
    /// gives the same result as the first try with the same data.
    struct StepState
    {
      dealii::TrilinosWrappers::MPI::Vector u_n, u_nm1, p_n, phi_n, phi_nm1;
      double                                current_time = 0, dt_last = 0, dt_before_last = 0;
      unsigned int                          step_number  = 0;
      bool                                  have_history = false;
    };
    StepState save_step() const;
    /// Back to @p state (same mesh as when it was saved).
    void restore_step(const StepState &state);

    double       time() const { return current_time; }
    /// Changes whenever the velocity vectors do (a step, a restore, a new mesh or a restart):
    /// other physics key per-step caches of velocity values on it.
    std::uint64_t state_id() const { return state_counter; }
    const StepStatistics &statistics() const { return stats; }
    unsigned int n_steps() const { return step_number; }

    /// Hydrodynamic force on boundary @p id, evaluated consistently as minus the residual
    /// of the discrete momentum equation tested with functions equal to e_d on it.
    dealii::Tensor<1, dim> boundary_force(dealii::types::boundary_id id) const;
    /// Pressure at a point (any rank may ask; the owner evaluates).
    double pressure_at(const dealii::Point<dim> &p) const;
    /// L2 errors of velocity and pressure (pressure means removed when p is floating).
    std::pair<double, double> l2_errors(const dealii::Function<dim> &u_exact,
                                        const dealii::Function<dim> &p_exact) const;
    double max_velocity() const;
    double kinetic_energy() const;  ///< ½∫ρ|u|²
    double minimal_cell_diameter() const;

    void add_to_output(dealii::DataOut<dim> &data_out) const override;

    dealii::types::global_dof_index n_velocity_dofs() const { return velocity_dofs.n_dofs(); }
    dealii::types::global_dof_index n_pressure_dofs() const { return pressure_dofs.n_dofs(); }
    const dealii::DoFHandler<dim> &velocity_dof_handler() const { return velocity_dofs; }
    const dealii::DoFHandler<dim> &pressure_dof_handler() const { return pressure_dofs; }
    const dealii::TrilinosWrappers::MPI::Vector &velocity() const { return u_n; }
    const dealii::TrilinosWrappers::MPI::Vector &pressure() const { return p_n; }
    /// True when the last step corrected the velocity after the pressure solve (the
    /// variable-density projection); then velocity() differs from momentum_velocity().
    bool velocity_corrected() const { return prm.variable_projection && !material.is_constant(); }
    /// ũ^{n+1}, the velocity of the last momentum step (before the variable-density
    /// correction; kept only when momentum terms need it), else velocity().
    const dealii::TrilinosWrappers::MPI::Vector &momentum_velocity() const
    {
      return velocity_corrected() && !momentum_terms.empty() ? u_momentum : u_n;
    }
    /// φ^{n+1} = p^{n+1} − p^n, the pressure increment of the last step.
    const dealii::TrilinosWrappers::MPI::Vector &pressure_increment() const { return phi_n; }
    /// u^n once a step has been taken (u^{n+1} is velocity()): the level-set transports use
    /// the midpoint velocity of the step.
    const dealii::TrilinosWrappers::MPI::Vector &previous_velocity() const { return u_nm1; }
    const dealii::Mapping<dim> &get_mapping() const { return mapping; }
    /// Cell reads of the ghosted velocity vectors (velocity(), previous_velocity(), ...).
    const CellDofReader<dim> &velocity_reader() const { return velocity_cells; }
    const CellDofReader<dim> &pressure_reader() const { return pressure_cells; }
    const dealii::TimerOutput &timer() const { return timer_output; }
    /// Whether the momentum and correction systems are solved as component blocks on this mesh
    /// (see use_component_blocks()).
    bool solves_component_blocks() const { return component_blocks; }
    /// Viscous stress form of the momentum equation: true for 2με(u), false for μ∇u.
    bool symmetric_stress() const { return prm.viscous_form == ViscousForm::symmetric; }
    const MaterialModel<dim> &material_model() const { return material; }

  private:
    struct BdfCoefficients
    {
      double a0, a1, a2;   ///< BDF derivative (a0 u^{n+1} + a1 u^n + a2 u^{n-1}) / τ
      double e0, e1;       ///< extrapolation u* = e0 u^n + e1 u^{n-1}
    };
    BdfCoefficients coefficients(double dt) const;

    void make_velocity_constraints(double t);
    void make_pressure_constraints();
    /// Hanging-node and periodicity constraints only (to fix transferred fields).
    void make_mesh_constraints(const dealii::DoFHandler<dim> &dofs, const dealii::IndexSet &relevant,
                               dealii::AffineConstraints<double> &c) const;
    void assemble_pressure_laplacian();
    /// G_ij = (∂_{c_i} q_j, v_i), rows condensed by the velocity constraints: the right-hand
    /// side (∇φ, v) of the variable-density correction is G φ (the mesh fixes G).
    void assemble_pressure_gradient();
    /// AMG of the current pressure_laplace (mesh Laplacian, or the ρ⁻¹-weighted one per step).
    void initialize_pressure_amg();
    void assemble_velocity_system(double dt, const BdfCoefficients &c);
    unsigned int solve_velocity(const BdfCoefficients &c);
    unsigned int solve_pressure_increment(double dt, const BdfCoefficients &c);
    /// Variable-density projection: u^{n+1} = ũ − (τ/(α0 ρ))∇φ^{n+1} (φ_n, just solved for),
    /// L²(ρ)-projected onto V_h with the mass assembled beside the momentum matrix.
    void         correct_velocity(double dt, const BdfCoefficients &c);

    MPI_Comm                                           comm;
    dealii::parallel::distributed::Triangulation<dim> &tria;
    NavierStokesParameters                             prm;
    const MaterialModel<dim>                          &material;
    dealii::MappingQ<dim>                              mapping;
    dealii::FESystem<dim>                              fe_velocity;
    dealii::FE_Q<dim>                                  fe_pressure;
    dealii::DoFHandler<dim>                            velocity_dofs, pressure_dofs;
    /// One velocity component (the scalar base element): the DoFs of the component blocks.
    /// Exists only while they are used: a DoFHandler without an element on a distributed mesh
    /// fails in its refinement callbacks.
    std::unique_ptr<dealii::DoFHandler<dim>>           component_dofs;
    dealii::IndexSet velocity_owned, velocity_relevant, pressure_owned, pressure_relevant;
    CellDofReader<dim> velocity_cells, pressure_cells;
    CellScatter<dim>   velocity_scatter, mass_scatter, pressure_scatter; ///< set up after the first assembly on a mesh
    /// ρ^{n+1} at the momentum assembly's quadrature points of each active cell (two phases):
    /// written by the assembly, read by the pressure projection of the same step.
    std::vector<double> step_density;
    /// diameter/√dim of the owned active cells (by active_cell_index), per mesh: diameter()
    /// reads the vertices on every call (0.4 % of a dam-break step in the momentum assembly)
    std::vector<double> cell_sizes;

    std::map<dealii::types::boundary_id, std::shared_ptr<dealii::Function<dim>>> dirichlet;
    std::map<dealii::types::boundary_id, unsigned int> slip; ///< face → its normal axis
    std::set<dealii::types::boundary_id>                                           outflow;
    struct Periodic { dealii::types::boundary_id b1, b2; unsigned int direction; };
    std::vector<Periodic>                  periodic;
    std::shared_ptr<dealii::Function<dim>> acceleration, force_density;

    dealii::AffineConstraints<double> velocity_constraints, pressure_constraints,
      increment_constraints;
    bool pressure_floating = false;

    dealii::TrilinosWrappers::SparseMatrix velocity_matrix, pressure_laplace, velocity_mass;
    /// Component blocks (use_component_blocks()): the momentum matrix and the L²(ρ) mass are
    /// diag(S, …, S) with one scalar S on component_dofs; the velocity is numbered so that a
    /// rank's owned part is its S-rows once per component, and the Krylov solves apply S to all
    /// components in one product (ComponentBlockMatrix): the matrix is stored, assembled and
    /// read once instead of dim times. velocity_matrix and velocity_mass stay empty.
    bool                                   component_blocks = false;
    dealii::AffineConstraints<double>      component_constraints; ///< of one component (homogeneous)
    dealii::TrilinosWrappers::SparseMatrix component_matrix, component_mass;
    CellScatter<dim>                       component_scatter, component_mass_scatter, rhs_scatter;
    /// Whether this scene's momentum matrix has the component-block form: μ∇u (no symmetric
    /// stress), no momentum terms (IBM), no slip walls (u·n = 0 constrains one component),
    /// and the Jacobi preconditioner (the others factor the vector matrix).
    bool use_component_blocks() const;
    /// Numbers the velocity DoFs in component blocks of component_dofs' numbering; false (and
    /// nothing renumbered) if a rank's owned DoFs do not split that way.
    bool number_velocity_by_components();
    dealii::TrilinosWrappers::SparseMatrix pressure_gradient; ///< see assemble_pressure_gradient()
    dealii::TrilinosWrappers::PreconditionAMG velocity_amg, pressure_amg;
    ReusableIlu                               velocity_ilu; ///< its fill graph kept per mesh
    dealii::TrilinosWrappers::PreconditionSSOR   velocity_ssor;
    InverseDiagonal                           velocity_jacobi, mass_jacobi;
    dealii::TrilinosWrappers::MPI::Vector     velocity_rhs, pressure_rhs;

    /// Ghosted state: u^n, u^{n-1}, p^n, φ^n, φ^{n-1}.
    dealii::TrilinosWrappers::MPI::Vector u_n, u_nm1, p_n, phi_n, phi_nm1;
    dealii::TrilinosWrappers::MPI::Vector u_momentum; ///< ũ^{n+1} (see momentum_velocity())
    dealii::TrilinosWrappers::MPI::Vector last_correction; ///< δ of the last velocity correction (the next guess)
    double       current_time = 0, dt_last = 0, dt_before_last = 0;
    unsigned int step_number = 0;
    bool         have_history = false; ///< u^{n-1} is a real previous step
    std::uint64_t state_counter = 0;   ///< see state_id()

    /// DoFs on each boundary whose force is asked for (found once per mesh, not per step).
    mutable std::map<dealii::types::boundary_id, dealii::IndexSet> force_dofs;

    std::vector<const MomentumTerm<dim> *> momentum_terms;

    using Transfer = dealii::parallel::distributed::SolutionTransfer<dim, dealii::TrilinosWrappers::MPI::Vector>;
    std::unique_ptr<Transfer> velocity_transfer, pressure_transfer;
    bool                      rebuild_velocity_preconditioner = true;
    /// Steps the variable-density pressure AMG has been applied to later matrices (see
    /// solve_pressure_increment); pressure_amg_interval or more: set it up for this step's.
    unsigned int              pressure_amg_age = std::numeric_limits<unsigned int>::max();
    unsigned int              fresh_pressure_iterations = 0; ///< CG iterations of the last solve with a fresh AMG

    StepStatistics           stats;
    dealii::ConditionalOStream  silent_stream{std::cout, false};
    mutable dealii::TimerOutput timer_output;
  };
} // namespace twinflow::fem
