#include <twinflow/core/errors.h>
#include <twinflow/fem/immersed_boundary.h>
#include <twinflow/fem/navier_stokes.h>
#include <twinflow/geometry/geometry.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_values.h>

#include <cmath>

namespace twinflow::fem
{
  using namespace dealii;

  void ImmersedBoundaryParameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Interface width", "1", Patterns::Double(0),
                      "epsilon / h_K: half-width of the smoothed Heaviside and delta (Eq. 13) of the solid level "
                      "set, in local cells (the paper: 1 to 2).");
    prm.declare_entry("Nitsche penalty", "10", Patterns::Double(0),
                      "gamma_alpha of the Nitsche penalty C_alpha = gamma_alpha mu / h_K (Eq. 15-16). Smeared over the "
                      "band by delta_eps it also acts as a drag on the fluid there: larger values widen the effective "
                      "body slightly (doc/benchmarks.md).");
    prm.declare_entry("Volume penalty", "100", Patterns::Double(0),
                      "gamma_beta of the penalty inside the solid C_beta = gamma_beta (rho/tau + mu/h_K^2) "
                      "(Eq. 15-16): the velocity inside the solid differs from u_s by about grad p / C_beta.");
  }

  void ImmersedBoundaryParameters::parse(ParameterHandler &prm)
  {
    interface_width = prm.get_double("Interface width");
    nitsche_penalty = prm.get_double("Nitsche penalty");
    volume_penalty  = prm.get_double("Volume penalty");
    require(interface_width > 0, "FEM/Immersed boundary/Interface width", prm.get("Interface width"),
            "the smoothed interface needs a width > 0 (1 to 2 cells)");
  }

  double smoothed_heaviside(const double x, const double eps)
  {
    if (x <= -eps)
      return 0;
    if (x >= eps)
      return 1;
    return 0.5 * (1 + x / eps + std::sin(numbers::PI * x / eps) / numbers::PI);
  }

  double smoothed_delta(const double x, const double eps)
  {
    return std::abs(x) >= eps ? 0.0 : 0.5 / eps * (1 + std::cos(numbers::PI * x / eps));
  }

  namespace
  {
    template <int dim>
    geometry::Vec<dim> to_vec(const Point<dim> &p)
    {
      geometry::Vec<dim> v;
      for (int d = 0; d < dim; ++d)
        v[d] = p[d];
      return v;
    }

    template <int dim>
    Tensor<1, dim> to_tensor(const geometry::Vec<dim> &v)
    {
      Tensor<1, dim> t;
      for (int d = 0; d < dim; ++d)
        t[d] = v[d];
      return t;
    }

    /// Binds a geometry shape's signed distance and normal to deal.II points.
    template <int dim, class Shape>
    void bind(const Shape &shape, std::function<double(const Point<dim> &)> &phi,
              std::function<Tensor<1, dim>(const Point<dim> &)> &grad)
    {
      phi  = [shape](const Point<dim> &x) { return shape.signed_distance(to_vec<dim>(x)); };
      grad = [shape](const Point<dim> &x) { return to_tensor<dim>(shape.normal(to_vec<dim>(x))); };
    }
  } // namespace

  template <int dim>
  ImmersedSolid<dim>::ImmersedSolid(const Solid &s, const double span, const bool periodic_span)
    : rotation(unit_symmetric_tensor<dim>())
    , adapted_rotation(unit_symmetric_tensor<dim>())
    , label(s.name)
  {
    geometry::Vec<dim> c;
    for (int d = 0; d < dim; ++d)
    {
      c[d]      = s.center[d];
      centre[d] = s.center[d];
    }
    initial_centre = adapted_centre = centre;
    const bool flat = s.shape == "box" || s.shape == "plate";
    extent          = flat ? 0.5 * std::hypot(s.length, s.thickness) : s.radius;
    if (flat && (s.length <= 0 || s.thickness <= 0))
      throw InputError("Solids/" + s.name + "/Shape = " + s.shape +
                       ": a box or plate needs Length > 0 and Thickness > 0");
    if constexpr (dim == 2)
    {
      if (s.shape == "disk")
        bind<2>(geometry::Ball<2>(c, s.radius), phi, grad_phi);
      else if (flat)
        bind<2>(geometry::Plate<2>(c, s.length, s.thickness, s.angle), phi, grad_phi);
      else
        throw InputError("Solids/" + s.name + "/Shape = " + s.shape + ": not a 2D shape; allowed in 2D: disk, box, plate");
    }
    else
    {
      if (s.shape == "cylinder")
      {
        // 0, or all of a periodic span: infinite (no caps at the periodic faces)
        const double length = s.length > 0 && !(periodic_span && s.length >= span * (1 - 1e-9)) ? s.length : 4 * span;
        bind<3>(geometry::Cylinder(c, geometry::Vec<3>::unit(2), s.radius, length), phi, grad_phi);
      }
      else if (flat)
        bind<3>(geometry::Plate<3>(c, s.length, s.thickness, 4 * span,
                                   geometry::Rotation<3>::from_axis_angle(geometry::Vec<3>::unit(2), s.angle)),
                phi, grad_phi);
      else
        throw InputError("Solids/" + s.name + "/Shape = " + s.shape +
                         ": not a 3D shape; allowed in 3D: cylinder, box, plate");
    }
  }

  template <int dim>
  Point<dim> ImmersedSolid<dim>::to_initial_frame(const Point<dim> &x) const
  {
    if (!moved)
      return x;
    return initial_centre + transpose(rotation) * (x - centre);
  }

  template <int dim>
  double ImmersedSolid<dim>::distance(const Point<dim> &x) const
  {
    return phi(to_initial_frame(x));
  }

  template <int dim>
  Tensor<1, dim> ImmersedSolid<dim>::normal(const Point<dim> &x) const
  {
    return moved ? Tensor<1, dim>(rotation * grad_phi(to_initial_frame(x))) : grad_phi(x);
  }

  template <int dim>
  void ImmersedSolid<dim>::set_motion(const Point<dim> &c, const Tensor<2, dim> &R, const Tensor<1, dim> &v,
                                      const Tensor<1, 3> &w)
  {
    centre                 = c;
    rotation               = R;
    translational_velocity = v;
    angular_velocity       = w;
    moved                  = true;
  }

  template <int dim>
  double ImmersedSolid<dim>::displacement_since_adaptation() const
  {
    return (centre - adapted_centre).norm() + extent * (rotation - adapted_rotation).norm();
  }

  template <int dim>
  void ImmersedSolid<dim>::mark_adapted()
  {
    adapted_centre   = centre;
    adapted_rotation = rotation;
  }

  template <int dim>
  Tensor<1, dim> ImmersedSolid<dim>::velocity(const Point<dim> &x) const
  {
    Tensor<1, dim> u = translational_velocity;
    const Tensor<1, dim> r = x - centre;
    if constexpr (dim == 2)
    {
      u[0] -= angular_velocity[2] * r[1];
      u[1] += angular_velocity[2] * r[0];
    }
    else
      u += cross_product_3d(angular_velocity, r);
    return u;
  }

  template class ImmersedSolid<2>;
  template class ImmersedSolid<3>;
} // namespace twinflow::fem
