// Contact patches: breadth-first labelling of the contact cells on the torus, with the
// unwrapped position of every cell so that a patch reaching its own periodic image is seen.
#include "gfmd/contact/patches.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

namespace {

struct RawPatch {
  std::size_t cells = 0;
  std::size_t x_faces = 0;  // faces to a non-contact x-neighbour (length dy each)
  std::size_t y_faces = 0;  // faces to a non-contact y-neighbour (length dx each)
  bool wraps_x = false, wraps_y = false;
};

void check_input(const Grid& g, const std::vector<unsigned char>& contact) {
  if (g.nx < 1 || g.ny < 1)
    throw ParameterError("grid", "nx and ny must be at least 1 (got nx = " + std::to_string(g.nx) +
                                     ", ny = " + std::to_string(g.ny) + ")");
  if (g.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw ParameterError("grid", "too many cells for patch labels (" + std::to_string(g.size()) + ")");
  if (contact.size() != g.size())
    throw ParameterError("contact", "the mask has " + std::to_string(contact.size()) + " entries, the grid " +
                                        std::to_string(g.size()));
}

// Labels the patches in the order of their first cell (row-major) into `labels` and returns
// their raw counts. wx, wy: the unwrapped position of cell i is (ix + wx[i] nx, iy + wy[i] ny)
// relative to the patch's first cell; reaching a labelled cell at another unwrapped position
// means that the patch wraps around the cell.
std::vector<RawPatch> label(const Grid& g, const std::vector<unsigned char>& contact,
                            std::vector<std::int32_t>& labels) {
  const std::size_t n = g.size(), nx = static_cast<std::size_t>(g.nx), ny = static_cast<std::size_t>(g.ny);
  labels.assign(n, -1);
  std::vector<std::int32_t> wx(n), wy(n);
  std::vector<std::uint32_t> queue(n);
  std::vector<RawPatch> patches;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (contact[seed] == 0 || labels[seed] >= 0) continue;
    const auto id = static_cast<std::int32_t>(patches.size());
    RawPatch p;
    labels[seed] = id;
    wx[seed] = wy[seed] = 0;
    std::size_t head = 0, tail = 0;
    queue[tail++] = static_cast<std::uint32_t>(seed);
    while (head < tail) {
      const std::size_t i = queue[head++];
      const std::size_t ix = i % nx, iy = i / nx;
      ++p.cells;
      // Neighbour j, reached from i with a change (dwx, dwy) of the wrap counts.
      auto visit = [&](std::size_t j, std::int32_t dwx, std::int32_t dwy, bool x_face) {
        if (contact[j] == 0) {
          ++(x_face ? p.x_faces : p.y_faces);
          return;
        }
        const std::int32_t ex = wx[i] + dwx, ey = wy[i] + dwy;
        if (labels[j] < 0) {
          labels[j] = id;
          wx[j] = ex;
          wy[j] = ey;
          queue[tail++] = static_cast<std::uint32_t>(j);
        } else {
          p.wraps_x = p.wraps_x || wx[j] != ex;
          p.wraps_y = p.wraps_y || wy[j] != ey;
        }
      };
      if (ix == 0)
        visit(i + nx - 1, -1, 0, true);
      else
        visit(i - 1, 0, 0, true);
      if (ix + 1 == nx)
        visit(i + 1 - nx, 1, 0, true);
      else
        visit(i + 1, 0, 0, true);
      if (iy == 0)
        visit(i + (ny - 1) * nx, 0, -1, false);
      else
        visit(i - nx, 0, 0, false);
      if (iy + 1 == ny)
        visit(ix, 0, 1, false);
      else
        visit(i + nx, 0, 0, false);
    }
    patches.push_back(p);
  }
  return patches;
}

}  // namespace

PatchStats contact_patches(const Grid& g, const std::vector<unsigned char>& contact,
                           std::vector<std::int32_t>& labels) {
  check_input(g, contact);
  const std::vector<RawPatch> raw = label(g, contact, labels);

  // Largest first; equal areas keep the order of their first cells.
  std::vector<std::size_t> order(raw.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return raw[a].cells > raw[b].cells; });

  const double dx = g.dx(), dy = g.dy();
  PatchStats s;
  s.count = raw.size();
  std::size_t total = 0;
  for (std::size_t k : order) {
    const RawPatch& p = raw[k];
    s.cells.push_back(p.cells);
    s.areas.push_back(static_cast<double>(p.cells) * dx * dy);
    s.perimeters.push_back(static_cast<double>(p.x_faces) * dy + static_cast<double>(p.y_faces) * dx);
    total += p.cells;
    s.percolating += (p.wraps_x || p.wraps_y) ? 1 : 0;
    s.percolates_x = s.percolates_x || p.wraps_x;
    s.percolates_y = s.percolates_y || p.wraps_y;
  }
  s.largest_area = s.areas.empty() ? 0.0 : s.areas.front();
  s.contact_area = static_cast<double>(total) * dx * dy;

  // Labels in the sorted order.
  std::vector<std::int32_t> rank(raw.size());
  for (std::size_t r = 0; r < order.size(); ++r) rank[order[r]] = static_cast<std::int32_t>(r);
  parallel_for(static_cast<std::ptrdiff_t>(labels.size()), [&](std::ptrdiff_t i) {
    if (labels[i] >= 0) labels[i] = rank[static_cast<std::size_t>(labels[i])];
  });
  return s;
}

PatchStats contact_patches(const Grid& g, const std::vector<unsigned char>& contact) {
  std::vector<std::int32_t> labels;
  return contact_patches(g, contact, labels);
}

std::vector<unsigned char> contact_mask(const ContactFields& f) {
  std::vector<unsigned char> mask(f.pressure.size());
  parallel_for(static_cast<std::ptrdiff_t>(mask.size()),
               [&](std::ptrdiff_t i) { mask[i] = f.in_contact(i) ? 1 : 0; });
  return mask;
}

}  // namespace gfmd
