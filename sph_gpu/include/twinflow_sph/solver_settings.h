#pragma once
/// @file solver_settings.h  Settings of the SPH solves and operator corrections, and solve results (no Thrust: host-safe).

namespace twinflow::sph
{
  struct SolverSettings
  {
    int    max_iterations = 2000;
    double tolerance      = 1e-8;   ///< on ||b − A x|| / ||b||
  };

  /// Conditioning checks of the consistent-operator corrections (operators.inl). With
  /// positive_definite_laplacian, a particle whose L_i is not positive definite gets L_i = I
  /// (the standard Laplacian row, in the pressure and the viscous system). Off: exact
  /// second-order consistency wherever the support allows it.
  struct CorrectionChecks
  {
    bool positive_definite_laplacian = false;
  };

  struct SolverResult
  {
    int    iterations = 0;
    double residual   = 0;          ///< final relative residual
    bool   converged  = false;
  };

} // namespace twinflow::sph
