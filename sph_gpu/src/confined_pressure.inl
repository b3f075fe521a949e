// Pressure system of confined flows (no free surface: pure Neumann, singular), see
// doc/equations.md "57 (confined flows)". Part of the single kernel source: included by
// engine.inl for both backends.
#pragma once
#include <twinflow_sph/backend.h>
#include <twinflow_sph/kernel_views.h>

namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
{
  /// V_i (or V_i f_i) for the fluid rows of a confined flow's pressure system (not the pin).
  template <int dim>
  struct ConfinedFluidRowWeight
  {
    ParticleView<dim> p;           ///< kind, V
    const double     *f = nullptr; ///< null: the weight V_i alone
    int               pinned = -1;
    TWINFLOW_HD double operator()(int i) const
    {
      if (!p.fluid(i) || i == pinned)
        return 0.0;
      return f ? p.V[i] * f[i] : p.V[i];
    }
  };

  /// rhs_i −= mean on the fluid rows (not the pin).
  template <int dim>
  struct ShiftConfinedFluidRows
  {
    ParticleView<dim> p; ///< kind
    int               pinned = -1;
    double            mean   = 0;
    double           *rhs    = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      if (p.fluid(i) && i != pinned)
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

  /// The diagonal of the fluid rows −= epsilon.
  template <int dim>
  struct ShiftFluidDiagonal
  {
    ParticleView<dim> p; ///< kind
    NeighborView<dim> nb;
    double            epsilon = 0;
    double           *values  = nullptr;
    TWINFLOW_HD void operator()(int i) const
    {
      const int kii = p.fluid(i) ? diagonal_entry(nb, i) : -1;
      if (kii >= 0)
        values[kii] -= epsilon;
    }
  };
} // namespace twinflow::sph::TWINFLOW_SPH_BACKEND::detail
