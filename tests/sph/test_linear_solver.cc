// CSR SpMV and Jacobi-BiCGStab of the SPH backend (CPU build) against Eigen.
#include <twinflow_sph/linear_solver.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace
{
  namespace sph = twinflow::sph;
  using sph::cpu::dvec;
  using SpMat    = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  using ColMat   = Eigen::SparseMatrix<double>;
  using Triplets = std::vector<Eigen::Triplet<double>>;

  struct DeviceCsr
  {
    dvec<int>    offsets, indices;
    dvec<double> values;
  };

  DeviceCsr to_device(SpMat A)
  {
    A.makeCompressed();
    const int rows = int(A.rows()), nnz = int(A.nonZeros());
    return {dvec<int>(A.outerIndexPtr(), A.outerIndexPtr() + rows + 1),
            dvec<int>(A.innerIndexPtr(), A.innerIndexPtr() + nnz),
            dvec<double>(A.valuePtr(), A.valuePtr() + nnz)};
  }

  dvec<double> to_device(const Eigen::VectorXd &v) { return dvec<double>(v.data(), v.data() + v.size()); }

  Eigen::VectorXd to_host(const dvec<double> &v)
  {
    Eigen::VectorXd h(v.size());
    thrust::copy(v.begin(), v.end(), h.data());
    return h;
  }

  SpMat from_triplets(int rows, int cols, const Triplets &t)
  {
    SpMat A(rows, cols);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  }

  /// -Δu + β·∇u on an m×m interior grid of the unit square, central differences.
  SpMat convection_diffusion(int m, double bx, double by)
  {
    const double h = 1.0 / (m + 1);
    Triplets     t;
    auto id = [m](int i, int j) { return j * m + i; };
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
      {
        t.emplace_back(id(i, j), id(i, j), 4 / (h * h));
        const double e = -1 / (h * h) + bx / (2 * h), w = -1 / (h * h) - bx / (2 * h);
        const double nn = -1 / (h * h) + by / (2 * h), s = -1 / (h * h) - by / (2 * h);
        if (i + 1 < m) t.emplace_back(id(i, j), id(i + 1, j), e);
        if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), w);
        if (j + 1 < m) t.emplace_back(id(i, j), id(i, j + 1), nn);
        if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), s);
      }
    return from_triplets(m * m, m * m, t);
  }

  /// Random nonsymmetric sparse matrix, strictly diagonally dominant by `margin`, mixed-sign diagonal.
  SpMat random_dominant(int n, int per_row, double margin, std::mt19937 &rng)
  {
    std::uniform_int_distribution<int>     col(0, n - 1);
    std::uniform_real_distribution<double> val(-1, 1);
    Triplets                               t;
    for (int i = 0; i < n; ++i)
    {
      double off = 0;
      for (int k = 0; k < per_row; ++k)
      {
        const int j = col(rng);
        if (j == i) continue;
        const double a = val(rng);
        t.emplace_back(i, j, a), off += std::abs(a);   // duplicates summed by setFromTriplets
      }
      t.emplace_back(i, i, (i % 7 == 0 ? -1 : 1) * (margin * off + 0.1));
    }
    return from_triplets(n, n, t);
  }

  /// SPH-like I − c·L: L_ij = V_j W(r_ij) (j ≠ i), L_ii = −Σ_j L_ij on jittered particles,
  /// unequal volumes V_j make it nonsymmetric. With `identity` false it is the (singular) −c·L.
  SpMat sph_like(int m, double c, std::mt19937 &rng, bool identity = true)
  {
    std::uniform_real_distribution<double> jitter(-0.3, 0.3), volume(0.5, 1.5);
    const double                           dx = 1.0 / m, radius = 2.2 * dx;
    const int                              n  = m * m;
    std::vector<double>                    px(n), py(n), vol(n);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        px[j * m + i] = (i + 0.5 + jitter(rng)) * dx, py[j * m + i] = (j + 0.5 + jitter(rng)) * dx,
                 vol[j * m + i] = volume(rng);
    Triplets t;
    for (int i = 0; i < n; ++i)
    {
      double diag = 0;
      for (int j = 0; j < n; ++j)
      {
        const double r = std::hypot(px[i] - px[j], py[i] - py[j]);
        if (j == i || r >= radius) continue;
        const double w = vol[j] * std::pow(1 - r / radius, 3) / (dx * dx);
        t.emplace_back(i, j, -c * w), diag += c * w;
      }
      t.emplace_back(i, i, diag + (identity ? 1 : 0));
    }
    return from_triplets(n, n, t);
  }

  Eigen::VectorXd random_vector(int n, std::mt19937 &rng)
  {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::VectorXd                        v(n);
    for (int i = 0; i < n; ++i) v[i] = u(rng);
    return v;
  }

  double relative(const Eigen::VectorXd &a, const Eigen::VectorXd &b) { return (a - b).norm() / b.norm(); }

  bool all_finite(const Eigen::VectorXd &v) { return v.allFinite(); }

  /// Solves with the backend and Eigen, checks both against SparseLU, prints iterations.
  void compare_with_eigen(const char *name, const SpMat &A, std::mt19937 &rng)
  {
    const int             n = int(A.rows());
    const Eigen::VectorXd b = random_vector(n, rng);
    const ColMat          Ac(A);

    Eigen::SparseLU<ColMat> lu(Ac);
    ASSERT_EQ(lu.info(), Eigen::Success);
    const Eigen::VectorXd exact = lu.solve(b);

    Eigen::BiCGSTAB<ColMat, Eigen::DiagonalPreconditioner<double>> eigen(Ac);
    eigen.setTolerance(1e-12);
    eigen.setMaxIterations(5000);
    const Eigen::VectorXd x_eigen = eigen.solve(b);

    const DeviceCsr    dA = to_device(A);
    const dvec<double> db = to_device(b);
    dvec<double>       dx(n, 0.0);
    sph::SolverSettings settings;
    settings.tolerance      = 1e-12;
    settings.max_iterations = 5000;
    const sph::SolverResult res = sph::cpu::bicgstab(dA.offsets, dA.indices, dA.values, db, dx, settings);
    const Eigen::VectorXd   x   = to_host(dx);

    const double true_res = (b - A * x).norm() / b.norm();
    std::printf("[%s] n=%d nnz=%ld  twinflow: %d it, res %.2e, err %.2e | Eigen: %ld it, res %.2e, err %.2e"
                " | |x-x_eigen|/|x| %.2e\n",
                name, n, long(A.nonZeros()), res.iterations, res.residual, relative(x, exact), long(eigen.iterations()),
                eigen.error(), relative(x_eigen, exact), relative(x, x_eigen));
    EXPECT_TRUE(res.converged);
    EXPECT_LE(res.residual, settings.tolerance);
    EXPECT_NEAR(res.residual, true_res, 1e-14);
    EXPECT_GT(res.iterations, 0);
    EXPECT_EQ(eigen.info(), Eigen::Success);
    EXPECT_LT(relative(x, exact), 1e-8);
    EXPECT_LT(relative(x_eigen, exact), 1e-8);
    EXPECT_LT(relative(x, x_eigen), 1e-8);
  }
} // namespace

