#pragma once
/**
 * @file rigid_body.h
 * A rigid body in 6 degrees of freedom (Section 3.3.3: the solids of the co-simulation). It
 * knows no fluid: the fluid's force and torque arrive as an external load held over a step.
 *
 * State: centre of mass x, orientation q (unit quaternion, body → world), velocity v and the
 * angular momentum about the centre in world axes L. Equations
 *
 *   m dv/dt = F + m g,   dx/dt = v,   dL/dt = τ,   dq/dt = ½ (0, ω) ⊗ q,   ω = I_w⁻¹ L,
 *
 * with I_w = R I_b Rᵀ. Locked degrees of freedom (world translations x, y, z and rotations
 * about the world axes x, y, z) are removed by a projector P onto the free ones: dv/dt keeps
 * only free components, dL/dt = P Pᵀ τ and ω = P (Pᵀ I_w P)⁻¹ Pᵀ L (a planar body: ω along z).
 *
 * Time integration: classical Runge–Kutta of order 4 on (x, v, q, L) with the load constant
 * over the step (co-simulation holds the fluid's load over a fluid step), q renormalised after
 * each step; `advance` takes sub-steps inside a fluid step. Torque-free rotation keeps L exactly
 * (dL/dt = 0 is integrated exactly) and the energy to O(Δt⁴) (tests/solids).
 *
 * Added-mass stabilisation (Söding's correction, optional): a light body in a heavy fluid under
 * explicit (force-from-the-last-step) coupling is unstable when the fluid's added mass exceeds
 * the body's. With an estimate m_a of the added mass, the translational equation becomes
 * (m + m_a) a = F + m g + m_a a_prev, a_prev the acceleration at the end of the last step: the
 * same equation whenever a = a_prev (steady state, free fall), and stable for m_a ≳ the true
 * added mass. Likewise with J_a for rotation.
 */
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <functional>
#include <string>

namespace twinflow::solids
{
  using Vector3    = Eigen::Vector3d;
  using Matrix3    = Eigen::Matrix3d;
  using Quaternion = Eigen::Quaterniond;

  /// Free degrees of freedom: translations along world x, y, z, then rotations about them.
  struct DofMask
  {
    std::array<bool, 6> free{{true, true, true, true, true, true}};

    /// All six free.
    static DofMask all() { return DofMask(); }
    /// 2D scenes: x, y and the rotation about z.
    static DofMask planar();
    /// Parses a comma-separated list of locked DoFs out of "x, y, z, rx, ry, rz" (empty: none)
    /// and adds the ones a 2D scene never moves (z, rx, ry). Throws std::invalid_argument naming
    /// the offending word and what is allowed (a 2D scene refuses z, rx, ry in the list).
    static DofMask parse_locked(const std::string &list, int dim);
    /// Number of free translations / rotations.
    int n_translations() const { return free[0] + free[1] + free[2]; }
    int n_rotations() const { return free[3] + free[4] + free[5]; }
  };

  /// Mass and inertia about the centre of mass, in body axes.
  struct MassProperties
  {
    double  mass = 1;
    Matrix3 inertia = Matrix3::Identity();

    /// Solid circular cylinder, axis along body z (a 2D disk: @p length = the unit depth 1).
    static MassProperties cylinder(double density, double radius, double length);
    /// Solid box with edge lengths a, b, c along body x, y, z.
    static MassProperties box(double density, double a, double b, double c);
    /// Solid ball.
    static MassProperties ball(double density, double radius);
  };

  struct RigidBodyState
  {
    Vector3    position         = Vector3::Zero(); ///< centre of mass
    Quaternion orientation      = Quaternion::Identity();
    Vector3    velocity         = Vector3::Zero();
    Vector3    angular_momentum = Vector3::Zero(); ///< about the centre of mass, world axes
  };

  class RigidBody
  {
  public:
    RigidBody(const MassProperties &mass, const RigidBodyState &initial, const DofMask &dofs, const Vector3 &gravity);

    /// Söding's added-mass stabilisation (see the file comment); 0, 0: off.
    void set_added_mass(double translational, double rotational);

    /// Sets the initial angular velocity (world axes; locked components dropped).
    void set_angular_velocity(const Vector3 &omega);

    /// External load (the fluid's force, and torque about the centre of mass), held constant by advance().
    void set_load(const Vector3 &force, const Vector3 &torque);

    /// Advances by @p dt in @p substeps equal RK4 steps with the current load. @p after_substep,
    /// if given, runs after each sub-step (the wall contacts of coupling.h apply their impulses
    /// there); the velocity those impulses change is counted into the step's accelerations.
    void advance(double dt, int substeps = 1, const std::function<void(RigidBody &)> &after_substep = {});

    /// An impulse @p J [N s] at the world point @p p: v += J / m, L += (p − c) × J, locked degrees
    /// of freedom dropped (the body's own mass and inertia: the fluid answers in its next step).
    void apply_impulse(const Vector3 &J, const Vector3 &p);
    /// Velocity change of the material point @p p that apply_impulse(J, p) would give (linear in J).
    Vector3 impulse_response(const Vector3 &J, const Vector3 &p) const;
    /// Moves the centre by @p d along the free translations (a contact's position projection).
    void translate(const Vector3 &d);

    const RigidBodyState &state() const { return x; }
    /// Puts the body back into a saved state (a restart): the state and the last step's
    /// accelerations (Söding's added-mass term uses them).
    void restore(const RigidBodyState &s, const Vector3 &acceleration, const Vector3 &angular_acceleration)
    {
      x                         = s;
      last_acceleration         = acceleration;
      last_angular_acceleration = angular_acceleration;
    }
    /// The angular acceleration at the end of the last step (Söding's term; acceleration() is the linear one).
    Vector3 previous_angular_acceleration() const { return last_angular_acceleration; }
    double                time() const { return t; }
    const MassProperties &mass_properties() const { return props; }
    const DofMask        &dofs() const { return mask; }

    Matrix3 rotation() const { return x.orientation.toRotationMatrix(); }
    Vector3 angular_velocity() const { return omega(x); }
    /// Translational and angular acceleration at the current state and load (the boundary
    /// acceleration the fluid sees, Eq. 61).
    Vector3 acceleration() const { return last_acceleration; }
    Vector3 angular_acceleration() const;
    /// Velocity and acceleration of the material point at world position @p p.
    Vector3 point_velocity(const Vector3 &p) const;
    Vector3 point_acceleration(const Vector3 &p) const;

    double  kinetic_energy() const;
    /// −m g·x (zero at the origin).
    double  potential_energy() const;
    Vector3 linear_momentum() const { return props.mass * x.velocity; }

  private:
    struct Rate
    {
      Vector3    dx, dv, dL;
      Eigen::Vector4d dq; ///< (w, x, y, z)
    };
    Vector3 omega(const RigidBodyState &s) const;
    Vector3 linear_acceleration() const;
    Rate    rate(const RigidBodyState &s) const;
    static RigidBodyState add(const RigidBodyState &s, const Rate &k, double h);

    MassProperties props;
    DofMask        mask;
    Vector3        gravity;
    Matrix3        translation_projector, rotation_projector; ///< diag(free)
    RigidBodyState x;
    double         t = 0;
    Vector3        force = Vector3::Zero(), torque = Vector3::Zero();
    double         added_mass = 0, added_inertia = 0;
    Vector3        last_acceleration = Vector3::Zero(), last_angular_acceleration = Vector3::Zero();
    Vector3        impulse_dv = Vector3::Zero(), impulse_dw = Vector3::Zero(); ///< within one advance()
  };
} // namespace twinflow::solids
