#pragma once
/**
 * @file linear_solve.h
 * One place that turns a Krylov solver's failure into an error a user can act on (which
 * system of which physics failed, after how many iterations, with what residual) and counts
 * the iterations of every named system for the run summary (the cost of a step is mostly
 * its Krylov iterations).
 */
#include <deal.II/base/exceptions.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace twinflow::fem
{
  /// Calls and Krylov iterations of one named linear system, summed over a run (this rank).
  struct LinearSolveCounts
  {
    unsigned long calls      = 0;
    unsigned long iterations = 0;
  };

  /// The counts of every system solved through solve_named() in this process.
  std::map<std::string, LinearSolveCounts> &linear_solve_counts();

  /// Run @p solve (a call of a deal.II solver driven by @p control); a
  /// SolverControl::NoConvergence becomes an error naming @p system ("Navier-Stokes
  /// velocity", ...). The iterations are added to linear_solve_counts()[system].
  template <typename Solve>
  void solve_named(const std::string &system, const dealii::SolverControl &control, Solve &&solve)
  {
    try
    {
      solve();
      auto &c = linear_solve_counts()[system];
      ++c.calls;
      c.iterations += control.last_step();
    }
    catch (const dealii::SolverControl::NoConvergence &e)
    {
      std::ostringstream msg;
      msg << "the linear solver of the " << system << " system did not converge: residual "
          << e.last_residual << " after " << e.last_step
          << " iterations. The system is probably ill-posed by a diverging state (check the time step "
             "and the CFL number) or its tolerance is below what the preconditioner reaches";
      AssertThrow(false, dealii::ExcMessage(msg.str()));
    }
  }

  /// As solve_named(), but a solve that does not converge within @p control's limit returns
  /// false instead of failing (the caller retries, e.g. with a fresh preconditioner). The
  /// iterations are counted either way.
  template <typename Solve>
  bool try_solve_named(const std::string &system, const dealii::SolverControl &control, Solve &&solve)
  {
    bool converged = true;
    try
    {
      solve();
    }
    catch (const dealii::SolverControl::NoConvergence &)
    {
      converged = false;
    }
    auto &c = linear_solve_counts()[system];
    ++c.calls;
    c.iterations += control.last_step();
    return converged;
  }

  /**
   * Sets @p amg up for @p matrix with the settings of @p data, as PreconditionAMG::initialize
   * does, but with ML's validation of the parameter list turned off: ML checks every entry of
   * the list against its table of valid names at each set-up, which was 16 % of the set-up time
   * of the pressure AMG that the two-phase flow rebuilds every step. The hierarchy is the same.
   * Every AMG of the FEM solvers is set up through here.
   */
  void initialize_amg(dealii::TrilinosWrappers::PreconditionAMG                       &amg,
                      const dealii::TrilinosWrappers::SparseMatrix                    &matrix,
                      const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data);

  /**
   * ILU(0) of a Trilinos matrix whose sparsity stays while its values change every step (the
   * level-set transports): Ifpack's symbolic factorisation (the fill graph) is built on the
   * first compute() for a matrix and kept; later calls redo only the numeric factorisation.
   * The same factors as dealii::TrilinosWrappers::PreconditionILU with its defaults (no fill,
   * no overlap, no thresholds). clear() after the matrix is re-created (a new mesh).
   */
  class ReusableIlu : public dealii::TrilinosWrappers::PreconditionBase
  {
  public:
    /// Factor the current values of @p matrix.
    void compute(const dealii::TrilinosWrappers::SparseMatrix &matrix);
    /// Forget the symbolic factorisation (the matrix object or its sparsity changed).
    void clear();

  private:
    const Epetra_CrsMatrix *factored = nullptr; ///< the matrix the symbolic part belongs to
  };

  /**
   * Point Jacobi (ω = 1) for a Trilinos matrix whose sparsity stays while its values change
   * (the momentum matrix, the correction's mass): the place of each local row's diagonal
   * entry is found once per matrix, and each compute() reads the values there. It applies the
   * same D⁻¹ as dealii::TrilinosWrappers::PreconditionJacobi with its defaults, without
   * Epetra's diagonal extraction through map look-ups and, on several ranks, without the local
   * copy of the whole matrix that Ifpack's additive Schwarz wrapper makes on every set-up.
   */
  class InverseDiagonal
  {
  public:
    /// D⁻¹ of the current values of @p matrix.
    void compute(const dealii::TrilinosWrappers::SparseMatrix &matrix);
    /// Forget the diagonal's places (the matrix object or its sparsity changed).
    void clear() { indexed = nullptr; }
    /// dst = D⁻¹ src; src may also be k copies of the matrix's rows one after the other
    /// (component blocks, see ComponentBlockMatrix): each copy is scaled by D⁻¹.
    void vmult(dealii::TrilinosWrappers::MPI::Vector &dst, const dealii::TrilinosWrappers::MPI::Vector &src) const;

  private:
    const Epetra_CrsMatrix               *indexed = nullptr;
    std::vector<int>                      place; ///< of the diagonal in each local row's storage
    dealii::TrilinosWrappers::MPI::Vector inverse;
  };

  /**
   * diag(S, …, S): k copies of one square matrix S acting on a vector whose owned part on
   * each rank is k consecutive pieces, each laid out as S's owned rows (the velocity numbered
   * by components, NavierStokes::number_velocity_by_components). vmult() views the pieces as
   * the k columns of an Epetra_MultiVector and forms S X in one product: S is read once for
   * all k instead of k times (the product is bound by reading the matrix), with the same
   * result as the k-block matrix.
   */
  class ComponentBlockMatrix
  {
  public:
    ComponentBlockMatrix(const dealii::TrilinosWrappers::SparseMatrix &block, unsigned int copies);
    void vmult(dealii::TrilinosWrappers::MPI::Vector &dst, const dealii::TrilinosWrappers::MPI::Vector &src) const;

  private:
    const Epetra_CrsMatrix &matrix;
    const unsigned int      copies;
  };
} // namespace twinflow::fem
