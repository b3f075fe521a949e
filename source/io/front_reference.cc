/**
 * @file front_reference.cc
 * Implementation of add_front_reference_errors() (front_reference.h).
 */
#include <twinflow/core/scene.h>
#include <twinflow/io/front_reference.h>
#include <twinflow/io/reference_data.h>

#include <cmath>
#include <optional>
#include <utility>

namespace twinflow::io
{
  namespace
  {
    /// The best delay tau in [lo, hi] on a grid of step @p dt (simulated times t -> t + tau):
    /// the smallest RMS relative error among the shifts that keep at least the samples of
    /// the unshifted comparison @p unshifted (tau = 0 if none is better).
    std::pair<double, SeriesError>
    best_shift(const std::vector<double> &t,
               const std::vector<double> &x,
               const ReferenceSeries &    reference,
               const SeriesError &        unshifted,
               const double               lo,
               const double               hi,
               const double               dt)
    {
      std::pair<double, SeriesError> best{0.0, unshifted};
      for (int k = int(std::ceil(lo / dt)); k * dt <= hi + 1e-15; ++k)
        {
          std::vector<double> shifted(t);
          for (double &ti : shifted)
            ti += k * dt;
          const auto e = compare_series(shifted, x, reference);
          if (e.n_samples >= unshifted.n_samples && e.rms_relative_error < best.second.rms_relative_error)
            best = {k * dt, e};
        }
      return best;
    }
  } // namespace

  FrontScale
  front_scale(const Scene &scene)
  {
    const double a = scene.reference_length;
    const double g = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                               scene.gravity[2] * scene.gravity[2]);
    return {1.0 / std::sqrt(2 * g / a), a};
  }

  void
  add_front_reference_errors(const Scene &                   scene,
                             const std::vector<double> &     t,
                             const std::vector<double> &     x_front,
                             RunSummary &                    summary,
                             std::map<std::string, double> & monitors)
  {
    if (scene.reference_front_file.empty())
      return;
    const FrontScale scale      = front_scale(scene);
    const double     time_scale = scale.time;
    const auto reference = ReferenceSeries::from_csv(scene.reference_front_file, "T", "Z", time_scale, scale.length);
    const auto   error      = compare_series(t, x_front, reference);
    const double tau_max    = scene.reference_front_time_uncertainty;
    // With a time-origin uncertainty the checked error is the fitted one below and the raw
    // error is reported beside it (no tolerance of its own).
    summary.add_series_error("front position x_f(t)", error,
                             tau_max > 0 ? std::optional<double>() : std::optional<double>(0.05),
                             "Martin & Moyce (1952), n^2 = 2, raw table (time origin = instantaneous release)");
    monitors["front rms relative error"] = error.rms_relative_error;
    // The simulated times delayed by tau (t -> t + tau), on a grid of 0.005 in T. Diagnostic
    // over [-0.5, 0.5] in T; the checked fit only over the admissible [0, tau_max].
    const double dT         = 0.005 * time_scale;
    const double T1         = 0.5 * time_scale;
    const auto   diagnostic = best_shift(t, x_front, reference, error, -T1, T1, dT);
    monitors["front rms relative error, best time shift"] = diagnostic.second.rms_relative_error;
    monitors["front best time shift [s]"]                = diagnostic.first;
    if (tau_max > 0)
      {
        const auto fitted = best_shift(t, x_front, reference, error, 0.0, tau_max, dT);
        summary.add_series_error("front position x_f(t), time origin fitted", fitted.second, 0.05,
                                 "Martin & Moyce (1952), simulated times delayed by tau = " +
                                   std::to_string(fitted.first) + " s, the best in [0, " + std::to_string(tau_max) +
                                   "] s (References/Front time origin uncertainty)");
        monitors["front rms relative error, time origin fitted"] = fitted.second.rms_relative_error;
        monitors["front fitted time origin delay [s]"]          = fitted.first;
      }
  }
} // namespace twinflow::io
