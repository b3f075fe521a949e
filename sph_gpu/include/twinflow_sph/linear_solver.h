#pragma once
/**
 * @file linear_solver.h
 * CSR sparse matrix–vector product and Jacobi-preconditioned BiCGStab over Thrust
 * vectors: one source for both backends (no library serves CPU and CUDA alike).
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

    /// Solves A x = b by BiCGStab with Jacobi preconditioning; x holds the initial guess.
    /// Rows with a zero diagonal use 1 in the preconditioner. Never throws on breakdown:
    /// the result says whether it converged.
    SolverResult bicgstab(const dvec<int> &offsets, const dvec<int> &indices, const dvec<double> &values,
                          const dvec<double> &b, dvec<double> &x, const SolverSettings &settings);
  } // namespace TWINFLOW_SPH_BACKEND
} // namespace twinflow::sph
