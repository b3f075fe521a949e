#pragma once
/**
 * @file checkpoint.h
 * Checkpoint and restart of an SPH run. The engine's whole dynamic state is the particles'
 * positions, velocities and pressures (the pressure is the next solve's initial guess; density,
 * neighbours, operators and matrices are rebuilt every step), so a run restarted from a
 * checkpoint continues bit for bit as the uninterrupted run would (test_sph_checkpoint).
 *
 * File (binary, native byte order, `SPH/Checkpoint interval`): magic "TWSPHCK3", int32 dim,
 * uint64 particle count, the spacing, time, step count, next output time, the output times
 * written so far, the energy budget summed so far (6 doubles, EnergyBudget's order), then
 * x, u (dim doubles each), p, ρ (doubles) and the kinds (int32).
 * It is written to `<file>.tmp` and renamed, so a run killed while writing keeps the previous one.
 */
#include <twinflow_sph/engine.h>

#include <cstddef>
#include <string>
#include <vector>

namespace twinflow::sph
{
  /// Where the run stood when the checkpoint was written.
  struct RunPosition
  {
    double              time        = 0;
    std::size_t         steps       = 0;
    double              next_output = 0; ///< time of the next particle output
    std::vector<double> output_times;    ///< times of particles_0.vtu, particles_1.vtu, ...
    EnergyBudget        budget;          ///< the energy budget summed over the steps so far
  };

  /// Writes @p P (x, u, p, ρ, kind) and @p pos to @p path (via path.tmp and a rename).
  template <int dim>
  void write_checkpoint(const std::string &path, const HostParticles<dim> &P, double spacing, const RunPosition &pos);

  /**
   * Reads the checkpoint @p path into @p P, which must hold the particles the scene generates
   * (same count and kinds, in the same order: the checkpoint replaces x, u, p and ρ; wall
   * velocities, normals and bodies stay the scene's). With @p fluid_may_leave (a scene with an
   * open top, open_boundary.h) the checkpoint may hold fewer fluid particles: its markers must
   * then be the scene's in the same order, and @p P becomes the checkpoint's particle set.
   * Throws InputError naming the file and what does not match (not a checkpoint, other
   * dimension, spacing or particle set).
   */
  template <int dim>
  RunPosition read_checkpoint(const std::string &path, double spacing, HostParticles<dim> &P,
                              bool fluid_may_leave = false);
} // namespace twinflow::sph
