// Fluid force on fixed solids (BCE markers of kind `solid`), see doc/equations.md "Forces on solids".
// Part of the single kernel source: included by engine.inl for both backends.
#pragma once
#include <twinflow_sph/backend.h>
#include <twinflow_sph/kernel_views.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
{
  /// Pressure of a solid's markers that see fluid (for the reference level p̄_s).
  template <int dim>
  struct SolidMarkerPressure
  {
    ParticleView<dim> p; ///< kind, body, support, pressure
    int               target = 0;
    TWINFLOW_HD double operator()(int i) const
    {
      return p.marker_of(i, target) && p.support[i] > 0 ? p.pressure[i] : 0.0;
    }
  };

  /// 1 for a marker of solid `target` that sees fluid (their count, for p̄_s).
  template <int dim>
  struct IsSolidMarkerWithFluid
  {
    ParticleView<dim> p; ///< kind, body, support
    int               target = 0;
    TWINFLOW_HD int operator()(int i) const { return p.marker_of(i, target) && p.support[i] > 0 ? 1 : 0; }
  };

  /// 1 if marker i of solid `target` has a free-surface fluid neighbour (its wetted surface is
  /// then open: the body pierces the free surface).
  template <int dim>
  struct MarkerMeetsFreeSurface
  {
    ParticleView<dim> p; ///< kind, body, surface
    NeighborView<dim> nb;
    int               target = 0;
    TWINFLOW_HD int operator()(int a) const
    {
      if (!p.marker_of(a, target))
        return 0;
      return any_neighbor(nb, a, [&](const int b) { return p.fluid(b) && p.surface[b]; }) ? 1 : 0;
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
    ParticleView<dim> p; ///< x, u, wall_velocity, kind, body, V, pressure, support
    NeighborView<dim> nb;
    Components<dim>   grad_p;
    double            mu = 0, dt = 0, inv_rho0 = 0;
    double            p_ref  = 0; ///< p̄_s
    int               target = 0;
    TWINFLOW_HD Vec<dim> end_of_step_velocity(int b) const
    {
      Vec<dim> v = p.u[b];
      for (int d = 0; d < dim; ++d)
        v[d] -= dt * inv_rho0 * grad_p[d][b];
      return v;
    }
    TWINFLOW_HD Vec<dim> operator()(int a) const
    {
      Vec<dim> f = Vec<dim>::zero();
      if (!p.marker_of(a, target) || p.support[a] <= 0)
        return f;
      Vec<dim> mirror = Vec<dim>::zero();
      for_each_neighbor(nb, a, [&](const int b, int, const Vec<dim> &r_ab) {
        if (p.fluid(b))
          mirror += nb.w(r_ab) * end_of_step_velocity(b);
      });
      for (int d = 0; d < dim; ++d)
        mirror[d] = 2.0 * p.wall_velocity[a][d] - mirror[d] / p.support[a];
      for_each_neighbor(nb, a, [&](const int b, int, const Vec<dim> &r_ab) {
        if (!p.fluid(b))
          return;
        const Vec<dim> r_ba = -r_ab; // exact: the minimum image is antisymmetric
        const double   r    = geometry::norm(r_ba);
        if (r <= 0.0)
          return;
        const double   dW   = nb.W.derivative(r);
        const Vec<dim> ub   = end_of_step_velocity(b);
        const double   pair = p.V[a] * p.V[b];
        const double   ps   = p.pressure[a] + p.pressure[b] - 2.0 * p_ref;
        for (int d = 0; d < dim; ++d)
          f[d] += pair * (ps * dW * r_ba[d] / r - 2.0 * mu * dW / r * (ub[d] - mirror[d]));
      });
      return f;
    }
  };

  /// Torque of marker a's force about `centre`: (x_a − c) × F_a (3 components; 2D: z only).
  template <int dim>
  struct SolidTorque
  {
    SolidForce<dim> force;
    double          centre[3] = {0, 0, 0};
    TWINFLOW_HD Vec<3> operator()(int a) const
    {
      const Vec<dim> f = force(a);
      Vec<3>         r = Vec<3>::zero(), F = Vec<3>::zero();
      for (int d = 0; d < dim; ++d)
      {
        r[d] = force.p.x[a][d] - centre[d];
        F[d] = f[d];
      }
      return geometry::cross(r, F);
    }
  };

  /// The motions of move_solids on the device.
  struct MotionsView
  {
    const MarkerMotion *motion = nullptr;
    int                 count  = 0;
  };

  /// Rigid motion of the markers of the solids in `motions` (MarkerMotion, engine.h).
  template <int dim>
  struct MoveMarkers
  {
    ParticleView<dim> p; ///< kind, body
    MotionsView       motions;
    Vec<dim>         *x = nullptr, *normal = nullptr, *wall_velocity = nullptr, *wall_acceleration = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.kind[i] != ParticleKind::solid)
        return;
      const int b = p.body ? p.body[i] : 0;
      for (int k = 0; k < motions.count; ++k)
      {
        const MarkerMotion &m = motions.motion[k];
        if (m.body != b)
          continue;
        Vec<3> r0 = Vec<3>::zero(), n0 = Vec<3>::zero(), r = Vec<3>::zero(), n = Vec<3>::zero();
        for (int d = 0; d < dim; ++d)
          r0[d] = x[i][d] - m.from[d], n0[d] = normal[i][d];
        for (int a = 0; a < 3; ++a)
          for (int c = 0; c < 3; ++c)
            r[a] += m.rotation[a][c] * r0[c], n[a] += m.rotation[a][c] * n0[c];
        const Vec<3> w{{m.angular_velocity[0], m.angular_velocity[1], m.angular_velocity[2]}};
        const Vec<3> al{{m.angular_acceleration[0], m.angular_acceleration[1], m.angular_acceleration[2]}};
        const Vec<3> wr = geometry::cross(w, r), ar = geometry::cross(al, r), wwr = geometry::cross(w, wr);
        for (int d = 0; d < dim; ++d)
        {
          x[i][d]                 = m.to[d] + r[d];
          normal[i][d]            = n[d];
          wall_velocity[i][d]     = m.velocity[d] + wr[d];
          wall_acceleration[i][d] = m.acceleration[d] + ar[d] + wwr[d];
        }
        return;
      }
    }
  };

  /// Last-resort no-penetration of the moved bodies (MarkerMotion::shape, Engine::move_solids).
  template <int dim>
  struct KeepOutOfSolids
  {
    ParticleView<dim> p; ///< kind
    MotionsView       motions;
    double            margin = 0;
    Vec<dim>         *x = nullptr, *u = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (!p.fluid(i))
        return;
      for (int k = 0; k < motions.count; ++k)
      {
        const MarkerMotion &m = motions.motion[k];
        if (m.shape == 0)
          continue;
        double r[3] = {0, 0, 0}, q[2] = {0, 0};
        for (int d = 0; d < dim; ++d)
          r[d] = x[i][d] - m.to[d];
        for (int a = 0; a < 2; ++a) // body-frame x–y of the point (Rᵀ r)
          q[a] = m.orientation[0][a] * r[0] + m.orientation[1][a] * r[1] + m.orientation[2][a] * r[2];
        double phi = 0, n[2] = {0, 0};
        if (m.shape == 1)
        {
          const double rho = sqrt(q[0] * q[0] + q[1] * q[1]);
          phi = rho - m.half_size[0];
          n[0] = rho > 0 ? q[0] / rho : 1.0, n[1] = rho > 0 ? q[1] / rho : 0.0;
        }
        else
        {
          const double e0 = fabs(q[0]) - m.half_size[0], e1 = fabs(q[1]) - m.half_size[1];
          if (e0 > 0 || e1 > 0)
          {
            const double o0 = e0 > 0 ? e0 : 0.0, o1 = e1 > 0 ? e1 : 0.0, len = sqrt(o0 * o0 + o1 * o1);
            phi = len, n[0] = (q[0] < 0 ? -o0 : o0) / len, n[1] = (q[1] < 0 ? -o1 : o1) / len;
          }
          else if (e0 > e1)
            phi = e0, n[0] = q[0] < 0 ? -1.0 : 1.0;
          else
            phi = e1, n[1] = q[1] < 0 ? -1.0 : 1.0;
        }
        if (phi >= margin)
          continue;
        // world normal and the push out to the margin
        double nw[3];
        for (int a = 0; a < 3; ++a)
          nw[a] = m.orientation[a][0] * n[0] + m.orientation[a][1] * n[1];
        for (int d = 0; d < dim; ++d)
          x[i][d] += (margin - phi) * nw[d], r[d] = x[i][d] - m.to[d];
        // body velocity there, v + ω × r, and no relative velocity into the body
        const double us[3] = {m.velocity[0] + m.angular_velocity[1] * r[2] - m.angular_velocity[2] * r[1],
                              m.velocity[1] + m.angular_velocity[2] * r[0] - m.angular_velocity[0] * r[2],
                              m.velocity[2] + m.angular_velocity[0] * r[1] - m.angular_velocity[1] * r[0]};
        double rel = 0;
        for (int d = 0; d < dim; ++d)
          rel += (u[i][d] - us[d]) * nw[d];
        if (rel < 0)
          for (int d = 0; d < dim; ++d)
            u[i][d] -= rel * nw[d];
      }
    }
  };

  template <int dim>
  struct VecPlus
  {
    TWINFLOW_HD Vec<dim> operator()(const Vec<dim> &a, const Vec<dim> &b) const { return a + b; }
  };
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
