#include <twinflow/core/errors.h>
#include <twinflow/core/scene.h>
#include <twinflow/io/csv_table.h>
#include <twinflow/io/reference_data.h>
#include <twinflow/solids/rigid_body.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace twinflow
{
  using namespace dealii;

  namespace
  {
    const char *face_names[6] = {"left", "right", "bottom", "top", "front", "back"};

    std::array<double, 3> parse_point(const std::string &text, const std::string &entry, int dim)
    {
      auto parts = Utilities::split_string_list(text, ',');
      // A 2D scene may give a 3D vector whose z component is zero (e.g. the default "0, 0, 0").
      if (dim == 2 && parts.size() == 3 && (parts[2] == "0" || parts[2] == "0.0"))
        parts.pop_back();
      require(static_cast<int>(parts.size()) == dim, entry, text,
              "expected " + std::to_string(dim) + " comma-separated numbers (the scene's dimension)");
      std::array<double, 3> p{{0, 0, 0}};
      for (int d = 0; d < dim; ++d)
      {
        try
        {
          std::size_t used = 0;
          p[d]             = std::stod(parts[d], &used);
          require(used == parts[d].size(), entry, text, "expected numbers");
        }
        catch (const std::logic_error &)
        {
          require(false, entry, text, "expected " + std::to_string(dim) + " comma-separated numbers");
        }
      }
      return p;
    }

    void declare_solid(ParameterHandler &prm)
    {
      prm.declare_entry("Name", "solid", Patterns::Anything(), "Name used in monitors and output.");
      prm.declare_entry("Shape", "disk", Patterns::Selection("disk|cylinder|box|plate"),
                        "disk (2D), cylinder (3D, axis along z), box (center and size Length x Thickness), plate.");
      prm.declare_entry("Center", "0, 0", Patterns::Anything(), "Centre of the solid (dim numbers).");
      prm.declare_entry("Radius", "0.05", Patterns::Double(0), "Radius of a disk/cylinder [m].");
      prm.declare_entry("Length", "0", Patterns::Double(0), "Cylinder length (3D) / box or plate length [m].");
      prm.declare_entry("Thickness", "0", Patterns::Double(0), "Box height / plate thickness [m].");
      prm.declare_entry("Angle", "0", Patterns::Double(), "Rotation about z [rad].");
      prm.declare_entry("Motion", "fixed", Patterns::Selection("fixed|rigid|elastic"),
                        "fixed: does not move; rigid: 6-DoF rigid body; elastic: ANCF structure.");
      prm.declare_entry("Density", "1000", Patterns::Double(0), "Solid density [kg/m^3] (rigid/elastic).");
      prm.declare_entry("Locked degrees of freedom", "", Patterns::Anything(),
                        "Rigid: comma-separated DoFs held fixed, out of x, y, z, rx, ry, rz (world axes; 2D scenes "
                        "always lock z, rx, ry). Empty: all free. E.g. 'x, rz' lets a 2D body move only vertically.");
      prm.declare_entry("Initial velocity", "0, 0, 0", Patterns::Anything(),
                        "Rigid: velocity of the centre at t = 0 [m/s] (dim numbers).");
      prm.declare_entry("Initial angular velocity", "0, 0, 0", Patterns::Anything(),
                        "Rigid: angular velocity at t = 0 [rad/s], 3 numbers (2D: only the z one may be non-zero).");
      prm.declare_entry("Added mass coefficient", "0", Patterns::Double(0),
                        "Rigid: C_a of Soeding's added-mass correction m_a = C_a rho_fluid V_body that keeps the "
                        "explicit co-simulation of a light body stable (0: off; 1 suits a disk or a cylinder; any "
                        "C_a above half the true one is stable).");
      prm.declare_entry("Young's modulus", "1e7", Patterns::Double(0), "[Pa] (elastic).");
      prm.declare_entry("Poisson's ratio", "0.4", Patterns::Double(0, 0.5), "[-] (elastic).");
    }
  } // namespace

  bool Scene::has_moving_solids() const
  {
    return std::any_of(solids.begin(), solids.end(), [](const Solid &b) { return b.motion != SolidMotion::fixed; });
  }

  bool Scene::wants(Method m) const { return std::find(methods.begin(), methods.end(), m) != methods.end(); }

  bool Scene::monitors_contain(const std::string &m) const
  {
    return std::find(monitors.begin(), monitors.end(), m) != monitors.end();
  }

  void declare_scene_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Dimension", "2", Patterns::Integer(2, 3), "Space dimension of the scene.");
    prm.enter_subsection("Scene");
    {
      prm.declare_entry("Name", "scene", Patterns::Anything(), "Name of the scene (used in output).");
      prm.declare_entry("Methods", "fem", Patterns::List(Patterns::Selection("fem|sph"), 1, 2),
                        "Methods to run on this scene: fem, sph, or both (fem, sph).");
      prm.declare_entry("End time", "1", Patterns::Double(), "Final time [s]; must be > 0.");
      prm.declare_entry("Output directory", "output/scene", Patterns::Anything(),
                        "Where results go (created; a method's files go to <dir>/<method>/).");
      prm.declare_entry("Output interval", "0", Patterns::Double(0),
                        "Simulated time between ParaView outputs [s]; 0 writes the final state only.");
      prm.declare_entry("Snapshot times", "", Patterns::Anything(),
                        "Comma-separated times [s], each in [0, End time], at which every method writes a "
                        "snapshot CSV (<method>/snapshots/<method>_t<time>.csv: SPH particles, FEM level-set "
                        "nodes) at its first step at or after the time; plotted as <Output directory>/plots/"
                        "snapshot_t<time>.png. Empty: none.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Domain");
    {
      prm.declare_entry("Geometry", "box", Patterns::Selection("box|channel with cylinder|box with cylinder"),
                        "box: the box Lower corner..Upper corner; channel with cylinder: the DFG benchmark "
                        "channel [0,2.2]x[0,0.41] with a body-fitted cylinder (boundary 'cylinder'); "
                        "box with cylinder (2D): the box Lower corner..Upper corner around Solid 1 (a fixed "
                        "disk), body-fitted in the FEM mesh (any face may be periodic); SPH sees box + solid.");
      prm.declare_entry("Lower corner", "0, 0", Patterns::Anything(), "Lower corner of the domain box [m].");
      prm.declare_entry("Upper corner", "1, 1", Patterns::Anything(), "Upper corner of the domain box [m].");
      prm.declare_entry("Periodic directions", "", Patterns::List(Patterns::Selection("x|y|z"), 0, 3),
                        "Directions in which the domain is periodic.");
      for (const auto *f : face_names)
        prm.declare_entry(std::string(f) + " boundary", "no slip",
                          Patterns::Selection("no slip|slip|inflow|outflow|periodic"),
                          std::string("Condition on the ") + f +
                            " face: no slip (u = 0), slip (u·n = 0, no shear: a wall whose boundary layer the "
                            "mesh does not resolve; FEM only), inflow (prescribed profile), outflow (do-nothing), "
                            "periodic (set by Periodic directions).");
      prm.declare_entry("Inflow profile", "parabolic", Patterns::Selection("parabolic|uniform"),
                        "Shape of the inflow velocity across the inflow face.");
      prm.declare_entry("Inflow velocity", "0", Patterns::Double(0),
                        "Maximum (parabolic) or uniform inflow speed [m/s].");
    }
    prm.leave_subsection();

    prm.enter_subsection("Fluids");
    {
      prm.declare_entry("Number of fluids", "1", Patterns::Integer(1, 2),
                        "1: single phase; 2: fluid 1 (water) in the initial region, fluid 2 (air) elsewhere.");
      prm.declare_entry("Initial region of fluid 1", "",
                        Patterns::Anything(),
                        "Box 'x0, y0 [, z0] ; x1, y1 [, z1]' initially filled by fluid 1; empty = everywhere.");
      for (const char *sub : {"Fluid 1", "Fluid 2"})
      {
        prm.enter_subsection(sub);
        prm.declare_entry("Name", std::string(sub) == "Fluid 1" ? "water" : "air", Patterns::Anything(), "");
        prm.declare_entry("Density", std::string(sub) == "Fluid 1" ? "1000" : "1.2", Patterns::Double(0),
                          "Density [kg/m^3], > 0.");
        prm.declare_entry("Viscosity", std::string(sub) == "Fluid 1" ? "1e-3" : "1.8e-5", Patterns::Double(0),
                          "Dynamic viscosity [Pa s], > 0.");
        prm.leave_subsection();
      }
    }
    prm.leave_subsection();

    prm.enter_subsection("Forces");
    prm.declare_entry("Gravity", "0, 0, 0", Patterns::Anything(), "Gravity acceleration vector [m/s^2] (dim components).");
    prm.declare_entry("Body force", "0, 0, 0", Patterns::Anything(),
                      "Additional body acceleration driving the flow [m/s^2] (e.g. 1, 0 for the periodic cylinder).");
    prm.leave_subsection();

    prm.enter_subsection("Solids");
    prm.declare_entry("Number of solids", "0", Patterns::Integer(0, 4), "Solids in the scene (each in 'Solid N').");
    prm.declare_entry("Sub-steps per fluid step", "10", Patterns::Integer(1, 1000),
                      "RK4 steps of each rigid body within one fluid step (the fluid load is held over them).");
    prm.declare_entry("Wall contact", "true", Patterns::Bool(),
                      "Rigid bodies touch the domain's walls: after each sub-step a body that reaches a wall gets the "
                      "impulse that stops its approach there (with the restitution and friction below) and is put "
                      "back on the wall (sequential impulses). false: a body that reaches a wall stops the run "
                      "with an error.");
    prm.declare_entry("Wall contact restitution", "0", Patterns::Double(0, 1),
                      "Coefficient of restitution e of a body's impact on a wall: the normal velocity after an impact "
                      "is -e times the one before (0: it stays on the wall, as a wet impact nearly does). Impacts "
                      "slower than two sub-steps of free fall are inelastic, so a resting body does not chatter.");
    prm.declare_entry("Wall contact friction", "0", Patterns::Double(0),
                      "Coulomb friction coefficient mu of a body on a wall (0: frictionless, it slides freely).");
    for (int i = 1; i <= 4; ++i)
    {
      prm.enter_subsection("Solid " + std::to_string(i));
      declare_solid(prm);
      prm.leave_subsection();
    }
    prm.leave_subsection();

    prm.enter_subsection("Monitors");
    prm.declare_entry("Monitors", "energy", Patterns::List(Patterns::Selection("forces|pressure probes|energy"), 0, 3),
                      "Time series written as CSV: forces (on each solid: F, C_d, C_l), pressure probes, energy.");
    prm.declare_entry("Pressure probes", "", Patterns::Anything(),
                      "Points 'x, y; x, y; ...' where the pressure is recorded (and their difference p1 - p2).");
    prm.declare_entry("Reference velocity", "1", Patterns::Double(0), "U in C = 2F/(rho U^2 D) [m/s].");
    prm.declare_entry("Reference length", "1", Patterns::Double(0), "D in C = 2F/(rho U^2 D) [m].");
    prm.leave_subsection();

    prm.enter_subsection("References");
    prm.declare_entry("Drag coefficient", "", Patterns::Anything(), "Reference C_d (empty: none).");
    prm.declare_entry("Lift coefficient", "", Patterns::Anything(), "Reference C_l (empty: none).");
    prm.declare_entry("Pressure difference", "", Patterns::Anything(), "Reference p(probe 1) - p(probe 2).");
    prm.declare_entry("Front position file", "", Patterns::Anything(),
                      "CSV with columns T, Z (Martin & Moyce scaling: Z = x_front / a, T = t sqrt(2 g / a), "
                      "a = Monitors/Reference length); relative paths are relative to the scene file. Empty: none.");
    prm.declare_entry("Front time origin uncertainty", "0", Patterns::Double(0),
                      "How late [s] the experiment's time origin may be against an instantaneous release (the "
                      "time its restraint took to clear the column). If > 0, a second front error is reported "
                      "and checked: the RMS error with the simulated times delayed by the best tau in [0, this "
                      "value]. The error against the raw table is always reported. 0: raw table only.");
    prm.declare_entry("Hydrostatic pressure", "false", Patterns::Bool(),
                      "At the end of the run, compare the pressure of the bulk fluid particles (more than 4 "
                      "spacings below the free surface and from the walls) with rho |g| (H - dx/2 - y), H = top of "
                      "Fluids/Initial region of fluid 1 (SPH; tolerance 1 % RMS). Needs gravity (0, -g) or "
                      "(0, 0, -g) and an initial fluid region.");
    prm.leave_subsection();
  }

  namespace
  {
    std::optional<double> optional_number(ParameterHandler &prm, const std::string &entry, const std::string &path)
    {
      const std::string s = prm.get(entry);
      if (s.find_first_not_of(" \t") == std::string::npos)
        return std::nullopt;
      try
      {
        return std::stod(s);
      }
      catch (const std::logic_error &)
      {
        require(false, path + "/" + entry, s, "a number, or empty for no reference");
      }
      return std::nullopt;
    }

    /// Scene/Snapshot times: comma-separated numbers in [0, End time], returned ascending.
    std::vector<double> parse_snapshot_times(const std::string &text, const double end_time)
    {
      const std::string entry = "Scene/Snapshot times";
      std::ostringstream range;
      range << "[0, " << end_time << "] s (0 to Scene/End time)";
      std::vector<double> times;
      for (const auto &part : Utilities::split_string_list(text, ','))
      {
        double      t    = 0;
        std::size_t used = 0;
        try
        {
          t = std::stod(part, &used);
        }
        catch (const std::logic_error &)
        {
          used = 0;
        }
        require(used > 0 && used == part.size() && std::isfinite(t), entry, part,
                "expected comma-separated times in " + range.str());
        require(t >= 0 && t <= end_time, entry, part, "every snapshot time must lie in " + range.str());
        times.push_back(t);
      }
      std::sort(times.begin(), times.end());
      return times;
    }

    Region parse_region(const std::string &text, const std::string &entry, int dim)
    {
      const auto halves = Utilities::split_string_list(text, ';');
      require(halves.size() == 2, entry, text, "expected 'lower corner ; upper corner'");
      Region r;
      r.lower = parse_point(halves[0], entry, dim);
      r.upper = parse_point(halves[1], entry, dim);
      for (int d = 0; d < dim; ++d)
        require(r.lower[d] < r.upper[d], entry, text, "each lower coordinate must be below the upper one");
      return r;
    }
  } // namespace

  Scene parse_scene(ParameterHandler &prm, const std::string &file)
  {
    Scene s;
    s.file      = file;
    s.dimension = prm.get_integer("Dimension");
    const int dim = s.dimension;

    prm.enter_subsection("Scene");
    s.name = prm.get("Name");
    for (const auto &m : Utilities::split_string_list(prm.get("Methods")))
      s.methods.push_back(m == "fem" ? Method::fem : Method::sph);
    s.end_time = prm.get_double("End time");
    require(s.end_time > 0 && std::isfinite(s.end_time), "Scene/End time", prm.get("End time"),
            "the end time must be a positive number of seconds");
    s.output_directory = prm.get("Output directory");
    require(!s.output_directory.empty(), "Scene/Output directory", "", "a directory path");
    s.output_interval = prm.get_double("Output interval");
    s.snapshot_times  = parse_snapshot_times(prm.get("Snapshot times"), s.end_time);
    prm.leave_subsection();

    prm.enter_subsection("Domain");
    s.geometry     = prm.get("Geometry");
    if (s.geometry == "channel with cylinder")
    {
      require(dim == 2 || dim == 3, "Dimension", std::to_string(dim), "2 or 3");
      s.domain.lower = {{0, 0, 0}};
      s.domain.upper = {{2.2, 0.41, 0.41}};
    }
    else
    {
      s.domain.lower = parse_point(prm.get("Lower corner"), "Domain/Lower corner", dim);
      s.domain.upper = parse_point(prm.get("Upper corner"), "Domain/Upper corner", dim);
      for (int d = 0; d < dim; ++d)
        require(s.domain.lower[d] < s.domain.upper[d], "Domain/Upper corner", prm.get("Upper corner"),
                "every coordinate of the upper corner must exceed the lower corner's (Domain/Lower corner = '" +
                  prm.get("Lower corner") + "')");
    }
    for (const auto &d : Utilities::split_string_list(prm.get("Periodic directions")))
    {
      const int k = d == "x" ? 0 : d == "y" ? 1 : 2;
      require(k < dim, "Domain/Periodic directions", d, "a direction of the scene's dimension");
      s.periodic[k] = true;
    }
    for (int f = 0; f < 2 * dim; ++f)
    {
      const std::string entry = std::string(face_names[f]) + " boundary";
      const std::string v     = prm.get(entry);
      s.boundary[f] = v == "inflow" ? BoundaryKind::inflow : v == "outflow" ? BoundaryKind::outflow
                    : v == "slip"    ? BoundaryKind::slip
                    : v == "periodic" ? BoundaryKind::periodic : BoundaryKind::no_slip;
      if (s.periodic[f / 2])
        s.boundary[f] = BoundaryKind::periodic;
      require(s.boundary[f] != BoundaryKind::periodic || s.periodic[f / 2], "Domain/" + entry, v,
              "'periodic' needs the direction listed in Domain/Periodic directions");
    }
    s.inflow_profile  = prm.get("Inflow profile");
    s.inflow_velocity = prm.get_double("Inflow velocity");
    prm.leave_subsection();

    prm.enter_subsection("Fluids");
    const int n_fluids = prm.get_integer("Number of fluids");
    for (int i = 1; i <= n_fluids; ++i)
    {
      prm.enter_subsection("Fluid " + std::to_string(i));
      Fluid f{prm.get("Name"), prm.get_double("Density"), prm.get_double("Viscosity")};
      const std::string path = "Fluids/Fluid " + std::to_string(i);
      require(f.density > 0, path + "/Density", prm.get("Density"), "the density must be > 0");
      require(f.viscosity > 0, path + "/Viscosity", prm.get("Viscosity"), "the viscosity must be > 0");
      s.fluids.push_back(f);
      prm.leave_subsection();
    }
    const std::string region = prm.get("Initial region of fluid 1");
    if (region.find_first_not_of(" \t") != std::string::npos)
    {
      s.fluid_region = parse_region(region, "Fluids/Initial region of fluid 1", dim);
      for (int d = 0; d < dim; ++d)
        require(s.fluid_region->lower[d] >= s.domain.lower[d] - 1e-12 &&
                  s.fluid_region->upper[d] <= s.domain.upper[d] + 1e-12,
                "Fluids/Initial region of fluid 1", region, "the region must lie inside the domain box");
    }
    prm.leave_subsection();

    prm.enter_subsection("Forces");
    s.gravity    = parse_point(prm.get("Gravity"), "Forces/Gravity", dim);
    s.body_force = parse_point(prm.get("Body force"), "Forces/Body force", dim);
    prm.leave_subsection();

    prm.enter_subsection("Solids");
    const int n_solids = prm.get_integer("Number of solids");
    s.solid_substeps   = prm.get_integer("Sub-steps per fluid step");
    s.wall_contact        = prm.get_bool("Wall contact");
    s.contact_restitution = prm.get_double("Wall contact restitution");
    s.contact_friction    = prm.get_double("Wall contact friction");
    for (int i = 1; i <= n_solids; ++i)
    {
      const std::string path = "Solids/Solid " + std::to_string(i);
      prm.enter_subsection("Solid " + std::to_string(i));
      Solid b;
      b.name           = prm.get("Name");
      b.shape          = prm.get("Shape");
      b.center         = parse_point(prm.get("Center"), path + "/Center", dim);
      b.radius         = prm.get_double("Radius");
      b.length         = prm.get_double("Length");
      b.thickness      = prm.get_double("Thickness");
      b.angle          = prm.get_double("Angle");
      const std::string m = prm.get("Motion");
      b.motion         = m == "rigid" ? SolidMotion::rigid : m == "elastic" ? SolidMotion::elastic : SolidMotion::fixed;
      b.density        = prm.get_double("Density");
      b.youngs_modulus = prm.get_double("Young's modulus");
      b.poisson_ratio  = prm.get_double("Poisson's ratio");
      if (b.motion == SolidMotion::rigid)
      {
        require(b.density > 0, path + "/Density", prm.get("Density"), "a rigid body needs a density > 0");
        try
        {
          solids::DofMask::parse_locked(prm.get("Locked degrees of freedom"), dim);
        }
        catch (const std::invalid_argument &e)
        {
          require(false, path + "/Locked degrees of freedom", prm.get("Locked degrees of freedom"), e.what());
        }
        b.locked_dofs = prm.get("Locked degrees of freedom");
        b.initial_velocity = parse_point(prm.get("Initial velocity"), path + "/Initial velocity", dim);
        b.initial_angular_velocity =
          parse_point(prm.get("Initial angular velocity"), path + "/Initial angular velocity", 3);
        require(dim == 3 || (b.initial_angular_velocity[0] == 0 && b.initial_angular_velocity[1] == 0),
                path + "/Initial angular velocity", prm.get("Initial angular velocity"),
                "a 2D body turns about z only: '0, 0, w'");
        b.added_mass_coefficient = prm.get_double("Added mass coefficient");
        require(b.shape != "plate", path + "/Shape", b.shape, "a rigid body is a disk, cylinder or box");
      }
      require(!(b.shape == "disk" && dim != 2), path + "/Shape", b.shape, "disk is 2D; use cylinder in 3D");
      require(!(b.shape == "cylinder" && dim != 3), path + "/Shape", b.shape, "cylinder is 3D; use disk in 2D");
      if (b.shape == "disk" || b.shape == "cylinder")
      {
        require(b.radius > 0, path + "/Radius", prm.get("Radius"), "the radius must be > 0");
        // A fixed solid may touch a wall; a rigid body must start clear of every wall.
        const double slack = b.motion == SolidMotion::rigid ? -1e-9 : 1e-12;
        for (int d = 0; d < std::min(dim, 2); ++d)
          require(b.center[d] - b.radius >= s.domain.lower[d] - slack && b.center[d] + b.radius <= s.domain.upper[d] + slack,
                  path + "/Center", prm.get("Center"),
                  b.motion == SolidMotion::rigid ? "a rigid body must start inside the domain box, clear of its walls"
                                                 : "the solid must lie inside the domain box");
      }
      else if (b.shape == "box" || b.shape == "plate")
      {
        require(b.length > 0, path + "/Length", prm.get("Length"), "a box or plate needs Length > 0 and Thickness > 0");
        require(b.thickness > 0, path + "/Thickness", prm.get("Thickness"),
                "a box or plate needs Length > 0 and Thickness > 0");
        // The Length x Thickness rectangle centred at Center, its length along (cos Angle, sin Angle):
        // its four corners (in 3D its x-y footprint; it spans the whole depth) must lie in the box.
        const double ca = std::cos(b.angle), sa = std::sin(b.angle);
        const double tolerance = (b.motion == SolidMotion::rigid ? -1e-9 : 1e-12) *
                                 std::max({1.0, s.domain.upper[0] - s.domain.lower[0], s.domain.upper[1] - s.domain.lower[1]});
        for (const double u : {-0.5 * b.length, 0.5 * b.length})
          for (const double v : {-0.5 * b.thickness, 0.5 * b.thickness})
          {
            const double corner[2] = {b.center[0] + ca * u - sa * v, b.center[1] + sa * u + ca * v};
            bool         inside    = true;
            for (int d = 0; d < 2; ++d)
              inside = inside && corner[d] >= s.domain.lower[d] - tolerance && corner[d] <= s.domain.upper[d] + tolerance;
            if (!inside)
            {
              std::ostringstream where;
              where << "the solid must lie inside the domain box (the corner (" << corner[0] << ", " << corner[1]
                    << ") of its Length x Thickness rectangle turned by Angle is outside)";
              require(false, path + "/Center", prm.get("Center"), where.str());
            }
          }
      }
      s.solids.push_back(b);
      prm.leave_subsection();
    }
    prm.leave_subsection();

    prm.enter_subsection("Monitors");
    s.monitors = Utilities::split_string_list(prm.get("Monitors"));
    const std::string probes = prm.get("Pressure probes");
    for (const auto &pt : Utilities::split_string_list(probes, ';'))
      s.pressure_probes.push_back(parse_point(pt, "Monitors/Pressure probes", dim));
    for (const auto &pt : s.pressure_probes)
      for (int d = 0; d < dim; ++d)
        require(pt[d] >= s.domain.lower[d] - 1e-12 && pt[d] <= s.domain.upper[d] + 1e-12, "Monitors/Pressure probes",
                probes, "every probe must lie inside the domain box");
    s.reference_velocity = prm.get_double("Reference velocity");
    s.reference_length   = prm.get_double("Reference length");
    require(s.reference_velocity > 0, "Monitors/Reference velocity", prm.get("Reference velocity"), "must be > 0");
    require(s.reference_length > 0, "Monitors/Reference length", prm.get("Reference length"), "must be > 0");
    require(!s.monitors_contain("pressure probes") || !s.pressure_probes.empty(), "Monitors/Pressure probes", probes,
            "the 'pressure probes' monitor needs at least one point");
    prm.leave_subsection();

    prm.enter_subsection("References");
    s.reference_drag                = optional_number(prm, "Drag coefficient", "References");
    s.reference_lift                = optional_number(prm, "Lift coefficient", "References");
    s.reference_pressure_difference = optional_number(prm, "Pressure difference", "References");
    const std::string front_file    = prm.get("Front position file");
    if (!front_file.empty())
    {
      const auto slash = file.find_last_of('/');
      s.reference_front_file =
        front_file[0] == '/' || slash == std::string::npos ? front_file : file.substr(0, slash + 1) + front_file;
      std::ifstream probe(s.reference_front_file);
      require(bool(probe), "References/Front position file", front_file,
              "an existing CSV file (looked for " + s.reference_front_file + ")");
      // read it now, so that a malformed table stops the run before it starts; the table's
      // own checks (rows, sorted distinct T) are those of the comparison (io::ReferenceSeries)
      const std::string allowed = "a CSV table with a header line naming columns T and Z, then rows of as many "
                                  "numbers as the header has columns, at least two rows, distinct T";
      std::string problem;
      try
      {
        const io::CsvTable table = io::read_csv(s.reference_front_file);
        if (!table.has_column("T") || !table.has_column("Z"))
          problem = s.reference_front_file + " has no column T or Z";
        else if (table.n_rows() < 2)
          problem = s.reference_front_file + " has " + std::to_string(table.n_rows()) + " rows";
        else
          io::ReferenceSeries(table.column("T"), table.column("Z"), s.reference_front_file);
      }
      catch (const std::exception &e)
      {
        problem = e.what();
      }
      require(problem.empty(), "References/Front position file", front_file, allowed + " (" + problem + ")");
    }
    s.reference_front_time_uncertainty = prm.get_double("Front time origin uncertainty");
    require(s.reference_front_time_uncertainty == 0 || !s.reference_front_file.empty(),
            "References/Front time origin uncertainty", prm.get("Front time origin uncertainty"),
            "0 unless References/Front position file is set (it qualifies that table)");
    s.reference_hydrostatic = prm.get_bool("Hydrostatic pressure");
    if (s.reference_hydrostatic)
    {
      const std::string entry = "References/Hydrostatic pressure";
      require(s.fluid_region.has_value(), entry, "true",
              "the hydrostatic check needs Fluids/Initial region of fluid 1 (H is the top of that region)");
      bool downward = s.gravity[dim - 1] < 0;
      for (int d = 0; d < dim - 1; ++d)
        downward = downward && s.gravity[d] == 0;
      require(downward, entry, "true",
              "the hydrostatic check needs Forces/Gravity along the last coordinate, pointing down "
              "(0, -g in 2D; 0, 0, -g in 3D)");
    }
    prm.leave_subsection();

    if (s.geometry == "channel with cylinder")
    {
      require(s.solids.size() == 1 && s.solids[0].motion == SolidMotion::fixed, "Solids/Number of solids",
              std::to_string(s.solids.size()),
              "the body-fitted 'channel with cylinder' geometry holds exactly one fixed solid (the cylinder)");
      const Solid &c = s.solids[0];
      require(std::abs(c.center[0] - 0.2) < 1e-12 && std::abs(c.center[1] - 0.2) < 1e-12 &&
                std::abs(c.radius - 0.05) < 1e-12,
              "Solids/Solid 1/Center", "", "the 'channel with cylinder' mesh has its cylinder at (0.2, 0.2) "
              "with Radius 0.05 (DFG benchmark); set those values or use Domain/Geometry = box");
      require(s.boundary[2] == s.boundary[3], "Domain/top boundary", "",
              "in the 'channel with cylinder' geometry the top and bottom walls share one boundary: give them the same condition");
    }
    if (s.geometry == "box with cylinder")
    {
      require(dim == 2, "Domain/Geometry", s.geometry, "'box with cylinder' is 2D; use Dimension = 2");
      require(s.solids.size() == 1 && s.solids[0].motion == SolidMotion::fixed && s.solids[0].shape == "disk",
              "Solids/Number of solids", std::to_string(s.solids.size()),
              "the body-fitted 'box with cylinder' geometry holds exactly one fixed disk (Solid 1)");
      const Solid &c    = s.solids[0];
      double       dmin = 1e300;
      for (int d = 0; d < 2; ++d)
        dmin = std::min({dmin, c.center[d] - s.domain.lower[d], s.domain.upper[d] - c.center[d]});
      require(dmin > c.radius * (1 + 1e-6), "Solids/Solid 1/Radius", std::to_string(c.radius),
              "the cylinder of the 'box with cylinder' geometry must not touch the box faces");
    }
    return s;
  }
} // namespace twinflow
