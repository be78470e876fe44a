// Without HYPRE in the build (GFMD_WITH_HYPRE=OFF): the BoomerAMG solver is refused.
#include "gfmd/core/error.hpp"
#include "reynolds_system.hpp"

namespace gfmd::flow_detail {

std::vector<LinearSolution> solve_boomeramg(const LinearSystem&, std::size_t, const RhsFn&,
                                            const FlowOptions&) {
  throw SolveError(
      "flow: solver boomeramg needs HYPRE, and this gfmd was built without it (GFMD_WITH_HYPRE=OFF)");
}

std::vector<LinearSolution> solve_boomeramg_slabs(const SlabSystem&, const std::vector<Buffer<double>>&,
                                                  const FlowOptions&) {
  throw SolveError(
      "flow: a distributed flow solve needs HYPRE, and this gfmd was built without it (GFMD_WITH_HYPRE=OFF)");
}

}  // namespace gfmd::flow_detail
