#pragma once
/**
 * @file cell_dof_reader.h
 * Fast reads of ghosted Trilinos vectors on the cells of one DoFHandler.
 *
 * `FEValues::get_function_values(trilinos_vector, ...)` allocates a dealii::Vector per call and
 * finds every DoF through Epetra's global-to-local map (a hash look-up per entry): on the
 * dam break at 8k cells these reads took ~10 % of a step. The reader computes, once per mesh
 * (after distribute_dofs), the position of each locally owned cell's DoFs in the ghosted
 * vector's local storage; `gather` then copies them with no look-up and no allocation, and
 * the `*_from_local_dof_values` functions of FEValues(Views) evaluate them.
 *
 * Valid for every ghosted vector built on the same (owned, relevant) index sets as the one
 * given to reinit(); gather() checks the size of the local storage.
 *
 * It also copies whole vectors between the owned and the ghosted layout of the partition.
 * deal.II's `operator=` between the two builds a new Epetra_Import (a global-to-local look-up
 * of every owned and ghost DoF) on every call: ~5 % of a dam-break step on 2 ranks, where the
 * Navier–Stokes and level-set solves copy their ghosted state to owned work vectors and back.
 * update_ghosted() imports through one Epetra_Import built per mesh; copy_owned() is a local
 * copy through the owned DoFs' positions in the ghosted storage.
 */
#include <deal.II/base/exceptions.h>
#include <deal.II/base/index_set.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_Import.h>
#include <Epetra_MultiVector.h>

#include <memory>
#include <vector>

namespace twinflow::fem
{
  template <int dim>
  class CellDofReader
  {
  public:
    /// Positions of the DoFs of every locally owned cell of @p dofs in a ghosted vector on
    /// (@p owned, @p relevant).
    void reinit(const dealii::DoFHandler<dim> &dofs, const dealii::IndexSet &owned, const dealii::IndexSet &relevant,
                MPI_Comm comm)
    {
      dealii::TrilinosWrappers::MPI::Vector probe(owned, relevant, comm), owned_probe(owned, comm);
      const auto &map = probe.trilinos_vector().Map();
      n_local         = map.NumMyElements();
      importer        = std::make_unique<Epetra_Import>(map, owned_probe.trilinos_vector().Map());
      const auto &owned_map = owned_probe.trilinos_vector().Map();
      owned_positions.resize(owned_map.NumMyElements());
      for (int i = 0; i < owned_map.NumMyElements(); ++i)
      {
        owned_positions[i] = map.LID(owned_map.GID(i));
        AssertThrow(owned_positions[i] >= 0, dealii::ExcMessage("CellDofReader: an owned DoF is not in the relevant set."));
      }
      per_cell        = dofs.get_fe().n_dofs_per_cell();
      offset.assign(dofs.get_triangulation().n_active_cells(), -1);
      positions.clear();
      std::vector<dealii::types::global_dof_index> indices(per_cell);
      for (const auto &cell : dofs.active_cell_iterators())
        if (cell->is_locally_owned())
        {
          offset[cell->active_cell_index()] = static_cast<long>(positions.size());
          cell->get_dof_indices(indices);
          for (const auto i : indices)
          {
            const int lid = map.LID(static_cast<dealii::TrilinosWrappers::types::int_type>(i));
            AssertThrow(lid >= 0, dealii::ExcMessage("CellDofReader: a cell's DoF is not in the relevant set."));
            positions.push_back(lid);
          }
        }
    }

    /// Whether @p v is a ghosted vector on the reader's index sets (gather() may read it).
    bool reads(const dealii::TrilinosWrappers::MPI::Vector &v) const { return v.trilinos_vector().MyLength() == n_local; }

    /// The values of the ghosted vector @p v at the DoFs of the locally owned @p cell.
    template <typename CellIterator>
    void gather(const CellIterator &cell, const dealii::TrilinosWrappers::MPI::Vector &v,
                std::vector<double> &out) const
    {
      const Epetra_MultiVector &ev = v.trilinos_vector();
      AssertThrow(ev.MyLength() == n_local,
                  dealii::ExcMessage("CellDofReader: the vector is not ghosted on the reader's index sets."));
      const long start = offset[cell->active_cell_index()];
      Assert(start >= 0, dealii::ExcMessage("CellDofReader: the cell is not locally owned."));
      if (out.size() != per_cell)
        out.resize(per_cell);
      const double *data = ev[0];
      for (unsigned int i = 0; i < per_cell; ++i)
        out[i] = data[positions[start + i]];
    }

    /// @p ghosted ← @p owned (ghost values from their owners): the ghosted vector on the
    /// reader's index sets, the owned one on its owned set.
    void update_ghosted(dealii::TrilinosWrappers::MPI::Vector &ghosted, const dealii::TrilinosWrappers::MPI::Vector &owned) const
    {
      AssertThrow(importer && ghosted.trilinos_vector().MyLength() == n_local &&
                    owned.trilinos_vector().MyLength() == static_cast<int>(owned_positions.size()),
                  dealii::ExcMessage("CellDofReader::update_ghosted: the vectors are not on the reader's index sets."));
      const int ierr = ghosted.trilinos_vector().Import(owned.trilinos_vector(), *importer, Insert);
      AssertThrow(ierr == 0, dealii::ExcMessage("CellDofReader::update_ghosted: Epetra import failed (the maps differ)."));
    }

    /// @p owned ← the owned entries of the ghosted @p ghosted (no communication).
    void copy_owned(dealii::TrilinosWrappers::MPI::Vector &owned, const dealii::TrilinosWrappers::MPI::Vector &ghosted) const
    {
      AssertThrow(ghosted.trilinos_vector().MyLength() == n_local &&
                    owned.trilinos_vector().MyLength() == static_cast<int>(owned_positions.size()),
                  dealii::ExcMessage("CellDofReader::copy_owned: the vectors are not on the reader's index sets."));
      const double *from = ghosted.trilinos_vector()[0];
      double       *to   = owned.trilinos_vector()[0];
      for (std::size_t i = 0; i < owned_positions.size(); ++i)
        to[i] = from[owned_positions[i]];
    }

    /// @p dst ← @p src for two vectors of the reader's partition, owned or ghosted in any
    /// combination (update_ghosted, copy_owned, or a plain copy between equal layouts).
    void assign(dealii::TrilinosWrappers::MPI::Vector &dst, const dealii::TrilinosWrappers::MPI::Vector &src) const
    {
      const int n_dst = dst.trilinos_vector().MyLength(), n_src = src.trilinos_vector().MyLength();
      const int n_owned = static_cast<int>(owned_positions.size());
      if (n_dst == n_local && n_src == n_owned && n_local != n_owned)
        update_ghosted(dst, src);
      else if (n_src == n_local && n_dst == n_owned)
        copy_owned(dst, src); // also the equal layouts of a rank without ghosts
      else
        dst = src;
    }

  private:
    std::unique_ptr<Epetra_Import> importer;        ///< owned map → ghosted map
    std::vector<int>               owned_positions; ///< local storage index of each owned DoF
    int                n_local  = 0;
    unsigned int       per_cell = 0;
    std::vector<long>  offset;    ///< by active_cell_index: start in positions, −1 if not owned
    std::vector<int>   positions; ///< local storage index of each DoF of each owned cell
  };
} // namespace twinflow::fem
