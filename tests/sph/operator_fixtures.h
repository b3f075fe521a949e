#pragma once
// Fixtures shared by the SPH operator tests (test_operators.cc, test_summation_by_parts.cc):
// host copies, boxes, CSR rows, perturbed lattices and a Problem holding the operators of one.
#include <twinflow_sph/neighbor_search.h>
#include <twinflow_sph/operators.h>

#include <thrust/copy.h>

#include <random>
#include <utility>
#include <vector>

namespace twinflow_test_sph_operators
{
  namespace sph = twinflow::sph;
  using sph::CubicSpline;
  using sph::DomainBox;
  using sph::OperatorKind;
  using sph::Tensor2;
  using sph::cpu::dvec;
  using sph::cpu::NeighborList;
  using sph::cpu::NeighborSearch;
  using sph::cpu::OperatorMatrices;
  template <int dim>
  using Vec = twinflow::geometry::Vec<dim>;

  template <typename T>
  std::vector<T> host(const dvec<T> &v)
  {
    std::vector<T> h(v.size());
    thrust::copy(v.begin(), v.end(), h.begin());
    return h;
  }

  template <int dim>
  DomainBox<dim> make_box(const double lo, const double hi, const std::vector<bool> &periodic)
  {
    DomainBox<dim> box;
    for (int d = 0; d < dim; ++d)
    {
      box.lower[d]    = lo;
      box.upper[d]    = hi;
      box.periodic[d] = periodic[d];
    }
    return box;
  }

  /// Rows of a CSR neighbour list on the host.
  inline std::vector<std::vector<int>> rows_of(const NeighborList &nl)
  {
    const auto                    off = host(nl.offsets), idx = host(nl.indices);
    std::vector<std::vector<int>> rows(nl.n);
    for (int i = 0; i < nl.n; ++i)
      rows[i].assign(idx.begin() + off[i], idx.begin() + off[i + 1]);
    return rows;
  }

  // ------------------------------------------------------------------ lattices

  /// Truncated lattice of N^dim particles of spacing dx = 1/N in [0,1]^dim (cell centres),
  /// each coordinate perturbed by U(−a, a)·dx.
  template <int dim>
  std::vector<Vec<dim>> lattice(const int N, const double a, const unsigned seed)
  {
    const double                           dx = 1.0 / N;
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> u(-a, a);
    std::vector<Vec<dim>>                  x;
    int                                    total = 1;
    for (int d = 0; d < dim; ++d)
      total *= N;
    for (int c = 0; c < total; ++c)
    {
      Vec<dim> p;
      int      code = c;
      for (int d = 0; d < dim; ++d)
      {
        p[d] = (code % N + 0.5) * dx;
        code /= N;
      }
      for (int d = 0; d < dim; ++d)
        p[d] += u(rng) * dx;
      x.push_back(p);
    }
    return x;
  }

  template <int dim>
  struct Problem
  {
    DomainBox<dim>        box;
    CubicSpline<dim>      W;
    std::vector<Vec<dim>> xh;
    dvec<Vec<dim>>        x;
    NeighborList          nl;
    dvec<double>          V;
    dvec<Tensor2<dim>>    G, L;
    int                   fallbacks = 0;
    OperatorMatrices<dim> standard, consistent;

    /// @p dx: the lattice spacing, which scales the standard rows as the engine does (lattice_scale)
    Problem(const DomainBox<dim> &box_, const double h, std::vector<Vec<dim>> xh_, const double dx = 0)
      : box(box_), W(h), xh(std::move(xh_)), x(xh.begin(), xh.end())
    {
      NeighborSearch<dim> search(box, W.support());
      search.build(x, nl);
      sph::cpu::compute_volumes(x, nl, box, W, V);
      fallbacks = sph::cpu::compute_corrections(x, V, nl, box, W, G, L);
      sph::cpu::assemble_operators(x, V, nl, box, W, OperatorKind::standard, G, L, standard, nullptr, nullptr,
                                   sph::cpu::lattice_scale(W, dx));
      sph::cpu::assemble_operators(x, V, nl, box, W, OperatorKind::consistent, G, L, consistent);
    }
  };
} // namespace twinflow_test_sph_operators
