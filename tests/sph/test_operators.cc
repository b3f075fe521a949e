// SPH neighbour search and operators of the CPU backend: neighbour lists against brute
// force, kernel normalisation, and the standard (Eq. 19–20) vs consistent (Eq. 22–26)
// gradient and Laplacian on regular and perturbed truncated lattices, interior vs edge.
#include "operator_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace
{
  using namespace twinflow_test_sph_operators;

  /// y = A f for one CSR value array.
  std::vector<double> apply(const NeighborList &nl, const dvec<double> &values, const std::vector<double> &f)
  {
    const auto          off = host(nl.offsets), idx = host(nl.indices);
    const auto          val = host(values);
    std::vector<double> y(nl.n, 0.0);
    for (int i = 0; i < nl.n; ++i)
      for (int k = off[i]; k < off[i + 1]; ++k)
        y[i] += val[k] * f[idx[k]];
    return y;
  }

  // ------------------------------------------------------------------ neighbour search

  template <int dim>
  void check_against_brute_force(const std::vector<bool> &periodic, const double L, const double radius,
                                 const int n, const bool far_particle, const unsigned seed, const int sparse_first = 0)
  {
    const DomainBox<dim>                   box = make_box<dim>(0.0, L, periodic);
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> inside(0.0, L), outside(-0.2 * L, 1.2 * L);
    std::vector<Vec<dim>>                  x(n);
    for (auto &p : x)
      for (int d = 0; d < dim; ++d)
        p[d] = periodic[d] ? inside(rng) : outside(rng);
    if (far_particle)
      for (int d = 0; d < dim; ++d)
        if (!periodic[d])
          x.back()[d] = 1e4 * L;
    // a few exact duplicates and particles on cell boundaries
    if (n > 10)
    {
      x[1] = x[0];
      for (int d = 0; d < dim; ++d)
        x[2][d] = periodic[d] ? 0.0 : radius;
    }

    NeighborSearch<dim> search(box, radius);
    NeighborList        nl;
    // sparse_first > 0: the search first sees only that many particles, so its neighbour slots
    // (sized by the last build's longest row) are too short for the full set and must grow
    if (sparse_first > 0)
      search.build(dvec<Vec<dim>>(x.begin(), x.begin() + sparse_first), nl);
    search.build(dvec<Vec<dim>>(x.begin(), x.end()), nl);
    ASSERT_EQ(nl.n, int(x.size()));
    ASSERT_EQ(nl.offsets.size(), x.size() + 1);
    const auto rows = rows_of(nl);

    std::size_t total = 0;
    for (int i = 0; i < int(x.size()); ++i)
    {
      std::vector<int> expected;
      for (int j = 0; j < int(x.size()); ++j)
      {
        const Vec<dim> r = box.difference(x[i], x[j]);
        if (twinflow::geometry::norm_square(r) < radius * radius || i == j)
          expected.push_back(j);
      }
      total += expected.size();
      ASSERT_EQ(rows[i], expected) << "particle " << i;
    }
    EXPECT_EQ(nl.n_entries(), total);
    // build again into the same list (reuse of the search's buffers)
    search.build(dvec<Vec<dim>>(x.begin(), x.end()), nl);
    EXPECT_EQ(rows_of(nl), rows);
  }

  TEST(SphNeighborSearch, BruteForce2D)
  {
    check_against_brute_force<2>({false, false}, 1.0, 0.07, 1500, false, 1);
    check_against_brute_force<2>({true, false}, 1.0, 0.07, 1500, false, 2);
    check_against_brute_force<2>({true, true}, 1.0, 0.07, 1500, false, 3);
    // periodic directions with 2 and 1 cells: every cell visited once
    check_against_brute_force<2>({true, true}, 1.0, 0.45, 300, false, 4);
    check_against_brute_force<2>({true, false}, 1.0, 0.7, 200, false, 5);
    // a far particle: the dense grid would be huge, cells are hashed
    check_against_brute_force<2>({false, false}, 1.0, 0.01, 2000, true, 6);
    check_against_brute_force<2>({true, false}, 1.0, 0.01, 2000, true, 7);
    check_against_brute_force<2>({false, false}, 1.0, 0.1, 1, false, 8);
    // rows 15x longer than those of the search's previous build
    check_against_brute_force<2>({false, false}, 1.0, 0.07, 1500, false, 9, 100);
  }

  TEST(SphNeighborSearch, BruteForce3D)
  {
    check_against_brute_force<3>({false, false, false}, 1.0, 0.12, 2500, false, 11);
    check_against_brute_force<3>({true, false, false}, 1.0, 0.12, 2500, false, 12);
    check_against_brute_force<3>({true, true, true}, 1.0, 0.12, 2500, false, 13);
    check_against_brute_force<3>({true, false, true}, 1.0, 0.45, 400, false, 14);
    check_against_brute_force<3>({true, true, true}, 1.0, 0.7, 200, false, 15);
    check_against_brute_force<3>({false, false, false}, 1.0, 0.05, 2500, true, 16);
    check_against_brute_force<3>({false, true, false}, 1.0, 0.05, 2500, true, 17);
    check_against_brute_force<3>({true, true, true}, 1.0, 0.12, 2500, false, 18, 100);
  }

  TEST(SphNeighborSearch, Empty)
  {
    NeighborSearch<2> search(make_box<2>(0, 1, {false, false}), 0.1);
    NeighborList      nl;
    search.build(dvec<Vec<2>>(), nl);
    EXPECT_EQ(nl.n, 0);
    EXPECT_EQ(nl.offsets.size(), 1u);
    EXPECT_EQ(nl.n_entries(), 0u);
  }


  // ------------------------------------------------------------------ kernel

  template <int dim>
  void check_kernel_normalisation()
  {
    const double     h = 0.37;
    CubicSpline<dim> W(h);
    const int        m     = dim == 2 ? 400 : 120;
    const double     delta = 4 * h / m;
    double           sum   = 0;
    int              total = 1;
    for (int d = 0; d < dim; ++d)
      total *= m;
    for (int c = 0; c < total; ++c)
    {
      double r2   = 0;
      int    code = c;
      for (int d = 0; d < dim; ++d)
      {
        const double t = -2 * h + (code % m + 0.5) * delta;
        r2 += t * t;
        code /= m;
      }
      sum += W.value(std::sqrt(r2));
    }
    sum *= std::pow(delta, dim);
    std::cout << dim << "D: integral of W on a lattice of spacing h/" << m / 4 << ": " << sum << "\n";
    EXPECT_NEAR(sum, 1.0, 1e-4);

    // Shepard sums Σ_j W_ij V_j on a regular lattice (exactly 1 in the interior) and a perturbed one
    for (const double a : {0.0, 0.2})
    {
      const int      N  = dim == 2 ? 24 : 12;
      const double   dx = 1.0 / N, hh = 1.2 * dx;
      Problem<dim>     s(make_box<dim>(0, 1, std::vector<bool>(dim, false)), hh, lattice<dim>(N, a, 21));
      const auto     V   = host(s.V);
      const auto     off = host(s.nl.offsets), idx = host(s.nl.indices);
      double         err_int = 0, err_all = 0, vol_err = 0;
      for (int i = 0; i < s.nl.n; ++i)
      {
        double shepard = 0;
        for (int k = off[i]; k < off[i + 1]; ++k)
          shepard += s.W.value(twinflow::geometry::norm(s.box.difference(s.xh[i], s.xh[idx[k]]))) * V[idx[k]];
        bool interior = true;
        for (int d = 0; d < dim; ++d)
          interior = interior && s.xh[i][d] > 4 * hh && s.xh[i][d] < 1 - 4 * hh;
        err_all = std::max(err_all, std::abs(shepard - 1));
        if (interior)
        {
          err_int = std::max(err_int, std::abs(shepard - 1));
          vol_err = std::max(vol_err, std::abs(V[i] / std::pow(dx, dim) - 1));
        }
      }
      std::cout << dim << "D lattice (perturbation " << a << " dx): |sum_j W_ij V_j - 1| interior " << err_int
                << ", all " << err_all << "; interior |V/dx^d - 1| " << vol_err << "\n";
      if (a == 0.0)
      {
        EXPECT_LT(err_int, 1e-12);
        EXPECT_LT(vol_err, 5e-3);
      }
      else
        EXPECT_LT(err_int, 0.2);  // Shepard sums are not exact on a disordered lattice
    }
  }

  TEST(SphKernel, Normalisation2D) { check_kernel_normalisation<2>(); }
  TEST(SphKernel, Normalisation3D) { check_kernel_normalisation<3>(); }

  // ------------------------------------------------------------------ operators

  /// Max relative errors of one operator kind, by particle class; lap_roundoff is the
  /// Laplacian error relative to Σ_k |A^L_ik f_k| (the size of the terms that cancel).
  struct Errors
  {
    double grad_interior = 0, grad_edge = 0, grad_corner = 0;
    double lap_interior = 0, lap_edge = 0, lap_corner = 0, lap_roundoff = 0;
  };

  /// The exact fields: f1 = c + b·x (linear), f2 = c + b·x + ½ xᵀHx (quadratic, ∇²f2 = tr H).
  template <int dim>
  struct Fields
  {
    double b[3]    = {1.1, -0.7, 0.5};
    double H[3][3] = {{1.3, 0.4, -0.2}, {0.4, -0.5, 0.3}, {-0.2, 0.3, 0.9}};
    double c       = 0.3;

    double linear(const Vec<dim> &x) const
    {
      double f = c;
      for (int d = 0; d < dim; ++d)
        f += b[d] * x[d];
      return f;
    }
    double quadratic(const Vec<dim> &x) const
    {
      double f = linear(x);
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          f += 0.5 * x[m] * H[m][n] * x[n];
      return f;
    }
    double grad_norm() const
    {
      double s = 0;
      for (int d = 0; d < dim; ++d)
        s += b[d] * b[d];
      return std::sqrt(s);
    }
    double laplacian() const
    {
      double t = 0;
      for (int d = 0; d < dim; ++d)
        t += H[d][d];
      return t;
    }
  };

  /// Class of particle i: 0 interior (≥ 4h from every face of [0,1]^dim: its support and
  /// its neighbours' supports are full), 1 near one face (edge: includes the outermost
  /// layers, whose support is one-sided), 2 near two or more faces (corner).
  template <int dim>
  int particle_class(const Vec<dim> &x, const double h)
  {
    int faces = 0;
    for (int d = 0; d < dim; ++d)
      faces += (x[d] < 4 * h) + (x[d] > 1 - 4 * h);
    return faces == 0 ? 0 : (faces == 1 ? 1 : 2);
  }

  template <int dim>
  Errors errors_of(const Problem<dim> &s, const OperatorMatrices<dim> &A, const double h)
  {
    const Fields<dim>   F;
    std::vector<double> f1(s.xh.size()), f2(s.xh.size());
    for (std::size_t i = 0; i < s.xh.size(); ++i)
    {
      f1[i] = F.linear(s.xh[i]);
      f2[i] = F.quadratic(s.xh[i]);
    }
    std::vector<std::vector<double>> g(dim);
    for (int d = 0; d < dim; ++d)
      g[d] = apply(s.nl, A.gradient[d], f1);
    const std::vector<double> lap = apply(s.nl, A.laplacian, f2);
    std::vector<double>       f2_abs(f2.size()), lap_abs_values = host(A.laplacian);
    for (std::size_t i = 0; i < f2.size(); ++i)
      f2_abs[i] = std::abs(f2[i]);
    for (double &v : lap_abs_values)
      v = std::abs(v);
    dvec<double>              lap_abs(lap_abs_values.begin(), lap_abs_values.end());
    const std::vector<double> scale = apply(s.nl, lap_abs, f2_abs);
    Errors                    e;
    for (std::size_t i = 0; i < s.xh.size(); ++i)
    {
      double ge = 0;
      for (int d = 0; d < dim; ++d)
        ge += (g[d][i] - F.b[d]) * (g[d][i] - F.b[d]);
      ge              = std::sqrt(ge) / F.grad_norm();
      const double le = std::abs(lap[i] - F.laplacian()) / std::abs(F.laplacian());
      e.lap_roundoff  = std::max(e.lap_roundoff, std::abs(lap[i] - F.laplacian()) / scale[i]);
      switch (particle_class(s.xh[i], h))
      {
        case 0:
          e.grad_interior = std::max(e.grad_interior, ge);
          e.lap_interior  = std::max(e.lap_interior, le);
          break;
        case 1:
          e.grad_edge = std::max(e.grad_edge, ge);
          e.lap_edge  = std::max(e.lap_edge, le);
          break;
        default:
          e.grad_corner = std::max(e.grad_corner, ge);
          e.lap_corner  = std::max(e.lap_corner, le);
      }
    }
    return e;
  }

  template <int dim>
  void check_operators(const double perturbation)
  {
    const int    N  = dim == 2 ? 30 : 14;
    const double dx = 1.0 / N, h = 1.2 * dx;
    Problem<dim>   s(make_box<dim>(0, 1, std::vector<bool>(dim, false)), h, lattice<dim>(N, perturbation, 42), dx);
    EXPECT_EQ(s.fallbacks, 0);

    const Errors st = errors_of(s, s.standard, h);
    const Errors co = errors_of(s, s.consistent, h);
    double       max_L = 0;
    for (const auto &t : host(s.L))
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          max_L = std::max(max_L, std::abs(t.a[m][n]));
    char line[1024];
    std::snprintf(line, sizeof line,
                  "%dD, %d^%d lattice, h = 1.2 dx, perturbation %.2f dx: max relative errors\n"
                  "              grad(linear): interior    edge      corner | lap(quadratic): interior    edge      corner"
                  " | lap err / sum|A_ik f_k|\n"
                  "  standard     %10.3e %10.3e %10.3e |            %10.3e %10.3e %10.3e | %10.3e\n"
                  "  consistent   %10.3e %10.3e %10.3e |            %10.3e %10.3e %10.3e | %10.3e\n"
                  "  max |L_i| entry %.3g\n",
                  dim, N, dim, perturbation, st.grad_interior, st.grad_edge, st.grad_corner, st.lap_interior,
                  st.lap_edge, st.lap_corner, st.lap_roundoff, co.grad_interior, co.grad_edge, co.grad_corner,
                  co.lap_interior, co.lap_edge, co.lap_corner, co.lap_roundoff, max_L);
    std::cout << line;

    // consistent operators reproduce linear / quadratic fields to round-off, also at the edge
    EXPECT_LT(co.grad_interior, 1e-12);
    EXPECT_LT(co.grad_edge, 1e-12);
    EXPECT_LT(co.grad_corner, 1e-12);
    EXPECT_LT(co.lap_interior, 1e-10);
    // the outermost layer has large L (one-sided second differences), so its rows have
    // large coefficients: exact up to round-off of the terms that cancel
    EXPECT_LT(co.lap_roundoff, 1e-12);
    EXPECT_LT(co.lap_edge, 1e-7);
    EXPECT_LT(co.lap_corner, 1e-7);
    // the standard ones do not near the edge
    EXPECT_GT(st.grad_edge, 1e-1);
    EXPECT_GT(st.lap_edge, 1.0);
    EXPECT_GT(st.grad_edge, 1e6 * co.grad_edge);
    EXPECT_GT(st.lap_edge, 1e3 * co.lap_edge);
    // … but are exact in the interior of a regular lattice, scaled by lattice_scale (unscaled,
    // h = 1.2 dx: 0.9 % short for both)
    if (perturbation == 0.0)
    {
      EXPECT_LT(st.grad_interior, 1e-12);
      EXPECT_LT(st.lap_interior, 1e-10);
    }
    // G and L are close to the identity in the regular interior
    if (perturbation == 0.0)
    {
      const auto G = host(s.G), L = host(s.L);
      for (std::size_t i = 0; i < s.xh.size(); ++i)
        if (particle_class(s.xh[i], h) == 0)
          for (int m = 0; m < dim; ++m)
            for (int n = 0; n < dim; ++n)
            {
              EXPECT_NEAR(G[i].a[m][n], m == n ? 1.0 : 0.0, 3e-2);
              EXPECT_NEAR(L[i].a[m][n], m == n ? 1.0 : 0.0, 3e-2);
            }
    }
  }

  TEST(SphOperators, RegularLattice2D) { check_operators<2>(0.0); }
  TEST(SphOperators, PerturbedLattice2D) { check_operators<2>(0.2); }
  TEST(SphOperators, RegularLattice3D) { check_operators<3>(0.0); }
  TEST(SphOperators, PerturbedLattice3D) { check_operators<3>(0.2); }

  /// Strip periodic in x, walls (truncation) at y = 0 and 1: f = f(y) only, through the
  /// periodic seam with minimum-image r_ij.
  TEST(SphOperators, PeriodicStrip2D)
  {
    const int N = 24;
    const double dx = 1.0 / N, h = 1.2 * dx;
    for (const double a : {0.0, 0.2})
    {
      const DomainBox<2>  box = make_box<2>(0, 1, {true, false});
      std::vector<Vec<2>> x   = lattice<2>(N, a, 7);
      for (auto &p : x)
        p = box.wrap(p);  // perturbed positions back into the periodic box
      Problem<2> s(box, h, x);
      EXPECT_EQ(s.fallbacks, 0);
      std::vector<double> f(s.xh.size()), g(s.xh.size());
      for (std::size_t i = 0; i < f.size(); ++i)
      {
        f[i] = 0.5 * s.xh[i][1] * s.xh[i][1] + 0.3 * s.xh[i][1];
        g[i] = 0.8 * s.xh[i][1] - 0.1;
      }
      const auto gx = apply(s.nl, s.consistent.gradient[0], g), gy = apply(s.nl, s.consistent.gradient[1], g),
                 lap = apply(s.nl, s.consistent.laplacian, f);
      double err_gy = 0;
      double err_lap = 0, err_gx = 0;
      for (std::size_t i = 0; i < f.size(); ++i)
      {
        err_lap = std::max(err_lap, std::abs(lap[i] - 1.0));
        err_gx  = std::max(err_gx, std::abs(gx[i]));
        err_gy  = std::max(err_gy, std::abs(gy[i] - 0.8));
      }
      std::cout << "periodic strip, perturbation " << a << " dx: consistent |lap - 1| max " << err_lap
                << ", gradient of 0.8 y - 0.1: |d/dx| max " << err_gx << ", |d/dy - 0.8| max " << err_gy << "\n";
      EXPECT_LT(err_gy, 1e-12);
      EXPECT_LT(err_lap, 1e-8);
      EXPECT_LT(err_gx, 1e-12);
    }
  }

  /// A particle far from all others: identity corrections, finite rows, no NaN anywhere.
  template <int dim>
  void check_isolated()
  {
    const int             N  = dim == 2 ? 12 : 8;
    const double          dx = 1.0 / N, h = 1.2 * dx;
    std::vector<Vec<dim>> x  = lattice<dim>(N, 0.1, 3);
    Vec<dim>              far;
    for (int d = 0; d < dim; ++d)
      far[d] = 50.0;
    x.push_back(far);
    const int  iso = int(x.size()) - 1;
    Problem<dim> s(make_box<dim>(0, 1, std::vector<bool>(dim, false)), h, x);
    EXPECT_EQ(s.fallbacks, 1);
    const auto rows = rows_of(s.nl);
    EXPECT_EQ(rows[iso], std::vector<int>{iso});
    const auto V = host(s.V), G = host(s.G), L = host(s.L);
    EXPECT_DOUBLE_EQ(V[iso], 1.0 / s.W.value(0.0));
    for (int m = 0; m < dim; ++m)
      for (int n = 0; n < dim; ++n)
      {
        EXPECT_EQ(G[iso].a[m][n], m == n ? 1.0 : 0.0);
        EXPECT_EQ(L[iso].a[m][n], m == n ? 1.0 : 0.0);
      }
    for (const auto *A : {&s.standard, &s.consistent})
    {
      for (int d = 0; d < dim; ++d)
        for (const double v : host(A->gradient[d]))
          ASSERT_TRUE(std::isfinite(v));
      for (const double v : host(A->laplacian))
        ASSERT_TRUE(std::isfinite(v));
    }
    for (const auto &t : G)
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          ASSERT_TRUE(std::isfinite(t.a[m][n]));
    for (const auto &t : L)
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          ASSERT_TRUE(std::isfinite(t.a[m][n]));
    // the isolated particle's rows are zero: no gradient, no Laplacian
    const int k = host(s.nl.offsets)[iso];
    EXPECT_EQ(host(s.consistent.laplacian)[k], 0.0);
    EXPECT_EQ(host(s.consistent.gradient[0])[k], 0.0);
  }

  /// The positive-definite check on L (CorrectionChecks, used for splashing flows): on a
  /// perturbed lattice, the truncated outer layers need indefinite L for exactness; with the
  /// check those particles get L = I, all others keep theirs, so the interior rows stay exact
  /// for quadratics.
  template <int dim>
  void check_positive_definite_laplacian()
  {
    const int    N  = dim == 2 ? 30 : 14;
    const double dx = 1.0 / N, h = 1.2 * dx;
    const DomainBox<dim>  box = make_box<dim>(0, 1, std::vector<bool>(dim, false));
    const std::vector<Vec<dim>> xh = lattice<dim>(N, 0.2, 42);
    Problem<dim>          s(box, h, xh); // no checks
    const auto            L_free = host(s.L);
    auto                  spd    = [](const Tensor2<dim> &t) {
      double m2 = t.a[0][0] * t.a[1][1] - t.a[0][1] * t.a[1][0];
      if constexpr (dim == 3)
      {
        const double m3 = t.a[0][0] * (t.a[1][1] * t.a[2][2] - t.a[1][2] * t.a[2][1]) -
                          t.a[0][1] * (t.a[1][0] * t.a[2][2] - t.a[1][2] * t.a[2][0]) +
                          t.a[0][2] * (t.a[1][0] * t.a[2][1] - t.a[1][1] * t.a[2][0]);
        return t.a[0][0] > 0 && m2 > 0 && m3 > 0;
      }
      return t.a[0][0] > 0 && m2 > 0;
    };
    // accepted: positive definite with every eigenvalue <= 4 (4 I - L positive definite too)
    auto well_conditioned = [&](const Tensor2<dim> &t) {
      Tensor2<dim> rest;
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          rest.a[m][n] = (m == n ? 4.0 : 0.0) - t.a[m][n];
      return spd(t) && spd(rest);
    };
    int indefinite = 0, ill = 0, ill_interior = 0;
    for (std::size_t i = 0; i < xh.size(); ++i)
    {
      indefinite += !spd(L_free[i]);
      if (!well_conditioned(L_free[i]))
      {
        ++ill;
        ill_interior += particle_class(xh[i], h) == 0;
      }
    }

    dvec<Tensor2<dim>> G, L;
    sph::CorrectionChecks checks;
    checks.positive_definite_laplacian = true;
    // without free-surface flags (a confined flow): only the indefinite ones are replaced
    EXPECT_EQ(sph::cpu::compute_corrections(s.x, s.V, s.nl, box, s.W, G, L, checks), indefinite);
    // every particle next to a free surface: exactly the ill-conditioned ones are replaced
    const dvec<int> surface(xh.size(), 1);
    const int replaced = sph::cpu::compute_corrections(s.x, s.V, s.nl, box, s.W, G, L, checks, &surface);
    const auto L_checked = host(L);
    int changed = 0;
    for (std::size_t i = 0; i < xh.size(); ++i)
    {
      EXPECT_TRUE(well_conditioned(L_checked[i]));
      bool same = true;
      for (int m = 0; m < dim; ++m)
        for (int n = 0; n < dim; ++n)
          same = same && L_checked[i].a[m][n] == L_free[i].a[m][n];
      changed += !same;
    }
    std::cout << dim << "D perturbed lattice: " << indefinite << " of " << xh.size()
              << " particles have an indefinite L, " << ill << " an indefinite or nearly singular one ("
              << ill_interior << " in the interior); replaced " << replaced << "\n";
    EXPECT_GT(indefinite, 0);
    EXPECT_GT(ill, indefinite); // positive definite, eigenvalue above 4: a degenerate truncated support
    EXPECT_EQ(ill_interior, 0);
    EXPECT_EQ(replaced, ill);
    EXPECT_EQ(changed, ill);

    // interior rows are untouched: the Laplacian of a quadratic stays exact there
    OperatorMatrices<dim> A;
    sph::cpu::assemble_operators(s.x, s.V, s.nl, box, s.W, OperatorKind::consistent, G, L, A);
    std::vector<double> f(xh.size());
    for (std::size_t i = 0; i < xh.size(); ++i)
      for (int d = 0; d < dim; ++d)
        f[i] += 0.5 * xh[i][d] * xh[i][d];
    const auto lap = apply(s.nl, A.laplacian, f);
    double     err = 0;
    for (std::size_t i = 0; i < xh.size(); ++i)
      if (particle_class(xh[i], h) == 0)
        err = std::max(err, std::abs(lap[i] - dim));
    EXPECT_LT(err, 1e-10 * dim);
  }

  TEST(SphOperators, PositiveDefiniteLaplacianCheck2D) { check_positive_definite_laplacian<2>(); }
  TEST(SphOperators, PositiveDefiniteLaplacianCheck3D) { check_positive_definite_laplacian<3>(); }

  TEST(SphOperators, IsolatedParticle2D) { check_isolated<2>(); }
  TEST(SphOperators, IsolatedParticle3D) { check_isolated<3>(); }
} // namespace
