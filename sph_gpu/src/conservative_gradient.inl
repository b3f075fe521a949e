// The conservative consistent gradient (single source for the CPU and CUDA backends; included
// by operators.inl). See operators.h, make_gradient_conservative().
//
// A^G of the fluid rows is rewritten from pair coefficients a_ij = V_i A^G_ij that are
// antisymmetric over fluid pairs, a_ji = −a_ij, with the diagonal of the sum form,
// (A^G p)_i = Σ_j a_ij (p_i + p_j) / V_i. Its divergence partner, the difference form
// Σ_j a_ij·(u_j − u_i) / V_i, is then its negative adjoint for any such a_ij:
// ⟨u, A^G p⟩_V + ⟨p, D u⟩_V = Σ_{fluid i, marker m} a_im·(u_i p_m + p_i u_m), the walls only.
// The a_ij are the smallest correction c_ij (least squares) of the antisymmetric part of the
// consistent pair, a⁰_ij = ½ V_i V_j (G_i + G_j) ∇_i W_ij (Eq. 22), that satisfies on each fluid
// row i
//   R1_i: Σ_j a_ij = 0                         (off the free surface: a constant has no gradient;
//                                               there sum and difference forms agree)
//   R2_i: Σ_j a_ij ⊗ (x_j − x_i + s_i) = V_i I  (exact for linear fields)
// with s_i = 0 but on a free-surface row, where s_i = −2 d n_i: there the sum form is exact for
// the fields that vanish d above the particle, as the free-surface offset p_s = d ∂p/∂n has it
// (the boundary closure: with p_s = 0 no antisymmetric pair of equal volumes is exact there).
// A pair with a BCE marker appears in the fluid row only, so its coefficient is free.
// The norm is not V near the free surface: on the rows with a free-surface particle in their
// support the quadrature weight ω_i = V_i + δω_i is an unknown of the least squares too (R2
// reads ... = ω_i I, and A^G = a / ω). With ω = V everywhere the closure leaves two
// incompatibilities per surface column (1D: 2m − 1 constraints on 2m − 3 pairs in the top m
// rows) that only a flux through the whole depth resolves: at rest the corrections were
// 1.2-1.9 × the coefficients everywhere, growing with the column (doc/benchmarks.md, "The
// surface norm"); with the two top rows' weights free, the top three rows close it (1D:
// ω = (1 + β, 1 − β) V, β the kernel's second-neighbour coefficient), as the boundary weights
// of a diagonal-norm SBP operator do. ω/V is kept in [kWeightFloor, 1/kWeightFloor]. How free a
// row's weight is, f_i ∈ [0, 1] (penalty δω²/f), follows the surface particles in its support
// continuously (FreeWeightF): a 0/1 flag made the multipliers jump whenever a surface flag
// flickered, and the splash kicked. With the
// Lagrange multipliers y_i = (λ_i, M_i), c_ij = w_ij [λ_i − λ_j + M_i (r_ji + s_i)/h + M_j (r_ji − s_j)/h]
// (marker: w_im [λ_i + M_i (r_mi + s_i)/h]), δω_i = −(f_i/h) tr M_i, and the multipliers solve
// (K + μ) y = −R(a⁰), K = J W Jᵀ + E F Eᵀ symmetric positive semi-definite (E: the weights' columns),
// by conjugate gradients preconditioned by block Jacobi plus, on the CPU backend, a coarse space
// of the smooth modes K nearly annihilates (conservative_coarse.inl);
// μ_i > 0 only on rows too thinly supported to carry the constraints (Geometry::mu).
#include <thrust/inner_product.h>
#include <thrust/transform.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace conservative_detail
  {
    using operators_detail::Pair;

    /// Unknowns (and constraints) per particle: λ (dim), M (dim × dim).
    template <int dim>
    constexpr int kUnknowns = dim + dim * dim;

    /// ω_i / V_i is kept in [kWeightFloor, 1 / kWeightFloor] (the Martin & Moyce collapse at
    /// CFL 1 asked ω < 0 at its toe from step 25 and diverged at step 31; clamped it gains 0.06 %).
    constexpr double kWeightFloor = 0.5;

    /// The coarse cells' size over the kernel support (conservative_coarse.inl).
    constexpr double kCoarseCell = 1.0;

    /// What a particle's row must satisfy.
    enum RowConstraints : int { none = 0, linear = 1, linear_and_constant = 2 };

    template <int dim>
    struct Geometry
    {
      NeighborView<dim>   nb;
      const double       *V       = nullptr;
      const Tensor2<dim> *G       = nullptr;
      const int          *kind    = nullptr;
      const int          *rows    = nullptr; ///< RowConstraints of each particle
      /// −2 d n_i for a free-surface row (n_i outward, d the centre's depth below the free
      /// surface): its linear fields vanish at x_i + d n_i; zero elsewhere
      const geometry::Vec<dim> *shift = nullptr;
      double              inv_h   = 1.0;
      /// f_i ∈ [0, 1]: how free the row's weight ω_i is (FreeWeightF: the free-surface particles
      /// in its support, kernel-weighted, so f moves continuously as they come and go)
      const double       *free_weight = nullptr;

      TWINFLOW_HD double freedom(const int i) const
      {
        return free_weight && rows[i] != none ? free_weight[i] : 0.0;
      }
      TWINFLOW_HD bool weight_free(const int i) const { return freedom(i) > 0; }
      /// δω_i = −f_i Eᵢᵀ y = −(f_i/h) Σ_d M_i,dd of the multipliers y: the least squares
      /// minimise Σ|c|² + Σ δω_i² / f_i (with a unit weight, 4 or 16 gave the same ω, which the
      /// local constraints determine)
      TWINFLOW_HD double delta_weight(const int i, const double *y) const
      {
        if (!weight_free(i))
          return 0.0;
        double t = 0;
        for (int d = 0; d < dim; ++d)
          t += y[kUnknowns<dim> * i + dim + dim * d + d];
        return -t * inv_h * free_weight[i];
      }

      TWINFLOW_HD bool fluid(const int j) const { return kind[j] == ParticleKind::fluid; }

      /// Weight w_ij of a pair's correction in the least-squares norm: uniform (the kernel
      /// weight W_ij / W(0) put the corrections on the close pairs, 4-5 × their coefficients,
      /// and the Martin & Moyce a/10 collapse diverged within 9 steps; uniform: 96 steps).
      TWINFLOW_HD double weight(const Pair<dim> &) const { return 1.0; }
      /// μ_i: on the rows with fewer neighbour entries than relax_below (corners, the toe, spray)
      /// the multipliers minimise Σ|c|²/w + Σ|R|²/μ instead; elsewhere the constraints hold.
      double regularisation = 0;
      double relax_below    = 0;
      TWINFLOW_HD double mu(const int i) const { return nb.count(i) < relax_below ? regularisation : 0.0; }

      /// a⁰_ij: the antisymmetric part of the consistent pair (fluid j), the consistent pair
      /// itself for a marker j.
      TWINFLOW_HD geometry::Vec<dim> start(const int i, const int j, const Pair<dim> &p) const
      {
        geometry::Vec<dim> a;
        const bool         both = fluid(j);
        for (int d = 0; d < dim; ++d)
        {
          double s = 0;
          for (int q = 0; q < dim; ++q)
            s += (both ? 0.5 * (G[i].a[d][q] + G[j].a[d][q]) : G[i].a[d][q]) * p.gradW[q];
          a[d] = V[i] * V[j] * s;
        }
        return a;
      }

      /// The correction c_ij of the multipliers y (kUnknowns per particle; zero where inactive):
      /// Jᵀ y of the pair, λ_i − λ_j + M_i (r_ji + s_i)/h + M_j (r_ji − s_j)/h (s: shift).
      TWINFLOW_HD geometry::Vec<dim> correction(const int i, const int j, const Pair<dim> &p, const double *y) const
      {
        constexpr int      nc = kUnknowns<dim>;
        const double       w  = weight(p);
        const double      *yi = y + nc * i;
        const bool         fj = fluid(j) && rows[j] != none;
        const double      *yj = y + nc * j;
        geometry::Vec<dim> c;
        for (int d = 0; d < dim; ++d)
        {
          double s = yi[d] - (fj ? yj[d] : 0.0);
          for (int q = 0; q < dim; ++q) // r_ji = −r_ij
          {
            s += yi[dim + dim * d + q] * (shift[i][q] - p.r[q]) * inv_h;
            if (fj)
              s -= yj[dim + dim * d + q] * (p.r[q] + shift[j][q]) * inv_h;
          }
          c[d] = w * s;
        }
        return c;
      }

      /// out[nc] += Pᵀ c: the constraints R1 (c) and R2 (c ⊗ (r_ji + s_i) / h) of row i.
      TWINFLOW_HD void add_constraints(const int i, const geometry::Vec<dim> &c, const Pair<dim> &p,
                                       double *out) const
      {
        for (int d = 0; d < dim; ++d)
        {
          out[d] += c[d];
          for (int q = 0; q < dim; ++q)
            out[dim + dim * d + q] += c[d] * (shift[i][q] - p.r[q]) * inv_h;
        }
      }

      /// Zeroes the components row i does not constrain.
      TWINFLOW_HD void mask(const int i, double *out) const
      {
        constexpr int nc = kUnknowns<dim>;
        if (!fluid(i) || rows[i] == none)
          for (int a = 0; a < nc; ++a)
            out[a] = 0;
        else if (rows[i] == linear)
          for (int d = 0; d < dim; ++d)
            out[d] = 0;
      }
    };

    /// b_i = −R_i(a⁰) (masked).
    template <int dim>
    struct ResidualF
    {
      Geometry<dim> g;
      double       *b = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        constexpr int nc = kUnknowns<dim>;
        double        R[nc];
        for (int a = 0; a < nc; ++a)
          R[a] = 0;
        if (g.fluid(i) && g.rows[i] != none)
        {
          for_each_neighbor(g.nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
            if (j == i)
              return;
            const Pair<dim> p(g.nb.W, r);
            if (p.dist <= 0)
              return;
            g.add_constraints(i, g.start(i, j, p), p, R);
          });
          for (int d = 0; d < dim; ++d)
            R[dim + dim * d + d] -= g.V[i] * g.inv_h;
        }
        g.mask(i, R);
        for (int a = 0; a < nc; ++a)
          b[nc * i + a] = -R[a];
      }
    };

    /// out = K y.
    template <int dim>
    struct ApplyF
    {
      Geometry<dim> g;
      const double *y   = nullptr;
      double       *out = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        constexpr int nc = kUnknowns<dim>;
        double        s[nc];
        for (int a = 0; a < nc; ++a)
          s[a] = 0;
        if (g.fluid(i) && g.rows[i] != none)
          for_each_neighbor(g.nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
            if (j == i)
              return;
            const Pair<dim> p(g.nb.W, r);
            if (p.dist <= 0)
              return;
            g.add_constraints(i, g.correction(i, j, p, y), p, s);
          });
        for (int a = 0; a < nc; ++a)
          s[a] += g.mu(i) * y[nc * i + a];
        const double dw = g.delta_weight(i, y); // R2 − δω_i I / h
        for (int d = 0; d < dim; ++d)
          s[dim + dim * d + d] -= dw * g.inv_h;
        g.mask(i, s);
        for (int a = 0; a < nc; ++a)
          out[nc * i + a] = s[a];
      }
    };

    /// The diagonal block of K at i (inactive components: identity).
    template <int dim>
    struct DiagonalBlockF
    {
      Geometry<dim> g;
      double       *blocks = nullptr; ///< nc × nc per particle, row-major

      TWINFLOW_HD void operator()(const int i) const
      {
        constexpr int nc = kUnknowns<dim>;
        double       *D  = blocks + nc * nc * i;
        for (int a = 0; a < nc * nc; ++a)
          D[a] = 0;
        bool active[nc];
        {
          double probe[nc];
          for (int a = 0; a < nc; ++a)
            probe[a] = 1;
          g.mask(i, probe);
          for (int a = 0; a < nc; ++a)
            active[a] = probe[a] != 0;
        }
        if (g.fluid(i) && g.rows[i] != none)
          for_each_neighbor(g.nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
            if (j == i)
              return;
            const Pair<dim> p(g.nb.W, r);
            if (p.dist <= 0)
              return;
            const double w = g.weight(p);
            // P (dim × nc): c = w P y_i; P = [I | −e_d ⊗ r/h]
            double P[dim][nc];
            for (int d = 0; d < dim; ++d)
              for (int a = 0; a < nc; ++a)
                P[d][a] = 0;
            for (int d = 0; d < dim; ++d)
            {
              P[d][d] = 1;
              for (int q = 0; q < dim; ++q)
                P[d][dim + dim * d + q] = (g.shift[i][q] - p.r[q]) * g.inv_h;
            }
            for (int a = 0; a < nc; ++a)
              for (int b = 0; b < nc; ++b)
              {
                double s = 0;
                for (int d = 0; d < dim; ++d)
                  s += P[d][a] * P[d][b];
                D[nc * a + b] += w * s;
              }
          });
        for (int a = 0; a < nc; ++a)
          D[nc * a + a] += g.mu(i);
        if (g.weight_free(i)) // f E Eᵀ
          for (int d = 0; d < dim; ++d)
            for (int e = 0; e < dim; ++e)
              D[nc * (dim + dim * d + d) + dim + dim * e + e] += g.freedom(i) * g.inv_h * g.inv_h;
        for (int a = 0; a < nc; ++a)
          for (int b = 0; b < nc; ++b)
            if (!active[a] || !active[b])
              D[nc * a + b] = a == b ? 1.0 : 0.0;
      }
    };

    /// The block-Jacobi preconditioner's D_i⁻¹, once per step.
    template <int dim>
    struct InvertBlockF
    {
      double *blocks = nullptr; ///< in: the diagonal blocks; out: their inverses

      /// A singular block (a row without constraints) becomes 1/max diag on its diagonal.
      TWINFLOW_HD void operator()(const int i) const
      {
        constexpr int nc = kUnknowns<dim>;
        double        K[nc][nc], e[nc], col[nc], inv[nc][nc];
        double        dmax = 0;
        for (int a = 0; a < nc; ++a)
          dmax = blocks[nc * nc * i + nc * a + a] > dmax ? blocks[nc * nc * i + nc * a + a] : dmax;
        bool ok = true;
        for (int c = 0; c < nc && ok; ++c)
        {
          for (int a = 0; a < nc; ++a)
          {
            for (int b = 0; b < nc; ++b)
              K[a][b] = blocks[nc * nc * i + nc * a + b];
            e[a] = a == c ? 1.0 : 0.0;
          }
          ok = operators_detail::solve<nc>(K, e, col);
          for (int a = 0; a < nc; ++a)
            inv[a][c] = col[a];
        }
        for (int a = 0; a < nc; ++a)
          for (int b = 0; b < nc; ++b)
            blocks[nc * nc * i + nc * a + b] = ok ? inv[a][b] : a == b && dmax > 0 ? 1.0 / dmax : 0.0;
      }
    };

    /// z_i = D_i⁻¹ r_i (blocks inverted by InvertBlockF)
    template <int dim>
    struct PreconditionF
    {
      const double *blocks = nullptr, *r = nullptr;
      double       *z      = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        constexpr int nc = kUnknowns<dim>;
        for (int a = 0; a < nc; ++a)
        {
          double s = 0;
          for (int c = 0; c < nc; ++c)
            s += blocks[nc * nc * i + nc * a + c] * r[nc * i + c];
          z[nc * i + a] = s;
        }
      }
    };

    /// Rewrites the fluid rows of A^G from a = a⁰ + c(y).
    template <int dim>
    struct WriteF
    {
      Geometry<dim> g;
      const double *y = nullptr;
      double       *grad[dim] = {};
      double       *weight    = nullptr; ///< ω_i (V_i off the fluid)

      TWINFLOW_HD void operator()(const int i) const
      {
        weight[i] = g.V[i];
        if (!g.fluid(i))
          return;
        geometry::Vec<dim> sum = geometry::Vec<dim>::zero();
        int                kd  = -1;
        const double       lo = kWeightFloor * g.V[i], hi = g.V[i] / kWeightFloor;
        double             omega = g.V[i] + g.delta_weight(i, y);
        omega                    = omega < lo ? lo : omega > hi ? hi : omega;
        const double       inv_V = omega > 0 ? 1.0 / omega : 0.0;
        weight[i]                = omega;
        for_each_neighbor(g.nb, i, [&](const int j, const int k, const geometry::Vec<dim> &r) {
          if (j == i)
          {
            kd = k;
            return;
          }
          const Pair<dim> p(g.nb.W, r);
          if (p.dist <= 0)
          {
            for (int d = 0; d < dim; ++d)
              grad[d][k] = 0;
            return;
          }
          const geometry::Vec<dim> a = g.start(i, j, p) + g.correction(i, j, p, y);
          for (int d = 0; d < dim; ++d)
            grad[d][k] = a[d] * inv_V;
          sum += a;
        });
        if (kd >= 0)
          for (int d = 0; d < dim; ++d)
            grad[d][kd] = sum[d] * inv_V; // the sum form Σ_j a_ij (p_i + p_j) / V_i
      }
    };

    /// RowConstraints of each particle: fluid rows with a correction G (not the identity of
    /// a deficient support) are exact for linear fields; off the free surface also for constants.
    template <int dim>
    struct RowsF
    {
      const int          *kind = nullptr, *surface = nullptr;
      const Tensor2<dim> *G    = nullptr;
      int                *rows = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        if (kind[i] != ParticleKind::fluid)
        {
          rows[i] = none;
          return;
        }
        bool identity = true;
        for (int m = 0; m < dim; ++m)
          for (int n = 0; n < dim; ++n)
            identity = identity && G[i].a[m][n] == (m == n ? 1.0 : 0.0);
        rows[i] = identity ? none : surface && surface[i] ? linear : linear_and_constant;
      }
    };

    /// shift[i] = −2 d n_i on the free-surface rows, zero elsewhere. n_i: against the last
    /// step's pressure gradient averaged over the interior fluid neighbours (the direction in
    /// which SurfacePressure extrapolates p_s, so the closure and p_s describe the same plane);
    /// where there is none (free fall, spray), away from the centroid of the neighbours.
    template <int dim>
    struct ShiftF
    {
      NeighborView<dim>   nb;
      const double       *V = nullptr;
      const int          *kind = nullptr, *surface = nullptr;
      Components<dim>     grad_p; ///< ∇p of the last step (null: the centroid only)
      double              depth = 0;
      geometry::Vec<dim> *shift = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        shift[i] = geometry::Vec<dim>::zero();
        if (kind[i] != ParticleKind::fluid || !surface || !surface[i] || !(depth > 0))
          return;
        geometry::Vec<dim> inward = geometry::Vec<dim>::zero(), gp = geometry::Vec<dim>::zero();
        for_each_neighbor(nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
          if (j == i)
            return;
          const double vw = V[j] * nb.w(r);
          inward -= vw * r;
          if (grad_p[0] && kind[j] == ParticleKind::fluid && !surface[j])
            for (int d = 0; d < dim; ++d)
              gp[d] += vw * grad_p[d][j];
        });
        // ∇p points into the liquid; use it where it has the sense of the centroid
        const double gl = geometry::norm(gp), len = geometry::norm(inward);
        if (gl > 0 && geometry::dot(gp, inward) > 0)
          shift[i] = gp * (2 * depth / gl);
        else if (len > 0)
          shift[i] = inward * (2 * depth / len);
      }
    };

    /// free[i] = min(1, Σ_{j free-surface fluid} W_ij / W(h)) on the fluid rows: 1 on the
    /// free-surface particles and the row below them, fading to 0 as the last one leaves the
    /// support (a 0/1 flag switched rows two spacings deep whenever a surface particle's flag
    /// flickered, and their multipliers jumped: the last step's were a worse start than zero).
    template <int dim>
    struct FreeWeightF
    {
      NeighborView<dim> nb;
      const int        *kind = nullptr, *surface = nullptr;
      double            W_h  = 1.0; ///< W at r = h
      double           *free = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        double f = 0;
        if (kind[i] == ParticleKind::fluid && surface)
          for_each_neighbor(nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
            if (kind[j] == ParticleKind::fluid && surface[j])
              f += nb.w(r) / W_h;
          });
        free[i] = f < 1 ? f : 1.0;
      }
    };

    struct AxpyF
    {
      double       *out;
      const double *x;
      double        a;
      const double *y;
      TWINFLOW_HD void operator()(const int k) const { out[k] = x[k] + a * y[k]; }
    };
  } // namespace conservative_detail
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND

