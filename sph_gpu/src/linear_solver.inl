// CSR SpMV and right-preconditioned BiCGStab (van der Vorst 1992), compiled once per
// backend. Every vector operation is a functor run through a Thrust algorithm with `exec`.
#include <twinflow_sph/linear_solver.h>

#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/inner_product.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/transform_reduce.h>

#include <cmath>
#include <limits>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND
{
  namespace
  {
    /// y[i] = sum_k values[k] x[indices[k]] over row i.
    struct SpmvRow
    {
      const int *offsets, *indices; const double *values, *x; double *y;
      TWINFLOW_HD void operator()(int i) const
      {
        double sum = 0;
        for (int k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * x[indices[k]];
        y[i] = sum;
      }
    };

    /// inv_diag[i] = 1 / A_ii (duplicates summed), 1 where the diagonal is zero.
    struct InverseDiagonal
    {
      const int *offsets, *indices; const double *values; double *inv_diag;
      TWINFLOW_HD void operator()(int i) const
      {
        double d = 0;
        for (int k = offsets[i]; k < offsets[i + 1]; ++k)
          if (indices[k] == i) d += values[k];
        inv_diag[i] = d != 0 ? 1 / d : 1;
      }
    };

    /// out[i] = x[i] + a y[i] (out may alias x).
    struct Axpy
    {
      double *out; const double *x; double a; const double *y;
      TWINFLOW_HD void operator()(int i) const { out[i] = x[i] + a * y[i]; }
    };

    /// out[i] = d[i] in[i].
    struct Scale
    {
      double *out; const double *d, *in;
      TWINFLOW_HD void operator()(int i) const { out[i] = d[i] * in[i]; }
    };

    /// p[i] = r[i] + beta (p[i] − omega v[i]).
    struct UpdateDirection
    {
      double *p; const double *r, *v; double beta, omega;
      TWINFLOW_HD void operator()(int i) const { p[i] = r[i] + beta * (p[i] - omega * v[i]); }
    };

    /// Vector updates shorter than this run on the calling thread with OpenMP (backend.h): a few
    /// ns of work per entry against a few µs to start the team. Element-wise: the same numbers.
    constexpr long long kSerialEntries = 16384;

    /// Matrix rows (tens of products each) are worth the team from far fewer.
    constexpr long long kSerialRows = 1024;

    template <typename F>
    void apply(int n, const F &f) { for_index(n, f, kSerialEntries); }

    // The inner products stay thrust reductions at every size: a serial sum rounds differently,
    // and the splash dam break's largest speed moves with round-off (doc/performance.md).
    double dot(const dvec<double> &a, const dvec<double> &b) { return thrust::inner_product(exec, a.begin(), a.end(), b.begin(), 0.0); }
    double norm(const dvec<double> &a) { return std::sqrt(dot(a, a)); }

    /// Two inner products in one pass: (a·b, b·b).
    struct DotPair
    {
      double ab, bb;
    };
    struct DotPairOf
    {
      const double *a, *b;
      TWINFLOW_HD DotPair operator()(int i) const { return {a[i] * b[i], b[i] * b[i]}; }
    };
    struct AddDotPair
    {
      TWINFLOW_HD DotPair operator()(const DotPair &x, const DotPair &y) const { return {x.ab + y.ab, x.bb + y.bb}; }
    };
    DotPair dot_pair(const dvec<double> &a, const dvec<double> &b)
    {
      return thrust::transform_reduce(exec, thrust::counting_iterator<int>(0), thrust::counting_iterator<int>(int(b.size())),
                                      DotPairOf{ptr(a), ptr(b)}, DotPair{0, 0}, AddDotPair());
    }

    /// x[i] += a y[i] + b z[i].
    struct Axpby
    {
      double *x; double a; const double *y; double b; const double *z;
      TWINFLOW_HD void operator()(int i) const { x[i] += a * y[i] + b * z[i]; }
    };

    struct Csr { const dvec<int> &offsets, &indices; const dvec<double> &values; };

    /// keep[i] = 1 unless row i's only non-zero is its (non-zero) diagonal; inv_diag[i] = 1 / A_ii.
    struct ClassifyRow
    {
      const int *offsets, *indices; const double *values; int *keep; double *inv_diag;
      TWINFLOW_HD void operator()(int i) const
      {
        double d = 0;
        bool   coupled = false;
        for (int k = offsets[i]; k < offsets[i + 1]; ++k)
          if (indices[k] == i) d += values[k];
          else coupled = coupled || values[k] != 0;
        keep[i]     = coupled || d == 0;
        inv_diag[i] = d != 0 ? 1 / d : 1;
      }
    };

    /// full_row[reduced_row[i]] = i for the kept rows.
    struct ListKept
    {
      const int *keep, *reduced_row; int *full_row;
      TWINFLOW_HD void operator()(int i) const { if (keep[i]) full_row[reduced_row[i]] = i; }
    };

    /// Non-zero entries of kept row r in kept columns: counted (values_r null) or written.
    struct ReduceRow
    {
      const int    *offsets = nullptr, *indices = nullptr;
      const double *values = nullptr;
      const int    *keep = nullptr, *reduced_row = nullptr, *full_row = nullptr;
      int          *count = nullptr;     ///< first pass: entries per reduced row
      int          *indices_r = nullptr; ///< second pass (values_r set): the entries
      const int    *offsets_r = nullptr;
      double       *values_r  = nullptr;
      TWINFLOW_HD void operator()(int r) const
      {
        const int i = full_row[r];
        int       m = 0;
        for (int k = offsets[i]; k < offsets[i + 1]; ++k)
          if (values[k] != 0 && keep[indices[k]])
          {
            if (values_r) indices_r[offsets_r[r] + m] = reduced_row[indices[k]], values_r[offsets_r[r] + m] = values[k];
            ++m;
          }
        if (!values_r) count[r] = m;
      }
    };

    /// known[i] = b_i / A_ii on the known rows, 0 on the kept ones.
    struct KnownValue
    {
      const int *keep; const double *b, *inv_diag; double *known;
      TWINFLOW_HD void operator()(int i) const { known[i] = keep[i] ? 0.0 : b[i] * inv_diag[i]; }
    };

    /// b_r[r] = b_i − Σ_j A_ij known_j and x_r[r] = x_i for i = full_row[r].
    struct ReduceRhs
    {
      const int    *offsets = nullptr, *indices = nullptr;
      const double *values = nullptr, *b = nullptr, *known = nullptr, *x = nullptr;
      const int    *full_row = nullptr;
      double       *b_r = nullptr, *x_r = nullptr;
      TWINFLOW_HD void operator()(int r) const
      {
        const int i = full_row[r];
        double    s = b[i];
        for (int k = offsets[i]; k < offsets[i + 1]; ++k) s -= values[k] * known[indices[k]];
        b_r[r] = s;
        x_r[r] = x[i];
      }
    };

    /// x_i = x_r of its reduced row, or its known value.
    struct ExpandSolution
    {
      const int *keep, *reduced_row; const double *x_r, *known; double *x;
      TWINFLOW_HD void operator()(int i) const { x[i] = keep[i] ? x_r[reduced_row[i]] : known[i]; }
    };

    /// r = b − A x, returns ||r||.
    double residual(const Csr &A, const dvec<double> &b, const dvec<double> &x, dvec<double> &r)
    {
      spmv(A.offsets, A.indices, A.values, x, r);
      apply(int(b.size()), Axpy{ptr(r), ptr(b), -1.0, ptr(r)});
      return norm(r);
    }
  } // namespace

  void spmv(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
            const dvec<double> &x, dvec<double> &y)
  {
    const int n = offsets.empty() ? 0 : int(offsets.size()) - 1;
    if (int(y.size()) != n) y.resize(n);
    for_index(n, SpmvRow{ptr(offsets), ptr(indices), ptr(values), ptr(x), ptr(y)}, kSerialRows);
  }

  void inverse_diagonal(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                        dvec<double> &inv_diag)
  {
    const int n = offsets.empty() ? 0 : int(offsets.size()) - 1;
    inv_diag.resize(n);
    for_index(n, InverseDiagonal{ptr(offsets), ptr(indices), ptr(values), ptr(inv_diag)}, kSerialRows);
  }

  JacobiPreconditioner::JacobiPreconditioner(const dvec<int> &offsets, const dvec<int> &indices,
                                             const dvec<double> &values)
  {
    inverse_diagonal(offsets, indices, values, inv_diag);
  }

  void JacobiPreconditioner::apply(const dvec<double> &r, dvec<double> &z) const
  {
    if (z.size() != r.size()) z.resize(r.size());
    TWINFLOW_SPH_BACKEND::apply(int(r.size()), Scale{ptr(z), ptr(inv_diag), ptr(r)});
  }

  void ReducedSystem::build(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values)
  {
    n_full       = offsets.empty() ? 0 : int(offsets.size()) - 1;
    full_offsets = ptr(offsets), full_indices = ptr(indices), full_values = ptr(values);
    keep.resize(n_full), inv_diag.resize(n_full), reduced_row.resize(n_full);
    for_index(n_full, ClassifyRow{full_offsets, full_indices, full_values, ptr(keep), ptr(inv_diag)}, kSerialRows);
    thrust::exclusive_scan(exec, keep.begin(), keep.end(), reduced_row.begin());
    n_kept = n_full == 0 ? 0 : int(reduced_row.back()) + int(keep.back());
    full_row.resize(n_kept);
    for_index(n_full, ListKept{ptr(keep), ptr(reduced_row), ptr(full_row)}, kSerialRows);
    offsets_r.resize(n_kept + 1);
    ReduceRow row;
    row.offsets     = full_offsets;
    row.indices     = full_indices;
    row.values      = full_values;
    row.keep        = ptr(keep);
    row.reduced_row = ptr(reduced_row);
    row.full_row    = ptr(full_row);
    row.count       = ptr(offsets_r);
    for_index(n_kept, row, kSerialRows); // counts into offsets_r[0, n_kept)
    offsets_r.back() = 0;
    thrust::exclusive_scan(exec, offsets_r.begin(), offsets_r.end(), offsets_r.begin());
    indices_r.resize(offsets_r.back()), values_r.resize(offsets_r.back());
    row.indices_r = ptr(indices_r);
    row.offsets_r = ptr(offsets_r);
    row.values_r  = ptr(values_r);
    for_index(n_kept, row, kSerialRows);
    jacobi_ready = false;
  }

  SolverResult ReducedSystem::solve(const dvec<double> &b, dvec<double> &x, const SolverSettings &settings,
                                    const Preconditioner *M)
  {
    if (int(x.size()) != n_full) x.assign(n_full, 0.0);
    known.resize(n_full), b_r.resize(n_kept), x_r.resize(n_kept);
    for_index(n_full, KnownValue{ptr(keep), ptr(b), ptr(inv_diag), ptr(known)}, kSerialEntries);
    ReduceRhs reduce;
    reduce.offsets  = full_offsets;
    reduce.indices  = full_indices;
    reduce.values   = full_values;
    reduce.b        = ptr(b);
    reduce.known    = ptr(known);
    reduce.x        = ptr(x);
    reduce.full_row = ptr(full_row);
    reduce.b_r      = ptr(b_r);
    reduce.x_r      = ptr(x_r);
    for_index(n_kept, reduce, kSerialRows);
    SolverResult result;
    result.converged = true;
    if (n_kept > 0)
    {
      if (!M && !jacobi_ready)
        jacobi = JacobiPreconditioner(offsets_r, indices_r, values_r), jacobi_ready = true;
      result = bicgstab(offsets_r, indices_r, values_r, b_r, x_r, settings, M ? *M : jacobi);
    }
    for_index(n_full, ExpandSolution{ptr(keep), ptr(reduced_row), ptr(x_r), ptr(known), ptr(x)}, kSerialEntries);
    return result;
  }

  SolverResult bicgstab(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                        const dvec<double> &b, dvec<double> &x, const SolverSettings &settings)
  {
    return bicgstab(offsets, indices, values, b, x, settings, JacobiPreconditioner(offsets, indices, values));
  }

  SolverResult bicgstab(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                        const dvec<double> &b, dvec<double> &x, const SolverSettings &settings,
                        const Preconditioner &M)
  {
    const Csr    A{offsets, indices, values};
    const int    n     = int(b.size());
    const double tiny  = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();
    SolverResult result;
    if (int(x.size()) != n) x.assign(n, 0.0);
    const double bnorm = norm(b);
    if (bnorm == 0) { thrust::fill(exec, x.begin(), x.end(), 0.0); result.converged = true; return result; }
    const double target = settings.tolerance * bnorm;

    // Work vectors, kept between calls (a solve per step and component: no allocation and
    // first-touch of ~9 n doubles each time). Deliberately never freed: a static device vector
    // would be destroyed after the CUDA runtime at exit.
    struct Workspace { dvec<double> r, r_hat, p, v, p_hat, s, s_hat, t, x_best; };
    static Workspace *work = new Workspace;
    for (dvec<double> *w : {&work->r, &work->r_hat, &work->p, &work->v, &work->p_hat, &work->s, &work->s_hat, &work->t,
                            &work->x_best})
      if (int(w->size()) != n) w->resize(n);
    dvec<double> &r = work->r, &r_hat = work->r_hat, &p = work->p, &v = work->v, &p_hat = work->p_hat, &s = work->s,
                 &s_hat = work->s_hat, &t = work->t, &x_best = work->x_best;
    thrust::copy(exec, x.begin(), x.end(), x_best.begin());
    double r_norm = residual(A, b, x, r), best = r_norm, r_hat_norm = 0, rho_old = 1, alpha = 1, omega = 1;
    bool   restart = true;
    int    it = 0, last_restart = -1;
    // r is the unpreconditioned residual (right preconditioning). When its recurrence claims
    // convergence the true residual is recomputed; if that disagrees the iteration restarts from it.
    // The iterate of least residual is kept: a failed solve (breakdown, iteration limit, singular
    // inconsistent system) returns it rather than a diverged one.
    while (r_norm > target && it < settings.max_iterations)
    {
      if (r_norm < best) best = r_norm, thrust::copy(exec, x.begin(), x.end(), x_best.begin());
      if (restart)
      {
        last_restart = it;
        thrust::copy(exec, r.begin(), r.end(), r_hat.begin());
        thrust::fill(exec, p.begin(), p.end(), 0.0);
        thrust::fill(exec, v.begin(), v.end(), 0.0);
        r_hat_norm = r_norm, rho_old = alpha = omega = 1, restart = false;
      }
      const double rho = dot(r_hat, r);
      // A breakdown restarts the iteration from the current residual (new shadow residual r̂);
      // one right after a restart, without progress in between, ends the solve.
      const bool fresh = last_restart == it;
      const auto recover = [&] {
        if (!fresh) r_norm = residual(A, b, x, r), restart = true;
        return !fresh;
      };
      if (!(std::abs(rho) > tiny * r_hat_norm * r_norm))                      // rho breakdown
      {
        if (recover()) continue;
        break;
      }
      const double beta = rho / rho_old * (alpha / omega);
      apply(n, UpdateDirection{ptr(p), ptr(r), ptr(v), beta, omega});
      M.apply(p, p_hat);
      spmv(offsets, indices, values, p_hat, v);
      const DotPair rv = dot_pair(r_hat, v); // (r̂·v, v·v)
      if (!(std::abs(rv.ab) > tiny * r_hat_norm * std::sqrt(rv.bb)))         // (r̂, v) breakdown
      {
        if (recover()) continue;
        break;
      }
      alpha = rho / rv.ab;
      apply(n, Axpy{ptr(s), ptr(r), -alpha, ptr(v)});
      ++it;
      const double s_norm = norm(s);
      if (s_norm <= target)                                                   // half step suffices
      {
        apply(n, Axpy{ptr(x), ptr(x), alpha, ptr(p_hat)});
        r_norm = residual(A, b, x, r), restart = true;
        continue;
      }
      M.apply(s, s_hat);
      spmv(offsets, indices, values, s_hat, t);
      const DotPair st = dot_pair(s, t); // (t·s, t·t)
      const double  tt = st.bb, ts = st.ab;
      if (!(std::abs(ts) > tiny * std::sqrt(tt) * s_norm))                   // omega breakdown
      {
        apply(n, Axpy{ptr(x), ptr(x), alpha, ptr(p_hat)});                    // keep the half step
        if (recover()) continue;
        break;
      }
      omega = ts / tt;
      apply(n, Axpby{ptr(x), alpha, ptr(p_hat), omega, ptr(s_hat)});
      apply(n, Axpy{ptr(r), ptr(s), -omega, ptr(t)});
      r_norm = norm(r), rho_old = rho;
      if (r_norm <= target) r_norm = residual(A, b, x, r), restart = true;
    }
    result.iterations = it;
    result.residual   = residual(A, b, x, r) / bnorm;                        // honest final residual
    if (!(result.residual <= settings.tolerance))                          // also when NaN
    {
      const double best_residual = residual(A, b, x_best, r) / bnorm;
      if (!(result.residual <= best_residual))
        thrust::copy(exec, x_best.begin(), x_best.end(), x.begin()), result.residual = best_residual;
    }
    result.converged  = result.residual <= settings.tolerance;
    return result;
  }
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND
