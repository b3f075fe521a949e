#pragma once
/**
 * @file cell_scatter.h
 * Fast addition of cell matrices into a Trilinos matrix whose sparsity is fixed.
 *
 * `AffineConstraints::distribute_local_to_global` into a TrilinosWrappers::SparseMatrix sums
 * each row through Epetra's SumIntoGlobalValues: a global-to-local map look-up per column and a
 * search in the row per entry. On the dam break (8k cells, Q2 velocity) that insertion was
 * ~60 % of the momentum assembly. For a cell with no constrained DoF whose rows are all owned
 * here, the position of every (i, j) entry in the matrix's row storage and of every row in the
 * right-hand side's local storage is fixed as long as the sparsity is: CellScatter computes
 * them once per mesh and `add` sums the cell's matrix and vector straight into Epetra's storage.
 * Cells with constraints or ghost rows return false from `add`, and the caller takes
 * distribute_local_to_global, so the sum is the same (each entry receives the same cell
 * contributions in the same order). compress(add) is still needed for the ghost rows.
 *
 * For a vector element of dim copies of one scalar element whose components do not couple
 * (the momentum matrix with μ∇u, the L²(ρ) mass), `add_blocks` sums the one scalar block S_ab
 * into every component's rows: no expansion to the full cell matrix, whose off-diagonal
 * component blocks are zero and outside the sparsity.
 */
#include <deal.II/base/exceptions.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>

#include <vector>

namespace twinflow::fem
{
  template <int dim>
  class CellScatter
  {
  public:
    /// Forgets the positions (call when the DoFs or the matrix's sparsity change).
    void clear() { offset.clear(); }
    bool ready() const { return !offset.empty(); }

    /// Positions of the entries of each owned, unconstrained cell of @p dofs in @p matrix
    /// (which must have its final sparsity) and of its rows in the owned vector @p rhs.
    void reinit(const dealii::DoFHandler<dim> &dofs, const dealii::AffineConstraints<double> &constraints,
                dealii::TrilinosWrappers::SparseMatrix &matrix, const dealii::TrilinosWrappers::MPI::Vector &rhs)
    {
      reinit(dofs, constraints, &matrix, rhs);
    }

    /// For the right-hand side alone (add_vector): a matrix assembled elsewhere.
    void reinit_vector(const dealii::DoFHandler<dim> &dofs, const dealii::AffineConstraints<double> &constraints,
                       const dealii::TrilinosWrappers::MPI::Vector &rhs)
    {
      reinit(dofs, constraints, nullptr, rhs);
    }
    /// rhs += b for a cell of the fast path (reinit_vector or reinit); false otherwise.
    template <typename CellIterator>
    bool add_vector(const CellIterator &cell, const dealii::Vector<double> &b,
                    dealii::TrilinosWrappers::MPI::Vector &rhs) const
    {
      const long start = offset[cell->active_cell_index()];
      if (start < 0)
        return false;
      add_rhs(start, &b, &rhs);
      return true;
    }

  private:
    void reinit(const dealii::DoFHandler<dim> &dofs, const dealii::AffineConstraints<double> &constraints,
                dealii::TrilinosWrappers::SparseMatrix *matrix, const dealii::TrilinosWrappers::MPI::Vector &rhs)
    {
      Epetra_CrsMatrix *A = matrix != nullptr ? const_cast<Epetra_CrsMatrix *>(&matrix->trilinos_matrix()) : nullptr;
      AssertThrow(A == nullptr || A->Filled(), dealii::ExcMessage("CellScatter: the matrix's sparsity is not final."));
      const auto &rhs_map = rhs.trilinos_vector().Map();
      per_cell            = dofs.get_fe().n_dofs_per_cell();
      const auto &fe      = dofs.get_fe();
      n_scalar            = fe.n_base_elements() == 1 ? fe.base_element(0).n_dofs_per_cell() : 0;
      component.assign(per_cell, 0);
      base.assign(per_cell, 0);
      system.assign(n_scalar > 0 ? fe.n_components() * n_scalar : 0, 0);
      for (unsigned int i = 0; i < per_cell && n_scalar > 0; ++i)
      {
        component[i] = fe.system_to_component_index(i).first;
        base[i]      = fe.system_to_component_index(i).second;
        system[component[i] * n_scalar + base[i]] = i;
      }
      offset.assign(dofs.get_triangulation().n_active_cells(), -1);
      rows.clear(), rhs_entries.clear(), entries.clear();
      std::vector<dealii::types::global_dof_index> indices(per_cell);
      std::vector<double *>                        row_values(per_cell);
      std::vector<int>                             row_rhs(per_cell), row_entries(per_cell * per_cell);
      for (const auto &cell : dofs.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        cell->get_dof_indices(indices);
        bool fast = true;
        for (unsigned int i = 0; i < per_cell; ++i)
        {
          const auto gi  = static_cast<dealii::TrilinosWrappers::types::int_type>(indices[i]);
          const int  lid = A != nullptr ? A->RowMap().LID(gi) : 0;
          row_rhs[i]     = rhs_map.LID(gi);
          if (constraints.is_constrained(indices[i]) || lid < 0 || row_rhs[i] < 0)
          {
            fast = false;
            break;
          }
          if (A == nullptr)
            continue;
          int     n_entries = 0, *columns = nullptr;
          double *values = nullptr;
          A->ExtractMyRowView(lid, n_entries, values, columns);
          row_values[i] = values;
          for (unsigned int j = 0; j < per_cell; ++j)
          {
            const int c = A->ColMap().LID(static_cast<dealii::TrilinosWrappers::types::int_type>(indices[j]));
            int       k = 0;
            while (k < n_entries && columns[k] != c)
              ++k;
            // an entry outside the sparsity (e.g. another component's block) is never assembled:
            // −1, skipped by add() as Trilinos would refuse a nonzero there
            row_entries[i * per_cell + j] = c >= 0 && k < n_entries ? k : -1;
          }
        }
        if (!fast)
          continue;
        offset[cell->active_cell_index()] = static_cast<long>(rhs_entries.size());
        rhs_entries.insert(rhs_entries.end(), row_rhs.begin(), row_rhs.end());
        if (A == nullptr)
          continue;
        rows.insert(rows.end(), row_values.begin(), row_values.end());
        entries.insert(entries.end(), row_entries.begin(), row_entries.end());
      }
    }

  public:
    /// Adds @p M (and @p b into @p rhs, when given) for @p cell; false if the cell has no fast
    /// path (constrained DoFs or ghost rows): the caller then distributes it the usual way.
    template <typename CellIterator>
    bool add(const CellIterator &cell, const dealii::FullMatrix<double> &M, const dealii::Vector<double> *b = nullptr,
             dealii::TrilinosWrappers::MPI::Vector *rhs = nullptr) const
    {
      const long start = offset[cell->active_cell_index()];
      if (start < 0)
        return false;
      Assert(!rows.empty(), dealii::ExcMessage("CellScatter: set up for a right-hand side only (reinit_vector)."));
      for (unsigned int i = 0; i < per_cell; ++i)
      {
        double    *values = rows[start + i];
        const int *k      = &entries[(start + i) * per_cell];
        for (unsigned int j = 0; j < per_cell; ++j)
          if (k[j] >= 0)
            values[k[j]] += M(i, j);
          else
            Assert(M(i, j) == 0, dealii::ExcMessage("CellScatter: a nonzero outside the sparsity pattern."));
      }
      add_rhs(start, b, rhs);
      return true;
    }

    /// Adds the block-diagonal cell matrix diag(S, ..., S) (S: @p block, one scalar block per
    /// component) and @p b, as add() would add the expanded matrix; false as add(). Needs an
    /// element of copies of one scalar element.
    template <typename CellIterator>
    bool add_blocks(const CellIterator &cell, const dealii::FullMatrix<double> &block,
                    const dealii::Vector<double> *b = nullptr, dealii::TrilinosWrappers::MPI::Vector *rhs = nullptr) const
    {
      Assert(n_scalar == block.m() && n_scalar == block.n(),
             dealii::ExcMessage("CellScatter::add_blocks: the block is not of the scalar element's size."));
      const long start = offset[cell->active_cell_index()];
      if (start < 0)
        return false;
      Assert(!rows.empty(), dealii::ExcMessage("CellScatter: set up for a right-hand side only (reinit_vector)."));
      for (unsigned int i = 0; i < per_cell; ++i)
      {
        double             *values = rows[start + i];
        const int          *k      = &entries[(start + i) * per_cell];
        const unsigned int *column = &system[component[i] * n_scalar];
        const double       *row    = &block(base[i], 0);
        for (unsigned int j = 0; j < n_scalar; ++j)
        {
          Assert(k[column[j]] >= 0, dealii::ExcMessage("CellScatter: a same-component entry outside the sparsity."));
          values[k[column[j]]] += row[j];
        }
      }
      add_rhs(start, b, rhs);
      return true;
    }

  private:
    /// b into the cell's rows of rhs (nothing when b is null).
    void add_rhs(const long start, const dealii::Vector<double> *b, dealii::TrilinosWrappers::MPI::Vector *rhs) const
    {
      if (b == nullptr)
        return;
      double *data = rhs->trilinos_vector()[0];
      for (unsigned int i = 0; i < per_cell; ++i)
        data[rhs_entries[start + i]] += (*b)(i);
    }

    unsigned int          per_cell = 0;
    unsigned int          n_scalar = 0;   ///< DoFs of the scalar base element (0: not one base)
    std::vector<unsigned int> component, base; ///< of each cell DoF
    std::vector<unsigned int> system;          ///< cell DoF of (component, base DoF)
    std::vector<long>     offset;      ///< by active_cell_index: first row in rows, −1 if no fast path
    std::vector<double *> rows;        ///< Epetra's value storage of each row of each fast cell
    std::vector<int>      rhs_entries; ///< local index of each row in the right-hand side
    std::vector<int>      entries;     ///< position of entry (i, j) in row i's storage
  };
} // namespace twinflow::fem
