// Fluid force on fixed solids (BCE markers of kind `solid`), see doc/equations.md "Forces on solids".
// Part of the single kernel source: included by engine.inl for both backends.
#pragma once
#include <twinflow_sph/backend.h>
#include <twinflow_sph/domain.h>
#include <twinflow_sph/engine.h>
#include <twinflow_sph/kernel.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
{
  /// Pressure of a solid's markers that see fluid, and their count (for the reference level p̄_s).
  template <int dim>
  struct SolidMarkerPressure
  {
    const int    *kind, *body;
    const double *pressure, *support;
    int           target;
    TWINFLOW_HD double operator()(int i) const
    {
      const bool mine = kind[i] == ParticleKind::solid && (body ? body[i] == target : target == 0) && support[i] > 0;
      return mine ? pressure[i] : 0.0;
    }
  };

  template <int dim>
  struct IsSolidMarkerWithFluid
  {
    const int    *kind, *body;
    const double *support;
    int           target;
    TWINFLOW_HD int operator()(int i) const
    {
      return kind[i] == ParticleKind::solid && (body ? body[i] == target : target == 0) && support[i] > 0 ? 1 : 0;
    }
  };

  /// Contribution of BCE marker a of solid `target` to the fluid force on that solid:
  ///   F_a = Σ_{b∈F} V_a V_b [ (p_b + p_a − 2p̄) ∇_b W_ba − 2μ (W'(r_ab)/r_ab) (u_b − ũ_a) ],
  /// the pairwise-antisymmetric SPH form of ∮ (−p n + μ ∂u/∂n) dS (doc/equations.md, Eq. 19–20
  /// in momentum-conserving pair form). u_b = u*_b − Δt/ρ0 ∇p_b is the end-of-step fluid
  /// velocity (Eq. 58); ũ_a = 2u^p_a − Σ_F u_b W_ab / Σ_F W_ab its no-slip mirror (Eq. 59–60).
  /// p̄ (the mean pressure of the solid's wetted markers) integrates to zero over a closed body
  /// and removes the discrete error proportional to the arbitrary pressure level.
  template <int dim>
  struct SolidForce
  {
    const Vec<dim> *x, *u, *wall_velocity;
    const int      *kind, *body, *offsets, *indices;
    const double   *V, *pressure, *support, *grad_p[dim];
    DomainBox<dim>  box;
    CubicSpline<dim> W;
    double          mu, dt, inv_rho0, p_ref;
    int             target;
    TWINFLOW_HD Vec<dim> end_of_step_velocity(int b) const
    {
      Vec<dim> v = u[b];
      for (int d = 0; d < dim; ++d)
        v[d] -= dt * inv_rho0 * grad_p[d][b];
      return v;
    }
    TWINFLOW_HD Vec<dim> operator()(int a) const
    {
      Vec<dim> f = Vec<dim>::zero();
      if (kind[a] != ParticleKind::solid || (body ? body[a] != target : target != 0) || support[a] <= 0)
        return f;
      Vec<dim> mirror = Vec<dim>::zero();
      for (int k = offsets[a]; k < offsets[a + 1]; ++k)
      {
        const int b = indices[k];
        if (kind[b] != ParticleKind::fluid)
          continue;
        const double w = W.value(geometry::norm(box.difference(x[a], x[b])));
        mirror += w * end_of_step_velocity(b);
      }
      for (int d = 0; d < dim; ++d)
        mirror[d] = 2.0 * wall_velocity[a][d] - mirror[d] / support[a];
      for (int k = offsets[a]; k < offsets[a + 1]; ++k)
      {
        const int b = indices[k];
        if (kind[b] != ParticleKind::fluid)
          continue;
        const Vec<dim> r_ba = box.difference(x[b], x[a]);
        const double   r    = geometry::norm(r_ba);
        if (r <= 0.0)
          continue;
        const double   dW   = W.derivative(r);
        const Vec<dim> ub   = end_of_step_velocity(b);
        const double   pair = V[a] * V[b];
        const double   ps   = pressure[a] + pressure[b] - 2.0 * p_ref;
        for (int d = 0; d < dim; ++d)
          f[d] += pair * (ps * dW * r_ba[d] / r - 2.0 * mu * dW / r * (ub[d] - mirror[d]));
      }
      return f;
    }
  };

  template <int dim>
  struct VecPlus
  {
    TWINFLOW_HD Vec<dim> operator()(const Vec<dim> &a, const Vec<dim> &b) const { return a + b; }
  };
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
