#pragma once
/**
 * @file immersed_boundary.h
 * Immersed solids in the FEM (Section 3.3.1, Eq. 15–16): the solid is the zero level of
 * the signed distance φ_s of a shared `geometry/` shape (φ_s < 0 inside); the no-slip
 * condition u = u_s on Γ_s enters the velocity step as
 *
 *   ∫ [−σ(u)n·v − σ(v)n·(u − u_s) + C_α v·(u − u_s)] δ_ε(φ_s)      (Nitsche, symmetric)
 * + ∫ C_β (u − u_s)·v H_s,  H_s = H_ε(−φ_s)                        (penalty inside the solid)
 *
 * with n = −∇φ_s the fluid's outward normal, σ(u) = μ∇u or 2με(u) as the flow solver's
 * viscous form, H_ε and δ_ε = H_ε' of Eq. 13 (φ_ls = π) and ε = (interface width) · h_K.
 * Inertia, convection, viscosity and body force are switched off inside by the fluid
 * fraction 1 − H_s: there only ∇p and the penalty remain (a porous ghost flow). Penalties:
 * C_α = γ_α μ / h_K, C_β = γ_β (ρ/τ + μ/h_K²).
 *
 * Accuracy: the smoothed interface makes the body act slightly larger than it is (the
 * penalty already stops the fluid where H_s ~ 1e-2, a fraction of ε outside Γ_s): forces
 * converge at first order in ε ∝ h, which is what the band refinement pays for
 * (doc/benchmarks.md: measured effect of ε, γ_α, γ_β).
 *
 * The force of the fluid on a solid is the reaction of these terms, tested with v = e_d
 * (σ(e_d) = 0): F = ∫ [−σ(u)n + C_α(u − u_s)] δ_ε + ∫ C_β (u − u_s) H_s. Inside
 * the solid ∇p = −C_β(u − u_s), so the penalty part is −∮ p n_s; the Nitsche part is the
 * viscous traction.
 */
#include <twinflow/core/scene.h>
#include <twinflow/fem/mesh_adaptation.h>
#include <twinflow/fem/momentum_term.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace twinflow::fem
{
  template <int dim>
  class NavierStokes;

  /// Parameters of subsection "FEM/Immersed boundary".
  struct ImmersedBoundaryParameters
  {
    double interface_width = 1;    ///< ε / h_K
    double nitsche_penalty = 10;   ///< γ_α of C_α = γ_α μ / h_K
    double volume_penalty  = 100;  ///< γ_β of C_β = γ_β (ρ/τ + μ/h_K²)

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// Regularised Heaviside of Eq. 13 (φ_ls = π) and its derivative δ_ε.
  double smoothed_heaviside(double x, double epsilon);
  double smoothed_delta(double x, double epsilon);

  /// One solid of the scene as the FEM sees it: φ_s, its normal and the rigid velocity u_s.
  template <int dim>
  class ImmersedSolid : public AdaptationInterface<dim>
  {
  public:
    /// Shapes: disk (2D), cylinder (3D, axis z, 'Length' along z; infinite if it spans a
    /// periodic z, @p periodic_span), box and plate (Length × Thickness, rotated by Angle about
    /// z; in 3D spanning @p span along z).
    ImmersedSolid(const Solid &solid, double span, bool periodic_span = false);

    std::string name() const override { return label; }
    double      distance(const dealii::Point<dim> &x) const override;
    /// ∇φ_s: the outward normal of the solid.
    dealii::Tensor<1, dim> normal(const dealii::Point<dim> &x) const;
    /// u_s(x) = v + ω × (x − c): zero for a fixed solid.
    dealii::Tensor<1, dim> velocity(const dealii::Point<dim> &x) const;
    const dealii::Point<dim> &center() const { return centre; }

    /// Rigid motion (co-simulation, solids/coupling.h): the body's centre, its rotation from
    /// the initial pose (body → world) and its velocity field v + ω × (x − c). φ_s follows:
    /// φ_s(x) = φ_s,0(c_0 + Rᵀ(x − c)).
    void set_motion(const dealii::Point<dim> &centre, const dealii::Tensor<2, dim> &rotation,
                    const dealii::Tensor<1, dim> &velocity, const dealii::Tensor<1, 3> &angular_velocity);
    /// Distance the surface moved since the last mark_adapted(): |Δc| + extent · |ΔR|.
    double displacement_since_adaptation() const override;
    void   mark_adapted() override;

  private:
    dealii::Point<dim> to_initial_frame(const dealii::Point<dim> &x) const;

    dealii::Point<dim>     initial_centre, adapted_centre;
    dealii::Tensor<2, dim> rotation, adapted_rotation; ///< identity until set_motion
    double                 extent = 0;                ///< largest distance of the surface from the centre
    bool                   moved  = false;
    std::string                                            label;
    dealii::Point<dim>                                     centre;
    std::function<double(const dealii::Point<dim> &)>      phi;
    std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &)> grad_phi;
    dealii::Tensor<1, dim>                                 translational_velocity;
    dealii::Tensor<1, 3>                                   angular_velocity;
  };

  /// Fluid load on one solid.
  template <int dim>
  struct SolidLoad
  {
    dealii::Tensor<1, dim> force;
    dealii::Tensor<1, 3>   torque; ///< about the solid's centre (2D: z component only)
  };

  template <int dim>
  class ImmersedBoundary : public MomentumTerm<dim>
  {
  public:
    ImmersedBoundary(const Scene &scene, const ImmersedBoundaryParameters &parameters);

    std::string name() const override { return "immersed boundary (Nitsche + penalty)"; }
    bool acts_on(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell) const override;
    void scale_fluid_fraction(const MomentumCell<dim> &cell, std::vector<double> &fraction) const override;
    void assemble(const MomentumCell<dim> &cell, dealii::FullMatrix<double> &matrix,
                  dealii::Vector<double> &rhs) const override;

    /// Fluid force and torque on each solid from the current velocity of @p flow.
    std::vector<SolidLoad<dim>> loads(const NavierStokes<dim> &flow) const;

    /// L2 norm of u − u_s over the solid (φ_s < 0) and over Γ_s approximated by the band
    /// (∫ δ_ε |u − u_s|²)^{1/2}: the no-slip errors.
    std::pair<double, double> slip_errors(const NavierStokes<dim> &flow) const;

    std::vector<std::unique_ptr<ImmersedSolid<dim>>>       &solids() { return bodies; }
    const std::vector<std::unique_ptr<ImmersedSolid<dim>>> &solids() const { return bodies; }
    const ImmersedBoundaryParameters                 &parameters() const { return prm; }

  private:
    /// φ_s = min over the solids, the index of the nearest one.
    double distance(const dealii::Point<dim> &x, unsigned int &nearest) const;
    /// H_s = H_ε(−φ_s): the penalty's weight (1 inside the solid) at signed distance @p phi.
    static double solid_fraction(double phi, double epsilon) { return smoothed_heaviside(-phi, epsilon); }
    /// Cell size h_K (edge length of a square/cubic cell).
    static double cell_size(const typename dealii::DoFHandler<dim>::active_cell_iterator &cell);

    ImmersedBoundaryParameters                      prm;
    std::vector<std::unique_ptr<ImmersedSolid<dim>>> bodies;
    mutable double                                  last_time_step = 0;
  };
} // namespace twinflow::fem
