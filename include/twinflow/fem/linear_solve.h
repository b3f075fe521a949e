#pragma once
/**
 * @file linear_solve.h
 * One place that turns a Krylov solver's failure into an error a user can act on: which
 * system of which physics failed, after how many iterations, with what residual.
 */
#include <deal.II/base/exceptions.h>
#include <deal.II/lac/solver_control.h>

#include <sstream>
#include <string>

namespace twinflow::fem
{
  /// Run @p solve (a call of a deal.II solver); a SolverControl::NoConvergence becomes an
  /// error naming @p system ("Navier-Stokes velocity", ...).
  template <typename Solve>
  void solve_named(const std::string &system, Solve &&solve)
  {
    try
    {
      solve();
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
} // namespace twinflow::fem
