#pragma once
/**
 * @file front.h
 * Surge-front position of a dam break (Martin & Moyce's Z = x_f / a): the leading edge of
 * the connected water, not of the spray. A particle thrown ahead of the front (a droplet
 * sliding along the floor, a splash) is not the front the experiments measure.
 */
#include <twinflow_sph/engine.h>

namespace twinflow::sph
{
  /// A fluid particle with fewer fluid neighbours than this within front_neighbour_radius
  /// spacings is spray and does not count for surge_front().
  inline constexpr int    front_min_neighbours   = 2;
  inline constexpr double front_neighbour_radius = 2.0;

  /**
   * The largest x_i + dx/2 over the fluid particles of @p P that have at least
   * front_min_neighbours other fluid particles within front_neighbour_radius · @p dx
   * (the leading edge of the connected water). Returns the plain maximum over all fluid
   * particles if none qualifies, and −∞ if there is no fluid particle. O(N log N).
   */
  template <int dim>
  double surge_front(const HostParticles<dim> &P, double dx);

  /// The largest x_i + dx/2 over all fluid particles, spray included (−∞ without fluid).
  template <int dim>
  double foremost_particle(const HostParticles<dim> &P, double dx);
} // namespace twinflow::sph
