// End-to-end timing of the Reynolds flow solve on a contact-like random gap:
// self-affine surface (H = 0.8, lambda_l = L/4, lambda_s = 4 dx) cut at the height that
// closes a given fraction of the cells, gap = max(c - h, 0).
//
//   bench_flow [N=2048] [closed_fraction=0.2] [solver=auto|native|boomeramg] [tolerance=1e-8]
//
// Prints one line per direction: iterations, residual, phase times (set-up of the
// preconditioner, PCG solve, total) and K / <g^3>.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gfmd/flow.hpp"
#include "gfmd/topography.hpp"

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 2048;
  const double closed = argc > 2 ? std::atof(argv[2]) : 0.2;
  const std::string which = argc > 3 ? argv[3] : "auto";
  const double tol = argc > 4 ? std::atof(argv[4]) : 1e-8;
  const gfmd::Grid grid{n, n, 1.0, 1.0};
  gfmd::SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = 0.25;
  p.lambda_short = 4.0 / n;
  p.lambda_rolloff = 1.0;
  p.rms_height = 1.0;
  p.seed = 11;
  const gfmd::Topography t = gfmd::make_selfaffine(grid, p);
  std::vector<double> sorted(t.h.begin(), t.h.end());
  const auto k = static_cast<std::size_t>((1.0 - closed) * static_cast<double>(sorted.size()));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  std::vector<double> gap(grid.size());
  for (std::size_t i = 0; i < gap.size(); ++i) gap[i] = std::max(sorted[k] - t.h[i], 0.0);

  gfmd::FlowOptions opt;
  opt.tolerance = tol;
  const auto solver = which == "native"      ? gfmd::detail::FlowSolver::Amg
                      : which == "boomeramg" ? gfmd::detail::FlowSolver::BoomerAMG
                                             : gfmd::detail::FlowSolver::Auto;
  std::printf("N = %d, closed fraction %.3f, solver %s, tolerance %.1e\n", n, closed, which.c_str(), tol);
  // One direction per call (what `gfmd flow --direction x` costs), then both at once.
  for (const std::vector<double>& angles :
       {std::vector<double>{0.0}, std::vector<double>{90.0}, std::vector<double>{0.0, 90.0}}) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto rs = gfmd::detail::solve_flow(grid, gap.data(), angles, opt, solver);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s:\n", angles.size() > 1 ? "both directions, one set-up" : "one direction");
    for (const gfmd::FlowResult& r : rs)
      std::printf(
          "  angle %3g: %3d iterations, residual %.2e, set-up %.2f s, PCG %.2f s, K/<g^3> = %.8f, "
          "conservation %.1e\n",
          r.angle_deg, r.iterations, r.residual, r.setup_s, r.solve_s, r.conductivity / r.mean_gap_cubed,
          r.conservation_error);
    std::printf("  total %.2f s\n", s);
  }
  return 0;
}
