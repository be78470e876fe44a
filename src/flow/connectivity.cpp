// Connectivity of the open gap: windings of the open cells around the torus, percolation.
#include "connectivity.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "gfmd/core/error.hpp"
#include "gfmd/flow/flow.hpp"

namespace gfmd {
namespace flow_detail {

// Whether open cells (g > 0) joined through faces between open cells wrap around the
// periodic cell along x and along y.
std::pair<bool, bool> open_windings(const Grid& grid, const double* gap) {
  const int nx = grid.nx, ny = grid.ny;
  WrapUnionFind uf(grid.size());
  unite_open_faces(
      uf, grid,
      [&](std::size_t i) {
        const std::size_t ix = i % nx, iy = i / nx;
        return gap[i] > 0.0 && gap[iy * nx + (ix + 1 == static_cast<std::size_t>(nx) ? 0 : ix + 1)] > 0.0;
      },
      [&](std::size_t i) {
        const std::size_t ix = i % nx, iy = i / nx;
        return gap[i] > 0.0 && gap[(iy + 1 == static_cast<std::size_t>(ny) ? 0 : iy + 1) * nx + ix] > 0.0;
      });
  return uf.windings();
}

void check_grid(const Grid& grid, const char* where) {
  if (grid.nx < 1 || grid.ny < 1) throw InputError(where, "grid must have nx, ny >= 1");
  if (grid.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw InputError(where, "grid too large");
  if (!(grid.lx > 0.0) || !(grid.ly > 0.0) || !std::isfinite(grid.lx) || !std::isfinite(grid.ly))
    throw InputError(where, "cell sizes lx, ly must be positive and finite");
}

}  // namespace flow_detail

bool percolates(const Grid& grid, const double* gap, int axis) {
  flow_detail::check_grid(grid, "percolates");
  if (gap == nullptr) throw InputError("percolates", "gap field is null");
  if (axis != 0 && axis != 1) throw InputError("percolates", "axis must be 0 (x) or 1 (y)");
  const auto [wx, wy] = flow_detail::open_windings(grid, gap);
  return axis == 0 ? wx : wy;
}

}  // namespace gfmd
