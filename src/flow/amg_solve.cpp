// The Reynolds system solved by our algebraic multigrid under CG.
#include <chrono>
#include <cmath>

#include "gfmd/core/error.hpp"
#include "gfmd/flow/amg.hpp"
#include "reynolds_system.hpp"

namespace gfmd::flow_detail {

std::vector<LinearSolution> solve_native(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                         const FlowOptions& opt, int max_iterations) {
  std::vector<LinearSolution> out;
  const auto t0 = std::chrono::steady_clock::now();
  ReducedSystem red(sys, true);
  if (red.size() == 0) return no_unknowns(sys.size(), nrhs);
  const AlgebraicMultigrid amg(red.take_matrix());
  red.release_index();
  const double setup_s = seconds_since(t0);
  if (opt.stop_request && opt.stop_request())
    throw Interrupted("flow solve interrupted after the AMG set-up");
  Buffer<double> b, br, xr;
  for (std::size_t k = 0; k < nrhs; ++k) {
    LinearSolution sol;
    sol.setup_s = k == 0 ? setup_s : 0.0;
    const auto t1 = std::chrono::steady_clock::now();
    make_rhs(k, b);
    const double bnorm =
        std::sqrt(range_sums(b.size(), 1, [&](std::size_t i, double* acc) { acc[0] += b[i] * b[i]; })[0]);
    red.reduce(b, br);
    xr.resize(br.size());
    const CgOutcome cg =
        amg_pcg(amg, br.data(), xr.data(), opt.tolerance, max_iterations, bnorm, opt.stop_request);
    red.expand(b, xr, sol.x);
    sol.solve_s = seconds_since(t1);
    sol.iterations = cg.iterations;
    sol.residual = bnorm > 0.0 ? full_residual_norm(sys, b, sol.x) / bnorm : 0.0;
    sol.converged = finite(sol) && cg.converged && sol.residual <= 10.0 * opt.tolerance;
    out.push_back(std::move(sol));
  }
  return out;
}

}  // namespace gfmd::flow_detail
