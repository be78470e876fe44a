// Deterministic parallel reductions: each row is summed serially, the row sums are
// added in row order, so the result does not depend on the number of threads.
#pragma once

#include <cstddef>
#include <vector>

#include "gfmd/grid.hpp"

namespace gfmd {

// sum over all points of f(i) where i = iy * nx + ix.
template <class F>
double grid_sum(const Grid& g, F&& f) {
  std::vector<double> rows(static_cast<std::size_t>(g.ny));
#pragma omp parallel for schedule(static)
  for (int iy = 0; iy < g.ny; ++iy) {
    double s = 0.0;
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) s += f(base + ix);
    rows[iy] = s;
  }
  double total = 0.0;
  for (double r : rows) total += r;
  return total;
}

// max over all points of f(i) (deterministic regardless of threads).
template <class F>
double grid_max(const Grid& g, F&& f, double init) {
  std::vector<double> rows(static_cast<std::size_t>(g.ny), init);
#pragma omp parallel for schedule(static)
  for (int iy = 0; iy < g.ny; ++iy) {
    double m = init;
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) {
      const double v = f(base + ix);
      if (v > m) m = v;
    }
    rows[iy] = m;
  }
  double m = init;
  for (double r : rows)
    if (r > m) m = r;
  return m;
}

}  // namespace gfmd
