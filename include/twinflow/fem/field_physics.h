#pragma once
/**
 * @file field_physics.h
 * The life cycle every field physics of the FEM follows (Navier–Stokes now; the level-set
 * sub-solvers NCLS, VOF, redistancing and mass correction next). FemSimulation drives it:
 *
 *   setup_dofs → initial state → { advance(dt) → output } ...
 *   mesh adaptation:  prepare_transfer(false) → execute → setup_dofs → finish_transfer(false)
 *   checkpoint:       prepare_transfer(true)  → Triangulation::save → save_state
 *   restart:          Triangulation::load → setup_dofs → finish_transfer(true) → load_state
 *
 * Each physics owns its parallel::distributed::SolutionTransfer objects and transfers every
 * history vector it keeps. Hooks that a physics does not need are no-ops.
 */
#include <deal.II/base/types.h>
#include <deal.II/numerics/data_out.h>

#include <iosfwd>
#include <string>

namespace twinflow::fem
{
  template <int dim>
  class FieldPhysics
  {
  public:
    virtual ~FieldPhysics() = default;

    /// Short name (progress lines, summaries, checkpoint sections).
    virtual std::string name() const = 0;

    /// Distribute DoFs on the current mesh, build constraints, sparsity, the matrices that
    /// depend only on the mesh and their preconditioners; size the state vectors.
    virtual void setup_dofs() = 0;

    /// Before the mesh changes: hand every history vector to a SolutionTransfer
    /// (@p serialization: for Triangulation::save instead of refinement).
    virtual void prepare_transfer(bool /*serialization*/) {}

    /// After setup_dofs() on the new mesh: interpolate (or deserialize) the history vectors
    /// and apply the new hanging-node constraints.
    virtual void finish_transfer(bool /*serialization*/) {}

    /// Advance the field from t^n to t^n + @p dt.
    virtual void advance(double /*dt*/) {}

    /// Add the fields to a DataOut (already attached to the triangulation).
    virtual void add_to_output(dealii::DataOut<dim> & /*data_out*/) const {}

    /// Scalars of the state that are not finite-element vectors (time, step sizes, counters),
    /// written by the root rank into the checkpoint's metadata and read on every rank.
    virtual void save_state(std::ostream & /*out*/) const {}
    virtual void load_state(std::istream & /*in*/) {}

    /// Degrees of freedom this physics owns (0: none).
    virtual dealii::types::global_dof_index n_dofs() const { return 0; }
  };
} // namespace twinflow::fem
