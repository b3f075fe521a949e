#pragma once
/// @file domain.h  The box the particles live in, with periodic directions (minimum image).
#include <twinflow/geometry/hd.h>
#include <twinflow/geometry/vec.h>

namespace twinflow::sph
{
  template <int dim>
  struct DomainBox
  {
    geometry::Vec<dim> lower, upper;
    bool               periodic[dim];

    /// r_ij = x_i − x_j with the minimum-image convention in periodic directions.
    TWINFLOW_HD geometry::Vec<dim> difference(const geometry::Vec<dim> &xi, const geometry::Vec<dim> &xj) const
    {
      geometry::Vec<dim> r;
      for (int d = 0; d < dim; ++d)
      {
        r[d] = xi[d] - xj[d];
        if (periodic[d])
        {
          const double L = upper[d] - lower[d];
          if (r[d] > 0.5 * L)
            r[d] -= L;
          else if (r[d] < -0.5 * L)
            r[d] += L;
        }
      }
      return r;
    }

    /// Wrap a position back into the box in periodic directions.
    TWINFLOW_HD geometry::Vec<dim> wrap(geometry::Vec<dim> x) const
    {
      for (int d = 0; d < dim; ++d)
        if (periodic[d])
        {
          const double L = upper[d] - lower[d];
          while (x[d] < lower[d]) x[d] += L;
          while (x[d] >= upper[d]) x[d] -= L;
        }
      return x;
    }
  };
} // namespace twinflow::sph
