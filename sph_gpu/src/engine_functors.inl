// Per-particle functors of Algorithm 2 (velocity prediction, pressure Poisson, correction).
// Part of the single kernel source: included by engine.inl for both backends. Each functor
// reads the particle state through a ParticleView `p` and its neighbours through a
// NeighborView `nb` (kernel_views.h); the engine assigns those and the named scalars.
#pragma once
#include <twinflow_sph/backend.h>
#include <twinflow_sph/kernel_views.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
{
  /// ρ_i = m0 Σ_j W_ij (summation density over fluid and BCE markers) and, for BCE
  /// markers, S_a = Σ_{b∈F} W_ab (Eq. 60–65); free-surface flag for fluid particles.
  template <int dim>
  struct DensityAndSupport
  {
    ParticleView<dim> p; ///< kind, V
    NeighborView<dim> nb;
    double            m0 = 0, rho0 = 0;
    double            ratio                = 0; ///< ρ_i < ratio ρ0: free surface
    double            divergence_threshold = 0; ///< ∇·r_i below this: free surface
    double            min_neighbours = 0; ///< fewer neighbours (all kinds, itself included): free surface
    double            min_fluid_neighbours = 0; ///< fewer fluid neighbours (itself excluded): a droplet, free surface
    bool              free_surface   = true;
    double           *rho = nullptr, *support = nullptr;
    int              *surface = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      double sum = 0, fluid_sum = 0, div_r = 0;
      int    fluid_count = 0;
      bool   by_solid    = false;
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        const double w = nb.w(r);
        sum += w;
        if (p.fluid(j) && j != i)
          fluid_sum += w, ++fluid_count;
        by_solid = by_solid || p.kind[j] == ParticleKind::solid;
        if (j != i)
          div_r -= p.V[j] * geometry::dot(r, nb.grad_w(r));
      });
      rho[i]     = m0 * sum;
      support[i] = fluid_sum;
      // Free surface: a density deficit, or (where BCE markers fill the density up, e.g. where
      // the surface meets a wall) a position divergence ∇·r = −Σ V_j r_ij·∇W_ij (= dim in a full
      // support) below the threshold (Lind et al. 2012), or a sparse neighbourhood (spray
      // clusters, whose compression hides the density deficit). A droplet against a wall or in
      // a corner has its support filled with BCE markers and passes all three; with too few
      // fluid neighbours it is free surface too: otherwise it and the markers beside it form a
      // block of the pressure system with no p = 0 row, singular (pure Neumann). Not next to a
      // solid body's markers: the thin film between a body and a wall carries the pressure
      // that keeps the body off the wall (there is no contact model).
      surface[i] = (p.fluid(i) && free_surface &&
                    (rho[i] < ratio * rho0 || div_r < divergence_threshold || nb.count(i) < min_neighbours ||
                     (fluid_count < min_fluid_neighbours && !by_solid))) ? 1 : 0;
    }
  };

  /// out[i] = 1 where particle i's rows of A^G, A^L are read: fluid particles and the BCE
  /// markers with fluid in their support (Eq. 62–67 rows, the Neumann variant's gradient).
  template <int dim>
  struct NeedsOperatorRow
  {
    ParticleView<dim> p; ///< kind, support
    int              *out = nullptr;
    TWINFLOW_HD void operator()(int i) const { out[i] = p.fluid(i) || p.support[i] > 0 ? 1 : 0; }
  };

  /// Standard operators with a free surface: out[i] = 1 for a fluid particle whose support
  /// holds a free-surface particle (itself included). Its standard rows are one-sided, so they
  /// are assembled as consistent rows (Eq. 22–26).
  template <int dim>
  struct TruncatedBySurface
  {
    ParticleView<dim> p; ///< kind, surface
    NeighborView<dim> nb;
    int              *out = nullptr;
    TWINFLOW_HD void  operator()(int i) const
    {
      int truncated = 0;
      if (p.fluid(i))
        for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &) { truncated |= p.fluid(j) && p.surface[j]; });
      out[i] = truncated;
    }
  };

  /// Velocity system of Eq. 56 (fluid rows) and Eq. 62–63 (BCE rows), matrix values.
  template <int dim>
  struct VelocityMatrix
  {
    ParticleView<dim> p; ///< kind, support
    NeighborView<dim> nb;
    OperatorView<dim> A; ///< A^L
    double            inv_dt = 0, half_nu = 0;
    double           *values = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      for_each_neighbor(nb, i, [&](const int j, const int k, const Vec<dim> &r) {
        if (p.fluid(i))
          values[k] = (j == i ? inv_dt : 0.0) - half_nu * A.laplacian[k];
        else if (p.support[i] > 0)
          values[k] = j == i ? p.support[i] : (p.fluid(j) ? nb.w(r) : 0.0);
        else
          values[k] = j == i ? 1.0 : 0.0;
      });
    }
  };

  /// Right-hand side of component c of the velocity system.
  template <int dim>
  struct VelocityRhs
  {
    ParticleView<dim> p;               ///< kind, support, u, wall_velocity
    const double     *lap_u = nullptr; ///< (A^L u^n_c)_i
    int               c     = 0;
    double            inv_dt = 0, half_nu = 0;
    double            f = 0; ///< component c of the body force per unit mass
    double           *rhs = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.fluid(i))
        rhs[i] = inv_dt * p.u[i][c] + half_nu * lap_u[i] + f;
      else
        rhs[i] = p.support[i] > 0 ? 2.0 * p.wall_velocity[i][c] * p.support[i] : p.wall_velocity[i][c];
    }
  };

  /// Pressure system of Eq. 57 (fluid), p = 0 (free surface), Eq. 64–65 or 66–67 (BCE).
  template <int dim>
  struct PressureMatrix
  {
    ParticleView<dim> p; ///< kind, surface, support, normal
    NeighborView<dim> nb;
    OperatorView<dim> A;
    double            inv_rho0 = 0;
    bool              neumann  = false;
    int               pinned   = -1; ///< particle whose pressure is fixed to 0 (confined flows), or −1
    double           *values   = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      const bool identity = (p.fluid(i) && (p.surface[i] || i == pinned)) || (!p.fluid(i) && p.support[i] <= 0);
      double     diag_neumann = 0;
      for_each_neighbor(nb, i, [&](const int j, const int k, const Vec<dim> &r) {
        double v = 0;
        if (identity)
          v = j == i ? 1.0 : 0.0;
        else if (p.fluid(i))
          v = inv_rho0 * A.laplacian[k];
        else if (!neumann)
          v = j == i ? p.support[i] : (p.fluid(j) ? -nb.w(r) : 0.0);
        else if (p.fluid(j) && j != i)
        {
          // n_a · ∇p_a restricted to fluid neighbours: Σ_b (A^G_ab·n_a)(p_b − p_a) = 0
          double gn = 0;
          for (int d = 0; d < dim; ++d)
            gn += A.gradient[d][k] * p.normal[i][d];
          v = gn;
          diag_neumann -= gn;
        }
        values[k] = v;
      });
      if (!identity && !p.fluid(i) && neumann)
      {
        const int kii = diagonal_entry(nb, i);
        if (kii >= 0)
          values[kii] = diag_neumann != 0 ? diag_neumann : 1.0;
      }
    }
  };

  /// Right-hand side of the pressure system.
  template <int dim>
  struct PressureRhs
  {
    ParticleView<dim> p; ///< kind, surface, rho, support, wall_acceleration
    NeighborView<dim> nb;
    const double     *div_u = nullptr;
    double            dt = 0, rho0 = 0, alpha = 0, g[dim] = {};
    double            relaxation_time = 0; ///< time over which the density error is removed (≥ dt)
    bool              neumann         = false;
    bool              rest_density_markers = false; ///< wall and body markers: ρ_b = ρ0 in Eq. 64 (else the summation density)
    const double     *surface_pressure = nullptr; ///< SurfacePressure of the surface rows (null: 0)
    int               pinned          = -1;
    double           *rhs             = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.fluid(i))
      {
        if (p.surface[i] || i == pinned)
        {
          rhs[i] = surface_pressure && i != pinned ? surface_pressure[i] : 0.0;
          return;
        }
        // Eq. 53: ρ* = ρ^n − Δt ρ^n ∇·u*. Eq. 55/57 with the density-invariance term measured
        // against the rest density (Asai et al. 2012) — with ρ^n itself it would equal the
        // divergence term exactly. Only compression (ρ* > ρ0) is corrected: summation
        // densities below ρ0 near a free surface are a kernel deficit, not an expansion.
        const double rho_star = p.rho[i] - dt * p.rho[i] * div_u[i];
        const double deficit  = rho0 - rho_star < 0.0 ? rho0 - rho_star : 0.0;
        // The density error is removed over relaxation_time (Δt in Eq. 55 as written: ρ0/Δt²).
        rhs[i] = alpha * deficit / (rho0 * dt * relaxation_time) + (1.0 - alpha) * div_u[i] / dt;
        return;
      }
      if (p.support[i] <= 0 || neumann)
      {
        rhs[i] = 0;
        return;
      }
      // (g − a^p)·Σ_b ρ_b r_ab W_ab, Eq. 64. Wetted walls, consistent operators: ρ_b = ρ0, the fluid is
      // incompressible and the summation density of the top rows is a kernel deficit (0.83 ρ0 on
      // the surface row), not the fluid's: with it the markers beside the surface sat below the
      // hydrostatic field and the contact line of still water sank from the first step. The
      // standard operators' surface rows are one-sided anyway; ρ0 made their jitter worse
      // (doc/benchmarks.md, "Still water at rest"). A body's markers too (2026-12-07): at a
      // floating body's waterline the same deficit left its markers low, and the heaving disk
      // floated 4.2 % of r off Archimedes (0.6 % with ρ0; doc/benchmarks.md, "Wall contact").
      const bool rest_density = rest_density_markers;
      double     s            = 0;
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (!p.fluid(j) || j == i)
          return;
        const double w = nb.w(r);
        for (int d = 0; d < dim; ++d)
          s += (g[d] - p.wall_acceleration[i][d]) * (rest_density ? rho0 : p.rho[j]) * r[d] * w;
      });
      rhs[i] = s;
    }
  };

  /// Pressure of a free-surface particle. The free surface lies half a spacing d = Δx/2 beyond
  /// the centres of the surface particles (each particle holds a volume Δx^dim), so p = 0 on it
  /// gives the particle p_s = d ∂p/∂n, the derivative of the pressure into the liquid. It is
  /// read from the pressure of the last step (the α = 0 one), differentiated with this step's
  /// consistent gradient and averaged (Shepard, V_j W_ij) over the interior fluid neighbours;
  /// n points to the centroid of all neighbours (the BCE markers included: at the contact line
  /// the wall continues the liquid). Then
  ///   p_s = d min(ρ0 |g|, κ ∂p/∂n),  and 0 where ∂p/∂n ≤ 0 or no interior neighbour is near
  /// (spray, droplets, a sheet of surface particles): hydrostatic at most (an impact's surge is
  /// not carried into the surface value), zero in free fall (∇p = 0 beneath) and never
  /// suction. κ = 1.1 takes a liquid at rest as hydrostatic: next to a wall the discrete
  /// gradient of the hydrostatic field reads 1-3 % low, and that unevenness along the surface
  /// drove a sloshing mode (still water 2.1e-3 m/s after 2 s with κ = 1, 8e-5 with 1.1).
  /// With p = 0 at the centres (the paper's form) the whole field under a free surface sat
  /// ρ0 |g| Δx/2 low: a held, half-submerged disk carried 12.6 % (Δx = R/6) and 7.1 % (R/12)
  /// less than its buoyancy, 1.6 / 1.7 % with this surface (doc/benchmarks.md).
  template <int dim>
  struct SurfacePressure
  {
    static constexpr double kappa = 1.1; ///< band read as hydrostatic (above)
    ParticleView<dim> p;                ///< kind, surface, V
    NeighborView<dim> nb;
    Components<dim>   grad_p;           ///< ∇p^n at this step's positions
    double            d     = 0;        ///< surface particle's centre to the free surface, Δx/2
    double            p_max = 0;        ///< ρ0 |g| d
    double           *out   = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      out[i] = 0;
      if (!p.fluid(i) || !p.surface[i])
        return;
      Vec<dim> inward = Vec<dim>::zero(), gp = Vec<dim>::zero();
      double   weight = 0;
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (j == i)
          return;
        const double vw = p.V[j] * nb.w(r);
        inward -= vw * r;
        if (p.fluid(j) && !p.surface[j])
        {
          weight += vw;
          for (int k = 0; k < dim; ++k)
            gp[k] += vw * grad_p[k][j];
        }
      });
      const double len = geometry::norm(inward);
      if (len <= 0 || weight <= 0)
        return;
      double dpdn = 0;
      for (int k = 0; k < dim; ++k)
        dpdn += gp[k] * inward[k];
      const double v = d * kappa * dpdn / (weight * len);
      out[i]         = v < 0 ? 0.0 : (v > p_max ? p_max : v);
    }
  };

  /// Pressure force of the standard operators: the pair-antisymmetric form of Eq. 19,
  ///   ∇p_i = Σ_j V_j (p_i + p_j) ∇_i W_ij = (A^G p)_i − 2 p_i A^G_ii,
  /// which is the negative adjoint of the Eq. 19 divergence in the volume-weighted inner
  /// product (Σ_i V_i u_i·∇p_i = −Σ_i V_i p_i ∇·u_i), so the projection cannot feed kinetic
  /// energy, and its pair terms are antisymmetric (V_i V_j weighted: momentum conserving).
  /// Where the support is full and symmetric, A^G_ii = −Σ_j V_j ∇_i W_ij vanishes and both
  /// forms agree. The difference form
  /// itself pulls a particle of raised pressure towards its sparse side (free surface:
  /// large V_j) — a compression feedback that breaks still water up.
  template <int dim>
  struct PairwisePressureGradient
  {
    ParticleView<dim> p; ///< kind, pressure
    NeighborView<dim> nb;
    OperatorView<dim> A;
    double           *grad_p[dim] = {};
    const int        *corrected = nullptr; ///< consistent rows (TruncatedBySurface): left as they are
    TWINFLOW_HD void operator()(int i) const
    {
      if (corrected && corrected[i])
        return;
      const int kii = p.fluid(i) ? diagonal_entry(nb, i) : -1;
      if (kii >= 0)
        for (int d = 0; d < dim; ++d)
          grad_p[d][i] -= 2.0 * p.pressure[i] * A.gradient[d][kii];
    }
  };

  /// Eq. 58 and the position update for fluid; BCE markers take the wall velocity.
  template <int dim>
  struct CorrectAndMove
  {
    ParticleView<dim> p; ///< kind, wall_velocity
    Components<dim>   grad_p;
    Components<dim>   grad_q; ///< gradient of the position-only pressure (null: none)
    DomainBox<dim>    box;
    double            dt = 0, inv_rho0 = 0, margin = 0;
    int               open_face = -1; ///< EngineSettings::open_face: no wall there, nothing to keep out of
    Vec<dim>         *x = nullptr, *u = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (!p.fluid(i))
      {
        u[i] = p.wall_velocity[i];
        return;
      }
      for (int d = 0; d < dim; ++d)
        u[i][d] -= dt * inv_rho0 * grad_p[d][i];
      for (int d = 0; d < dim; ++d)
        x[i][d] += dt * u[i][d] - (grad_q[0] ? dt * dt * inv_rho0 * grad_q[d][i] : 0.0);
      // Last-resort no-penetration of the domain walls: a fluid particle never enters the BCE
      // layers (whose pressure rows cannot push it back once inside). An open face has no layers:
      // fluid crosses it freely (the host removes it beyond, source/sph/open_boundary.cc).
      for (int d = 0; d < dim; ++d)
        if (!box.periodic[d])
        {
          if (x[i][d] < box.lower[d] + margin && open_face != 2 * d)
          {
            x[i][d] = box.lower[d] + margin;
            u[i][d] = u[i][d] < 0 ? 0.0 : u[i][d];
          }
          else if (x[i][d] > box.upper[d] - margin && open_face != 2 * d + 1)
          {
            x[i][d] = box.upper[d] - margin;
            u[i][d] = u[i][d] > 0 ? 0.0 : u[i][d];
          }
        }
      x[i] = box.wrap(x[i]);
    }
  };

  /// Shepard extrapolation of the fluid velocity to BCE markers, ũ_a = Σ_F u_b W_ab / Σ_F W_ab
  /// (Eq. 60); fluid particles and markers without fluid neighbours get their own velocity.
  template <int dim>
  struct ExtrapolateToMarkers
  {
    ParticleView<dim> p; ///< kind, support, u
    NeighborView<dim> nb;
    Vec<dim>         *out = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.fluid(i) || p.support[i] <= 0)
      {
        out[i] = p.u[i];
        return;
      }
      Vec<dim> s = Vec<dim>::zero();
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (!p.fluid(j) || j == i)
          return;
        const double w = nb.w(r);
        for (int d = 0; d < dim; ++d)
          s[d] += w * p.u[j][d];
      });
      for (int d = 0; d < dim; ++d)
        out[i][d] = s[d] / p.support[i];
    }
  };

  /// Velocity seen by the continuity source of the pressure equation. Fluid: u*. BCE markers:
  /// the fluid's extrapolated ũ*_a = 2u^p_a − u_a (Eq. 59–60), with the normal component of
  /// the fluid's *approach* velocity at t^n, (ũ^n_a − u^p_a)·n, mirrored. The force-balance
  /// pressure rows (Eq. 64) already carry the wall's reaction to ρ(g − a^p); mirroring all of
  /// u* would count it twice (12 % hydrostatic error), mirroring nothing lets particles that
  /// move towards the wall pass through it. With wetted_walls, motion away from a wall marker
  /// is mirrored too at a wetted marker (every wall marker; not solid bodies' markers),
  /// up to |g| Δt: liquid pressed on a wall cannot creep off it, and nothing else in the
  /// pressure equation keeps it there (still water lifted off the floor at a constant
  /// 8e-5 m/s², doc/benchmarks.md); the wall holds it back with at most the suction of one
  /// smoothing length of head (ρ|g|h), so liquid that is thrown off a wall (a jet, the splash)
  /// separates. Uncapped, the mirroring sucked the splash of the coarse paper dam break back
  /// onto the walls: its energy rose 4-fold. Where the fluid next to the wall has a free
  /// surface it separates freely.
  template <int dim>
  struct ContinuityVelocity
  {
    ParticleView<dim> p;                  ///< kind, support, surface, u, wall_velocity, normal
    NeighborView<dim> nb;
    bool              wetted_walls = false; ///< EngineSettings::wetted_walls
    double            max_separation = 0;   ///< largest mirrored motion away from a wetted marker, |g| Δt [m/s]
    const Vec<dim>   *approach = nullptr; ///< ũ^n (ExtrapolateToMarkers of u^n)
    Vec<dim>         *out      = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.fluid(i))
        out[i] = p.u[i];
      else if (p.support[i] > 0)
      {
        double un = 0, nn = 0;
        for (int d = 0; d < dim; ++d)
        {
          un += (approach[i][d] - p.wall_velocity[i][d]) * p.normal[i][d];
          nn += p.normal[i][d] * p.normal[i][d];
        }
        un = nn > 0 ? un / nn : 0.0;
        // Every wall marker is wetted, also where its support reaches the free surface (the contact
        // line): the |g| Δt cap lets a splash leave a wall, and without the hold there the wall-side
        // particles of still water's top two rows drifted off the walls at a growing speed until one
        // was flagged free surface for a step (t = 9.87 s: a 0.013 m/s kick; doc/benchmarks.md).
        const bool   wetted = wetted_walls && p.kind[i] == ParticleKind::wall;
        // motion into the wall; away from it only if wetted, and then at most |g| Δt
        const double toward = un < 0 ? un : (wetted ? (un < max_separation ? un : max_separation) : 0.0);
        for (int d = 0; d < dim; ++d)
          out[i][d] = 2.0 * p.wall_velocity[i][d] - p.u[i][d] - 2.0 * toward * p.normal[i][d];
      }
      else
        out[i] = p.wall_velocity[i];
    }
  };

  /// Fickian particle shifting (Lind et al. 2012, Skillen et al. 2013): interior fluid particles
  /// move by δr = −D ∇C, ∇C_i = Σ_j V_j ∇_i W_ij, D = A h |u_i| Δt (A = coefficient); it keeps
  /// the distribution near-isotropic, which the consistent operators need in violent flows.
  /// Free-surface particles are not shifted (their ∇C points out of the fluid). Positions are
  /// taken at the start of the step (the neighbour lists are those of the step: nb.x).
  /// With a velocity floor U_f > 0, D = A h max(|u_i|, U_f) Δt: shifting also acts at rest,
  /// where it damps the row-pairing mode of the consistent operators next to walls (doc/
  /// benchmarks.md, "Still water: the growing modes"); particles with a free-surface
  /// neighbour are then not shifted either (∇C there points out of the fluid: at rest it
  /// would pull the second row into the first).
  template <int dim>
  struct ShiftingDisplacement
  {
    ParticleView<dim> p;  ///< kind, surface, V, u
    NeighborView<dim> nb; ///< positions at the start of the step
    double            coefficient = 0, dt = 0, max_shift = 0;
    double            u_min = 0; ///< velocity floor U_f
    Vec<dim>         *x     = nullptr;
    Vec<dim>         *moved = nullptr; ///< the displacement applied (null: not wanted)
    TWINFLOW_HD void operator()(int i) const
    {
      if (moved)
        moved[i] = Vec<dim>::zero();
      if (!p.fluid(i) || p.surface[i])
        return;
      if (u_min > 0 && any_neighbor(nb, i, [&](const int j) { return p.surface[j] && p.fluid(j); }))
        return;
      Vec<dim> gradC = Vec<dim>::zero();
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (j == i)
          return;
        const Vec<dim> g = nb.grad_w(r);
        for (int d = 0; d < dim; ++d)
          gradC[d] += p.V[j] * g[d];
      });
      const double un = geometry::norm(p.u[i]);
      const double D  = coefficient * nb.W.h * (un > u_min ? un : u_min) * dt;
      Vec<dim>     dr;
      double       len = 0;
      for (int d = 0; d < dim; ++d)
      {
        dr[d] = -D * gradC[d];
        len += dr[d] * dr[d];
      }
      len                = sqrt(len);
      const double scale = len > max_shift ? max_shift / len : 1.0;
      for (int d = 0; d < dim; ++d)
        x[i][d] += scale * dr[d];
      x[i] = nb.box.wrap(x[i]);
      if (moved)
        moved[i] = scale * dr;
    }
  };

  /// The velocity of a shifted particle carried to its new position, u_i + (δx_i·∇)u_i (the ALE
  /// correction of particle shifting), with the step's gradient rows in the difference form (the
  /// off-diagonal entries). Experimental: EngineSettings::shifting_velocity_correction.
  template <int dim>
  struct ShiftVelocity
  {
    ParticleView<dim>  p; ///< kind, u
    NeighborView<dim>  nb;
    OperatorView<dim>  A;
    const Vec<dim>    *moved = nullptr; ///< ShiftingDisplacement::moved
    Vec<dim>          *out   = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      out[i] = p.u[i];
      const Vec<dim> dx = moved[i];
      if (!p.fluid(i) || geometry::norm(dx) == 0)
        return;
      for_each_neighbor(nb, i, [&](const int j, const int k, const Vec<dim> &) {
        if (j == i)
          return;
        double w = 0;
        for (int d = 0; d < dim; ++d)
          w += A.gradient[d][k] * dx[d];
        out[i] += w * (p.u[j] - p.u[i]);
      });
    }
  };

  /// ∇p_i = 0 at a strict local pressure maximum (p_i > 0 above every neighbour, markers
  /// included) of a fluid particle: there the one-sided consistent gradient ≈ −p_i G_i Σ V_j ∇W_ij
  /// points out of the water and pulls the particle into its neighbours (the spray kicks of
  /// colliding splash sheets); the gradient of a smooth field at its maximum is zero. The same at
  /// a strict local minimum (p_i < 0 below every neighbour): the tear of two separating streams
  /// next to the surface (−50 kPa at the second splash of the H/80 dam break) pushed the particle
  /// out of the water by 8.5 m/s in one step. Not next to a solid body, whose force is the
  /// reaction of its neighbours' pressure forces.
  template <int dim>
  struct PeakGradientLimiter
  {
    ParticleView<dim> p; ///< kind, surface, pressure
    NeighborView<dim> nb;
    double           *grad_p[dim] = {};
    const int        *rows = nullptr; ///< only the rows with rows[i] ≠ 0 (the standard operators' consistent rows; null: all)
    TWINFLOW_HD void operator()(int i) const
    {
      if (!p.fluid(i) || p.surface[i] || p.pressure[i] == 0 || (rows && !rows[i]))
        return;
      // a peak (p_i > 0 above every neighbour) or a trough (p_i < 0 below every neighbour)
      const double sign = p.pressure[i] > 0 ? 1.0 : -1.0;
      if (any_neighbor(nb, i, [&](const int j) {
            return (j != i && sign * p.pressure[j] >= sign * p.pressure[i]) || p.kind[j] == ParticleKind::solid;
          }))
        return;
      for (int d = 0; d < dim; ++d)
        grad_p[d][i] = 0;
    }
  };

  /// Exact equality of two positions (thrust::equal: did a pass move any particle).
  template <int dim>
  struct SamePosition
  {
    TWINFLOW_HD bool operator()(const Vec<dim> &a, const Vec<dim> &b) const
    {
      for (int d = 0; d < dim; ++d)
        if (a[d] != b[d])
          return false;
      return true;
    }
  };

  /// Pair separation: a fluid particle closer than d_min to fluid neighbours moves by
  /// Σ_j ½ (d_min − r_ij) e_ij, e_ij = (x_i − x_j)/r_ij, from the positions nb was built for
  /// (an isolated pair ends exactly d_min apart; the shifts of a pair are opposite, so the
  /// centre of mass stays). Velocities are not touched. Pairs form at the free surface, where
  /// p = 0 gives no pressure force; any pair counts, not only one with a free-surface particle of
  /// this step: a pair formed at the surface and swept into the water in the same step is
  /// interior when this step looks at it, and its pressure row answers the pair's local
  /// compression with 10^5 Pa (paper dam break, t = 2.4285 s: a pair 0.35 Δx apart, both interior,
  /// 146 and 155 kPa; the one-sided gradient created 12.5 J/m of kinetic energy within 10 Δx in
  /// one step and threw one particle out at 14.7 m/s). Water that keeps its volume has no pair
  /// closer than ½ Δx, so this touches nothing else.
  template <int dim>
  struct PairSeparation
  {
    ParticleView<dim> p;  ///< kind
    NeighborView<dim> nb; ///< positions before the separation
    double            min_distance = 0;
    Vec<dim>         *x            = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (!p.fluid(i))
        return;
      Vec<dim> dr    = Vec<dim>::zero();
      bool     moved = false;
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (j == i || !p.fluid(j))
          return;
        const double d = geometry::norm(r);
        if (d >= min_distance)
          return;
        // coincident particles: split them along the first axis, by index
        const double s = d > 0 ? 0.5 * (min_distance - d) / d : (i < j ? -0.5 : 0.5) * min_distance;
        for (int k = 0; k < dim; ++k)
          dr[k] += d > 0 ? s * r[k] : (k == 0 ? s : 0.0);
        moved = true;
      });
      // not next to a solid body: its markers keep fluid out (KeepOutOfSolids), and the
      // floating disk settled 2.4 % of R low when the film around it was spread as well
      if (moved && !any_neighbor(nb, i, [&](const int j) { return p.kind[j] == ParticleKind::solid; }))
      {
        for (int k = 0; k < dim; ++k)
          x[i][k] = nb.x[i][k] + dr[k];
        x[i] = nb.box.wrap(x[i]);
      }
    }
  };

  /// Pressure noise of an interior fluid particle (not free surface): the squared deviation of
  /// p_i from its Shepard average over the fluid neighbours, p̄_i = Σ_F p_j V_j W_ij / Σ_F V_j W_ij;
  /// 0 for other particles. The RMS over the interior particles measures the particle-scale
  /// pressure oscillation (checkerboard, density-deficit noise) independently of the mean field.
  template <int dim>
  struct PressureNoise
  {
    ParticleView<dim> p; ///< kind, surface, pressure, V
    NeighborView<dim> nb;
    TWINFLOW_HD double operator()(int i) const
    {
      if (!p.fluid(i) || p.surface[i])
        return 0.0;
      double num = 0, den = 0;
      for_each_neighbor(nb, i, [&](const int j, int, const Vec<dim> &r) {
        if (!p.fluid(j))
          return;
        const double w = p.V[j] * nb.w(r);
        num += w * p.pressure[j];
        den += w;
      });
      const double d = den > 0 ? p.pressure[i] - num / den : 0.0;
      return d * d;
    }
  };

  /// 1 for interior fluid particles (not free surface), else 0.
  template <int dim>
  struct InteriorFluid
  {
    ParticleView<dim> p; ///< kind, surface
    TWINFLOW_HD int operator()(int i) const { return p.fluid(i) && !p.surface[i] ? 1 : 0; }
  };

  /// |u_i| for fluid particles, 0 otherwise (max reduction).
  template <int dim>
  struct FluidSpeed
  {
    ParticleView<dim> p; ///< kind, u
    TWINFLOW_HD double operator()(int i) const { return p.fluid(i) ? geometry::norm(p.u[i]) : 0.0; }
  };

  /// Energy of fluid particle i for the step's energy budget (StepReport::budget): kinetic
  /// ½ m0 |u_i|² (potential: false) or potential −m0 g·x_i (potential: true); 0 for markers.
  template <int dim>
  struct FluidEnergy
  {
    ParticleView<dim> p; ///< kind
    const Vec<dim>   *u = nullptr, *x = nullptr;
    double            m0 = 0, g[dim] = {};
    bool              potential = false;
    TWINFLOW_HD double operator()(int i) const
    {
      if (!p.fluid(i))
        return 0.0;
      double e = 0;
      for (int d = 0; d < dim; ++d)
        e += potential ? -m0 * g[d] * x[i][d] : 0.5 * m0 * u[i][d] * u[i][d];
      return e;
    }
  };

  /// ΔPE −m0 g·δx_i of fluid particle i's density-error displacement δx_i = −Δt²/ρ0 ∇q_i
  /// (EnergyBudget::density_correction); 0 for markers.
  template <int dim>
  struct DisplacementEnergy
  {
    ParticleView<dim> p; ///< kind
    Components<dim>   grad_q;
    double            scale = 0; ///< Δt²/ρ0
    double            m0 = 0, g[dim] = {};
    TWINFLOW_HD double operator()(int i) const
    {
      if (!p.fluid(i))
        return 0.0;
      double e = 0;
      for (int d = 0; d < dim; ++d)
        e += m0 * g[d] * scale * grad_q[d][i];
      return e;
    }
  };

  /// Work of the body force over the prediction, m0 Δt a·(u^n + u*)/2 (a = gravity + body
  /// force), for fluid particle i: the part of ΔKE of the prediction that is not viscous.
  template <int dim>
  struct BodyForceWork
  {
    ParticleView<dim> p; ///< kind, u (= u*)
    const Vec<dim>   *u_old = nullptr;
    double            m0 = 0, dt = 0, a[dim] = {};
    TWINFLOW_HD double operator()(int i) const
    {
      if (!p.fluid(i))
        return 0.0;
      double w = 0;
      for (int d = 0; d < dim; ++d)
        w += a[d] * 0.5 * (u_old[i][d] + p.u[i][d]);
      return m0 * dt * w;
    }
  };

} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
