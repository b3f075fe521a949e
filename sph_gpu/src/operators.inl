// SPH operators (single source for the CPU and CUDA backends): volumes (Eq. 17),
// correction tensors G (Eq. 24) and L (Eq. 25–26), and the matrices A^G, A^L of the
// standard (Eq. 19–20, 29, 36–39) and consistent (Eq. 22–23) discretisations.
//
// Conventions: r_ij = x_i − x_j (minimum image), e_ij = r_ij/|r_ij|, ∇_i W_ij =
// CubicSpline::gradient(r_ij). One functor per particle (row) walks the row of the CSR
// neighbour list; the matrices share that pattern.
#include <twinflow_sph/operators.h>

#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/reduce.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace operators_detail
  {
    /// G^{-1} is inverted only if |det| > kGDetTolerance · ‖G^{-1}‖_∞^dim (else G = I).
    constexpr double kGDetTolerance = 1e-3;
    /// The L system is singular if a pivot ≤ kLPivotTolerance · max |K_ab| (then L = I).
    constexpr double kLPivotTolerance = 1e-8;

    TWINFLOW_HD inline double abs_(const double a) { return a < 0 ? -a : a; }
    TWINFLOW_HD inline bool   finite_(const double a) { return a - a == 0.0; }

    template <int dim>
    TWINFLOW_HD inline Tensor2<dim> identity()
    {
      Tensor2<dim> t;
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          t.a[m][n] = m == n ? 1.0 : 0.0;
      return t;
    }

    /// Inverse of a dim × dim matrix by cofactors; false if (relatively) singular.
    template <int dim>
    TWINFLOW_HD inline bool invert(const double M[dim][dim], double R[dim][dim])
    {
      double scale = 0;
      for (int m = 0; m < dim; ++m)
      {
        double row = 0;
        for (int n = 0; n < dim; ++n)
          row += abs_(M[m][n]);
        scale = row > scale ? row : scale;
      }
      if (!(scale > 0) || !finite_(scale))
        return false;
      double det, scale_dim = scale * scale;
      if constexpr (dim == 2)
      {
        det     = M[0][0] * M[1][1] - M[0][1] * M[1][0];
        R[0][0] = M[1][1];
        R[0][1] = -M[0][1];
        R[1][0] = -M[1][0];
        R[1][1] = M[0][0];
      }
      else
      {
        scale_dim *= scale;
        R[0][0] = M[1][1] * M[2][2] - M[1][2] * M[2][1];
        R[0][1] = M[0][2] * M[2][1] - M[0][1] * M[2][2];
        R[0][2] = M[0][1] * M[1][2] - M[0][2] * M[1][1];
        R[1][0] = M[1][2] * M[2][0] - M[1][0] * M[2][2];
        R[1][1] = M[0][0] * M[2][2] - M[0][2] * M[2][0];
        R[1][2] = M[0][2] * M[1][0] - M[0][0] * M[1][2];
        R[2][0] = M[1][0] * M[2][1] - M[1][1] * M[2][0];
        R[2][1] = M[0][1] * M[2][0] - M[0][0] * M[2][1];
        R[2][2] = M[0][0] * M[1][1] - M[0][1] * M[1][0];
        det     = M[0][0] * R[0][0] + M[0][1] * R[1][0] + M[0][2] * R[2][0];
      }
      if (!(abs_(det) > kGDetTolerance * scale_dim))
        return false;
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          R[m][n] /= det;
      return true;
    }

    /// A Laplacian correction L (symmetric) that is not positive definite turns the row of
    /// A^L from an elliptic (negative-diagonal, diffusive) one into an indefinite one. In
    /// sparse or distorted neighbourhoods (splash) such rows gave a tiny diagonal and an
    /// arbitrary pressure: 9.5e5 Pa in a 0.5 m deep pool, and a 19 m/s kick in one step
    /// (doc/benchmarks.md). Sylvester's criterion (leading minors > 0).
    template <int dim>
    TWINFLOW_HD inline bool positive_definite(const Tensor2<dim> &L)
    {
      const double m1 = L.a[0][0];
      const double m2 = L.a[0][0] * L.a[1][1] - L.a[0][1] * L.a[1][0];
      if constexpr (dim == 2)
        return m1 > 0 && m2 > 0;
      else
      {
        const double m3 = L.a[0][0] * (L.a[1][1] * L.a[2][2] - L.a[1][2] * L.a[2][1]) -
                          L.a[0][1] * (L.a[1][0] * L.a[2][2] - L.a[1][2] * L.a[2][0]) +
                          L.a[0][2] * (L.a[1][0] * L.a[2][1] - L.a[1][1] * L.a[2][0]);
        return m1 > 0 && m2 > 0 && m3 > 0;
      }
    }

    /// Largest eigenvalue of a Laplacian correction accepted by the conditioning check. Where
    /// the support is full, L ≈ I; one row below a free surface its eigenvalues reach ~2. A
    /// degenerate support (a few neighbours nearly on a line, a close pair at the surface) gives
    /// an L that is positive definite but nearly singular in one direction, with eigenvalues up
    /// to 1e3–1e4: its row then weighs some neighbours 4–5 × the diagonal with the diagonal's
    /// sign and solves to an arbitrary extreme pressure (−95 kPa next to the surface of the
    /// paper's dam break at 1.45 s, a 13.5 m/s kick in one step; doc/benchmarks.md).
    constexpr double kLMaxEigenvalue = 4.0;

    /// L positive definite with all eigenvalues ≤ kLMaxEigenvalue: L and kLMaxEigenvalue·I − L
    /// both positive definite (L is symmetric).
    template <int dim>
    TWINFLOW_HD inline bool well_conditioned(const Tensor2<dim> &L)
    {
      Tensor2<dim> rest;
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          rest.a[m][n] = (m == n ? kLMaxEigenvalue : 0.0) - L.a[m][n];
      return positive_definite<dim>(L) && positive_definite<dim>(rest);
    }

    /// Solves K y = b (N × N, overwritten) by Gaussian elimination with partial pivoting;
    /// false if a pivot is below kLPivotTolerance · max |K| or the result is not finite.
    template <int N>
    TWINFLOW_HD inline bool solve(double K[N][N], double b[N], double y[N])
    {
      double scale = 0;
      for (int a = 0; a < N; ++a)
        for (int c = 0; c < N; ++c)
          scale = abs_(K[a][c]) > scale ? abs_(K[a][c]) : scale;
      if (!(scale > 0) || !finite_(scale))
        return false;
      const double tol = kLPivotTolerance * scale;
      for (int col = 0; col < N; ++col)
      {
        int    p    = col;
        double best = abs_(K[col][col]);
        for (int a = col + 1; a < N; ++a)
          if (abs_(K[a][col]) > best)
          {
            best = abs_(K[a][col]);
            p    = a;
          }
        if (!(best > tol))
          return false;
        if (p != col)
        {
          for (int c = 0; c < N; ++c)
          {
            const double t = K[col][c];
            K[col][c]      = K[p][c];
            K[p][c]        = t;
          }
          const double t = b[col];
          b[col]         = b[p];
          b[p]           = t;
        }
        for (int a = col + 1; a < N; ++a)
        {
          const double f = K[a][col] / K[col][col];
          for (int c = col; c < N; ++c)
            K[a][c] -= f * K[col][c];
          b[a] -= f * b[col];
        }
      }
      for (int a = N - 1; a >= 0; --a)
      {
        double s = b[a];
        for (int c = a + 1; c < N; ++c)
          s -= K[a][c] * y[c];
        y[a] = s / K[a][a];
        if (!finite_(y[a]))
          return false;
      }
      return true;
    }

    /// Neighbour geometry of one pair: r_ij, |r_ij|, e_ij, ∇_i W_ij (|r| = 0: all zero).
    template <int dim>
    struct Pair
    {
      geometry::Vec<dim> r, e, gradW;
      double             dist;

      TWINFLOW_HD Pair(const CubicSpline<dim> &W, const geometry::Vec<dim> &rij)
      {
        r    = rij;
        dist = geometry::norm(r);
        if (dist > 0)
        {
          // one square root and one division per pair: ∇W = (dW/dr) e (Eq. 21)
          e                 = r * (1 / dist);
          const double dWdr = W.derivative(dist);
          for (int d = 0; d < dim; ++d)
            gradW[d] = dWdr * e[d];
        }
        else
        {
          e     = geometry::Vec<dim>::zero();
          gradW = geometry::Vec<dim>::zero();
        }
      }
    };

    /// V_i = 1 / Σ_j W_ij (Eq. 17).
    template <int dim>
    struct VolumeF
    {
      NeighborView<dim> nb;
      double           *V = nullptr;

      TWINFLOW_HD void operator()(const int i) const
      {
        double sum = 0;
        for_each_neighbor(nb, i, [&](int, int, const geometry::Vec<dim> &r) { sum += nb.w(r); });
        V[i] = sum > 0 ? 1.0 / sum : 0.0;
      }
    };

    /// G_i (Eq. 24) and L_i (Eq. 25–26); fallback[i] = 1 where either used the identity.
    template <int dim>
    struct CorrectionF
    {
      static constexpr int NL = dim * (dim + 1) / 2;  ///< unknowns of the symmetric L

      NeighborView<dim> nb;
      const double     *V = nullptr;
      Tensor2<dim>     *G = nullptr, *L = nullptr;
      int              *fallback = nullptr;
      CorrectionChecks  checks;
      const int        *surface = nullptr; ///< free-surface flags (null: none, a confined flow)
      const int        *rows    = nullptr; ///< rows[i] = 0: not needed, G_i = L_i = I (null: all)

      TWINFLOW_HD void operator()(const int i) const
      {
        if (rows && !rows[i])
        {
          G[i] = L[i] = identity<dim>();
          fallback[i] = 0;
          return;
        }
        // One pass over the neighbours gathers every moment; G_i only enters afterwards, since
        // A^{kmn} = G^{kq} B^{qmn} and Eq. 25's matrix is K1 + A·K2 (below).
        //   (G^{-1})^{mn} = −Σ_j r^m ∇_n W V_j
        //   B^{qmn}       =  Σ_j r^m r^n ∇_q W V_j
        //   K1^{(mn),c}   =  Σ_j r^m e^n col_c,   K2^{q,c} = Σ_j e^q col_c
        // with col_c = c_op V_j for the unknown c = (o, p) of L (see Eq. 25 below).
        int pm[NL], pn[NL];
        {
          int a = 0;
          for (int m = 0; m < dim; ++m)
            for (int n = m; n < dim; ++n)
            {
              pm[a] = m;
              pn[a] = n;
              ++a;
            }
        }
        double Minv[dim][dim], B[dim][dim][dim], K1[NL][NL], K2[dim][NL];
        for (int m = 0; m < dim; ++m)
        {
          for (int n = 0; n < dim; ++n)
          {
            Minv[m][n] = 0;
            for (int q = 0; q < dim; ++q)
              B[q][m][n] = 0;
          }
          for (int c = 0; c < NL; ++c)
            K2[m][c] = 0;
        }
        for (int a = 0; a < NL; ++a)
          for (int c = 0; c < NL; ++c)
            K1[a][c] = 0;
        bool near_surface = surface && surface[i];
        for_each_neighbor(nb, i, [&](const int j, int, const geometry::Vec<dim> &r) {
          if (j == i)
            return;
          near_surface = near_surface || (surface && surface[j]);
          const Pair<dim> p(nb.W, r);
          if (p.dist <= 0)
            return; // ∇W = 0 and no direction: contributes to no moment
          const double Vj = V[j];
          for (int m = 0; m < dim; ++m)
            for (int n = 0; n < dim; ++n)
            {
              const double rmn = p.r[m] * p.r[n] * Vj;
              Minv[m][n] -= p.r[m] * p.gradW[n] * Vj;
              for (int q = 0; q < dim; ++q)
                B[q][m][n] += rmn * p.gradW[q];
            }
          double col[NL];
          for (int c = 0; c < NL; ++c)
          {
            const int o = pm[c], q = pn[c];
            col[c] = (o == q ? p.e[o] * p.gradW[o] : p.e[o] * p.gradW[q] + p.e[q] * p.gradW[o]) * Vj;
          }
          for (int a = 0; a < NL; ++a)
          {
            const double rme = p.r[pm[a]] * p.e[pn[a]];
            for (int c = 0; c < NL; ++c)
              K1[a][c] += rme * col[c];
          }
          for (int q = 0; q < dim; ++q)
            for (int c = 0; c < NL; ++c)
              K2[q][c] += p.e[q] * col[c];
        });

        // --- G_i
        Tensor2<dim> Gi;
        bool         g_ok = invert<dim>(Minv, Gi.a);
        if (!g_ok)
          Gi = identity<dim>();
        G[i] = Gi;

        // --- Eq. 26, A^{kmn} = Σ_j r^m r^n G^{kq} ∇_q W V_j = G^{kq} B^{qmn}, and Eq. 25 for the
        //     pairs m ≤ n (rows) in the unknowns L^{op}, o ≤ p (columns):
        //     Σ_j (A^{kmn} e^k + r^m e^n) (Σ_{o≤p} c_op L^{op}) V_j = −δ^{mn},
        //     c_oo = e^o ∇_o W, c_op = e^o ∇_p W + e^p ∇_o W (o < p, L symmetric),
        //     i.e. K = K1 + Σ_k A^{kmn} K2^{k,·}.
        double K[NL][NL], b[NL], y[NL];
        for (int a = 0; a < NL; ++a)
        {
          const int m = pm[a], n = pn[a];
          b[a]        = m == n ? -1.0 : 0.0;
          double Amn[dim];
          for (int kk = 0; kk < dim; ++kk)
          {
            Amn[kk] = 0;
            for (int q = 0; q < dim; ++q)
              Amn[kk] += Gi.a[kk][q] * B[q][m][n];
          }
          for (int c = 0; c < NL; ++c)
          {
            double v = K1[a][c];
            for (int kk = 0; kk < dim; ++kk)
              v += Amn[kk] * K2[kk][c];
            K[a][c] = v;
          }
        }
        Tensor2<dim> Li;
        bool         l_ok = solve<NL>(K, b, y);
        if (l_ok)
          for (int a = 0; a < NL; ++a)
          {
            Li.a[pm[a]][pn[a]] = y[a];
            Li.a[pn[a]][pm[a]] = y[a];
          }
        else
          Li = identity<dim>();
        // Every particle, free-surface ones included: their L only enters the viscous row (the
        // pressure row is p = 0), where an indefinite L is anti-diffusive (a surface particle
        // 3e-5 m from a neighbour, L ~ 1e3, got a 45 m/s viscous kick in the Martin & Moyce
        // dam break at a/80).
        // Next to a free surface the support is truncated, and a degenerate one (a few neighbours
        // nearly on a line, a close pair) gives a positive definite L with eigenvalues of 1e2–1e4:
        // bounded there (well_conditioned). Inside the water an L above the bound comes from a
        // disordered but full support, where the correction is what keeps the row consistent:
        // the periodic cylinder's wake diverged at t = 1.57 s when those rows were replaced too.
        if (l_ok && checks.positive_definite_laplacian &&
            !(near_surface ? well_conditioned<dim>(Li) : positive_definite<dim>(Li)))
        {
          Li   = identity<dim>();
          l_ok = false;
        }
        L[i]        = Li;
        fallback[i] = (g_ok && l_ok) ? 0 : 1;
      }
    };

    /// Row i of A^G and A^L.
    template <int dim>
    struct AssembleF
    {
      NeighborView<dim>   nb;
      const double       *V          = nullptr;
      bool                consistent = false;
      const Tensor2<dim> *G = nullptr, *L = nullptr;
      double             *grad[dim] = {};
      double             *lap       = nullptr;
      const int          *rows      = nullptr; ///< rows[i] = 0: a zero row (null: all rows)
      /// standard kind: rows[i] ≠ 0 are consistent rows (null: none); see assemble_operators()
      const int          *corrected = nullptr;
      double              scale     = 1.0;     ///< standard rows: lattice_scale()

      TWINFLOW_HD void operator()(const int i) const
      {
        if (rows && !rows[i])
        {
          for (int k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
          {
            for (int d = 0; d < dim; ++d)
              grad[d][k] = 0;
            lap[k] = 0;
          }
          return;
        }
        const bool   consistent = this->consistent || (corrected && corrected[i]);
        Tensor2<dim> Gi = identity<dim>(), Li = identity<dim>();
        if (consistent)
        {
          Gi = G[i];
          Li = L[i];
        }
        geometry::Vec<dim> diag_g = geometry::Vec<dim>::zero(), s = geometry::Vec<dim>::zero();
        double             diag_l = 0;
        int                kd     = -1;
        for_each_neighbor(nb, i, [&](const int j, const int k, const geometry::Vec<dim> &r) {
          if (j == i)
          {
            kd = k;
            return;
          }
          const Pair<dim> p(nb.W, r);
          if (p.dist <= 0)
          {
            for (int d = 0; d < dim; ++d)
              grad[d][k] = 0;
            lap[k] = 0;
            return;
          }
          // gradient, Eq. 36–39 / 22: V_j (G) ∇_i W_ij
          geometry::Vec<dim> v;
          for (int d = 0; d < dim; ++d)
          {
            double gd = p.gradW[d];
            if (consistent)
            {
              gd = 0;
              for (int q = 0; q < dim; ++q)
                gd += Gi.a[d][q] * p.gradW[q];
            }
            v[d] = V[j] * gd;
          }
          if (!consistent) // standard: the kernel's lattice scale (lattice_scale)
            v *= scale;
          for (int d = 0; d < dim; ++d)
            grad[d][k] = v[d];
          diag_g -= v;
          // Laplacian, Eq. 29 / 23: c = 2 V_j (e·∇W) or 2 V_j (L : e ⊗ ∇W)
          double c = 0;
          if (consistent)
          {
            for (int o = 0; o < dim; ++o)
              for (int q = 0; q < dim; ++q)
                c += Li.a[o][q] * p.e[o] * p.gradW[q];
          }
          else
            c = geometry::dot(p.e, p.gradW);
          c *= 2.0 * V[j];
          if (!consistent)
            c *= scale;
          lap[k] = -c / p.dist;
          diag_l += c / p.dist;
          if (consistent)
            s += c * p.e;
        });
        if (kd >= 0)
        {
          for (int d = 0; d < dim; ++d)
            grad[d][kd] = diag_g[d];
          lap[kd] = diag_l;
        }
        // Eq. 23's −Σ_j c_j e_ij · ∇f_i with ∇f_i = (A^G f)_i: subtract s · A^G_ik
        if (consistent)
          for (int k = nb.offsets[i]; k < nb.offsets[i + 1]; ++k)
          {
            double t = 0;
            for (int d = 0; d < dim; ++d)
              t += s[d] * grad[d][k];
            lap[k] -= t;
          }
      }
    };

  } // namespace operators_detail

  template <int dim>
  void compute_volumes(const dvec<Vec<dim>> &x, const NeighborList &nl, const DomainBox<dim> &box,
                       const CubicSpline<dim> &W, dvec<double> &V)
  {
    const int n = static_cast<int>(x.size());
    V.resize(n);
    if (n == 0)
      return;
    const operators_detail::VolumeF<dim> f{neighbor_view(x, nl, box, W), ptr(V)};
    thrust::counting_iterator<int> first(0);
    thrust::for_each(exec, first, first + n, f);
  }

  template <int dim>
  int compute_corrections(const dvec<Vec<dim>> &x, const dvec<double> &V, const NeighborList &nl,
                          const DomainBox<dim> &box, const CubicSpline<dim> &W, dvec<Tensor2<dim>> &G,
                          dvec<Tensor2<dim>> &L, const CorrectionChecks &checks, const dvec<int> *surface,
                          const dvec<int> *rows)
  {
    const int n = static_cast<int>(x.size());
    G.resize(n);
    L.resize(n);
    if (n == 0)
      return 0;
    dvec<int>                           fallback(n);
    operators_detail::CorrectionF<dim> f;
    f.nb       = neighbor_view(x, nl, box, W);
    f.V        = ptr(V);
    f.G        = ptr(G);
    f.L        = ptr(L);
    f.fallback = ptr(fallback);
    f.checks   = checks;
    f.surface  = surface ? ptr(*surface) : nullptr;
    f.rows     = rows ? ptr(*rows) : nullptr;
    thrust::counting_iterator<int> first(0);
    thrust::for_each(exec, first, first + n, f);
    return thrust::reduce(exec, fallback.begin(), fallback.end(), 0);
  }

  template <int dim>
  void assemble_operators(const dvec<Vec<dim>> &x, const dvec<double> &V, const NeighborList &nl,
                          const DomainBox<dim> &box, const CubicSpline<dim> &W, const OperatorKind kind,
                          const dvec<Tensor2<dim>> &G, const dvec<Tensor2<dim>> &L, OperatorMatrices<dim> &A,
                          const dvec<int> *rows, const dvec<int> *corrected, const double standard_scale)
  {
    const int         n         = static_cast<int>(x.size());
    const std::size_t n_entries = nl.indices.size();
    for (int d = 0; d < dim; ++d)
      A.gradient[d].resize(n_entries);
    A.laplacian.resize(n_entries);
    if (n == 0)
      return;
    operators_detail::AssembleF<dim> f;
    f.nb         = neighbor_view(x, nl, box, W);
    f.V          = ptr(V);
    f.consistent = kind == OperatorKind::consistent;
    f.corrected  = !f.consistent && corrected ? ptr(*corrected) : nullptr;
    f.scale      = standard_scale;
    f.G          = f.consistent || f.corrected ? ptr(G) : nullptr;
    f.L          = f.consistent || f.corrected ? ptr(L) : nullptr;
    for (int d = 0; d < dim; ++d)
      f.grad[d] = ptr(A.gradient[d]);
    f.lap  = ptr(A.laplacian);
    f.rows = rows ? ptr(*rows) : nullptr;
    thrust::counting_iterator<int> first(0);
    thrust::for_each(exec, first, first + n, f);
  }

  template <int dim>
  double lattice_scale(const CubicSpline<dim> &W, const double spacing)
  {
    // the regular lattice of the particle setup: V = 1 / Σ_j W_0j, trace = −V Σ_j r_0j·∇W_0j
    if (!(spacing > 0) || !(W.support() / spacing < 64))
      return 1.0;
    const int reach = static_cast<int>(W.support() / spacing) + 1;
    double    sum_w = 0, trace = 0;
    int       k[3]  = {0, 0, 0};
    const int n_cells = dim == 2 ? (2 * reach + 1) * (2 * reach + 1) : (2 * reach + 1) * (2 * reach + 1) * (2 * reach + 1);
    for (int c = 0; c < n_cells; ++c)
    {
      int rest = c;
      for (int d = 0; d < dim; ++d)
      {
        k[d] = rest % (2 * reach + 1) - reach;
        rest /= 2 * reach + 1;
      }
      geometry::Vec<dim> r;
      for (int d = 0; d < dim; ++d)
        r[d] = k[d] * spacing;
      const double dist = geometry::norm(r);
      if (dist >= W.support())
        continue;
      sum_w += W.value(dist);
      if (dist > 0)
        trace -= geometry::dot(r, operators_detail::Pair<dim>(W, r).gradW);
    }
    return sum_w > 0 && trace > 0 ? dim * sum_w / trace : 1.0;
  }

#define TWINFLOW_SPH_OPERATORS_INSTANTIATE(dim)                                                              \
  template void compute_volumes<dim>(const dvec<Vec<dim>> &, const NeighborList &, const DomainBox<dim> &,   \
                                     const CubicSpline<dim> &, dvec<double> &);                              \
  template int  compute_corrections<dim>(const dvec<Vec<dim>> &, const dvec<double> &, const NeighborList &, \
                                        const DomainBox<dim> &, const CubicSpline<dim> &,                   \
                                        dvec<Tensor2<dim>> &, dvec<Tensor2<dim>> &,                         \
                                        const CorrectionChecks &, const dvec<int> *, const dvec<int> *);  \
  template void assemble_operators<dim>(const dvec<Vec<dim>> &, const dvec<double> &, const NeighborList &,  \
                                        const DomainBox<dim> &, const CubicSpline<dim> &, OperatorKind,      \
                                        const dvec<Tensor2<dim>> &, const dvec<Tensor2<dim>> &,              \
                                        OperatorMatrices<dim> &, const dvec<int> *, const dvec<int> *,       \
                                        double);                                                             \
  template double lattice_scale<dim>(const CubicSpline<dim> &, double);
  TWINFLOW_SPH_OPERATORS_INSTANTIATE(2)
  TWINFLOW_SPH_OPERATORS_INSTANTIATE(3)
#undef TWINFLOW_SPH_OPERATORS_INSTANTIATE
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND

#include "conservative_gradient.inl"
