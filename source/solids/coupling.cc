#include <twinflow/solids/coupling.h>

#include <algorithm>
#include <cmath>
#include <istream>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace twinflow::solids
{
  double solid_volume(const Solid &s, const int dim, const double span)
  {
    if (s.shape == "disk")
      return M_PI * s.radius * s.radius;
    if (s.shape == "cylinder")
      return M_PI * s.radius * s.radius * s.length;
    return s.length * s.thickness * (dim == 3 ? span : 1.0); // box, plate
  }

  MassProperties solid_mass_properties(const Solid &s, const int dim, const double span)
  {
    if (!(s.density > 0))
      throw std::invalid_argument("Solids/" + s.name + "/Density = " + std::to_string(s.density) +
                                  ": a moving solid needs a density > 0");
    if (s.shape == "disk")
      return MassProperties::cylinder(s.density, s.radius, 1.0);
    if (s.shape == "cylinder")
      return MassProperties::cylinder(s.density, s.radius, s.length);
    return MassProperties::box(s.density, s.length, s.thickness, dim == 3 ? span : 1.0);
  }

  CoSimulation::CoSimulation(const Scene &scene)
  {
    const int    dim  = scene.dimension;
    const double span = dim == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 1.0;
    const double rho_fluid = scene.fluids.empty() ? 0.0 : scene.fluids.front().density;
    n_substeps   = scene.solid_substeps;
    wall_contact = scene.wall_contact;
    restitution  = scene.contact_restitution;
    friction     = scene.contact_friction;
    if (!(restitution >= 0 && restitution <= 1) || !(friction >= 0))
      throw std::invalid_argument("Solids/Wall contact restitution must lie in [0, 1] and Solids/Wall contact friction be >= 0 "
                                  "(got " + std::to_string(restitution) + ", " + std::to_string(friction) + ")");
    gravity = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                        (dim == 3 ? scene.gravity[2] * scene.gravity[2] : 0.0));
    for (int d = 0; d < std::min(dim, 2); ++d) // bodies are extrusions along z
    {
      wall_active[d] = !scene.periodic[d];
      wall_lower[d]  = scene.domain.lower[d];
      wall_upper[d]  = scene.domain.upper[d];
    }
    for (std::size_t k = 0; k < scene.solids.size(); ++k)
    {
      const Solid &s = scene.solids[k];
      if (s.motion != SolidMotion::rigid)
        continue;
      RigidBodyState initial;
      for (int d = 0; d < dim; ++d)
      {
        initial.position[d] = s.center[d];
        initial.velocity[d] = s.initial_velocity[d];
      }
      if (dim == 2 && s.shape == "cylinder")
        throw std::invalid_argument("Solids/" + s.name + "/Shape: a cylinder is 3D");
      initial.orientation = Quaternion(Eigen::AngleAxisd(s.angle, Vector3::UnitZ()));
      const DofMask mask  = DofMask::parse_locked(s.locked_dofs, dim);
      RigidBody     body(solid_mass_properties(s, dim, span), initial, mask, Vector3(scene.gravity[0], scene.gravity[1],
                                                                                      dim == 3 ? scene.gravity[2] : 0.0));
      body.set_angular_velocity(Vector3(dim == 3 ? s.initial_angular_velocity[0] : 0.0,
                                        dim == 3 ? s.initial_angular_velocity[1] : 0.0, s.initial_angular_velocity[2]));
      const double ma = s.added_mass_coefficient * rho_fluid * solid_volume(s, dim, span);
      body.set_added_mass(ma, 0.0);
      bodies.push_back(body);
      solid_of_body.push_back(static_cast<int>(k));
      names.push_back(s.name);
      added_mass.push_back(ma);
      const bool round = s.shape == "disk" || s.shape == "cylinder";
      extent.push_back(round ? s.radius : 0.5 * std::hypot(s.length, s.thickness));
      ContactShape shape;
      shape.inradius = round ? s.radius : 0.5 * std::min(s.length, s.thickness);
      if (round)
        shape.radius = s.radius;
      else
        for (const double a : {-0.5, 0.5})
          for (const double c : {-0.5, 0.5})
            shape.corners.emplace_back(a * s.length, c * s.thickness, 0.0);
      shapes.push_back(shape);
    }
  }

  int CoSimulation::body_of_solid(const std::size_t s) const
  {
    for (std::size_t b = 0; b < solid_of_body.size(); ++b)
      if (solid_of_body[b] == static_cast<int>(s))
        return static_cast<int>(b);
    return -1;
  }

  void CoSimulation::advance(const double dt, const std::vector<BodyLoad> &loads)
  {
    if (loads.size() != bodies.size())
      throw std::logic_error("CoSimulation::advance: one load per body expected");
    for (std::size_t b = 0; b < bodies.size(); ++b)
    {
      bodies[b].set_load(loads[b].force, loads[b].torque);
      if (wall_contact)
        bodies[b].advance(dt, n_substeps, [&, b](RigidBody &body) { resolve_wall_contacts(body, b, dt / n_substeps); });
      else
        bodies[b].advance(dt, n_substeps);
      taken += n_substeps;
    }
  }

  void CoSimulation::resolve_wall_contacts(RigidBody &body, const std::size_t b, const double h)
  {
    struct Contact
    {
      Vector3 p, n;
      double  depth, target, k_n, lambda = 0;
      Vector3 t = Vector3::Zero();
      double  k_t = 0, lambda_t = 0;
    };
    std::vector<Contact> found;
    const Vector3       &c = body.state().position;
    const Matrix3        R = body.rotation();
    for (int d = 0; d < 2; ++d)
      for (const bool low : {true, false})
      {
        if (!wall_active[d])
          continue;
        const double  wall = low ? wall_lower[d] : wall_upper[d];
        const Vector3 n    = (low ? 1.0 : -1.0) * Vector3::Unit(d); // into the domain
        auto add = [&](const Vector3 &p) {
          const double depth = -n[d] * (p[d] - wall);
          if (depth > 0)
            found.push_back(Contact{p, n, depth, 0, 0});
        };
        if (shapes[b].radius > 0)
          add(c - shapes[b].radius * n);
        else
          for (const Vector3 &q : shapes[b].corners)
            add(c + R * q);
      }
    if (found.empty())
      return;
    ++contacts;
    // Sequential impulses: each contact's normal velocity is driven to its target (−e times its
    // approach speed; inelastic below two sub-steps of free fall) by an accumulated impulse kept
    // >= 0; friction's accumulated impulse along the initial sliding direction is kept within
    // μ times the normal one.
    const double slow = 2 * gravity * h;
    for (Contact &k : found)
    {
      deepest       = std::max(deepest, k.depth);
      const double vn = k.n.dot(body.point_velocity(k.p));
      k.target      = vn < -slow ? -restitution * vn : 0.0;
      k.k_n         = k.n.dot(body.impulse_response(k.n, k.p));
      const Vector3 vt = body.point_velocity(k.p) - vn * k.n;
      if (friction > 0 && vt.norm() > 0)
      {
        k.t   = vt.normalized();
        k.k_t = k.t.dot(body.impulse_response(k.t, k.p));
      }
    }
    for (int pass = 0; pass < 20; ++pass)
    {
      double change = 0; // largest impulse change of this pass, as a velocity [m/s]
      for (Contact &k : found)
      {
        if (k.k_n > 0)
        {
          const double vn = k.n.dot(body.point_velocity(k.p));
          const double l  = std::max(0.0, k.lambda + (k.target - vn) / k.k_n);
          body.apply_impulse((l - k.lambda) * k.n, k.p);
          change   = std::max(change, std::abs(l - k.lambda) * k.k_n);
          k.lambda = l;
        }
        if (k.k_t > 0)
        {
          const double vt    = k.t.dot(body.point_velocity(k.p));
          const double bound = friction * k.lambda;
          const double l     = std::clamp(k.lambda_t - vt / k.k_t, -bound, bound);
          body.apply_impulse((l - k.lambda_t) * k.t, k.p);
          change     = std::max(change, std::abs(l - k.lambda_t) * k.k_t);
          k.lambda_t = l;
        }
      }
      if (change <= 1e-6 * slow) // converged to a millionth of a sub-step's fall (one contact: the first pass)
        break;
    }
    // back onto each wall crossed (the deepest point of each)
    for (int d = 0; d < 2; ++d)
      for (const double side : {1.0, -1.0})
      {
        double depth = 0;
        for (const Contact &k : found)
          if (k.n[d] == side)
            depth = std::max(depth, k.depth);
        if (depth > 0)
          body.translate(side * depth * Vector3::Unit(d));
      }
  }

  double CoSimulation::weight_scale(const double gravity) const
  {
    double w = 0;
    for (const auto &b : bodies)
      w += b.mass_properties().mass * gravity;
    return w;
  }

  LoadRelaxation::LoadRelaxation(const int max_iterations, const double tolerance, const double initial_omega)
    : max_iterations(max_iterations), tolerance(tolerance), omega0(initial_omega)
  {
    if (max_iterations < 1 || !(tolerance > 0) || !(initial_omega > 0 && initial_omega <= 1))
      throw std::invalid_argument("LoadRelaxation: need max_iterations >= 1, tolerance > 0, 0 < omega <= 1");
  }

  void LoadRelaxation::start(const std::vector<BodyLoad> &first_guess, const std::vector<double> &extents,
                             const double load_scale)
  {
    current        = first_guess;
    extent         = extents;
    scale          = load_scale;
    iteration      = 0;
    omega          = omega0;
    done_converged = false;
    previous_residual.resize(0);
  }

  bool LoadRelaxation::update(const std::vector<BodyLoad> &computed)
  {
    const std::size_t n = current.size();
    Eigen::VectorXd   r(6 * n);
    double            magnitude = 0;
    for (std::size_t b = 0; b < n; ++b)
    {
      const double l = extent[b] > 0 ? extent[b] : 1.0;
      r.segment<3>(6 * b)     = computed[b].force - current[b].force;
      r.segment<3>(6 * b + 3) = (computed[b].torque - current[b].torque) / l;
      magnitude = std::max({magnitude, computed[b].force.norm(), computed[b].torque.norm() / l});
    }
    ++iteration;
    last_residual  = r.norm() / std::max({scale, magnitude, 1e-300});
    done_converged = last_residual <= tolerance;
    if (done_converged || iteration >= max_iterations)
    {
      current = computed;
      return true;
    }
    if (previous_residual.size() == r.size())
    {
      const Eigen::VectorXd dr = r - previous_residual;
      const double          d2 = dr.squaredNorm();
      if (d2 > 0)
        omega = -omega * previous_residual.dot(dr) / d2;
    }
    previous_residual = r;
    for (std::size_t b = 0; b < n; ++b)
    {
      const double l = extent[b] > 0 ? extent[b] : 1.0;
      current[b].force += omega * r.segment<3>(6 * b);
      current[b].torque += omega * l * r.segment<3>(6 * b + 3);
    }
    return false;
  }

  void CoSimulation::check_clear_of_walls(const Scene &scene) const
  {
    static const char *faces[6] = {"left", "right", "bottom", "top", "front", "back"};
    for (std::size_t b = 0; b < bodies.size(); ++b)
    {
      const Vector3 &c = bodies[b].state().position;
      for (int d = 0; d < std::min(scene.dimension, 2); ++d) // bodies are extrusions along z
      {
        if (scene.periodic[d])
          continue;
        // with contact the body only touches a wall; its centre within half its inradius of one
        // means the contact failed (it cannot happen with the projection: a guard)
        const double reach = wall_contact ? 0.5 * shapes[b].inradius : extent[b];
        const bool   low = c[d] - reach <= scene.domain.lower[d], high = c[d] + reach >= scene.domain.upper[d];
        if (low || high)
        {
          if (wall_contact)
            throw std::runtime_error("rigid body '" + names[b] + "' went through the " + faces[2 * d + (high ? 1 : 0)] +
                                     " wall at t = " + std::to_string(bodies[b].time()) +
                                     " s although wall contact is on: the fluid load diverged (reduce the time step)");
          std::ostringstream m;
          m << "rigid body '" << names[b] << "' reached the " << faces[2 * d + (high ? 1 : 0)] << " wall at t = "
            << bodies[b].time() << " s (centre " << c[d] << " m along " << "xyz"[d]
            << "): wall contact is off (Solids/Wall contact = false), so the run stops here (turn it on, end the "
               "scene before the body lands, or lock its vertical degree of freedom)";
          throw std::runtime_error(m.str());
        }
      }
    }
  }

  double CoSimulation::max_surface_speed() const
  {
    double v = 0;
    for (std::size_t b = 0; b < bodies.size(); ++b)
      v = std::max(v, bodies[b].state().velocity.norm() + bodies[b].angular_velocity().norm() * extent[b]);
    return v;
  }

  BodyKinematics CoSimulation::kinematics(const std::size_t b) const
  {
    const RigidBody &r = bodies[b];
    BodyKinematics   k;
    k.position             = r.state().position;
    k.rotation             = r.rotation();
    k.velocity             = r.state().velocity;
    k.angular_velocity     = r.angular_velocity();
    k.acceleration         = r.acceleration();
    k.angular_acceleration = r.angular_acceleration();
    return k;
  }

  std::vector<std::string> CoSimulation::describe() const
  {
    std::vector<std::string> out;
    for (std::size_t b = 0; b < bodies.size(); ++b)
    {
      static const char *dof[6] = {"x", "y", "z", "rx", "ry", "rz"};
      std::ostringstream s;
      s << "rigid body '" << names[b] << "' (m = " << bodies[b].mass_properties().mass << " kg, free DoFs:";
      for (int i = 0; i < 6; ++i)
        if (bodies[b].dofs().free[i])
          s << " " << dof[i];
      s << "; RK4, " << n_substeps << " sub-steps per fluid step; explicit force-displacement coupling";
      if (wall_contact)
        s << "; wall contact (impulses, e = " << restitution << ", mu = " << friction << ")";
      if (added_mass[b] > 0)
        s << " with Soeding's added-mass correction m_a = " << added_mass[b] << " kg";
      s << ")";
      out.push_back(s.str());
    }
    return out;
  }

  void CoSimulation::save(std::ostream &out) const
  {
    out << "bodies " << bodies.size() << ' ' << taken << '\n';
    const auto put = [&](const auto &v) {
      for (int i = 0; i < int(v.size()); ++i)
        out << ' ' << v[i];
    };
    for (const RigidBody &b : bodies)
    {
      const RigidBodyState &s = b.state();
      const Quaternion     &q = s.orientation;
      out << "body";
      put(s.position);
      out << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z();
      put(s.velocity);
      put(s.angular_momentum);
      put(b.acceleration());
      put(b.previous_angular_acceleration());
      out << '\n';
    }
  }

  void CoSimulation::load(std::istream &in)
  {
    std::string tag;
    std::size_t n = 0;
    in >> tag >> n >> taken;
    if (!in || tag != "bodies" || n != bodies.size())
      throw std::runtime_error("checkpoint: the rigid bodies' state is missing or is for " + std::to_string(n) +
                               " bodies, the scene has " + std::to_string(bodies.size()));
    const auto get = [&](Vector3 &v) { in >> v[0] >> v[1] >> v[2]; };
    for (RigidBody &b : bodies)
    {
      RigidBodyState s;
      Vector3        a, alpha;
      double         w, x, y, z;
      in >> tag;
      get(s.position);
      in >> w >> x >> y >> z;
      s.orientation = Quaternion(w, x, y, z);
      get(s.velocity);
      get(s.angular_momentum);
      get(a);
      get(alpha);
      if (!in || tag != "body")
        throw std::runtime_error("checkpoint: a rigid body's state is truncated");
      b.restore(s, a, alpha);
    }
  }
} // namespace twinflow::solids
