#pragma once
/**
 * @file front_reference.h
 * The dam-break surge front x_f(t) against the scene's front table (References/Front
 * position file, Martin & Moyce 1952 scaling): one comparison shared by the SPH and the
 * FEM two-phase solver, so that both report the same errors under the same names.
 */
#include <twinflow/io/summary.h>

#include <map>
#include <string>
#include <vector>

namespace twinflow
{
  struct Scene;
}

namespace twinflow::io
{
  /// Martin & Moyce scaling of the front table: t = time · T and x_f = length · Z, with
  /// time = 1 / sqrt(2 g / a), length = a (a = Monitors/Reference length, g = |Forces/Gravity|).
  struct FrontScale
  {
    double time   = 1;
    double length = 1;
  };

  FrontScale
  front_scale(const Scene &scene);

  /**
   * Compare the simulated front (@p t, @p x_front) with the table of
   * Scene::reference_front_file, scaled as t = T / sqrt(2 g / a), x_f = Z a
   * (a = Monitors/Reference length, g = |Forces/Gravity|). Does nothing without a table.
   *
   * Adds to @p summary:
   *  - "front position x_f(t)": against the raw table (tolerance 5 % unless a time-origin
   *    uncertainty is set; then it is reported without a tolerance of its own);
   *  - "front position x_f(t), time origin fitted" (only if
   *    Scene::reference_front_time_uncertainty = tau_max > 0): the simulated times delayed
   *    by the best tau in [0, tau_max] (grid 0.005 in T), tolerance 5 %.
   *
   * Sets in @p monitors: "front rms relative error", "front rms relative error, best time
   * shift" and "front best time shift [s]" (a diagnostic over tau in [-0.5, 0.5] in T), and
   * with tau_max > 0 "front rms relative error, time origin fitted" and "front fitted time
   * origin delay [s]". A shift counts only if it keeps at least as many samples as the raw
   * comparison.
   */
  void
  add_front_reference_errors(const Scene &                      scene,
                             const std::vector<double> &        t,
                             const std::vector<double> &        x_front,
                             RunSummary &                       summary,
                             std::map<std::string, double> &    monitors);
} // namespace twinflow::io
