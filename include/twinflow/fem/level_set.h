#pragma once
/**
 * @file level_set.h
 * Two phases by the conservative level set of the paper (Section 3.1, Algorithm 1; Kees et
 * al. 2011): φ is the signed distance to the free surface, negative in water, positive in
 * air; θ the air volume fraction. Per step, after Navier–Stokes (which used ρ(φⁿ), μ(φⁿ)):
 *
 *   NclsTransport   Eq. 7   ∂φ/∂t + u·∇φ = 0                   → φ*
 *   VofTransport    Eq. 8   ∂θ/∂t + ∇·(uθ) = 0 (conservative)   → θ*
 *   Redistancing    Eq. 14  steady state |∇φ| = 1, φ = 0 on Γ  → φ**
 *   MassCorrection  Eq. 12  H_ε(φ** + u) − θ* = κ Δu (Newton)   → φ = φ** + u, θ = H_ε(φ)
 *
 * Each is a FieldPhysics (setup, transfer, advance, output, checkpoint) on the Q_k space of
 * LevelSetSpace, which is itself the first physics of the list (it distributes the DoFs) and
 * the AdaptationInterface of the free surface (the refinement band follows φ = 0).
 * TwoPhaseMaterial hands ρ, μ (Eq. 9–10 with H_ε of Eq. 13, ε = factor × h_K) and the two
 * earlier densities ρ^n, ρ^{n−1} (for the √ρ form of the time derivative) to Navier–Stokes. A scene with one fluid constructs none of this.
 */
