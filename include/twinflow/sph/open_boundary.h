#pragma once
/**
 * @file open_boundary.h
 * The open top of a free-surface SPH scene: `outflow` on the face opposite to gravity (the FEM
 * imposes do-nothing there, e.g. the paper's dam break). SPH places no BCE markers on that
 * face, and a fluid particle whose centre has left the domain through it is removed from the
 * simulation (the host compacts the particle arrays and hands them to the engine again; the
 * kernels see an ordinary, smaller particle set). Checkpoints hold the particles that remain
 * (read_checkpoint() then accepts fewer fluid particles than the scene generates).
 *
 * No other inflow/outflow face is available in SPH: open_face() throws an InputError naming it.
 */
#include <twinflow/core/scene.h>
#include <twinflow_sph/engine.h>

#include <cstddef>
#include <string>

namespace twinflow::sph
{
  /// The open face of a scene, if any.
  struct OpenFace
  {
    int         face     = -1;    ///< 0..5: left, right, bottom, top, front, back; −1: none
    int         axis     = 0;     ///< direction of its normal
    bool        upper    = true;  ///< the face at the upper end of that direction
    double      position = 0;     ///< its coordinate along @p axis
    std::string name;             ///< "top", ...

    bool active() const { return face >= 0; }
    /// True if @p coordinate (along @p axis) lies beyond the face, outside the domain.
    bool beyond(const double coordinate) const { return upper ? coordinate > position : coordinate < position; }
  };

  /**
   * The scene's open face: an `outflow` face opposite to gravity (Forces/Gravity along one
   * axis) in a free-surface scene (Fluids/Initial region of fluid 1 set). Returns an inactive
   * OpenFace if no face is inflow/outflow. Throws InputError naming the entry (Domain/<face>
   * boundary) for any other inflow or outflow face.
   */
  OpenFace open_face(const Scene &scene);

  /// Removes the fluid particles of @p P beyond @p open (all per-particle arrays are compacted,
  /// the order of the others kept). Returns how many were removed (0 if @p open is inactive).
  template <int dim>
  std::size_t remove_beyond(const OpenFace &open, HostParticles<dim> &P);
} // namespace twinflow::sph
