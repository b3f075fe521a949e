#pragma once
/**
 * @file linear_solver.h
 * CSR sparse matrix–vector product and right-preconditioned BiCGStab over Thrust vectors:
 * one source for both backends (no library serves CPU and CUDA alike). The preconditioner
 * is Jacobi by default, or any Preconditioner (e.g. the cell-aggregation multigrid of
 * multigrid.h) that applies a fixed linear operator z = M⁻¹ r.
 */
#include <twinflow_sph/backend.h>
#include <twinflow_sph/solver_settings.h>

namespace twinflow::sph
{
  namespace TWINFLOW_SPH_BACKEND
  {
    /// y = A x for A in CSR form (offsets n+1, column indices, values).
    void spmv(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
              const dvec<double> &x, dvec<double> &y);

    /// inv_diag[i] = 1 / A_ii (duplicates summed), 1 where the diagonal is zero.
    void inverse_diagonal(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                          dvec<double> &inv_diag);

    /// z = M⁻¹ r for a fixed linear M (BiCGStab needs the same operator in every call).
    class Preconditioner
    {
    public:
      virtual ~Preconditioner() = default;
      virtual void apply(const dvec<double> &r, dvec<double> &z) const = 0;
    };

    /// M = diag(A) (rows with a zero diagonal use 1).
    class JacobiPreconditioner : public Preconditioner
    {
    public:
      JacobiPreconditioner() = default;
      JacobiPreconditioner(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values);
      void apply(const dvec<double> &r, dvec<double> &z) const override;

    private:
      dvec<double> inv_diag;
    };

    /// Solves A x = b by BiCGStab with Jacobi preconditioning; x holds the initial guess.
    /// Never throws on breakdown: the result says whether it converged.
    SolverResult bicgstab(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                          const dvec<double> &b, dvec<double> &x, const SolverSettings &settings);

    /// The same with the preconditioner @p M (right preconditioning: the residual is A's own).
    SolverResult bicgstab(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                          const dvec<double> &b, dvec<double> &x, const SolverSettings &settings,
                          const Preconditioner &M);

    /// A x = b without its known rows. A row whose only non-zero is its diagonal (a free-surface
    /// particle's p = p_s, a BCE marker with no fluid in its support, a prescribed velocity) fixes
    /// x_i = b_i / A_ii; in a dam break those are ~40 % of the pressure rows, and the zero entries
    /// of the marker–marker pairs another ~35 % of the matrix. build() keeps the other rows and their
    /// non-zero entries in a compact CSR; solve() moves the known columns to the right-hand side,
    /// solves the kept rows by BiCGStab from the kept part of x and writes every row of x back.
    /// The solution is that of the full system; a Krylov iteration over it has the same iterates
    /// on the kept rows (the known rows are exact from the start), at ~60 % of the cost.
    class ReducedSystem
    {
    public:
      void build(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values);
      /// Rows of the reduced system.
      int size() const { return n_kept; }
      /// kept()[r]: the row of the full system that reduced row r is.
      const dvec<int> &kept() const { return full_row; }
      const dvec<int> &offsets() const { return offsets_r; }
      const dvec<int> &indices() const { return indices_r; }
      const dvec<double> &values() const { return values_r; }
      /// Solves the full system A x = b (x: the initial guess of the kept rows) through the
      /// reduced one, preconditioned by @p M (built on the reduced matrix) or, if null, Jacobi
      /// (built once per build(): the velocity's components share it).
      /// The result's residual is that of the kept rows (the known rows have none).
      SolverResult solve(const dvec<double> &b, dvec<double> &x, const SolverSettings &settings,
                         const Preconditioner *M = nullptr);

    private:
      int          n_full = 0, n_kept = 0;
      const int   *full_offsets = nullptr, *full_indices = nullptr; ///< the matrix of the last build
      const double *full_values = nullptr;
      dvec<int>    keep, reduced_row, full_row, offsets_r, indices_r;
      dvec<double> inv_diag, values_r, known, b_r, x_r;
      JacobiPreconditioner jacobi;          ///< of the reduced matrix, when a solve needs it
      bool                 jacobi_ready = false;
    };
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
