#include <twinflow/sph/front.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace twinflow::sph
{
  template <int dim>
  double foremost_particle(const HostParticles<dim> &P, const double dx)
  {
    double xf = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.kind[i] == ParticleKind::fluid)
        xf = std::max(xf, P.x[i][0] + 0.5 * dx);
    return xf;
  }

  template <int dim>
  double surge_front(const HostParticles<dim> &P, const double dx)
  {
    const double xmax = foremost_particle(P, dx) - 0.5 * dx;
    if (std::isinf(xmax))
      return xmax;
    const double r = front_neighbour_radius * dx, r2 = r * r;
    // Only the particles within a window behind the foremost one are sorted (foremost first)
    // and tested in that order; the first connected one is the front. A candidate's verdict
    // is final if all of its neighbours lie in the window (x_c − r ≥ window start); otherwise
    // the window is doubled, up to the whole fluid.
    std::vector<std::size_t> window;
    for (double width = 8 * dx;; width *= 2)
    {
      const double lo = xmax - width;
      window.clear();
      bool everything = true;
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.kind[i] == ParticleKind::fluid)
        {
          if (P.x[i][0] >= lo)
            window.push_back(i);
          else
            everything = false;
        }
      std::sort(window.begin(), window.end(), [&](std::size_t a, std::size_t b) { return P.x[a][0] > P.x[b][0]; });
      for (std::size_t c = 0; c < window.size(); ++c)
      {
        const auto &xc = P.x[window[c]];
        if (!everything && xc[0] - r < lo)
          break; // its neighbourhood is not all in the window: widen it
        int neighbours = 0;
        // the particles within r in x lie in a stretch of the sorted window around c
        for (std::size_t k = c; k-- > 0 && P.x[window[k]][0] - xc[0] <= r;)
          neighbours += geometry::norm_square(P.x[window[k]] - xc) <= r2;
        for (std::size_t k = c + 1; k < window.size() && xc[0] - P.x[window[k]][0] <= r; ++k)
          neighbours += geometry::norm_square(P.x[window[k]] - xc) <= r2;
        if (neighbours >= front_min_neighbours)
          return xc[0] + 0.5 * dx;
      }
      if (everything)
        return xmax + 0.5 * dx; // no connected particle at all
    }
  }

  template double surge_front<2>(const HostParticles<2> &, double);
  template double surge_front<3>(const HostParticles<3> &, double);
  template double foremost_particle<2>(const HostParticles<2> &, double);
  template double foremost_particle<3>(const HostParticles<3> &, double);
} // namespace twinflow::sph
