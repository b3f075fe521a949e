// The coarse level of the two-level preconditioner of make_gradient_conservative()'s multipliers
// (host code; the CPU backend only: the CUDA backend keeps block Jacobi).
//
// Block Jacobi alone needs ~200 iterations on a column 10 particles wide but 16,000-27,700 on
// one 100 wide: every smooth λ with M = (h/2)∇λ leaves the pair corrections unchanged to third
// order, so the operator K's smallest eigenvalues fall with a high power of the width. The
// coarse space holds exactly those modes: per cell of size 2h (the kernel support, so only
// adjacent cells couple), for each component d, λ_d = φ(ξ) with φ ∈ {1, ξ_e, ξ_e ξ_f} (6 in 2D,
// 10 in 3D; ξ the position in the cell over the cell size) and M_d = (h/2)∇φ, masked like the
// rows. E = Zᵀ K Z is assembled from the pair energy, Σ_pairs c(z_a)·c(z_b) + μ + the weights'
// E F Eᵀ, and factored every step by CHOLMOD's supernodal Cholesky (through Eigen; 77 ms on the
// splash's 10,584 coarse unknowns, Eigen's simplicial LDLᵀ 180 ms). A factorisation kept for
// later steps is no use: the system jumps with the free-surface flags, and one step later the
// iterations went from ~105 to 1,300-2,000. The preconditioner is additive,
// z = D⁻¹ r + Z E⁻¹ Zᵀ r. Measured: 282 → 45 iterations at a/10, 27,668 → 79 on the splash
// column (to 1e-8).
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/CholmodSupport>

