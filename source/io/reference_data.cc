/**
 * @file reference_data.cc
 * Implementation of ReferenceSeries, interpolate_linear() and compare_series().
 */
#include <twinflow/io/csv_table.h>
#include <twinflow/io/reference_data.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace twinflow::io
{
  namespace
  {
    double
    range_tolerance(const double lo, const double hi)
    {
      return 1e-12 * std::max({std::abs(hi - lo), std::abs(lo), std::abs(hi), 1e-300});
    }
  } // namespace

  double
  interpolate_linear(const std::vector<double> &x, const std::vector<double> &y, const double xq)
  {
    if (x.empty() || x.size() != y.size())
      throw std::invalid_argument("interpolate_linear: empty table or size mismatch");
    const double tol = range_tolerance(x.front(), x.back());
    if (!(xq >= x.front() - tol && xq <= x.back() + tol))
      throw std::out_of_range("interpolate_linear: " + std::to_string(xq) + " outside [" +
                              std::to_string(x.front()) + ", " + std::to_string(x.back()) + "]");
    const double xc = std::max(xq, x.front()); // clamp values within the tolerance
    if (xc >= x.back())
      return y.back();
    // first index with x[i] > xc; then x[i-1] <= xc < x[i] (x[i-1]: last of repeated x)
    const auto   i  = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), xc) - x.begin());
    const double x0 = x[i - 1], x1 = x[i];
    const double w  = (xc - x0) / (x1 - x0);
    return (1.0 - w) * y[i - 1] + w * y[i];
  }

  ReferenceSeries::ReferenceSeries(std::vector<double> x, std::vector<double> y, std::string name)
    : label(std::move(name))
  {
    if (x.empty() || x.size() != y.size())
      throw std::invalid_argument("ReferenceSeries '" + label + "': empty or size mismatch");
    std::vector<std::size_t> order(x.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return x[a] < x[b]; });
    xs.reserve(x.size());
    ys.reserve(y.size());
    for (const auto i : order)
      {
        if (!xs.empty() && xs.back() == x[i])
          throw std::invalid_argument("ReferenceSeries '" + label + "': duplicate x = " +
                                      std::to_string(x[i]));
        xs.push_back(x[i]);
        ys.push_back(y[i]);
      }
  }

  ReferenceSeries
  ReferenceSeries::from_csv(const std::string &path,
                            const std::string &x_column,
                            const std::string &y_column,
                            const double       x_scale,
                            const double       y_scale,
                            const double       y_offset)
  {
    const CsvTable      table = read_csv(path);
    std::vector<double> x     = table.column(x_column);
    std::vector<double> y     = table.column(y_column);
    for (auto &v : x)
      v *= x_scale;
    for (auto &v : y)
      v = y_scale * v + y_offset;
    return ReferenceSeries(std::move(x), std::move(y), path + ":" + y_column);
  }

  double
  ReferenceSeries::operator()(const double x) const
  {
    return interpolate_linear(xs, ys, x);
  }

  bool
  ReferenceSeries::covers(const double x) const
  {
    const double tol = range_tolerance(xs.front(), xs.back());
    return x >= xs.front() - tol && x <= xs.back() + tol;
  }

  double
  ReferenceSeries::x_min() const
  {
    return xs.front();
  }

  double
  ReferenceSeries::x_max() const
  {
    return xs.back();
  }

  std::size_t
  ReferenceSeries::size() const
  {
    return xs.size();
  }

  const std::vector<double> &
  ReferenceSeries::x() const
  {
    return xs;
  }

  const std::vector<double> &
  ReferenceSeries::y() const
  {
    return ys;
  }

  const std::string &
  ReferenceSeries::name() const
  {
    return label;
  }

  SeriesError
  compare_series(const std::vector<double> &t,
                 const std::vector<double> &y,
                 const ReferenceSeries &    reference,
                 const SamplePoints         where)
  {
    if (t.size() != y.size())
      throw std::invalid_argument("compare_series: time and value series differ in size");
    if (!std::is_sorted(t.begin(), t.end()))
      throw std::invalid_argument("compare_series: simulated times are not non-decreasing");

    SeriesError  result;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (t.empty() || t.back() < reference.x_min() || t.front() > reference.x_max())
      {
        result.rms_error = result.max_error = nan;
        result.rms_relative_error = result.max_relative_error = nan;
        result.t_begin = result.t_end = nan;
        return result;
      }
    result.t_begin = std::max(t.front(), reference.x_min());
    result.t_end   = std::min(t.back(), reference.x_max());

    double sum_e2 = 0, sum_r2 = 0, max_e = 0, max_r = 0;
    auto   add = [&](const double sim, const double ref) {
      const double e = sim - ref;
      sum_e2 += e * e;
      sum_r2 += ref * ref;
      max_e = std::max(max_e, std::abs(e));
      max_r = std::max(max_r, std::abs(ref));
      ++result.n_samples;
    };
    if (where == SamplePoints::reference)
      {
        for (std::size_t i = 0; i < reference.size(); ++i)
          {
            const double tr = reference.x()[i];
            if (tr >= result.t_begin && tr <= result.t_end)
              add(interpolate_linear(t, y, tr), reference.y()[i]);
          }
      }
    else
      {
        for (std::size_t i = 0; i < t.size(); ++i)
          if (t[i] >= result.t_begin && t[i] <= result.t_end)
            add(y[i], reference(t[i]));
      }

    if (result.n_samples == 0)
      {
        result.rms_error = result.max_error = nan;
        result.rms_relative_error = result.max_relative_error = nan;
        return result;
      }
    const double n            = static_cast<double>(result.n_samples);
    result.rms_error          = std::sqrt(sum_e2 / n);
    result.max_error          = max_e;
    result.rms_relative_error = sum_r2 > 0 ? std::sqrt(sum_e2 / sum_r2) : nan;
    result.max_relative_error = max_r > 0 ? max_e / max_r : nan;
    return result;
  }
} // namespace twinflow::io
