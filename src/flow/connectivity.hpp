// Connectivity of the open gap on the periodic grid (private to the flow part): a
// union-find that tracks windings around the torus, and the grid check shared by the
// flow entry points.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "gfmd/core/buffer.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd::flow_detail {

// ---------------------------------------------------------------------------------------
// Union-find over a periodic lattice that also tracks windings: every node stores its
// unwrapped lattice offset from its parent, so that closing a loop around the torus is
// detected (the two paths give positions that differ by a nonzero lattice period).

class WrapUnionFind {
 public:
  using Path = std::vector<std::int32_t>;  // scratch of find(), one per thread

  explicit WrapUnionFind(std::size_t n) : parent_(n), size_(n), ox_(n), oy_(n), wrap_(n) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
      const auto u = static_cast<std::size_t>(i);
      parent_[u] = static_cast<std::int32_t>(i);
      size_[u] = 1;
      ox_[u] = oy_[u] = 0;
      wrap_[u] = 0;
    }
  }

  // Root of i and the offset of i relative to the root (with path compression).
  std::int32_t find(std::int32_t i, std::int64_t& ox, std::int64_t& oy, Path& path) {
    path.clear();
    std::int32_t r = i;
    while (parent_[r] != r) {
      path.push_back(r);
      r = parent_[r];
    }
    // Walk back from the node nearest to the root, accumulating offsets.
    std::int64_t ax = 0, ay = 0;
    for (auto it = path.rbegin(); it != path.rend(); ++it) {
      ax += ox_[*it];
      ay += oy_[*it];
      ox_[*it] = static_cast<std::int32_t>(ax);
      oy_[*it] = static_cast<std::int32_t>(ay);
      parent_[*it] = r;
    }
    ox = (i == r) ? 0 : ox_[i];
    oy = (i == r) ? 0 : oy_[i];
    return r;
  }

  // Joins i and j, where j sits at unwrapped position pos(i) + (sx, sy).
  void unite(std::int32_t i, std::int32_t j, int sx, int sy, Path& path) {
    std::int64_t oix, oiy, ojx, ojy;
    const std::int32_t ri = find(i, oix, oiy, path);
    const std::int32_t rj = find(j, ojx, ojy, path);
    const std::int64_t dx = oix + sx - ojx, dy = oiy + sy - ojy;  // pos(rj) - pos(ri)
    if (ri == rj) {
      if (dx != 0) wrap_[ri] |= 1;
      if (dy != 0) wrap_[ri] |= 2;
      return;
    }
    if (size_[ri] >= size_[rj]) {
      parent_[rj] = ri;
      ox_[rj] = static_cast<std::int32_t>(dx);
      oy_[rj] = static_cast<std::int32_t>(dy);
      size_[ri] += size_[rj];
      wrap_[ri] |= wrap_[rj];
    } else {
      parent_[ri] = rj;
      ox_[ri] = static_cast<std::int32_t>(-dx);
      oy_[ri] = static_cast<std::int32_t>(-dy);
      size_[rj] += size_[ri];
      wrap_[rj] |= wrap_[ri];
    }
  }

  // Marks i's component as wrapping along the axes in `bits` (1: x, 2: y): what a part of
  // it labelled elsewhere found (a distributed run's slabs, flow_slabs.cpp).
  void add_wraps(std::int32_t i, unsigned char bits, Path& path) {
    std::int64_t ox, oy;
    wrap_[find(i, ox, oy, path)] |= bits;
  }

  // Root of i without changing the structure (safe from several threads once the unions
  // are done).
  [[nodiscard]] std::int32_t root(std::int32_t i) const {
    while (parent_[i] != i) i = parent_[i];
    return i;
  }
  [[nodiscard]] bool wraps(std::int32_t root, int axis) const { return (wrap_[root] >> axis) & 1; }
  // Whether some component wraps along x, and whether some wraps along y.
  [[nodiscard]] std::pair<bool, bool> windings() const {
    unsigned char any = 0;
    for (std::size_t i = 0; i < parent_.size() && any != 3; ++i)
      if (parent_[i] == static_cast<std::int32_t>(i)) any |= wrap_[i];
    return {(any & 1) != 0, (any & 2) != 0};
  }

 private:
  Buffer<std::int32_t> parent_, size_;
  Buffer<std::int32_t> ox_, oy_;  // |offset| <= number of cells on a path < 2^31
  Buffer<unsigned char> wrap_;
};

// Unites neighbouring cells across open faces (open_x[i]: face between i and its +x
// neighbour, open_y[i]: between i and its +y neighbour). Bands of rows (a function of the
// grid only) are united side by side, each touching only its own cells, then the faces
// between bands in order: the structure does not depend on the number of threads.
template <class OpenX, class OpenY>
void unite_open_faces(WrapUnionFind& uf, const Grid& grid, OpenX&& open_x, OpenY&& open_y) {
  const int nx = grid.nx, ny = grid.ny;
  const int bands = std::clamp(ny / 64, 1, 16);
  auto band_lo = [&](int b) { return ny * b / bands; };
#pragma omp parallel if (bands > 1)
  {
    WrapUnionFind::Path path;
#pragma omp for schedule(dynamic, 1)
    for (int b = 0; b < bands; ++b) {
      const int y0 = band_lo(b), y1 = band_lo(b + 1);
      for (int iy = y0; iy < y1; ++iy)
        for (int ix = 0; ix < nx; ++ix) {
          const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
          const auto i = static_cast<std::int32_t>(iy * nx + ix);
          if (open_x(static_cast<std::size_t>(i))) uf.unite(i, iy * nx + ixe, 1, 0, path);
          if (iy + 1 < y1 && open_y(static_cast<std::size_t>(i))) uf.unite(i, (iy + 1) * nx + ix, 0, 1, path);
        }
    }
  }
  WrapUnionFind::Path path;
  for (int b = 0; b < bands; ++b) {
    const int iy = band_lo(b + 1) - 1, iyn = (iy + 1 == ny) ? 0 : iy + 1;
    for (int ix = 0; ix < nx; ++ix) {
      const auto i = static_cast<std::int32_t>(iy * nx + ix);
      if (open_y(static_cast<std::size_t>(i))) uf.unite(i, iyn * nx + ix, 0, 1, path);
    }
  }
}

// Which axes (x, y) the open gap (gap > 0) winds around.
std::pair<bool, bool> open_windings(const Grid& grid, const double* gap);

// Throws InputError(where, ...) for a grid the flow solver cannot take.
void check_grid(const Grid& grid, const char* where);

}  // namespace gfmd::flow_detail
