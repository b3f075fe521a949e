#pragma once
/**
 * @file reference_data.h
 * Comparison of simulated time series with reference data (experiments,
 * analytic solutions, published benchmark curves): piecewise-linear
 * interpolation of a reference table and RMS / maximum errors over the
 * overlapping range of the two series.
 */
#include <cstddef>
#include <string>
#include <vector>

namespace twinflow::io
{
  /**
   * A reference curve y(x) given at points x_0 < x_1 < ... < x_{n-1},
   * evaluated by linear interpolation. Points are sorted by x on construction;
   * equal x values are not allowed.
   */
  class ReferenceSeries
  {
  public:
    /// Throws std::invalid_argument if sizes differ, n == 0 or x has duplicates.
    ReferenceSeries(std::vector<double> x, std::vector<double> y, std::string name = "");

    /**
     * Read columns @p x_column and @p y_column of a CSV file (see read_csv()),
     * scaled as x = x_scale * x_file, y = y_scale * y_file + y_offset (e.g. to
     * convert the nondimensional Martin & Moyce data to seconds and metres).
     */
    static ReferenceSeries
    from_csv(const std::string &path,
             const std::string &x_column,
             const std::string &y_column,
             double             x_scale  = 1.0,
             double             y_scale  = 1.0,
             double             y_offset = 0.0);

    /**
     * Linear interpolation at @p x. Throws std::out_of_range if @p x lies
     * outside [x_min(), x_max()] by more than 1e-12 of the range.
     */
    double
    operator()(double x) const;

    /// True if x_min() <= x <= x_max() (with the tolerance of operator()).
    bool
    covers(double x) const;

    double
    x_min() const;
    double
    x_max() const;
    std::size_t
    size() const;
    const std::vector<double> &
    x() const;
    const std::vector<double> &
    y() const;
    const std::string &
    name() const;

  private:
    std::vector<double> xs;
    std::vector<double> ys;
    std::string         label;
  };

  /**
   * Linear interpolation of the table (@p x, @p y) at @p xq; @p x must be
   * non-decreasing (for repeated x the later value wins). Throws
   * std::out_of_range outside [x.front(), x.back()] and
   * std::invalid_argument for empty or inconsistent input.
   */
  double
  interpolate_linear(const std::vector<double> &x, const std::vector<double> &y, double xq);

  /// Where the two series are compared.
  enum class SamplePoints
  {
    /// At the reference abscissae inside the overlap (simulation interpolated).
    /// Natural for sparse experimental data: every measurement counts once.
    reference,
    /// At the simulated times inside the overlap (reference interpolated).
    simulation
  };

  /**
   * Errors of a simulated series against a reference, evaluated at N sample
   * points t_i in the overlap [t_begin, t_end] of the two abscissa ranges,
   * with e_i = y_sim(t_i) - y_ref(t_i):
   *  - rms_error          = sqrt(1/N sum e_i^2)
   *  - max_error          = max |e_i|
   *  - rms_relative_error = sqrt(sum e_i^2 / sum y_ref(t_i)^2)
   *  - max_relative_error = max |e_i| / max |y_ref(t_i)|
   * (relative errors are normalised by the reference magnitude, which stays
   * well defined when the reference crosses zero). If the ranges do not
   * overlap, n_samples == 0 and all errors are NaN.
   */
  struct SeriesError
  {
    double      rms_error          = 0;
    double      max_error          = 0;
    double      rms_relative_error = 0;
    double      max_relative_error = 0;
    std::size_t n_samples          = 0;
    double      t_begin            = 0; ///< start of the overlapping range
    double      t_end              = 0; ///< end of the overlapping range
  };

  /**
   * Compare the simulated series (@p t, @p y) — @p t non-decreasing, as
   * written by a CsvMonitor — with @p reference (see SeriesError).
   * Throws std::invalid_argument if @p t and @p y differ in size.
   */
  SeriesError
  compare_series(const std::vector<double> &t,
                 const std::vector<double> &y,
                 const ReferenceSeries &    reference,
                 SamplePoints               where = SamplePoints::reference);
} // namespace twinflow::io
