// solve_named (linear_solve.h): the iterations of every named system are counted for the run
// summary, and a solve that does not converge becomes an error naming the system.
#include <twinflow/fem/linear_solve.h>

#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

using namespace twinflow::fem;

namespace
{
  /// A = diag(1, ..., n): CG without a preconditioner needs exactly n iterations (n distinct
  /// eigenvalues, the right-hand side has a component along each eigenvector).
  struct Diagonal
  {
    explicit Diagonal(const unsigned int n)
      : b(n), x(n)
    {
      pattern.reinit(n, n, 1);
      for (unsigned int i = 0; i < n; ++i)
        pattern.add(i, i);
      pattern.compress();
      a.reinit(pattern);
      for (unsigned int i = 0; i < n; ++i)
      {
        a.set(i, i, i + 1.0);
        b[i] = 1.0;
      }
    }
    dealii::SparsityPattern      pattern;
    dealii::SparseMatrix<double> a;
    dealii::Vector<double>       b, x;
  };
} // namespace

TEST(LinearSolve, CountsIterationsAndCallsPerSystem)
{
  linear_solve_counts().clear();
  Diagonal d(5);
  for (int call = 0; call < 2; ++call)
  {
    d.x = 0;
    dealii::SolverControl            control(100, 1e-12);
    dealii::SolverCG<dealii::Vector<double>> cg(control);
    solve_named("diagonal", control, [&] { cg.solve(d.a, d.x, d.b, dealii::PreconditionIdentity()); });
  }
  const auto &c = linear_solve_counts().at("diagonal");
  EXPECT_EQ(c.calls, 2u);
  EXPECT_EQ(c.iterations, 10u); // 5 per solve
  for (unsigned int i = 0; i < 5; ++i)
    EXPECT_NEAR(d.x[i], 1.0 / (i + 1.0), 1e-10);
}

TEST(LinearSolve, NonConvergenceNamesTheSystem)
{
  Diagonal d(5);
  dealii::SolverControl                    control(2, 1e-14); // 2 < 5 iterations needed
  dealii::SolverCG<dealii::Vector<double>> cg(control);
  try
  {
    solve_named("test system", control, [&] { cg.solve(d.a, d.x, d.b, dealii::PreconditionIdentity()); });
    FAIL() << "a solve stopped after 2 of 5 iterations must throw";
  }
  catch (const std::exception &e)
  {
    const std::string what = e.what();
    EXPECT_NE(what.find("test system"), std::string::npos) << what;
    EXPECT_NE(what.find("did not converge"), std::string::npos) << what;
  }
}
