#include <twinflow/solids/rigid_body.h>

#include <Eigen/Dense>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace twinflow::solids
{
  DofMask DofMask::planar()
  {
    DofMask m;
    m.free = {{true, true, false, false, false, true}};
    return m;
  }

  DofMask DofMask::parse_locked(const std::string &list, const int dim)
  {
    static const char *names[6] = {"x", "y", "z", "rx", "ry", "rz"};
    DofMask m = dim == 2 ? planar() : all();
    std::stringstream in(list);
    std::string       word;
    while (std::getline(in, word, ','))
    {
      const auto b = word.find_first_not_of(" \t"), e = word.find_last_not_of(" \t");
      if (b == std::string::npos)
        continue;
      word = word.substr(b, e - b + 1);
      int k = -1;
      for (int i = 0; i < 6; ++i)
        if (word == names[i])
          k = i;
      if (k < 0)
        throw std::invalid_argument("'" + word + "' is not a degree of freedom; allowed: x, y, z, rx, ry, rz" +
                                    std::string(dim == 2 ? " (2D: x, y, rz)" : ""));
      if (dim == 2 && (k == 2 || k == 3 || k == 4))
        throw std::invalid_argument("'" + word + "' does not exist in a 2D scene (always locked there); allowed: x, y, rz");
      m.free[k] = false;
    }
    return m;
  }

  MassProperties MassProperties::cylinder(const double density, const double radius, const double length)
  {
    MassProperties p;
    p.mass          = density * M_PI * radius * radius * length;
    const double lr = p.mass * (3 * radius * radius + length * length) / 12;
    p.inertia       = Vector3(lr, lr, 0.5 * p.mass * radius * radius).asDiagonal();
    return p;
  }

  MassProperties MassProperties::box(const double density, const double a, const double b, const double c)
  {
    MassProperties p;
    p.mass    = density * a * b * c;
    p.inertia = Vector3(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal();
    p.inertia *= p.mass / 12;
    return p;
  }

  MassProperties MassProperties::ball(const double density, const double radius)
  {
    MassProperties p;
    p.mass    = density * 4.0 / 3.0 * M_PI * radius * radius * radius;
    p.inertia = Matrix3::Identity() * 0.4 * p.mass * radius * radius;
    return p;
  }

  RigidBody::RigidBody(const MassProperties &mass, const RigidBodyState &initial, const DofMask &dofs,
                       const Vector3 &g)
    : props(mass), mask(dofs), gravity(g), x(initial)
  {
    if (!(mass.mass > 0) || !std::isfinite(mass.mass))
      throw std::invalid_argument("rigid body: the mass must be positive and finite (got " + std::to_string(mass.mass) + ")");
    Eigen::SelfAdjointEigenSolver<Matrix3> eig(mass.inertia);
    if (!(eig.eigenvalues().minCoeff() > 0))
      throw std::invalid_argument("rigid body: the inertia tensor must be symmetric positive definite");
    translation_projector = Vector3(mask.free[0], mask.free[1], mask.free[2]).asDiagonal();
    rotation_projector    = Vector3(mask.free[3], mask.free[4], mask.free[5]).asDiagonal();
    x.orientation.normalize();
    x.velocity         = translation_projector * x.velocity;
    x.angular_momentum = rotation_projector * x.angular_momentum;
    last_acceleration  = linear_acceleration();
  }

  void RigidBody::set_added_mass(const double translational, const double rotational)
  {
    if (translational < 0 || rotational < 0)
      throw std::invalid_argument("rigid body: added mass and inertia must be >= 0");
    // L is the momentum of the augmented body: keep ω when the inertia changes.
    const Vector3 w = omega(x);
    added_mass      = translational;
    added_inertia   = rotational;
    set_angular_velocity(w);
    last_acceleration = linear_acceleration();
  }

  void RigidBody::set_angular_velocity(const Vector3 &w)
  {
    const Matrix3 R  = rotation();
    const Matrix3 Iw = R * props.inertia * R.transpose() + added_inertia * Matrix3::Identity();
    x.angular_momentum = rotation_projector * (Iw * (rotation_projector * w));
  }

  void RigidBody::set_load(const Vector3 &f, const Vector3 &tq)
  {
    if (!f.allFinite() || !tq.allFinite())
      throw std::runtime_error("rigid body: the load applied is not finite (force " + std::to_string(f.norm()) +
                               " N, torque " + std::to_string(tq.norm()) + " N m): the fluid solution diverged");
    force  = f;
    torque = tq;
  }

  Vector3 RigidBody::omega(const RigidBodyState &s) const
  {
    const Matrix3 R  = s.orientation.toRotationMatrix();
    const Matrix3 Iw = R * props.inertia * R.transpose() + added_inertia * Matrix3::Identity();
    const int     k  = mask.n_rotations();
    if (k == 3)
      return Iw.ldlt().solve(s.angular_momentum);
    if (k == 0)
      return Vector3::Zero();
    if (k == 1) // a planar body: ω along its one free axis (the same division as the 1×1 solve below)
    {
      const int i = mask.free[3] ? 0 : (mask.free[4] ? 1 : 2);
      Vector3   w = Vector3::Zero();
      w[i]        = s.angular_momentum[i] / Iw(i, i);
      return w;
    }
    // ω = P (Pᵀ I_w P)⁻¹ Pᵀ L over the free axes
    Eigen::MatrixXd P(3, k);
    for (int i = 0, c = 0; i < 3; ++i)
      if (mask.free[3 + i])
        P.col(c++) = Vector3::Unit(i);
    const Eigen::MatrixXd reduced = P.transpose() * Iw * P;
    return P * reduced.ldlt().solve(P.transpose() * s.angular_momentum);
  }

  Vector3 RigidBody::linear_acceleration() const
  {
    const Vector3 a = (force + props.mass * gravity + added_mass * last_acceleration) / (props.mass + added_mass);
    return translation_projector * a;
  }

  Vector3 RigidBody::angular_acceleration() const
  {
    // α = dω/dt along the exact rate (ω = I_w⁻¹ L with I_w turning): a central difference,
    // exact to O(h²), which is what the BCE acceleration of Eq. 61 needs.
    const double   h = 1e-5;
    const Rate     k = rate(x);
    RigidBodyState p = add(x, k, h), m = add(x, k, -h);
    p.orientation.normalize();
    m.orientation.normalize();
    return (omega(p) - omega(m)) / (2 * h);
  }

  RigidBody::Rate RigidBody::rate(const RigidBodyState &s) const
  {
    Rate          r;
    const Vector3 w = omega(s);
    r.dx            = s.velocity;
    r.dv            = linear_acceleration();
    r.dL            = rotation_projector * (torque + added_inertia * last_angular_acceleration);
    const Quaternion wq(0, w.x(), w.y(), w.z());
    const Quaternion dq = wq * s.orientation;
    r.dq                = 0.5 * Eigen::Vector4d(dq.w(), dq.x(), dq.y(), dq.z());
    return r;
  }

  RigidBodyState RigidBody::add(const RigidBodyState &s, const Rate &k, const double h)
  {
    RigidBodyState out;
    out.position         = s.position + h * k.dx;
    out.velocity         = s.velocity + h * k.dv;
    out.angular_momentum = s.angular_momentum + h * k.dL;
    out.orientation      = Quaternion(s.orientation.w() + h * k.dq[0], s.orientation.x() + h * k.dq[1],
                                      s.orientation.y() + h * k.dq[2], s.orientation.z() + h * k.dq[3]);
    return out;
  }

  void RigidBody::apply_impulse(const Vector3 &J, const Vector3 &p)
  {
    const Vector3 w0 = omega(x);
    const Vector3 dv = translation_projector * J / props.mass;
    x.velocity += dv;
    x.angular_momentum += rotation_projector * (p - x.position).cross(J);
    impulse_dv += dv;
    impulse_dw += omega(x) - w0;
  }

  Vector3 RigidBody::impulse_response(const Vector3 &J, const Vector3 &p) const
  {
    RigidBodyState d = x; // ω is linear in L at a fixed orientation
    d.angular_momentum = rotation_projector * (p - x.position).cross(J);
    return translation_projector * J / props.mass + omega(d).cross(p - x.position);
  }

  void RigidBody::translate(const Vector3 &d) { x.position += translation_projector * d; }

  void RigidBody::advance(const double dt, const int substeps, const std::function<void(RigidBody &)> &after_substep)
  {
    if (!(dt > 0) || substeps < 1)
      throw std::invalid_argument("rigid body: advance needs dt > 0 and at least one sub-step");
    const double h = dt / substeps;
    impulse_dv = impulse_dw = Vector3::Zero();
    for (int n = 0; n < substeps; ++n)
    {
      const Rate     k1 = rate(x);
      const Rate     k2 = rate(add(x, k1, 0.5 * h));
      const Rate     k3 = rate(add(x, k2, 0.5 * h));
      const Rate     k4 = rate(add(x, k3, h));
      Rate           k;
      k.dx = (k1.dx + 2 * k2.dx + 2 * k3.dx + k4.dx) / 6;
      k.dv = (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv) / 6;
      k.dL = (k1.dL + 2 * k2.dL + 2 * k3.dL + k4.dL) / 6;
      k.dq = (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6;
      x    = add(x, k, h);
      x.orientation.normalize();
      t += h;
      if (after_substep)
        after_substep(*this);
    }
    // the load's acceleration plus the mean of the contact impulses over the step: the body's
    // actual acceleration (a body resting on the floor: zero), which the fluid's boundary
    // condition and Söding's term need
    const Vector3 a = linear_acceleration() + impulse_dv / dt;
    last_angular_acceleration = angular_acceleration() + impulse_dw / dt;
    last_acceleration         = a;
  }

  Vector3 RigidBody::point_velocity(const Vector3 &p) const
  {
    return x.velocity + angular_velocity().cross(p - x.position);
  }

  Vector3 RigidBody::point_acceleration(const Vector3 &p) const
  {
    const Vector3 r = p - x.position, w = angular_velocity();
    return acceleration() + angular_acceleration().cross(r) + w.cross(w.cross(r));
  }

  double RigidBody::kinetic_energy() const
  {
    const Vector3 w = angular_velocity();
    const Matrix3 R = rotation();
    return 0.5 * props.mass * x.velocity.squaredNorm() + 0.5 * w.dot(R * props.inertia * R.transpose() * w);
  }

  double RigidBody::potential_energy() const { return -props.mass * gravity.dot(x.position); }
} // namespace twinflow::solids