TEST(SphLinearSolver, SpmvMatchesEigen)
{
  std::mt19937 rng(42);
  for (const auto [rows, cols, density] : {std::tuple{1, 1, 1.0}, std::tuple{50, 50, 0.1}, std::tuple{300, 200, 0.02},
                                           std::tuple{200, 300, 0.05}, std::tuple{1000, 1000, 0.005},
                                           std::tuple{3000, 3000, 0.002}}) // above the serial-row threshold too
  {
    std::uniform_real_distribution<double> u(0, 1), val(-2, 2);
    Triplets                               t;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        if (u(rng) < density) t.emplace_back(i, j, val(rng));
    const SpMat           A = from_triplets(rows, cols, t);   // includes empty rows
    const Eigen::VectorXd x = random_vector(cols, rng);
    const DeviceCsr       dA = to_device(A);
    dvec<double>          y;                                 // resized by spmv
    sph::cpu::spmv(dA.offsets, dA.indices, dA.values, to_device(x), y);
    ASSERT_EQ(int(y.size()), rows);
    const Eigen::VectorXd ref = A * x, got = to_host(y);
    EXPECT_LE((got - ref).lpNorm<Eigen::Infinity>(), 1e-13 * (1 + ref.lpNorm<Eigen::Infinity>()))
      << rows << "x" << cols;
  }
}

