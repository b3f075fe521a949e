// Counts of the named linear solves (linear_solve.h).
#include <twinflow/fem/linear_solve.h>

#include <Ifpack.h>
#include <Ifpack_Preconditioner.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <memory>

namespace twinflow::fem
{
  std::map<std::string, LinearSolveCounts> &linear_solve_counts()
  {
    static std::map<std::string, LinearSolveCounts> counts;
    return counts;
  }

  void initialize_amg(dealii::TrilinosWrappers::PreconditionAMG                       &amg,
                      const dealii::TrilinosWrappers::SparseMatrix                    &matrix,
                      const dealii::TrilinosWrappers::PreconditionAMG::AdditionalData &data)
  {
    // ML copies the constant modes during the set-up (as in PreconditionAMG::initialize)
    std::unique_ptr<Epetra_MultiVector> modes;
    Teuchos::ParameterList              list;
    data.set_parameters(list, modes, matrix);
    list.set("ML validate parameter list", false);
    amg.initialize(matrix, list);
  }

  void ReusableIlu::compute(const dealii::TrilinosWrappers::SparseMatrix &matrix)
  {
    const Epetra_CrsMatrix &m = matrix.trilinos_matrix();
    if (factored != &m || preconditioner.is_null())
    {
      preconditioner.reset();
      preconditioner = Teuchos::rcp(Ifpack().Create("ILU", const_cast<Epetra_CrsMatrix *>(&m), 0));
      AssertThrow(!preconditioner.is_null(), dealii::ExcMessage("Ifpack could not create an ILU preconditioner"));
      auto *ifpack = static_cast<Ifpack_Preconditioner *>(preconditioner.get());
      Teuchos::ParameterList list;
      list.set("fact: level-of-fill", 0);
      list.set("fact: absolute threshold", 0.0);
      list.set("fact: relative threshold", 1.0);
      list.set("schwarz: combine mode", "Add");
      AssertThrow(ifpack->SetParameters(list) == 0 && ifpack->Initialize() == 0,
                  dealii::ExcMessage("Ifpack ILU: the symbolic factorisation failed"));
      factored = &m;
    }
    AssertThrow(static_cast<Ifpack_Preconditioner *>(preconditioner.get())->Compute() == 0,
                dealii::ExcMessage("Ifpack ILU: the numeric factorisation failed (a zero pivot?)"));
  }

  void ReusableIlu::clear()
  {
    preconditioner.reset();
    factored = nullptr;
  }

  void InverseDiagonal::compute(const dealii::TrilinosWrappers::SparseMatrix &matrix)
  {
    const Epetra_CrsMatrix &m = matrix.trilinos_matrix();
    AssertThrow(m.Filled(), dealii::ExcMessage("InverseDiagonal: the matrix is not compressed"));
    if (indexed != &m)
    {
      place.assign(m.NumMyRows(), -1);
      for (int r = 0; r < m.NumMyRows(); ++r)
      {
        int     n       = 0;
        double *values  = nullptr;
        int    *columns = nullptr;
        m.ExtractMyRowView(r, n, values, columns);
        const int diagonal = m.ColMap().LID(m.RowMap().GID64(r));
        for (int k = 0; k < n; ++k)
          if (columns[k] == diagonal)
            place[r] = k;
      }
      inverse.reinit(matrix.locally_owned_range_indices(), matrix.get_mpi_communicator());
      AssertThrow(inverse.trilinos_vector().MyLength() == m.NumMyRows(),
                  dealii::ExcMessage("InverseDiagonal: the vector's rows differ from the matrix's"));
      indexed = &m;
    }
    double *out = inverse.trilinos_vector()[0];
    for (int r = 0; r < m.NumMyRows(); ++r)
    {
      int     n       = 0;
      double *values  = nullptr;
      int    *columns = nullptr;
      m.ExtractMyRowView(r, n, values, columns);
      const double d = place[r] >= 0 ? values[place[r]] : 0.0;
      AssertThrow(d != 0.0, dealii::ExcMessage("InverseDiagonal: row " + std::to_string(r) +
                                               " has no or a zero diagonal entry; Jacobi needs one"));
      out[r] = 1.0 / d;
    }
  }

  void InverseDiagonal::vmult(dealii::TrilinosWrappers::MPI::Vector       &dst,
                              const dealii::TrilinosWrappers::MPI::Vector &src) const
  {
    // Y = D⁻¹.*X, as Ifpack's point Jacobi applies it, copy by copy
    const double *d   = inverse.trilinos_vector()[0];
    const int     n   = inverse.trilinos_vector().MyLength();
    const int     len = src.trilinos_vector().MyLength();
    AssertThrow(len == dst.trilinos_vector().MyLength() && (n == 0 ? len == 0 : len % n == 0),
                dealii::ExcMessage("InverseDiagonal: the vectors are not copies of the matrix's rows"));
    const double *x = src.trilinos_vector()[0];
    double       *y = dst.trilinos_vector()[0];
    for (int b = 0; b < len; b += n)
      for (int r = 0; r < n; ++r)
        y[b + r] = d[r] * x[b + r];
  }

  ComponentBlockMatrix::ComponentBlockMatrix(const dealii::TrilinosWrappers::SparseMatrix &block,
                                             const unsigned int                            copies)
    : matrix(block.trilinos_matrix())
    , copies(copies)
  {
    AssertThrow(matrix.Filled() && matrix.DomainMap().SameAs(matrix.RangeMap()),
                dealii::ExcMessage("ComponentBlockMatrix: the block must be a compressed square matrix"));
  }

  void ComponentBlockMatrix::vmult(dealii::TrilinosWrappers::MPI::Vector       &dst,
                                   const dealii::TrilinosWrappers::MPI::Vector &src) const
  {
    const int n = matrix.DomainMap().NumMyElements();
    AssertThrow(src.trilinos_vector().MyLength() == int(copies) * n && dst.trilinos_vector().MyLength() == int(copies) * n,
                dealii::ExcMessage("ComponentBlockMatrix: the vectors are not " + std::to_string(copies) +
                                   " copies of the block's rows"));
    // column c of the views = copy c of the owned part (leading dimension n)
    Epetra_MultiVector x(View, matrix.DomainMap(), const_cast<double *>(src.trilinos_vector()[0]), n, int(copies));
    Epetra_MultiVector y(View, matrix.RangeMap(), dst.trilinos_vector()[0], n, int(copies));
    const int          error = matrix.Multiply(false, x, y);
    AssertThrow(error == 0, dealii::ExcMessage("ComponentBlockMatrix: Epetra's product failed"));
  }
} // namespace twinflow::fem
