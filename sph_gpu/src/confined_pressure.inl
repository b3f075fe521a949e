// Pressure system of confined flows (no free surface: pure Neumann, singular), see
// doc/equations.md "57 (confined flows)". Part of the single kernel source: included by
// engine.inl for both backends.
#pragma once
#include <twinflow_sph/backend.h>
#include <twinflow_sph/engine.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
{
  /// V_i (or V_i rhs_i) for the fluid rows of a confined flow's pressure system (not the pin).
  struct ConfinedFluidRowWeight
  {
    const int    *kind;
    const double *V, *rhs;
    int           pinned;
    TWINFLOW_HD double operator()(int i) const
    {
      if (kind[i] != ParticleKind::fluid || i == pinned)
        return 0.0;
      return rhs ? V[i] * rhs[i] : V[i];
    }
  };

  struct ShiftConfinedFluidRows
  {
    const int *kind;
    int        pinned;
    double     mean;
    double    *rhs;
    TWINFLOW_HD void operator()(int i) const
    {
      if (kind[i] == ParticleKind::fluid && i != pinned)
        rhs[i] -= mean;
    }
  };

  /// values[i] −= shift, every particle.
  struct ShiftAll
  {
    double  shift;
    double *values;
    TWINFLOW_HD void operator()(int i) const { values[i] -= shift; }
  };
  struct ShiftFluidDiagonal
  {
    const int *kind, *offsets, *indices;
    double     epsilon;
    double    *values;
    TWINFLOW_HD void operator()(int i) const
    {
      if (kind[i] != ParticleKind::fluid)
        return;
      for (int k = offsets[i]; k < offsets[i + 1]; ++k)
        if (indices[k] == i)
          values[k] -= epsilon;
    }
  };
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
