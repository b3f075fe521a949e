// Counts of the named linear solves (linear_solve.h).
#include <twinflow/fem/linear_solve.h>

#include <Ifpack.h>
#include <Ifpack_Preconditioner.h>
#include <Teuchos_ParameterList.hpp>

namespace twinflow::fem
{
  std::map<std::string, LinearSolveCounts> &linear_solve_counts()
  {
    static std::map<std::string, LinearSolveCounts> counts;
    return counts;
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
} // namespace twinflow::fem