#include <array>
#include <cmath>
#include <map>
#include <vector>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace conservative_detail
  {
    template <int dim>
    class CoarseSpace
    {
    public:
      static constexpr int n_poly  = dim == 2 ? 6 : 10;
      static constexpr int n_modes = dim * n_poly;
      static constexpr int nc      = kUnknowns<dim>;

      /// The cells of the active rows (fluid rows with constraints; a lattice of size @p cell
      /// anchored at the origin), the basis, E = Zᵀ K Z and its factorisation. The arrays are the
      /// CPU backend's (host memory): @p free_w the rows' f_i of E F Eᵀ, μ = @p regularisation on
      /// the rows with fewer than @p relax_below neighbour entries.
      void setup(const int n, const geometry::Vec<dim> *x, const int *kind, const int *rows, const double *free_w,
                 const int *offsets, const int *indices, const geometry::Vec<dim> *shift, const double relax_below,
                 const double regularisation, const DomainBox<dim> &box, const double cell, const double inv_h)
      {
        this->inv_h = inv_h;
        L           = cell;
        cell_of.assign(n, -1);
        ids.clear();
        centres.clear();
        for (int i = 0; i < n; ++i)
        {
          if (kind[i] != ParticleKind::fluid || rows[i] == none)
            continue;
          const auto key = key_of(x[i]);
          auto       it  = ids.find(key);
          if (it == ids.end())
          {
            it = ids.emplace(key, static_cast<int>(centres.size())).first;
            geometry::Vec<dim> c;
            for (int d = 0; d < dim; ++d)
              c[d] = (key[d] + 0.5) * L;
            centres.push_back(c);
          }
          cell_of[i] = it->second;
        }
        n_cells = static_cast<int>(centres.size());
        evaluate_basis(x, rows, box);
        // E = Zᵀ K Z from the pair energy
        std::map<std::pair<int, int>, std::vector<double>> blocks;
        auto block = [&](const int a, const int b) -> std::vector<double> & {
          auto &B = blocks[{a, b}];
          if (B.empty())
            B.assign(n_modes * n_modes, 0.0);
          return B;
        };
        auto A_part = [&](const int i, const double *z, const geometry::Vec<dim> &r, geometry::Vec<dim> &c) {
          for (int d = 0; d < dim; ++d)
          {
            double s = z[d];
            for (int q = 0; q < dim; ++q)
              s += z[dim + dim * d + q] * (shift[i][q] - r[q]) * inv_h;
            c[d] = s;
          }
        };
        auto B_part = [&](const int j, const double *z, const geometry::Vec<dim> &r, geometry::Vec<dim> &c) {
          for (int d = 0; d < dim; ++d)
          {
            double s = z[d];
            for (int q = 0; q < dim; ++q)
              s += z[dim + dim * d + q] * (r[q] + shift[j][q]) * inv_h;
            c[d] = s;
          }
        };
        std::vector<geometry::Vec<dim>> ci(n_modes), cj(n_modes), u(n_modes), v(n_modes);
        for (int i = 0; i < n; ++i)
        {
          if (cell_of[i] < 0)
            continue;
          for (int k = offsets[i]; k < offsets[i + 1]; ++k)
          {
            const int j = indices[k];
            if (j == i)
              continue;
            const geometry::Vec<dim> r = box.difference(x[i], x[j]);
            if (geometry::norm(r) <= 0)
              continue;
            const bool fj = kind[j] == ParticleKind::fluid && rows[j] != none;
            if (fj && j < i)
              continue; // once per fluid pair
            for (int a = 0; a < n_modes; ++a)
            {
              A_part(i, &basis[(static_cast<std::size_t>(i) * n_modes + a) * nc], r, ci[a]);
              if (fj && cell_of[j] >= 0)
                B_part(j, &basis[(static_cast<std::size_t>(j) * n_modes + a) * nc], r, cj[a]);
              else
                cj[a] = geometry::Vec<dim>::zero();
            }
            const int ca = cell_of[i], cb = fj ? cell_of[j] : -1;
            // c(z) for z of cell ca: ci (and −cj if cb == ca); for z of cell cb: −cj
            for (int a = 0; a < n_modes; ++a)
            {
              u[a] = ci[a];
              if (cb == ca)
                u[a] -= cj[a];
              v[a] = cj[a] * -1.0;
            }
            auto add = [&](const int p, const std::vector<geometry::Vec<dim>> &U, const int q2,
                           const std::vector<geometry::Vec<dim>> &W2) {
              auto &B = block(p, q2);
              for (int a = 0; a < n_modes; ++a)
                for (int b = 0; b < n_modes; ++b)
                  B[a * n_modes + b] += geometry::dot(U[a], W2[b]);
            };
            add(ca, u, ca, u);
            if (cb >= 0 && cb != ca)
            {
              add(ca, u, cb, v);
              add(cb, v, ca, u);
              add(cb, v, cb, v);
            }
          }
          // μ and the weights' E F Eᵀ
          const double mu = offsets[i + 1] - offsets[i] < relax_below ? regularisation : 0.0;
          auto        &D  = block(cell_of[i], cell_of[i]);
          for (int a = 0; a < n_modes; ++a)
            for (int b = 0; b < n_modes; ++b)
            {
              const double *za = &basis[(static_cast<std::size_t>(i) * n_modes + a) * nc];
              const double *zb = &basis[(static_cast<std::size_t>(i) * n_modes + b) * nc];
              double        s  = 0;
              for (int c = 0; c < nc; ++c)
                s += mu * za[c] * zb[c];
              if (free_w[i])
              {
                double ta = 0, tb = 0;
                for (int d = 0; d < dim; ++d)
                {
                  ta += za[dim + dim * d + d];
                  tb += zb[dim + dim * d + d];
                }
                s += free_w[i] * ta * tb * inv_h * inv_h;
              }
              D[a * n_modes + b] += s;
            }
        }
        const int                          N = n_cells * n_modes;
        std::vector<Eigen::Triplet<double>> t;
        double                              dmax = 0;
        for (const auto &[key, B] : blocks)
          for (int a = 0; a < n_modes; ++a)
            if (key.first == key.second)
              dmax = std::max(dmax, B[a * n_modes + a]);
        for (const auto &[key, B] : blocks)
          for (int a = 0; a < n_modes; ++a)
            for (int b = 0; b < n_modes; ++b)
              if (B[a * n_modes + b] != 0)
                t.emplace_back(key.first * n_modes + a, key.second * n_modes + b, B[a * n_modes + b]);
        for (int a = 0; a < N; ++a)
          t.emplace_back(a, a, 1e-12 * dmax + 1e-300);
        Eigen::SparseMatrix<double> E(N, N);
        E.setFromTriplets(t.begin(), t.end());
        solver.compute(E);
        ok = solver.info() == Eigen::Success;
      }

      /// z += Z E⁻¹ Zᵀ r (nc values per particle, the CPU backend's arrays)
      void apply(const double *r, double *z) const
      {
        if (!ok)
          return;
        const int n = static_cast<int>(cell_of.size());
        rr.setZero(static_cast<long>(n_cells) * n_modes);
        for (int i = 0; i < n; ++i)
        {
          if (cell_of[i] < 0)
            continue;
          for (int a = 0; a < n_modes; ++a)
          {
            const double *za = &basis[(static_cast<std::size_t>(i) * n_modes + a) * nc];
            double        s  = 0;
            for (int c = 0; c < nc; ++c)
              s += za[c] * r[nc * i + c];
            rr[cell_of[i] * n_modes + a] += s;
          }
        }
        e = solver.solve(rr);
        for (int i = 0; i < n; ++i)
        {
          if (cell_of[i] < 0)
            continue;
          for (int a = 0; a < n_modes; ++a)
          {
            const double *za = &basis[(static_cast<std::size_t>(i) * n_modes + a) * nc];
            const double  ea = e[cell_of[i] * n_modes + a];
            for (int c = 0; c < nc; ++c)
              z[nc * i + c] += za[c] * ea;
          }
        }
      }

      bool ok = false;

    private:
      std::array<long, dim> key_of(const geometry::Vec<dim> &x) const
      {
        std::array<long, dim> key;
        for (int d = 0; d < dim; ++d)
          key[d] = static_cast<long>(std::floor(x[d] / L));
        return key;
      }

      /// basis values per particle: modes × nc (masked like the rows)
      void evaluate_basis(const geometry::Vec<dim> *x, const int *rows, const DomainBox<dim> &box)
      {
        const int n = static_cast<int>(cell_of.size());
        basis.assign(static_cast<std::size_t>(n) * n_modes * nc, 0.0);
        for (int i = 0; i < n; ++i)
        {
          if (cell_of[i] < 0)
            continue;
          const geometry::Vec<dim> xi = box.difference(x[i], centres[cell_of[i]]) * (1.0 / L);
          double                   phi[n_poly], grad[n_poly][dim];
          poly(xi, phi, grad);
          for (int d = 0; d < dim; ++d)
            for (int q = 0; q < n_poly; ++q)
            {
              double *z = &basis[(static_cast<std::size_t>(i) * n_modes + d * n_poly + q) * nc];
              if (rows[i] == linear_and_constant)
                z[d] = phi[q];
              for (int e = 0; e < dim; ++e)
                z[dim + dim * d + e] = 0.5 / inv_h * grad[q][e] / L;
            }
        }
      }

      static void poly(const geometry::Vec<dim> &xi, double *phi, double (*grad)[dim])
      {
        for (int q = 0; q < n_poly; ++q)
          for (int e = 0; e < dim; ++e)
            grad[q][e] = 0;
        int q = 0;
        phi[q++] = 1;
        for (int d = 0; d < dim; ++d)
        {
          phi[q]       = xi[d];
          grad[q++][d] = 1;
        }
        for (int d = 0; d < dim; ++d)
          for (int e = d; e < dim; ++e)
          {
            phi[q] = xi[d] * xi[e];
            grad[q][d] += xi[e];
            grad[q][e] += xi[d];
            ++q;
          }
      }

      double                                           inv_h = 1, L = 1;
      int                                              n_cells = 0;
      std::vector<int>                                 cell_of;
      std::vector<geometry::Vec<dim>>                  centres;
      std::vector<double>                              basis;
      std::map<std::array<long, dim>, int>             ids; ///< the cells' lattice keys
      Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver;
      mutable Eigen::VectorXd                          rr, e; ///< restricted residual, coarse solution
    };
  } // namespace conservative_detail
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
