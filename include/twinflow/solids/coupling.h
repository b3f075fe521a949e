#pragma once
/**
 * @file coupling.h
 * Force–displacement co-simulation of the moving solids with a fluid solver (Section 3.3.3,
 * Fig. 1), one interface for both the FEM and the SPH:
 *
 *   loop: (1) the fluid's force and torque on each body, from the last fluid step, are applied
 *         (2) the bodies advance over Δt (RK4 sub-steps, rigid_body.h)
 *         (3) their position, velocity and acceleration go back to the fluid as boundary data
 *         (4) the fluid advances over the same Δt, giving the next loads.
 *
 * Light bodies in a heavy fluid (ρ_s ≲ ρ_w) are where this explicit scheme meets the
 * added-mass instability; the bodies carry Söding's added-mass correction with
 * m_a = C_a ρ_fluid V_body (Solids/Solid N/Added mass coefficient), stable for any C_a above
 * half the body's true added-mass coefficient minus its mass ratio, at no extra fluid solve.
 *
 * Wall contact (Solids/Wall contact, default on): after each RK4 sub-step every point of a
 * body's cross-section that lies beyond a non-periodic wall in x or y (a disk's or cylinder's
 * point nearest the wall, a box's or plate's corners) is a contact. Sequential impulses
 * (accumulated and clamped, 20 passes over the contacts) make each contact's normal velocity
 * −e times its approach speed (e = 0 below the speed of two sub-steps of free fall, so a resting
 * body does not chatter) and never pull; Coulomb friction (μ) clamps the tangential impulse to μ
 * times the normal one. The body is then translated back onto each wall it crossed. Impulses
 * only remove relative normal velocity (e ≤ 1) and friction only opposes sliding, so a contact
 * never adds kinetic energy; the projection adds the potential energy of the sub-step's
 * penetration (½ g h² for a body at rest), which the impulse took out as kinetic energy.
 * The fluid's unresolved gap (thinner than a particle spacing or a cell) exerts no
 * lubrication force: the contact is the rigid limit of that film.
 *
 * Bodies are built from the scene's solids with Motion = rigid; `solids/` knows no fluid.
 */
