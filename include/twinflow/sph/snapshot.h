#pragma once
/**
 * @file snapshot.h
 * SPH snapshots (Scene/Snapshot times, io/snapshots.h): the particles at one time as CSV,
 * for figures like the paper's Figs 7-8 (scripts/plot_snapshots.py).
 *
 * File layout (read_csv() reads it):
 * @code
 * # twinflow SPH snapshot: requested t = 0.5 s, written at t = 0.50125 s (step 167)
 * # kind: 0 = fluid, 1 = wall (BCE) marker, 2 = solid marker
 * x [m],y [m],speed [m/s],pressure [Pa],kind
 * @endcode
 * (with a `z [m]` column after y in 3D), one row per particle, fluid and markers alike.
 */
#include <twinflow_sph/engine.h>

#include <cstddef>
#include <string>

namespace twinflow::sph
{
  /// Writes @p P at time @p time (the snapshot of @p requested, step @p step) to @p path;
  /// creates its directory. Throws std::runtime_error if the file cannot be written.
  template <int dim>
  void write_snapshot(const std::string &path, const HostParticles<dim> &P, double requested, double time,
                      std::size_t step);
} // namespace twinflow::sph