#ifndef __CUDACC__ // the coarse level (host code, Eigen): CPU backend only
#include "conservative_coarse.inl"
#endif

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  template <int dim>
  ConservativeGradientReport make_gradient_conservative(const dvec<Vec<dim>> &x, const dvec<double> &V,
                                                        const NeighborList &nl, const DomainBox<dim> &box,
                                                        const CubicSpline<dim> &W, const dvec<Tensor2<dim>> &G,
                                                        const dvec<int> &kind, const dvec<int> *surface,
                                                        OperatorMatrices<dim> &A, ConservativeGradientWork<dim> &work,
                                                        const double surface_depth, const dvec<double> *grad_p,
                                                        const double regularisation, const double relax_below,
                                                        const double tolerance, const int max_iterations)
  {
    using namespace conservative_detail;
    constexpr int              nc = kUnknowns<dim>;
    const int                  n  = static_cast<int>(x.size());
    ConservativeGradientReport report;
    if (n == 0)
      return report;
    work.rows.resize(n);
    RowsF<dim> rf;
    rf.kind    = ptr(kind);
    rf.surface = surface ? ptr(*surface) : nullptr;
    rf.G       = ptr(G);
    rf.rows    = ptr(work.rows);
    const thrust::counting_iterator<int> first(0);
    thrust::for_each(exec, first, first + n, rf);

    Geometry<dim> g;
    g.nb     = neighbor_view(x, nl, box, W);
    g.V      = ptr(V);
    g.G      = ptr(G);
    g.kind   = ptr(kind);
    g.rows   = ptr(work.rows);
    work.shift.resize(n);
    {
      ShiftF<dim> sf;
      sf.nb      = g.nb;
      sf.V       = ptr(V);
      sf.kind    = ptr(kind);
      sf.surface = surface ? ptr(*surface) : nullptr;
      sf.depth   = surface_depth;
      for (int d = 0; d < dim; ++d)
        sf.grad_p.c[d] = grad_p && grad_p[d].size() == static_cast<std::size_t>(n) ? ptr(grad_p[d]) : nullptr;
      if (!sf.grad_p.c[dim - 1])
        sf.grad_p.c[0] = nullptr;
      sf.shift   = ptr(work.shift);
      thrust::for_each(exec, first, first + n, sf);
    }
    g.shift = ptr(work.shift);
    g.inv_h  = 2.0 / W.support();
    g.regularisation = regularisation;
    g.relax_below    = relax_below;
    work.free_weight.resize(n);
    {
      FreeWeightF<dim> fw;
      fw.nb      = g.nb;
      fw.kind    = ptr(kind);
      fw.surface = surface ? ptr(*surface) : nullptr;
      fw.W_h     = W.value(0.5 * W.support());
      fw.free    = ptr(work.free_weight);
      thrust::for_each(exec, first, first + n, fw);
    }
    g.free_weight = ptr(work.free_weight);

    const std::size_t m = static_cast<std::size_t>(nc) * n;
    for (dvec<double> *v : {&work.b, &work.r, &work.z, &work.p, &work.q})
      v->resize(m);
    if (work.y.size() != m) // else: warm start from the caller's multipliers
    {
      work.y.resize(m);
      thrust::fill(exec, work.y.begin(), work.y.end(), 0.0);
    }
    work.blocks.resize(m * nc);
    thrust::for_each(exec, first, first + n, ResidualF<dim>{g, ptr(work.b)});
    thrust::for_each(exec, first, first + n, DiagonalBlockF<dim>{g, ptr(work.blocks)});
    thrust::for_each(exec, first, first + n, InvertBlockF<dim>{ptr(work.blocks)});
    auto apply = [&](const dvec<double> &in, dvec<double> &out) {
      ApplyF<dim> f;
      f.g   = g;
      f.y   = ptr(in);
      f.out = ptr(out);
      thrust::for_each(exec, first, first + n, f);
    };
    auto dot = [&](const dvec<double> &a, const dvec<double> &b) {
      return thrust::inner_product(exec, a.begin(), a.end(), b.begin(), 0.0);
    };
    auto axpy = [&](dvec<double> &out, const dvec<double> &a, const double s, const dvec<double> &b) {
      thrust::for_each(exec, first, first + static_cast<int>(m), AxpyF{ptr(out), ptr(a), s, ptr(b)});
    };
#ifndef __CUDACC__ // the CPU backend: its arrays are host memory
    if (!work.coarse)
      work.coarse = std::make_shared<CoarseSpace<dim>>();
    CoarseSpace<dim> &coarse = *work.coarse; // conservative_coarse.inl
    coarse.setup(n, ptr(x), ptr(kind), ptr(work.rows), ptr(work.free_weight), ptr(nl.offsets), ptr(nl.indices),
                 ptr(work.shift), relax_below, regularisation, box, kCoarseCell * W.support(), g.inv_h);
#endif
    auto precondition = [&]() {
      thrust::for_each(exec, first, first + n, PreconditionF<dim>{ptr(work.blocks), ptr(work.r), ptr(work.z)});
#ifndef __CUDACC__
      coarse.apply(ptr(work.r), ptr(work.z));
#endif
    };
    const double b_norm = std::sqrt(dot(work.b, work.b));
    report.initial      = b_norm;
    apply(work.y, work.q);
    axpy(work.r, work.b, -1.0, work.q); // r = b − K y
    double r_norm = std::sqrt(dot(work.r, work.r));
    if (r_norm > b_norm) // the last step's multipliers are a worse start than none
    {
      thrust::fill(exec, work.y.begin(), work.y.end(), 0.0);
      thrust::copy(exec, work.b.begin(), work.b.end(), work.r.begin());
      r_norm = b_norm;
    }
    if (b_norm > 0 && r_norm > tolerance * b_norm)
    {
      precondition();
      thrust::copy(exec, work.z.begin(), work.z.end(), work.p.begin());
      double rz = dot(work.r, work.z);
      for (int it = 0; it < max_iterations; ++it)
      {
        apply(work.p, work.q);
        const double pq = dot(work.p, work.q);
        if (!(pq > 0))
          break;
        const double alpha = rz / pq;
        axpy(work.y, work.y, alpha, work.p);
        axpy(work.r, work.r, -alpha, work.q);
        report.iterations = it + 1;
        r_norm            = std::sqrt(dot(work.r, work.r));
        if (r_norm <= tolerance * b_norm)
          break;
        precondition();
        const double rz_new = dot(work.r, work.z);
        axpy(work.p, work.z, rz_new / rz, work.p);
        rz = rz_new;
      }
    }
    report.residual  = b_norm > 0 ? r_norm / b_norm : 0.0;
    report.converged = report.residual <= tolerance;
    WriteF<dim> wf;
    wf.g = g;
    wf.y = ptr(work.y);
    work.weight.resize(n);
    wf.weight = ptr(work.weight);
    for (int d = 0; d < dim; ++d)
      wf.grad[d] = ptr(A.gradient[d]);
    thrust::for_each(exec, first, first + n, wf);
    return report;
  }

#define TWINFLOW_SPH_CONSERVATIVE_INSTANTIATE(dim)                                                               \
  template ConservativeGradientReport make_gradient_conservative<dim>(                                          \
    const dvec<Vec<dim>> &, const dvec<double> &, const NeighborList &, const DomainBox<dim> &,                  \
    const CubicSpline<dim> &, const dvec<Tensor2<dim>> &, const dvec<int> &, const dvec<int> *,                 \
    OperatorMatrices<dim> &, ConservativeGradientWork<dim> &, double, const dvec<double> *, double, double, double, int);
  TWINFLOW_SPH_CONSERVATIVE_INSTANTIATE(2)
  TWINFLOW_SPH_CONSERVATIVE_INSTANTIATE(3)
#undef TWINFLOW_SPH_CONSERVATIVE_INSTANTIATE
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
