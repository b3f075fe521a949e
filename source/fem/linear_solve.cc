// Counts of the named linear solves (linear_solve.h).
#include <twinflow/fem/linear_solve.h>

namespace twinflow::fem
{
  std::map<std::string, LinearSolveCounts> &linear_solve_counts()
  {
    static std::map<std::string, LinearSolveCounts> counts;
    return counts;
  }
} // namespace twinflow::fem
