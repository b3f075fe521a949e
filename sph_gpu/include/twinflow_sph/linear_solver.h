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
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