namespace
{
  struct CountVisit
  {
    int *visits;
    void operator()(int i) const { ++visits[i]; }
  };
} // namespace

// for_index (backend.h) runs a short loop on the calling thread and a long one on the OpenMP
// team: both visit every index of [0, n) exactly once.
TEST(SphLinearSolver, ForIndexVisitsEveryIndexOnceOnBothPaths)
{
  for (const int n : {0, 1, 2047, 2048, 5000})
  {
    dvec<int> visits(n, 0);
    sph::cpu::for_index(n, CountVisit{sph::cpu::ptr(visits)}, 2048);
    const std::vector<int> host(visits.begin(), visits.end());
    for (int i = 0; i < n; ++i)
      ASSERT_EQ(host[i], 1) << "n = " << n << ", i = " << i;
  }
}

TEST(SphLinearSolver, ConvectionDiffusion)
{
  std::mt19937 rng(1);
  compare_with_eigen("convection-diffusion 50x50", convection_diffusion(50, 40, -25), rng);
}

TEST(SphLinearSolver, RandomDiagonallyDominant)
{
  std::mt19937 rng(2);
  compare_with_eigen("random dominant", random_dominant(600, 8, 1.05, rng), rng);
}

TEST(SphLinearSolver, SphLikeIMinusCL)
{
  std::mt19937 rng(3);
  compare_with_eigen("SPH-like I-cL", sph_like(30, 0.05, rng), rng);
}

TEST(SphLinearSolver, ZeroRightHandSide)
{
  std::mt19937        rng(4);
  const SpMat         A  = convection_diffusion(10, 1, 1);
  const DeviceCsr     dA = to_device(A);
  const dvec<double>  b(A.rows(), 0.0);
  dvec<double>        x = to_device(random_vector(int(A.rows()), rng));
  const auto          res = sph::cpu::bicgstab(dA.offsets, dA.indices, dA.values, b, x, {});
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_EQ(res.residual, 0);
  EXPECT_EQ(to_host(x).lpNorm<Eigen::Infinity>(), 0);
}

TEST(SphLinearSolver, InitialGuessIsSolution)
{
  std::mt19937            rng(5);
  const SpMat             A = random_dominant(300, 6, 1.2, rng);
  const Eigen::VectorXd   b = random_vector(300, rng);
  Eigen::SparseLU<ColMat> lu{ColMat(A)};
  const Eigen::VectorXd   exact = lu.solve(b);
  const DeviceCsr         dA    = to_device(A);
  dvec<double>            x     = to_device(exact);
  const auto res = sph::cpu::bicgstab(dA.offsets, dA.indices, dA.values, to_device(b), x, {});
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_LE(res.residual, 1e-14);
  EXPECT_EQ(to_host(x), exact);
}

TEST(SphLinearSolver, IterationLimit)
{
  std::mt19937        rng(6);
  const SpMat         A  = convection_diffusion(50, 40, -25);
  const DeviceCsr     dA = to_device(A);
  dvec<double>        x(A.rows(), 0.0);
  sph::SolverSettings settings;
  settings.max_iterations = 3;
  const auto res = sph::cpu::bicgstab(dA.offsets, dA.indices, dA.values, to_device(random_vector(int(A.rows()), rng)),
                                      x, settings);
  EXPECT_FALSE(res.converged);
  EXPECT_EQ(res.iterations, 3);
  EXPECT_TRUE(std::isfinite(res.residual));
  EXPECT_GT(res.residual, settings.tolerance);
}

