#pragma once
/**
 * @file scene.h
 * The scene: what is simulated (domain, fluids, solids, forces, monitors, methods),
 * independent of how. Parsed once from a `.prm` file into this plain value; each
 * requested method composes its simulation from it and builds only what it needs.
 */
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace dealii { class ParameterHandler; }

namespace twinflow
{
  enum class Method { fem, sph };

  /// Kinds of boundary condition a face of the domain can carry.
  enum class BoundaryKind { no_slip, slip, inflow, outflow, periodic };

  /// Axis-aligned region (3 components; the z ones unused in 2D).
  struct Region
  {
    std::array<double, 3> lower{{0, 0, 0}}, upper{{0, 0, 0}};
  };

  struct Fluid
  {
    std::string name;
    double      density   = 1000;
    double      viscosity = 1e-3;
  };

  enum class SolidMotion { fixed, rigid, elastic };

  struct Solid
  {
    std::string           name;
    std::string           shape;   ///< disk | cylinder | box | plate
    std::array<double, 3> center{{0, 0, 0}};
    double                radius = 0, length = 0, thickness = 0, angle = 0;
    SolidMotion           motion = SolidMotion::fixed;
    double                density = 0, youngs_modulus = 0, poisson_ratio = 0;
    // rigid (solids/rigid_body.h, solids/coupling.h)
    std::string           locked_dofs;                        ///< e.g. "x, rz" (2D adds z, rx, ry)
    std::array<double, 3> initial_velocity{{0, 0, 0}};
    std::array<double, 3> initial_angular_velocity{{0, 0, 0}}; ///< 2D: only the z component
    double                added_mass_coefficient = 0;         ///< m_a = C_a ρ_fluid V (Söding)
  };

  struct Scene
  {
    std::string         name;
    std::string         file;   ///< the .prm it came from
    int                 dimension = 2;
    std::vector<Method> methods;
    double              end_time        = 1;
    std::string         output_directory;
    double              output_interval = 0;   ///< 0: write the final state only
    /// Scene/Snapshot times: ascending, each in [0, end_time] (io/snapshots.h); empty: none.
    std::vector<double> snapshot_times;

    // Domain
    std::string         geometry = "box";   ///< box | channel with cylinder
    Region              domain;
    std::array<bool, 3> periodic{{false, false, false}};
    /// Boundary kind per face: left, right, bottom, top, front, back (x-, x+, y-, y+, z-, z+).
    std::array<BoundaryKind, 6> boundary{{BoundaryKind::no_slip, BoundaryKind::no_slip, BoundaryKind::no_slip,
                                          BoundaryKind::no_slip, BoundaryKind::no_slip, BoundaryKind::no_slip}};
    std::string inflow_profile  = "parabolic"; ///< parabolic | uniform
    double      inflow_velocity = 0;           ///< maximum (parabolic) or uniform value

    // Fluids: fluids[0] fills `fluid_region` (everything if not set); fluids[1], if any, the rest.
    std::vector<Fluid>    fluids;
    std::optional<Region> fluid_region;

    std::array<double, 3> gravity{{0, 0, 0}};
    std::array<double, 3> body_force{{0, 0, 0}};   ///< acceleration driving the flow

    std::vector<Solid> solids;
    int                solid_substeps = 10; ///< rigid-body RK4 sub-steps per fluid step
    /// Rigid bodies against the domain's walls (solids/coupling.h): contact on, its coefficient
    /// of restitution and Coulomb friction coefficient.
    bool               wall_contact = true;
    double             contact_restitution = 0, contact_friction = 0;

    bool has_moving_solids() const;

    // Monitors and references
    std::vector<std::string>           monitors;   ///< forces | pressure probes | energy
    std::vector<std::array<double, 3>> pressure_probes;
    double reference_velocity = 1, reference_length = 1;
    std::optional<double> reference_drag, reference_lift, reference_pressure_difference;
    /// Martin & Moyce style front table (columns T, Z = x_f/a at T = t sqrt(2g/a), a = Reference
    /// length); absolute path, or empty.
    std::string reference_front_file;
    /// Largest delay [s] of the experiment's time origin against an instantaneous release; > 0
    /// adds the front error with the best delay in [0, this] (the raw error is always reported).
    double reference_front_time_uncertainty = 0;
    /// Compare the final bulk pressure with rho |g| (H - dx/2 - y) (sph/hydrostatic_check.h).
    bool reference_hydrostatic = false;

    bool has_free_surface() const { return fluids.size() > 1; }
    bool has_solids() const { return !solids.empty(); }
    bool wants(Method m) const;
    bool monitors_contain(const std::string &m) const;
  };

  /// Declares every scene entry (with documentation and defaults) in @p prm.
  void declare_scene_parameters(dealii::ParameterHandler &prm);

  /// Reads the scene from a parsed @p prm; checks consistency and throws
  /// twinflow::InputError naming the entry and what is allowed.
  Scene parse_scene(dealii::ParameterHandler &prm, const std::string &file);
} // namespace twinflow
