// End-to-end timing of the Reynolds flow solve on a contact-like random gap:
// self-affine surface (H = 0.8, lambda_l = L/4, lambda_s = ls dx) cut at the height that
// closes a given fraction of the cells, gap = max(c - h, 0).
//
//   bench_flow [N=2048] [closed_fraction=0.2] [solver=auto|amg|boomeramg] [tolerance=1e-8]
//              [repeat=1] [ls=4]
//
// Each repetition solves one direction (x), then the other (y), then both with one set-up,
// each call from scratch (conductances, components, set-up, PCG, currents), as
// `gfmd flow --direction x|y|both` does. Prints iterations, residual, the set-up and PCG
// times, the wall time of the call and K / <g^3>. The first call of the process touches
// memory the system has to provide afresh (on a virtual machine that costs up to ~1 s at
// 2048^2); later ones reuse it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gfmd/flow/flow.hpp"
#include "gfmd/surface/topography.hpp"

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 2048;
  const double closed = argc > 2 ? std::atof(argv[2]) : 0.2;
  const std::string which = argc > 3 ? argv[3] : "auto";
  const double tol = argc > 4 ? std::atof(argv[4]) : 1e-8;
  const int repeat = argc > 5 ? std::max(1, std::atoi(argv[5])) : 1;
  const double ls = argc > 6 ? std::atof(argv[6]) : 4.0;
  if (n < 8 || !(closed >= 0.0 && closed < 1.0) || !(tol > 0.0 && tol < 1.0) || !(ls >= 2.0)) {
    std::fprintf(stderr,
                 "usage: bench_flow [N>=8] [closed_fraction in [0,1)] [auto|amg|boomeramg] [tolerance] "
                 "[repeat] [ls>=2]\n");
    return 2;
  }
  const gfmd::Grid grid{n, n, 1.0, 1.0};
  gfmd::SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = 0.25;
  p.lambda_short = ls / n;
  p.lambda_rolloff = 1.0;
  p.rms_height = 1.0;
  p.seed = 11;
  const gfmd::Topography t = gfmd::make_selfaffine(grid, p);
  std::vector<double> sorted(t.h.begin(), t.h.end());
  const auto k = std::min(sorted.size() - 1,
                          static_cast<std::size_t>((1.0 - closed) * static_cast<double>(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  std::vector<double> gap(grid.size());
  for (std::size_t i = 0; i < gap.size(); ++i) gap[i] = std::max(sorted[k] - t.h[i], 0.0);

  gfmd::FlowOptions opt;
  opt.tolerance = tol;
  if (!gfmd::parse_flow_solver(which, opt.solver)) {
    std::fprintf(stderr, "solver must be auto, amg or boomeramg\n");
    return 2;
  }
  std::printf("N = %d, closed fraction %.3f, lambda_s = %g dx, solver %s, tolerance %.1e\n", n, closed, ls,
              which.c_str(), tol);
  for (int rep = 0; rep < repeat; ++rep) {
    for (const std::vector<double>& angles :
         {std::vector<double>{0.0}, std::vector<double>{90.0}, std::vector<double>{0.0, 90.0}}) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto rs = gfmd::solve_flow(grid, gap.data(), angles, opt);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%s (run %d): total %.2f s\n",
                  angles.size() > 1 ? "both directions, one set-up" : "one direction", rep + 1, s);
      for (const gfmd::FlowResult& r : rs)
        std::printf(
            "  angle %3g: %3d iterations (%s), residual %.2e, set-up %.2f s, PCG %.2f s, K/<g^3> = %.8f, "
            "conservation %.1e, faces cut %zu\n",
            r.angle_deg, r.iterations, r.solver.c_str(), r.residual, r.setup_s, r.solve_s,
            r.conductivity / r.mean_gap_cubed, r.conservation_error, r.faces_cut);
    }
  }
  return 0;
}
