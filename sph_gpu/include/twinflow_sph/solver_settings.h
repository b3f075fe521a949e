#pragma once
/// @file solver_settings.h  Settings and result of the SPH Krylov solves (no Thrust: host-safe).

namespace twinflow::sph
{
  struct SolverSettings
  {
    int    max_iterations = 1000;
    double tolerance      = 1e-8;   ///< on ||b − A x|| / ||b||
  };

  struct SolverResult
  {
    int    iterations = 0;
    double residual   = 0;          ///< final relative residual
    bool   converged  = false;
  };

} // namespace twinflow::sph
