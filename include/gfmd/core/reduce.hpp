// Deterministic reductions over the current backend: each row is summed serially, the row
// sums are added in row order, so the result does not depend on the backend or on the
// number of its workers. On a slab (a distributed run) the row sums of every process are
// gathered first (mpi::all_rows) and every process adds all ny rows in the same order: the
// same bits as one process.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/core/mpi.hpp"

namespace gfmd {

// The row partials rows[r * k + j] (k per row) of the rows held here, gathered from every
// process on a slab, added in row order: the one way every reduction below ends.
inline std::vector<double> add_rows(const Grid& g, std::vector<double> rows, std::size_t k) {
  if (g.is_slab()) rows = mpi::all_rows(g, rows, k);
  std::vector<double> total(k, 0.0);
  const std::size_t all = k > 0 ? rows.size() / k : 0;
  for (std::size_t r = 0; r < all; ++r)
    for (std::size_t j = 0; j < k; ++j) total[j] += rows[r * k + j];
  return total;
}

// K sums in one pass: f(i, acc) adds point i's contributions into acc[0..K-1]. Same
// sums each row serially and adds the row sums in row order, so the results do not
// depend on the number of threads.
template <std::size_t K, class F>
std::array<double, K> grid_sums(const Grid& g, F&& f) {
  const int rows = g.rows();
  std::vector<double> part(static_cast<std::size_t>(rows) * K);
  for_rows(rows, [&](int iy) {
    std::array<double, K> s{};
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) f(base + ix, s);
    std::copy(s.begin(), s.end(), part.begin() + static_cast<std::ptrdiff_t>(iy * K));
  });
  const std::vector<double> sums = add_rows(g, std::move(part), K);
  std::array<double, K> total{};
  std::copy(sums.begin(), sums.end(), total.begin());
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
  const int rows_here = g.rows();
  std::vector<double> rows(static_cast<std::size_t>(rows_here) * k, 0.0);
  for_rows(rows_here, [&](int iy) {
    double* s = rows.data() + static_cast<std::size_t>(iy) * k;
    const std::size_t base = static_cast<std::size_t>(iy) * g.nx;
    for (int ix = 0; ix < g.nx; ++ix) f(base + ix, s);
  });
  return add_rows(g, std::move(rows), k);
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

// Sums over the entries of a list whose entries belong to grid rows (a list of grid points):
// row r's entries are order[start[r]] .. order[start[r + 1] - 1], in list order, for the rows
// held here (start has g.rows() + 1 items). Each row's entries are summed serially and the
// row sums added in row order (gathered over the processes on a slab), so the results depend
// neither on the threads nor on the processes, as long as each row lists the same entries
// in the same order. f(e, acc) adds entry e's contributions into acc[0..k-1].
template <class F>
std::vector<double> row_grouped_sums(const Grid& g, const std::vector<std::uint32_t>& start,
                                     const std::vector<std::uint32_t>& order, std::size_t k, F&& f) {
  const int rows_here = g.rows();
  std::vector<double> rows(static_cast<std::size_t>(rows_here) * k, 0.0);
  for_rows(rows_here, [&](int r) {
    double* s = rows.data() + static_cast<std::size_t>(r) * k;
    for (std::uint32_t j = start[static_cast<std::size_t>(r)]; j < start[static_cast<std::size_t>(r) + 1];
         ++j)
      f(static_cast<std::size_t>(order[j]), s);
  });
  return add_rows(g, std::move(rows), k);
}

// max over all points of f(i) (deterministic regardless of threads and processes).
template <class F>
double grid_max(const Grid& g, F&& f, double init) {
  std::vector<double> rows(static_cast<std::size_t>(g.rows()), init);
  for_rows(g.rows(), [&](int iy) {
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
  return mpi::max_all(g, m);
}

// The largest f(i) over all points and the global index (iy * nx + ix, row-major) of the first
// point that holds it, as one process scanning the whole grid finds them: (index, value).
// The index is found as the largest negated index among the points equal to the maximum
// (exact below 2^53 points).
template <class F>
std::pair<std::size_t, double> grid_argmax(const Grid& g, F&& f) {
  const double none = -std::numeric_limits<double>::infinity();
  const double max = grid_max(g, f, none);
  const double first = static_cast<double>(g.y0) * g.nx;
  const double neg = grid_max(
      g, [&](std::size_t i) { return f(i) == max ? -(first + static_cast<double>(i)) : none; }, none);
  return {neg == none ? 0 : static_cast<std::size_t>(-neg), max};
}

}  // namespace gfmd