#include <twinflow/fem/cell_dof_reader.h>
#include <twinflow/fem/cell_scatter.h>
#include <twinflow/fem/linear_solve.h>
#include <twinflow/fem/field_physics.h>
#include <twinflow/fem/material_model.h>
#include <twinflow/fem/mesh_adaptation.h>
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>
#include <cstdint>
#include <limits>
#include <memory>
#include <array>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace twinflow::fem
{
  /// Parameters of subsection "FEM/Level set".
  struct LevelSetParameters
  {
    unsigned int degree           = 1;    ///< Q_k of φ and θ
    double       interface_width  = 1.5;  ///< ε / h_K of H_ε (Eq. 13); the paper: h < ε < 2h
    double       shock_capturing  = 0.0;  ///< c_sc of the NCLS/VOF shock-capturing viscosity (0: SUPG alone)
    double       correction_diffusion = 10; ///< κ / h_K of the mass correction (Eq. 12)
    double       correction_tolerance = 1e-10; ///< Newton: |∫H(φ+u) − ∫θ| / ∫1 below this
    bool         redistance       = true; ///< Eq. 14 (false: never)
    /// Redistance only the far field (|φ| beyond far_field_band ε_min), the band keeps its
    /// transported φ: "Redistancing = far field".
    bool         far_field_only   = false;
    static constexpr double far_field_band = 2.0; ///< the untouched band |φ| < this × ε of the finest cell
    unsigned int redistancing_interval = 1; ///< steps between redistancings
    bool         mass_correction  = true; ///< Eq. 12 every step (false: θ and φ drift apart)
    bool         dry_moving_solids = true; ///< φ ← max(φ, −φ_s) inside moving solids every step
    double       linear_tolerance = 1e-10;

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// Sign convention and the phase properties of Eq. 9–10.
  struct TwoFluids
  {
    double rho_water = 1000, mu_water = 1e-3, rho_air = 1.2, mu_air = 1.8e-5;
  };

  template <int dim>
  class NclsTransport;
  template <int dim>
  class VofTransport;

  /**
   * The finite-element space of φ and θ (Q_k on the flow's mesh): DoFs, hanging-node and
   * periodicity constraints, the sparsity all level-set matrices share, the lumped mass.
   * Also the free surface as an interface the mesh adaptation follows (|φ| at cell centres;
   * before any field exists, the initial signed distance).
   */
  /// ψ_a(x_q) of @p fe at the points of @p quad, (a, q): the same on every cell for FE_Q, so
  /// the cell loops that need only values at a fixed rule read them from this table.
  template <int dim>
  dealii::FullMatrix<double> reference_shape_values(const dealii::FiniteElement<dim> &fe,
                                                    const dealii::Quadrature<dim>     &quad)
  {
    dealii::FullMatrix<double> shape(fe.n_dofs_per_cell(), quad.size());
    for (unsigned int a = 0; a < shape.m(); ++a)
      for (unsigned int q = 0; q < shape.n(); ++q)
        shape(a, q) = fe.shape_value(a, quad.point(q));
    return shape;
  }

  /// Σ_a local_a ψ_a(x_q) from a reference_shape_values() table.
  inline void values_at_points(const dealii::FullMatrix<double> &shape, const std::vector<double> &local,
                               std::vector<double> &out)
  {
    out.resize(shape.n());
    for (unsigned int q = 0; q < shape.n(); ++q)
    {
      double v = 0;
      for (unsigned int a = 0; a < shape.m(); ++a)
        v += shape(a, q) * local[a];
      out[q] = v;
    }
  }

  template <int dim>
  class LevelSetSpace : public FieldPhysics<dim>, public AdaptationInterface<dim>
  {
  public:
    LevelSetSpace(dealii::parallel::distributed::Triangulation<dim> &tria, const LevelSetParameters &parameters,
                  std::shared_ptr<const dealii::Function<dim>> initial_distance);

    std::string name() const override { return "level-set space"; }
    void        setup_dofs() override;
    dealii::types::global_dof_index n_dofs() const override { return dofs.n_dofs(); }

    void set_periodic(dealii::types::boundary_id b1, dealii::types::boundary_id b2, unsigned int direction);
    /// The fields that decide the distance (once they exist).
    void attach(const NclsTransport<dim> &ncls) { level_set = &ncls; }

    // AdaptationInterface: the free surface φ = 0.
    double distance(const dealii::Point<dim> &x) const override;
    double cell_distance(const typename dealii::Triangulation<dim>::active_cell_iterator &cell) const override;
    double displacement_since_adaptation() const override { return travelled; }
    void   mark_adapted() override { travelled = 0; }
    /// The interface moved at most @p distance this step (max|u| dt).
    void   add_travel(double distance) { travelled += distance; }

    /// ε of H_ε on a cell.
    double epsilon(const typename dealii::Triangulation<dim>::cell_iterator &cell) const;
    /// diameter/√dim of a cell: an active cell's from a table filled per mesh (the cell loops
    /// of every level-set sub-solver ask for it, and diameter() reads the vertices each time).
    double cell_size(const typename dealii::Triangulation<dim>::cell_iterator &cell) const
    {
      if (cell->is_active() && cell->active_cell_index() < sizes.size())
        return sizes[cell->active_cell_index()];
      return cell->diameter() / std::sqrt(double(dim));
    }

    const LevelSetParameters                  &parameters() const { return prm; }
    const dealii::DoFHandler<dim>             &dof_handler() const { return dofs; }
    const dealii::FE_Q<dim>                   &fe() const { return finite_element; }
    const dealii::MappingQ<dim>               &mapping() const { return map; }
    const dealii::AffineConstraints<double>   &constraints() const { return mesh_constraints; }
    const dealii::DynamicSparsityPattern      &sparsity() const { return dsp; }
    const dealii::IndexSet                    &owned() const { return owned_dofs; }
    const dealii::IndexSet                    &relevant() const { return relevant_dofs; }
    /// Cell reads of ghosted fields of the space (no look-up, no allocation per cell).
    const CellDofReader<dim>                  &reader() const { return cells; }
    /// ∫ψ_i of the constrained basis (owned entries).
    const dealii::TrilinosWrappers::MPI::Vector &lumped_mass() const { return lumped; }
    /// Support points of the locally owned DoFs.
    const std::map<dealii::types::global_dof_index, dealii::Point<dim>> &support_points() const { return points; }
    MPI_Comm communicator() const { return comm; }
    /// A ghosted vector of the space / an owned one.
    void reinit_ghosted(dealii::TrilinosWrappers::MPI::Vector &v) const { v.reinit(owned_dofs, relevant_dofs, comm); }
    void reinit_owned(dealii::TrilinosWrappers::MPI::Vector &v) const { v.reinit(owned_dofs, comm); }
    /// The level-set cell of a triangulation cell.
    typename dealii::DoFHandler<dim>::active_cell_iterator
    cell_of(const typename dealii::Triangulation<dim>::active_cell_iterator &cell) const
    {
      return typename dealii::DoFHandler<dim>::active_cell_iterator(&tria, cell->level(), cell->index(), &dofs);
    }

    /// L² projection of H_ε(φ) into @p theta: ∫(θ − H_ε(φ)) v = 0 for every v of the space, so
    /// ∫θ = ∫H_ε(φ) and, at rest, the mass correction's residual vanishes (a lumped projection
    /// would smooth θ and the correction would erode the shape step after step).
    void project_heaviside(const dealii::TrilinosWrappers::MPI::Vector &phi,
                           dealii::TrilinosWrappers::MPI::Vector       &theta) const;
    /// The L² projection of a fraction f ∈ [0, 1] given by its moments b_i = ∫f ψ_i (an owned,
    /// compressed vector with the mesh constraints applied by distribute_local_to_global) into
    /// @p theta (ghosted), with ∫θ = Σ_i b_i made exact (project_heaviside's second half).
    void project_moments(const dealii::TrilinosWrappers::MPI::Vector &moments,
                         dealii::TrilinosWrappers::MPI::Vector       &theta) const;
    /// ∫(1 − H_ε(φ)): the water volume (the quadrature the mass correction uses).
    double water_volume(const dealii::TrilinosWrappers::MPI::Vector &phi) const;
    /// ∫(1 − H_ε(φ)) over the points where @p inside is true (e.g. the water held inside an
    /// immersed solid's ghost region).
    double water_volume(const dealii::TrilinosWrappers::MPI::Vector            &phi,
                        const std::function<bool(const dealii::Point<dim> &)> &inside) const;
    /// ∫v of a field of the space (Σ_i ∫ψ_i v_i over the constrained basis; owned or ghosted v).
    double integral(const dealii::TrilinosWrappers::MPI::Vector &v) const;
    /// Make ∫v = @p target for a fraction v ∈ [0, 1] (owned vector, constraints applied here) by
    /// adding c v(1 − v): the difference goes where the field is partial, i.e. to the interface,
    /// and a field that is 0 or 1 everywhere is left alone.
    void restore_integral(dealii::TrilinosWrappers::MPI::Vector &v, double target) const;
    /// Quadrature of every nonlinear level-set integral (H_ε, the mass correction, volumes).
    dealii::QGauss<dim> nonlinear_quadrature() const { return dealii::QGauss<dim>(prm.degree + 2); }

    dealii::TimerOutput &timer() const { return timer_output; }

    /// The Crank–Nicolson midpoint velocity (uⁿ + uⁿ⁺¹)/2 and its divergence at the points of a
    /// Gauss rule on every owned cell (index active_cell_index × n_points + q), for one state of
    /// the flow (NavierStokes::state_id): the NCLS and the VOF transport of a step share it.
    struct MidpointTable
    {
      std::uint64_t                       flow_state = std::numeric_limits<std::uint64_t>::max();
      unsigned int                        n_points   = 0;
      std::vector<dealii::Tensor<1, dim>> u;
      std::vector<double>                 div;
    };
    MidpointTable &midpoint_table() const { return midpoint; }

    /// What the free-surface monitors (measure_free_surface) read of the mesh on every owned
    /// cell, per mesh: the points' JxW (flow's and own mapping) and −g·x, the cells' vertex x
    /// and floor edges, and the shape values (the same on every cell). They are measured every
    /// step, and two FEValues per cell were 3.4 % of a dam-break step.
    struct MeasureTable
    {
      bool                                                            valid = false;
      dealii::Tensor<1, dim>                                          gravity;
      std::vector<typename dealii::DoFHandler<dim>::active_cell_iterator> cells, velocity_cells;
      std::vector<double>        JxW, JxW_volume, height, vertex_x;
      std::vector<unsigned int>  floor_lines; ///< bit l: line l of the cell lies on the floor
      dealii::FullMatrix<double> shape_u, shape_phi; ///< scalar velocity / level-set ψ_a(x_q)
    };
    MeasureTable &measure_table() const { return measures; }

  private:
    mutable MidpointTable midpoint;
    mutable MeasureTable  measures;
    MPI_Comm                                           comm;
    dealii::parallel::distributed::Triangulation<dim> &tria;
    LevelSetParameters                                 prm;
    std::shared_ptr<const dealii::Function<dim>>       initial;
    dealii::FE_Q<dim>                                  finite_element;
    dealii::MappingQ<dim>                              map;
    dealii::DoFHandler<dim>                            dofs;
    dealii::IndexSet                                   owned_dofs, relevant_dofs;
    CellDofReader<dim>                                 cells;
    std::vector<double>                                sizes; ///< cell_size() by active_cell_index
    dealii::AffineConstraints<double>                  mesh_constraints;
    dealii::DynamicSparsityPattern                     dsp;
    dealii::TrilinosWrappers::MPI::Vector              lumped;
    dealii::TrilinosWrappers::SparseMatrix             mass;
    dealii::TrilinosWrappers::PreconditionJacobi       mass_preconditioner;
    std::map<dealii::types::global_dof_index, dealii::Point<dim>> points;
    struct Periodic { dealii::types::boundary_id b1, b2; unsigned int direction; };
    std::vector<Periodic>     periodic;
    const NclsTransport<dim> *level_set = nullptr;
    double                    travelled = 0;
    dealii::ConditionalOStream  silent{std::cout, false};
    mutable dealii::TimerOutput timer_output;
  };

  /// Shared machinery of the two transports: ghosted history, its transfer and output.
  template <int dim>
  class LevelSetField : public FieldPhysics<dim>
  {
  public:
    LevelSetField(LevelSetSpace<dim> &space, const NavierStokes<dim> &flow, std::string field_name);

    void setup_dofs() override;
    void prepare_transfer(bool serialization) override;
    void finish_transfer(bool serialization) override;
    void add_to_output(dealii::DataOut<dim> &data_out) const override;
    void save_state(std::ostream &out) const override;
    void load_state(std::istream &in) override;

    /// Current value (ghosted), the value before the last advance and the one before that.
    const dealii::TrilinosWrappers::MPI::Vector &value() const { return current; }
    const dealii::TrilinosWrappers::MPI::Vector &previous() const { return before; }
    const dealii::TrilinosWrappers::MPI::Vector &older() const { return before_previous; }
    /// Overwrite the current value (owned or ghosted vector; constraints applied here).
    void set(const dealii::TrilinosWrappers::MPI::Vector &v);
    /// Interpolate @p f as the initial value (previous = current).
    void initialize(const dealii::Function<dim> &f);
    double last_step() const { return dt_last; }
    /// The flow that carries the field.
    const NavierStokes<dim> &carrier() const { return flow; }
    unsigned int last_iterations() const { return iterations; }

  protected:
    /// One implicit Crank–Nicolson step with SUPG at the midpoint velocity (u^n + u^{n+1})/2:
    /// conservative (∇·(uθ), weak, with open-boundary fluxes) or advective (u·∇φ); @p nu
    /// per cell adds shock-capturing diffusion. Returns the solution; Krylov iterations counted.
    void solve_transport(double dt, bool conservative, const std::vector<double> *nu,
                         dealii::TrilinosWrappers::MPI::Vector &result);
    /// Residual-based shock-capturing viscosity per active cell (index: active_cell_index):
    /// ν_K = c h_K max_q |R| / |∇θ|, capped at h_K |u| / 2, R of (@p provisional − current)/dt.
    std::vector<double> shock_capturing(double dt, const dealii::TrilinosWrappers::MPI::Vector &provisional) const;

    LevelSetSpace<dim>      &space;
    const NavierStokes<dim> &flow;
    std::string              field_name;
    dealii::TrilinosWrappers::MPI::Vector current, before, before_previous;
    /// Shift the history (older ← previous ← current) and store @p next as the current value.
    void push(const dealii::TrilinosWrappers::MPI::Vector &next, double dt);
    double                   dt_last    = 0;
    unsigned int             iterations = 0;
    /// A volume fraction (θ): a mesh adaptation keeps its integral (the interpolation onto
    /// coarsened cells does not, and each adaptation would add or remove water).
    bool                     conserved_by_transfer = false;
    std::set<dealii::types::boundary_id> open_boundaries;
    double                   inflow_value = 0;

  private:
    using Transfer = dealii::parallel::distributed::SolutionTransfer<dim, dealii::TrilinosWrappers::MPI::Vector>;
    std::unique_ptr<Transfer>             transfer;
    std::array<double, 3>                 integral_before_transfer{};
    dealii::TrilinosWrappers::SparseMatrix matrix;
    CellScatter<dim>                       scatter; ///< fast insertion into matrix (set up after its first assembly)
    ReusableIlu                            ilu;     ///< of matrix, its fill graph kept per mesh
  };

  /// Eq. 7: the non-conservative level set φ carried by the flow (SUPG, Crank–Nicolson).
  template <int dim>
  class NclsTransport : public LevelSetField<dim>
  {
  public:
    NclsTransport(LevelSetSpace<dim> &space, const NavierStokes<dim> &flow)
      : LevelSetField<dim>(space, flow, "phi")
    {}
    std::string name() const override { return "NCLS"; }
    void        advance(double dt) override;
  };

  /// Eq. 8: the air volume fraction θ, transported conservatively (SUPG + shock capturing);
  /// on open boundaries the outflow carries θ away and the inflow brings air (θ = 1, i.e.
  /// the water fraction 1 − θ has the paper's zero Dirichlet value).
  template <int dim>
  class VofTransport : public LevelSetField<dim>
  {
  public:
    VofTransport(LevelSetSpace<dim> &space, const NavierStokes<dim> &flow,
                 const std::set<dealii::types::boundary_id> &open);
    std::string name() const override { return "VOF"; }
    void        advance(double dt) override;
  };

  /**
   * Eq. 14 solved for its steady state directly, with the zero level held: the DoFs of cut
   * cells are divided by the mean |∇φ| of their cut cells (one factor per cell keeps that
   * cell's zero level; a node shared by cut cells of different slopes moves it by their
   * difference only); every other DoF gets sign(φ) dist(x, Γ), Γ the zero level of the current
   * Q_k field sampled in every cut cell (points projected onto φ = 0 by Newton in reference
   * coordinates, with their normals) and gathered on all ranks; the distance is to the tangent
   * plane of the nearest samples (to the sample itself beyond the sample's patch).
   *
   * Far-field mode (LevelSetParameters::far_field_only): only DoFs with |φ| ≥ band (a multiple
   * of ε on the finest cell) get the distance; the band around Γ, cut cells included, keeps
   * the transported φ bit for bit, so Γ, H_ε(φ) and the water volume do not change, while
   * the far field, which the transport alone erodes, gets its distance back; without the
   * cut-cell rescaling that breaks the surface up next to a moving body.
   *
   * The distance of a node costs a nearest-samples query; only the near field needs it every
   * step. Nodes with |φ| ≥ B = near_field_band × (largest ε of a cut cell) keep their transported
   * φ until the surface has travelled B/4 (Σ max|u| dt over the steps advance() was called for,
   * this step's included) since the last pass over every node: such a node was at least B from Γ
   * then, so it is still ≥ 3B/4 = 3ε away, outside the band where H_ε(φ) and δ_ε(φ) vary, and a
   * node whose transported |φ| drops below B is redistanced at once. At the CFL 0.25 step of the
   * dam break that is one full pass in six steps. redistance() called alone counts no travel.
   */
  template <int dim>
  class Redistancing : public FieldPhysics<dim>
  {
  public:
    Redistancing(LevelSetSpace<dim> &space, NclsTransport<dim> &ncls) : space(space), ncls(ncls) {}
    std::string name() const override { return "redistancing"; }
    void        setup_dofs() override { have_full = false; } // a new mesh: every node next time
    /// The step count and the travel since the last full pass (a restart redistances as the
    /// uninterrupted run would).
    void        save_state(std::ostream &out) const override;
    void        load_state(std::istream &in) override;
    static constexpr double near_field_band = 4.0; ///< B / ε of the nodes redistanced every step
    void        advance(double dt) override;
    /// Redistance the current φ of the NCLS.
    void        redistance();
    /// Interface samples of the last call (all ranks).
    std::size_t n_samples() const { return samples; }

  private:
    LevelSetSpace<dim> &space;
    NclsTransport<dim> &ncls;
    std::size_t         samples = 0;
    unsigned int        steps   = 0; ///< steps since the start (or restart)
    bool                have_full      = false; ///< a pass over every node was made on this mesh
    double              travel         = 0;     ///< Σ max|u| dt of the steps advanced
    double              travel_at_full = 0;     ///< travel at that pass
  };

  /// A moving solid's interior holds no water: after the transports, φ ← max(φ, −φ_s) at the
  /// DoFs inside a moving solid (φ_s < 0), the signed distance of air ∪ solid (φ > 0 in air).
  /// The body's interior is carried as an air region by the IBM's rigid velocity, but the
  /// smeared interface along its submerged surface lets water diffuse in step after step
  /// (16 % of a floating disk's submerged volume in 4 s), which lowers the waterline around it.
  /// The VOF's θ still holds that water, so the mass correction that follows puts it back at
  /// the interfaces outside: water is conserved, only where it sits changes. A DoF whose φ
  /// already lies above −φ_s (the smeared inner half of the body's own interface, air) is left
  /// alone, so φ stays continuous at φ_s = 0.
  template <int dim>
  class SolidInteriorDrying : public FieldPhysics<dim>
  {
  public:
    SolidInteriorDrying(LevelSetSpace<dim> &space, NclsTransport<dim> &ncls,
                        std::function<double(const dealii::Point<dim> &)> solid_distance)
      : space(space), ncls(ncls), solid_distance(std::move(solid_distance))
    {}
    std::string name() const override { return "solid interior drying"; }
    void        setup_dofs() override {}
    void        advance(double dt) override;

  private:
    LevelSetSpace<dim>                               &space;
    NclsTransport<dim>                               &ncls;
    std::function<double(const dealii::Point<dim> &)> solid_distance;
  };

  /// Eq. 12 by Newton: ∫(H_ε(φ+u) − θ) v + κ ∇u·∇v = 0 for all v (∂_n u = 0), κ = c h_K; then
  /// φ ← φ + u and θ ← the lumped projection of H_ε(φ). With v = 1: ∫H_ε(φ) = ∫θ exactly.
  template <int dim>
  class MassCorrection : public FieldPhysics<dim>
  {
  public:
    MassCorrection(LevelSetSpace<dim> &space, NclsTransport<dim> &ncls, VofTransport<dim> &vof)
      : space(space), ncls(ncls), vof(vof)
    {}
    std::string name() const override { return "mass correction"; }
    void        setup_dofs() override;
    void        advance(double dt) override;
    void        correct();
    void        add_to_output(dealii::DataOut<dim> &data_out) const override;
    unsigned int last_newton_iterations() const { return newton; }
    double       last_correction() const { return max_correction; } ///< max |u| of the last call

  private:
    LevelSetSpace<dim>                    &space;
    NclsTransport<dim>                    &ncls;
    VofTransport<dim>                     &vof;
    dealii::TrilinosWrappers::SparseMatrix jacobian;
    CellScatter<dim>                       jacobian_scatter; ///< fast insertion into the Jacobian
    /// AMG of the Jacobian, kept for amg_lifetime steps on one mesh: the Jacobian κK + δ_ε M is
    /// the mesh's stiffness plus a mass in the band around Γ, which moves by ≤ a cell per step.
    /// Dam break: 7.0 CG iterations per Newton solve with a set-up every 10 or every 25 steps
    /// (one set-up costs ~6 ms on 2 ranks, 10 CG iterations).
    dealii::TrilinosWrappers::PreconditionAMG amg;
    static constexpr unsigned int             amg_lifetime = 25;
    unsigned int                              amg_age      = amg_lifetime; ///< steps since its set-up
    double                                    domain       = 0;            ///< ∫1 of the mesh (0: to compute)
    dealii::TrilinosWrappers::MPI::Vector  correction;
    unsigned int                           newton = 0;
    double                                 max_correction = 0;
    /// φ + u, ε and JxW at the quadrature points with |φ + u| < 2ε (the uniform shift's band)
    struct BandPoint { double s, eps, JxW; };
    std::vector<BandPoint>                 band;
    /// The owned cells with ε and JxW at their quadrature points and the shape values (FE_Q
    /// has them the same on every cell), per mesh; φ and θ at the points, per correction (both
    /// stay fixed through it). The Newton residual, the uniform shift and the moments of
    /// H_ε(φ + u) for θ then read only u per cell, without FEValues: the three cell loops
    /// with FEValues were ~60 % of a correction.
    struct PointCache
    {
      std::vector<typename dealii::DoFHandler<dim>::active_cell_iterator> cells;
      std::vector<double>        eps, phi, theta, JxW;
      dealii::FullMatrix<double> shape; ///< ψ_i(x_q)
      /// a field of the space at the points of cached cell @p k (@p local: its nodal values)
      void evaluate(const CellDofReader<dim> &reader, std::size_t k, const dealii::TrilinosWrappers::MPI::Vector &u,
                    std::vector<double> &local, std::vector<double> &u_q) const
      {
        reader.gather(cells[k], u, local);
        values_at_points(shape, local, u_q);
      }
    };
    /// The point cache, the diffusion matrix κK (κ = correction diffusion × cell size, the
    /// Jacobian off the band) and the scatter, once per mesh.
    void setup_points();
    PointCache                             points;
    bool                                   points_ready = false;
    dealii::TrilinosWrappers::SparseMatrix diffusion;
  };

  /// ρ, μ of Eq. 9–10 from the current φ (t^n: Algorithm 1 runs Navier–Stokes first);
  /// ∂ρ/∂t from the last two level sets, ∇ρ = (ρ_a − ρ_w) δ_ε(φ) ∇φ.
  template <int dim>
  class TwoPhaseMaterial : public MaterialModel<dim>
  {
  public:
    TwoPhaseMaterial(const LevelSetSpace<dim> &space, const TwoFluids &fluids);
    /// The level set the material reads (constructed after Navier–Stokes, which needs the material).
    void attach(const NclsTransport<dim> &level_set) { ncls = &level_set; }
    void evaluate(const typename dealii::Triangulation<dim>::active_cell_iterator &cell,
                  const std::vector<dealii::Point<dim>> &points, double time,
                  MaterialValues<dim> &values) const override;
    double minimum_density() const override { return std::min(fluids.rho_water, fluids.rho_air); }
    const TwoFluids &properties() const { return fluids; }

  private:
    const LevelSetSpace<dim>             &space;
    const NclsTransport<dim>             *ncls = nullptr;
    TwoFluids                             fluids;
    /// FEValues of the level-set space per Gauss quadrature size asked for (QGauss(n), n^dim points).
    mutable std::map<unsigned int, std::unique_ptr<dealii::FEValues<dim>>> fe_values;
    mutable std::vector<double>           phi, phi_old, phi_older;
    mutable std::array<std::vector<double>, 3> cell_values; ///< nodal φ, φ_old, φ_older of a cell
  };

  /// What the free-surface monitors measure (collective).
  struct FreeSurfaceMeasures
  {
    double water_volume = 0;
    double x_front      = 0;  ///< furthest wetted point on the floor along x
    double x_foremost   = 0;  ///< furthest point with φ < 0 anywhere along x
    double kinetic_water = 0, potential_water = 0; ///< ½∫ρ_w(1−H)|u|², −∫ρ_w(1−H) g·x
    double kinetic_all = 0, potential_all = 0;     ///< the same over both phases
    /// largest |u| at the velocity quadrature points in the water (φ < 0): what SPH's
    /// "max speed" measures (it has no air); the CFL step uses the largest over both phases
    double max_water_speed = 0;
    /// range of the nodal φ: a (transported, redistanced) distance stays within the domain's
    /// diameter; beyond it the level set in the air has run away (doc/benchmarks.md, 3D falling
    /// cylinder without redistancing: −6.7 in a 1.4 m box)
    double phi_min = 0, phi_max = 0;
  };

  template <int dim>
  FreeSurfaceMeasures measure_free_surface(const LevelSetSpace<dim> &space, const NclsTransport<dim> &ncls,
                                           const NavierStokes<dim> &flow, const TwoFluids &fluids,
                                           const dealii::Tensor<1, dim> &gravity, double floor_height);
} // namespace twinflow::fem