#include <twinflow/core/scene.h>
#include <twinflow/solids/rigid_body.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace twinflow::solids
{
  /// Fluid load on one body (force, torque about its centre of mass; world axes).
  struct BodyLoad
  {
    Vector3 force  = Vector3::Zero();
    Vector3 torque = Vector3::Zero();
  };

  /// What a fluid needs of a body: its pose and rigid velocity/acceleration fields.
  struct BodyKinematics
  {
    Vector3 position = Vector3::Zero();             ///< centre of mass
    Matrix3 rotation = Matrix3::Identity();         ///< body → world
    Vector3 velocity = Vector3::Zero(), angular_velocity = Vector3::Zero();
    Vector3 acceleration = Vector3::Zero(), angular_acceleration = Vector3::Zero();

    /// u_s(p) = v + ω × (p − c) and a_s(p) = a + α × r + ω × (ω × r).
    Vector3 point_velocity(const Vector3 &p) const { return velocity + angular_velocity.cross(p - position); }
    Vector3 point_acceleration(const Vector3 &p) const
    {
      const Vector3 r = p - position;
      return acceleration + angular_acceleration.cross(r) + angular_velocity.cross(angular_velocity.cross(r));
    }
  };

  /// Volume of a scene solid (2D: per unit depth; 3D boxes/plates span @p span along z).
  double solid_volume(const Solid &solid, int dim, double span);

  /// Mass properties of a scene solid of its Density (2D: per unit depth).
  MassProperties solid_mass_properties(const Solid &solid, int dim, double span);

  /// Implicit coupling by fixed-point sub-iterations on the body loads with Aitken's dynamic
  /// relaxation (Küttler & Wall 2008): a step is repeated with the guess F_k, the fluid returns
  /// F̃_k, r_k = F̃_k − F_k, F_{k+1} = F_k + ω_k r_k with ω_k = −ω_{k−1} r_{k−1}·(r_k − r_{k−1}) /
  /// |r_k − r_{k−1}|². For a light body the explicit map F_k → F̃_k has the gain −M_a/m (added
  /// over body mass) and diverges for M_a > m; the secant-like ω makes it converge in a few
  /// iterations whatever the ratio. Torques enter the residual divided by the body's extent
  /// (so that every entry is a force). Converged: |r_k| ≤ tolerance · max(|F̃_k|, Σ m g).
  class LoadRelaxation
  {
  public:
    LoadRelaxation(int max_iterations, double tolerance, double initial_omega = 0.5);
    /// A new step: the first guess (usually the last step's loads), @p extents per body for
    /// the torque scale, @p load_scale (Σ m g) for the tolerance.
    void start(const std::vector<BodyLoad> &first_guess, const std::vector<double> &extents, double load_scale);
    const std::vector<BodyLoad> &guess() const { return current; }
    /// The fluid's loads for the current guess: true when converged (or the iteration limit
    /// is reached); otherwise guess() is the next, relaxed load.
    bool update(const std::vector<BodyLoad> &computed);
    int    iterations() const { return iteration; }
    bool   converged() const { return done_converged; }
    double residual() const { return last_residual; } ///< |r_k| / scale of the last update

  private:
    int                   max_iterations;
    double                tolerance, omega0, omega = 0, scale = 1, last_residual = 0;
    int                   iteration = 0;
    bool                  done_converged = false;
    std::vector<double>   extent;
    std::vector<BodyLoad> current;
    Eigen::VectorXd       previous_residual;
  };

  class CoSimulation
  {
  public:
    /// Builds one rigid body per scene solid with Motion = rigid (none: an empty coupling
    /// that no fluid consults). @p fluid_density: ρ of fluid 1 (for the added mass).
    explicit CoSimulation(const Scene &scene);

    std::size_t n_bodies() const { return bodies.size(); }
    bool        empty() const { return bodies.empty(); }
    /// Index of the scene solid that body @p b is.
    int         solid_index(std::size_t b) const { return solid_of_body[b]; }
    /// Body of scene solid @p s, or −1 if that solid does not move.
    int         body_of_solid(std::size_t s) const;

    /// Steps (1)–(2): applies @p loads (one per body) and advances every body over @p dt.
    void advance(double dt, const std::vector<BodyLoad> &loads);

    /// Throws std::runtime_error naming the body, the wall and the time if a body's surface
    /// reached a non-periodic face of @p scene's domain without wall contact (Solids/Wall
    /// contact = false: a body that sinks to the floor stops the run there), or, with it, if a
    /// body's centre got within half its inradius of a wall (the contact failed).
    void check_clear_of_walls(const Scene &scene) const;
    /// Sub-steps in which some body touched a wall, and the largest penetration found before
    /// a projection [m] (the contact's resolution).
    std::size_t contact_substeps() const { return contacts; }
    double      max_contact_depth() const { return deepest; }

    BodyKinematics          kinematics(std::size_t b) const;
    /// Largest speed of a material point on any body's surface, |v| + |ω| · extent (for the
    /// fluid's CFL step); 0 without bodies.
    double                  max_surface_speed() const;
    const RigidBody        &body(std::size_t b) const { return bodies[b]; }
    const std::string      &name(std::size_t b) const { return names[b]; }
    int                     substeps() const { return n_substeps; }
    /// Total RK4 sub-steps taken (the coupling's cost, besides the fluid's load evaluation).
    std::size_t             substeps_taken() const { return taken; }
    /// Largest distance of body @p b's surface from its centre.
    double                  body_extent(std::size_t b) const { return extent[b]; }
    /// Σ m g over the bodies (the load scale of the coupling tolerance).
    double                  weight_scale(double gravity) const;
    /// The bodies' states as text (checkpoints): every body's position, orientation,
    /// velocity, angular momentum and last accelerations, full precision.
    void save(std::ostream &out) const;
    /// Reads what save() wrote; throws std::runtime_error if it does not fit these bodies.
    void load(std::istream &in);
    /// One line per body for the run's "active physics" list.
    std::vector<std::string> describe() const;

  private:
    /// A body's cross-section for the wall contacts: a circle (radius > 0) or polygon corners
    /// (body axes).
    struct ContactShape
    {
      double               radius = 0;
      std::vector<Vector3> corners;
      double               inradius = 0; ///< smallest distance of the surface from the centre
    };
    /// Contacts of body @p b with the walls after a sub-step of length @p h.
    void resolve_wall_contacts(RigidBody &body, std::size_t b, double h);

    std::vector<ContactShape> shapes;
    bool                     wall_contact = true;
    double                   restitution = 0, friction = 0, gravity = 0;
    double                   wall_lower[2] = {0, 0}, wall_upper[2] = {0, 0};
    bool                     wall_active[2] = {false, false};
    std::size_t              contacts = 0;
    double                   deepest  = 0;
    std::vector<RigidBody>   bodies;
    std::vector<int>         solid_of_body;
    std::vector<std::string> names;
    std::vector<double>      added_mass, extent; ///< extent: largest distance of the surface from the centre
    int                      n_substeps = 1;
    std::size_t              taken      = 0;
  };
} // namespace twinflow::solids
