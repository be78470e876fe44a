// Deterministic reductions over the current backend: each row is summed serially, the row
// sums are added in row order, so the result does not depend on the backend or on the
// number of its workers.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd {

// K sums in one pass: f(i, acc) adds point i's contributions into acc[0..K-1]. Same
// sums each row serially and adds the row sums in row order, so the results do not
// depend on the number of threads.
template <std::size_t K, class F>
std::array<double, K> grid_sums(const Grid& g, F&& f) {
  std::vector<std::array<double, K>> rows(static_cast<std::size_t>(g.ny));
  for_rows(g.ny, [&](int iy) {
    std::array<double, K> s{};
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) f(base + ix, s);
    rows[iy] = s;
  });
  std::array<double, K> total{};
  for (const auto& r : rows)
    for (std::size_t k = 0; k < K; ++k) total[k] += r[k];
  return total;
}

// sum over all points of f(i) where i = iy * nx + ix (the one-sum case of grid_sums).
template <class F>
double grid_sum(const Grid& g, F&& f) {
  return grid_sums<1>(g, [&](std::size_t i, std::array<double, 1>& acc) { acc[0] += f(i); })[0];
}

// As grid_sums with a run-time number k of sums: f(i, acc) adds into acc[0..k-1].
template <class F>
std::vector<double> grid_sums(const Grid& g, std::size_t k, F&& f) {
  std::vector<double> rows(static_cast<std::size_t>(g.ny) * k, 0.0);
  for_rows(g.ny, [&](int iy) {
    double* s = rows.data() + static_cast<std::size_t>(iy) * k;
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) f(base + ix, s);
  });
  std::vector<double> total(k, 0.0);
  for (int iy = 0; iy < g.ny; ++iy)
    for (std::size_t j = 0; j < k; ++j) total[j] += rows[static_cast<std::size_t>(iy) * k + j];
  return total;
}

// As the run-time grid_sums over the indices 0..len-1 of a list (not a grid): blocks of a
// fixed length are summed serially and the block sums added in order, so the results do
// not depend on the number of threads either.
template <class F>
std::vector<double> range_sums(std::size_t len, std::size_t k, F&& f) {
  constexpr std::size_t block = 4096;
  const std::ptrdiff_t nb = static_cast<std::ptrdiff_t>((len + block - 1) / block);
  std::vector<double> blocks(static_cast<std::size_t>(nb) * k, 0.0);
  parallel_for(nb, [&](std::ptrdiff_t b) {
    double* s = blocks.data() + static_cast<std::size_t>(b) * k;
    const std::size_t lo = static_cast<std::size_t>(b) * block, hi = std::min(len, lo + block);
    for (std::size_t i = lo; i < hi; ++i) f(i, s);
  });
  std::vector<double> total(k, 0.0);
  for (std::ptrdiff_t b = 0; b < nb; ++b)
    for (std::size_t j = 0; j < k; ++j) total[j] += blocks[static_cast<std::size_t>(b) * k + j];
  return total;
}

// max over all points of f(i) (deterministic regardless of threads).
template <class F>
double grid_max(const Grid& g, F&& f, double init) {
  std::vector<double> rows(static_cast<std::size_t>(g.ny), init);
  for_rows(g.ny, [&](int iy) {
    double m = init;
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) {
      const double v = f(base + ix);
      if (v > m) m = v;
    }
    rows[iy] = m;
  });
  double m = init;
  for (double r : rows)
    if (r > m) m = r;
  return m;
}

}  // namespace gfmd
