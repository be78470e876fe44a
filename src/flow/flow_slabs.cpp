// Reynolds flow on a slab of rows (a distributed run under mpirun): the same discretisation
// as flow.cpp (include/gfmd/flow/flow.hpp), every process assembling the rows of the cells it
// holds and HYPRE's BoomerAMG-PCG solving the whole system over all processes.
//
// What crosses processes: the gap, face conductances, unknown numbers and pressures of the
// rows next to each slab (mpi::neighbour_rows); for the connected components, only each
// slab's first and last rows (label_slabs below); the reductions (row order, as everywhere).
// No process holds anything of the whole cell.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "connectivity.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "reynolds_system.hpp"

namespace gfmd::flow_detail {

namespace {
constexpr unsigned char kStill = 1, kPinned = 2;  // a cell's status bits

// The connected components of the open faces of the whole cell, each process labelling its
// slab: every cell's status (kStill: its component does not wrap around the cell and carries
// no current; kPinned: still, or the one gauge cell of a wrapping component) and whether some
// component wraps along x and along y. open[i]: bit 0 the +x face of cell i is open, bit 1
// its +y face (for the last row: the face to the next slab's first row).
//
// Each process unites the faces inside its slab (a union-find that tracks windings, as one
// process does for the whole cell); then every process gathers the first and last rows of
// every slab (the root of each of their cells, its unwrapped offset from the root and the
// root's windings: 4 numbers per cell, and the last row's +y faces) and unites, in one small
// union-find of those rows' cells, the cells that share a slab's component and the faces
// between slabs. All processes build the same small structure, so they agree on which
// components wrap and which cell is each one's gauge: 8 bytes times 9 per grid column and
// slab cross the network, and no process holds more than its slab.
struct SlabLabels {
  std::vector<unsigned char> status;
  bool wraps_x = false, wraps_y = false;
};

SlabLabels label_slabs(const Grid& slab, const std::vector<unsigned char>& open) {
  const int nx = slab.nx, rows = slab.rows();
  const std::size_t n = slab.local_size();
  WrapUnionFind::Path path;
  WrapUnionFind local(n);
  for (int row = 0; row < rows; ++row)
    for (int ix = 0; ix < nx; ++ix) {
      const auto i = static_cast<std::int32_t>(row * nx + ix);
      if (open[static_cast<std::size_t>(i)] & 1)
        local.unite(i, row * nx + (ix + 1 == nx ? 0 : ix + 1), 1, 0, path);
      if ((open[static_cast<std::size_t>(i)] & 2) && row + 1 < rows) local.unite(i, i + nx, 0, 1, path);
    }
  // This slab's boundary rows: per cell its root, offset and the root's windings (the first
  // row, then the last), then the last row's +y faces.
  constexpr int kPer = 4;
  std::vector<std::int64_t> mine;
  if (rows > 0) {
    mine.reserve(static_cast<std::size_t>(nx) * (2 * kPer + 1));
    for (const int row : {0, rows - 1})
      for (int ix = 0; ix < nx; ++ix) {
        std::int64_t ox = 0, oy = 0;
        const std::int32_t r = local.find(row * nx + ix, ox, oy, path);
        mine.insert(mine.end(), {r, ox, oy, (local.wraps(r, 0) ? 1 : 0) | (local.wraps(r, 1) ? 2 : 0)});
      }
    for (int ix = 0; ix < nx; ++ix)
      mine.push_back((open[static_cast<std::size_t>(rows - 1) * nx + ix] & 2) ? 1 : 0);
  }
  const std::vector<std::int64_t> all = mpi::all_gather(mine);
  const std::size_t per_slab = static_cast<std::size_t>(nx) * (2 * kPer + 1);
  const std::size_t slabs = all.size() / per_slab;  // the processes that hold rows, in rank order
  // Which of those slabs is this process's (the rank order of the processes that hold rows).
  const std::vector<double> held = mpi::all_values(rows > 0 ? 1.0 : 0.0);
  std::size_t me = 0;
  for (int r = 0; r < mpi::rank(); ++r) me += held[static_cast<std::size_t>(r)] > 0 ? 1 : 0;
  // Nodes of the small union-find: slab s's first-row cell ix is 2 nx s + ix, its last-row
  // cell 2 nx s + nx + ix.
  const std::size_t nodes = 2 * static_cast<std::size_t>(nx) * slabs;
  WrapUnionFind merged(nodes);
  const auto entry = [&](std::size_t s, std::size_t node_in_slab) {
    return all.data() + s * per_slab + node_in_slab * kPer;
  };
  for (std::size_t s = 0; s < slabs; ++s) {
    // Cells of one component of slab s: united with the first such cell at their offset.
    std::vector<std::pair<std::int64_t, std::size_t>> by_root(2 * static_cast<std::size_t>(nx));
    for (std::size_t k = 0; k < by_root.size(); ++k) by_root[k] = {entry(s, k)[0], k};
    std::stable_sort(by_root.begin(), by_root.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t first = 0;  // the first entry of the current root
    for (std::size_t k = 0; k < by_root.size(); ++k) {
      const std::size_t node = 2 * nx * s + by_root[k].second;
      const std::int64_t* e = entry(s, by_root[k].second);
      if (k == 0 || by_root[k].first != by_root[k - 1].first) {
        first = k;
        if (e[3] != 0)
          merged.add_wraps(static_cast<std::int32_t>(node), static_cast<unsigned char>(e[3]), path);
        continue;
      }
      const std::int64_t* f = entry(s, by_root[first].second);
      merged.unite(static_cast<std::int32_t>(2 * nx * s + by_root[first].second),
                   static_cast<std::int32_t>(node), static_cast<int>(e[1] - f[1]),
                   static_cast<int>(e[2] - f[2]), path);
    }
  }
  for (std::size_t s = 0; s < slabs; ++s) {
    // The last row's open +y faces join the next slab's first row (the first slab after the last).
    const std::size_t next = (s + 1) % slabs;
    const std::int64_t* faces = all.data() + s * per_slab + 2 * static_cast<std::size_t>(nx) * kPer;
    for (int ix = 0; ix < nx; ++ix)
      if (faces[ix])
        merged.unite(static_cast<std::int32_t>(2 * nx * s + nx + ix),
                     static_cast<std::int32_t>(2 * nx * next + ix), 0, 1, path);
  }
  SlabLabels out;
  const auto [mx, my] = merged.windings();
  // This slab's components that reach its boundary rows: their fate (and gauge) is the merged
  // component's; one node per merged component is its root, and the local root of that node's
  // cell is the gauge.
  std::vector<std::pair<std::int32_t, unsigned char>> boundary;  // local root -> bits
  if (rows > 0)
    for (std::size_t k = 0; k < 2 * static_cast<std::size_t>(nx); ++k) {
      const auto node = static_cast<std::int32_t>(2 * nx * me + k);
      const std::int32_t g = merged.root(node);
      const bool still = !(merged.wraps(g, 0) || merged.wraps(g, 1));
      const auto r = static_cast<std::int32_t>(entry(me, k)[0]);
      boundary.emplace_back(r, static_cast<unsigned char>((still ? kStill : 0) | (g == node ? kPinned : 0)));
    }
  std::sort(boundary.begin(), boundary.end());
  // Merge the bits of one root's entries (kPinned: any of its cells is the merged root).
  std::vector<std::pair<std::int32_t, unsigned char>> roots;
  for (const auto& [r, b] : boundary)
    if (!roots.empty() && roots.back().first == r)
      roots.back().second |= b;
    else
      roots.emplace_back(r, b);
  out.status.resize(n);
  unsigned char local_wraps = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t r = local.root(static_cast<std::int32_t>(i));
    const auto it =
        std::lower_bound(roots.begin(), roots.end(), std::make_pair(r, static_cast<unsigned char>(0)));
    if (it != roots.end() && it->first == r) {
      const bool still = (it->second & kStill) != 0;
      const bool gauge = (it->second & kPinned) != 0 && r == static_cast<std::int32_t>(i);
      out.status[i] = static_cast<unsigned char>((still ? kStill : 0) | ((still || gauge) ? kPinned : 0));
      continue;
    }
    // A component inside the slab: it can wrap only along x.
    const bool wraps = local.wraps(r, 0) || local.wraps(r, 1);
    if (wraps && r == static_cast<std::int32_t>(i))
      local_wraps |= (local.wraps(r, 0) ? 1 : 0) | (local.wraps(r, 1) ? 2 : 0);
    out.status[i] = static_cast<unsigned char>((wraps ? 0 : kStill) |
                                               ((!wraps || r == static_cast<std::int32_t>(i)) ? kPinned : 0));
  }
  const unsigned w = mpi::any_bits(local_wraps | (mx ? 1u : 0u) | (my ? 2u : 0u));
  out.wraps_x = (w & 1) != 0;
  out.wraps_y = (w & 2) != 0;
  return out;
}

}  // namespace

std::vector<FlowResult> solve_flow_slabs(const Grid& g, const double* gap, const std::vector<double>& angles,
                                         const FlowOptions& opt) {
  const int nx = g.nx, rows = g.rows();
  const std::size_t n = g.local_size(), cells = g.size();
  // The first non-finite gap of the cell (row-major), as one process would name it.
  const auto [bad, any_bad] =
      grid_argmax(g, [&](std::size_t i) { return std::isfinite(gap[i]) ? 0.0 : 1.0; });
  if (any_bad > 0.0) throw InputError("flow", "non-finite gap at index " + std::to_string(bad));
  const double gmax = grid_max(
      g, [&](std::size_t i) { return gap[i]; }, 0.0);
  const double dx = g.dx(), dy = g.dy();
  const double wx = dy / dx, wy = dx / dy;
  std::vector<FlowResult> results = results_with_gap_means(g, gap, angles);
  const double mean_gap = results.empty() ? 0.0 : results.front().mean_gap;
  if (!(gmax > 0.0)) {
    for (FlowResult& res : results) {
      res.qx.assign(n, 0.0);
      res.qy.assign(n, 0.0);
    }
    return results;
  }
  const double kscale = gmax * gmax * gmax;
  const auto kcell = [&](double v) {
    const double q = std::max(v, 0.0) / gmax;
    return q * q * q;
  };
  const double kcut = opt.closed_face_conductance;
  const auto harmonic = [kcut](double ki, double kj) {
    const double kf = (ki > 0.0 && kj > 0.0) ? 2.0 * ki * kj / (ki + kj) : 0.0;
    return kf >= kcut ? kf : 0.0;
  };
  // Face conductances: +x faces within the row, +y faces with the row above.
  const RealField gap_here(gap, gap + n);
  const mpi::NeighbourRows gap_next = mpi::neighbour_rows(g, gap_here);
  const auto up = [&](const RealField& f, const RealField& above, int row, int ix) {
    return row + 1 < rows ? f[static_cast<std::size_t>(row + 1) * nx + ix]
                          : above[static_cast<std::size_t>(ix)];
  };
  const auto down = [&](const RealField& f, const RealField& below, int row, int ix) {
    return row > 0 ? f[static_cast<std::size_t>(row - 1) * nx + ix] : below[static_cast<std::size_t>(ix)];
  };
  RealField kx(n), ky(n);
  std::vector<unsigned char> open(n);
  const double cut = grid_sum(g, [&](std::size_t i) {
    const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
    const std::size_t ie = i - ix + (ix + 1 == nx ? 0 : ix + 1);
    const double gn = up(gap_here, gap_next.above, row, ix);
    const double ki = kcell(gap[i]);
    kx[i] = wx * harmonic(ki, kcell(gap[ie]));
    ky[i] = wy * harmonic(ki, kcell(gn));
    open[i] = static_cast<unsigned char>((kx[i] > 0.0 ? 1 : 0) | (ky[i] > 0.0 ? 2 : 0));
    return static_cast<double>(gap[i] > 0.0 && gap[ie] > 0.0 && kx[i] == 0.0) +
           static_cast<double>(gap[i] > 0.0 && gn > 0.0 && ky[i] == 0.0);
  });
  const auto faces_cut = static_cast<std::size_t>(cut);
  SlabLabels labels = label_slabs(g, open);
  const std::vector<unsigned char> status = std::move(labels.status);
  bool wraps_x = labels.wraps_x, wraps_y = labels.wraps_y;
  if (faces_cut > 0 && !(wraps_x && wraps_y)) {
    // The geometric flags (g > 0), as flow.cpp: faces between open cells.
    std::vector<unsigned char> geo(n);
    for (std::size_t i = 0; i < n; ++i) {
      const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
      const std::size_t ie = i - ix + (ix + 1 == nx ? 0 : ix + 1);
      const bool here = gap[i] > 0.0;
      geo[i] = static_cast<unsigned char>((here && gap[ie] > 0.0 ? 1 : 0) |
                                          (here && up(gap_here, gap_next.above, row, ix) > 0.0 ? 2 : 0));
    }
    const SlabLabels open_gap = label_slabs(g, geo);
    wraps_x = open_gap.wraps_x;
    wraps_y = open_gap.wraps_y;
  }
  // Unknowns: the cells not pinned, numbered process by process.
  SlabSystem sys;
  RealField index(n, -1.0);
  for (std::size_t i = 0; i < n; ++i)
    if (!(status[i] & kPinned)) index[i] = static_cast<double>(sys.count++);
  const std::vector<double> counts = mpi::all_values(static_cast<double>(sys.count));
  for (int r = 0; r < static_cast<int>(counts.size()); ++r) {
    if (r < mpi::rank()) sys.first += static_cast<std::int64_t>(counts[static_cast<std::size_t>(r)]);
    sys.total += static_cast<std::int64_t>(counts[static_cast<std::size_t>(r)]);
  }
  for (double& v : index)
    if (v >= 0.0) v += static_cast<double>(sys.first);
  const mpi::NeighbourRows index_next = mpi::neighbour_rows(g, index);
  const mpi::NeighbourRows ky_next = mpi::neighbour_rows(g, ky);
  for (std::size_t i = 0; i < n; ++i) {
    if (index[i] < 0.0) continue;
    const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
    const std::size_t iw = i - ix + (ix == 0 ? nx - 1 : ix - 1), ie = i - ix + (ix + 1 == nx ? 0 : ix + 1);
    const double ks = down(ky, ky_next.below, row, ix);
    const std::array<std::pair<double, double>, 4> faces = {{{index[iw], kx[iw]},
                                                             {index[ie], kx[i]},
                                                             {down(index, index_next.below, row, ix), ks},
                                                             {up(index, index_next.above, row, ix), ky[i]}}};
    int c = 1;
    sys.cols.push_back(static_cast<std::int64_t>(index[i]));
    sys.vals.push_back(kx[iw] + kx[i] + ks + ky[i]);
    for (const auto& [j, k] : faces)
      if (j >= 0.0 && k != 0.0) {
        sys.cols.push_back(static_cast<std::int64_t>(j));
        sys.vals.push_back(-k);
        ++c;
      }
    sys.ncols.push_back(c);
  }
  // Right-hand sides: the divergence of the imposed current of each direction.
  std::vector<Buffer<double>> rhs(angles.size());
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    rhs[k].resize(static_cast<std::size_t>(sys.count));
    std::size_t r = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (index[i] < 0.0) continue;
      const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
      const std::size_t iw = i - ix + (ix == 0 ? nx - 1 : ix - 1);
      rhs[k][r++] = dxd * dx * (kx[iw] - kx[i]) + dyd * dy * (down(ky, ky_next.below, row, ix) - ky[i]);
    }
  }
  if (opt.stop_request && opt.stop_request()) throw Interrupted("flow solve interrupted before BoomerAMG");
  std::vector<LinearSolution> sols;
  if (sys.total > 0) {
    sols = solve_boomeramg_slabs(sys, rhs, opt);
  } else {
    sols.resize(angles.size());
    for (LinearSolution& s : sols) s.converged = true;
  }
  for (const LinearSolution& sol : sols)
    if (!sol.converged)
      throw SolveError("flow: linear solve did not converge to " + sci(opt.tolerance) + ": " +
                       shortfall("BoomerAMG-PCG", sol) + " (distributed)");
  RealField qxf(n), qyf(n), P(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    take_solve(res, sols[k], dxd, dyd, wraps_x, wraps_y, faces_cut,
               sys.total > 0 ? "boomeramg (distributed)" : "none");
    for (std::size_t i = 0, r = 0; i < n; ++i) P[i] = index[i] >= 0.0 ? sols[k].x[r++] : 0.0;
    const mpi::NeighbourRows p_next = mpi::neighbour_rows(g, P);
    for (std::size_t i = 0; i < n; ++i) {
      const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
      const std::size_t ie = i - ix + (ix + 1 == nx ? 0 : ix + 1);
      const bool still = (status[i] & kStill) != 0;
      qxf[i] = (kx[i] > 0.0 && !still) ? -kscale * kx[i] * (P[ie] - P[i] - dxd * dx) / dy : 0.0;
      qyf[i] = (ky[i] > 0.0 && !still)
                   ? -kscale * ky[i] * (up(P, p_next.above, row, ix) - P[i] - dyd * dy) / dx
                   : 0.0;
    }
    const mpi::NeighbourRows qy_next = mpi::neighbour_rows(g, qyf);
    res.qx.resize(n);
    res.qy.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const int ix = static_cast<int>(i % nx), row = static_cast<int>(i / nx);
      res.qx[i] = 0.5 * (qxf[i] + qxf[i - ix + (ix == 0 ? nx - 1 : ix - 1)]);
      res.qy[i] = 0.5 * (qyf[i] + down(qyf, qy_next.below, row, ix));
    }
    const double mqx = grid_sum(g, [&](std::size_t i) { return qxf[i]; }) / static_cast<double>(cells);
    const double mqy = grid_sum(g, [&](std::size_t i) { return qyf[i]; }) / static_cast<double>(cells);
    res.conductivity = mqx * dxd + mqy * dyd;
    res.conductivity_transverse = -mqx * dyd + mqy * dxd;
    res.flow_factor = mean_gap > 0.0 ? res.conductivity / (mean_gap * mean_gap * mean_gap) : 0.0;
    // Conservation (flow.cpp): column totals of x faces over all processes, row totals of y
    // faces within each slab.
    std::vector<double> col(static_cast<std::size_t>(nx), 0.0);
    double dev = 0.0;
    for (int row = 0; row < rows; ++row) {
      double t = 0.0;
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = static_cast<std::size_t>(row) * nx + ix;
        col[static_cast<std::size_t>(ix)] += qxf[i];
        t += qyf[i];
      }
      dev = std::max(dev, std::abs(t / nx - mqy));
    }
    col = mpi::add_over_processes(col);
    for (double c : col) dev = std::max(dev, std::abs(c / g.ny - mqx));
    dev = mpi::max_all(g, dev);
    const double film = mean_gap * mean_gap * mean_gap;
    const double scale = std::max(std::abs(mqx), std::abs(mqy)) + (res.percolates ? 0.0 : film);
    res.conservation_error = scale > 0.0 ? dev / scale : 0.0;
  }
  return results;
}

}  // namespace gfmd::flow_detail