TEST(SphLinearSolver, BreakdownAndSingularReportedNotConverged)
{
  struct Case
  {
    const char     *name;
    SpMat           A;
    Eigen::VectorXd b;
  };
  std::mt19937      rng(7);
  std::vector<Case> cases;
  // Rotation (zero diagonal): (r̂, A r̂) = 0 at the first step.
  cases.push_back({"rotation", from_triplets(2, 2, {{0, 1, 1.0}, {1, 0, -1.0}}), Eigen::Vector2d(1, 0)});
  // Zero row with nonzero right-hand side: inconsistent, breaks down.
  cases.push_back({"zero row", from_triplets(2, 2, {{0, 0, 1.0}}), Eigen::Vector2d(1, 1)});
  // Singular rank-one matrix, inconsistent right-hand side.
  cases.push_back({"rank one", from_triplets(2, 2, {{0, 0, 1.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 1.0}}),
                   Eigen::Vector2d(1, 0)});
  // Pure SPH Laplacian (constants in the kernel) with a right-hand side of nonzero mean.
  {
    SpMat L = sph_like(12, 1, rng, false);
    cases.push_back({"singular Laplacian", L, Eigen::VectorXd::Ones(L.rows()) + random_vector(int(L.rows()), rng)});
  }
  for (const auto &c : cases)
  {
    const DeviceCsr     dA = to_device(c.A);
    dvec<double>        x(c.A.rows(), 0.0);
    sph::SolverSettings settings;
    settings.max_iterations = 5000;
    sph::SolverResult res;
    EXPECT_NO_THROW(res = sph::cpu::bicgstab(dA.offsets, dA.indices, dA.values, to_device(c.b), x, settings));
    const Eigen::VectorXd xh = to_host(x);
    std::printf("[%s] converged=%d it=%d residual=%.3e\n", c.name, int(res.converged), res.iterations, res.residual);
    EXPECT_FALSE(res.converged) << c.name;
    EXPECT_TRUE(std::isfinite(res.residual)) << c.name;
    EXPECT_LE(res.residual, 1 + 1e-12) << c.name;   // no worse than the initial guess x = 0
    EXPECT_TRUE(all_finite(xh)) << c.name;
    EXPECT_NEAR(res.residual, (c.b - c.A * xh).norm() / c.b.norm(), 1e-12) << c.name;
  }
}

// ReducedSystem: the rows with only a diagonal (free-surface particles, dry BCE markers) are
// known; the kept rows are solved alone. An SPH-like system in which every third row is made
// such a row, its off-diagonal entries kept as stored zeros as the engine's matrices keep them,
// and some kept rows' entries zeroed too: the solution equals the full system's (SparseLU), the
// known rows are exact, and the reduced matrix holds exactly the kept rows' non-zeros in kept columns.
TEST(SphLinearSolver, ReducedSystemDropsKnownRows)
{
  std::mt19937 rng(8);
  SpMat        A = sph_like(24, 0.05, rng);
  const int    n = int(A.rows());
  std::vector<bool> known(n);
  for (int i = 0; i < n; ++i) known[i] = i % 3 == 1;
  long expected_nnz = 0;
  for (int i = 0; i < n; ++i)
    for (SpMat::InnerIterator it(A, i); it; ++it)
    {
      if (known[i]) it.valueRef() = it.col() == i ? 2.0 : 0.0;
      else if (it.col() != i && (i + it.col()) % 11 == 0) it.valueRef() = 0.0; // a stored zero of a kept row
      expected_nnz += !known[i] && !known[it.col()] && it.value() != 0;
    }
  const Eigen::VectorXd   b = random_vector(n, rng);
  Eigen::SparseLU<ColMat> lu{ColMat(A)};
  ASSERT_EQ(lu.info(), Eigen::Success);
  const Eigen::VectorXd exact = lu.solve(b);

  const DeviceCsr    dA = to_device(A);
  sph::cpu::ReducedSystem reduced;
  reduced.build(dA.offsets, dA.indices, dA.values);
  EXPECT_EQ(reduced.size(), n - n / 3);
  EXPECT_EQ(long(reduced.values().size()), expected_nnz);
  EXPECT_EQ(long(reduced.indices().size()), expected_nnz);
  dvec<double>        x(n, 0.0);
  sph::SolverSettings settings;
  settings.tolerance = 1e-12;
  const sph::SolverResult res = reduced.solve(to_device(b), x, settings);
  EXPECT_TRUE(res.converged);
  const Eigen::VectorXd h = to_host(x);
  EXPECT_LT(relative(h, exact), 1e-9);
  EXPECT_LT((b - A * h).norm() / b.norm(), 1e-11);
  for (int i = 0; i < n; ++i)
    if (known[i]) EXPECT_EQ(h[i], 0.5 * b[i]) << "row " << i;
}
