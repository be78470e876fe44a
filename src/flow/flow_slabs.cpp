// Reynolds flow on a slab of rows (a distributed run under mpirun): the same discretisation
// as flow.cpp (include/gfmd/flow/flow.hpp), every process assembling the rows of the cells it
// holds and HYPRE's BoomerAMG-PCG solving the whole system over all processes.
//
// What crosses processes: the gap, face conductances, unknown numbers and pressures of the
// rows next to each slab (mpi::neighbour_rows); the open-face flags of every cell, gathered
// on rank 0 (one byte per point), which labels the connected components with their windings
// exactly as one process does (the same pinned gauge cells, the same percolation flags) and
// scatters each cell's status back (one byte per point); the reductions (row order, as
// everywhere). Rank 0 holds the union-find of the whole cell while it labels (about 17 bytes
// per point of the cell).
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

// Status of every cell (kStill, kPinned) and the windings of the open cluster, labelled on
// rank 0 from the open-face flags (bit 0: the +x face is open, bit 1: the +y face).
std::vector<unsigned char> label_on_root(const Grid& slab, const std::vector<unsigned char>& open,
                                         bool& wraps_x, bool& wraps_y) {
  std::vector<unsigned char> whole_open = mpi::gather(slab, open), status;
  int wraps = 0;
  if (mpi::root()) {
    const Grid whole = slab.whole();
    const std::size_t n = whole.size();
    status.resize(n);
    WrapUnionFind uf(n);
    unite_open_faces(
        uf, whole, [&](std::size_t i) { return (whole_open[i] & 1) != 0; },
        [&](std::size_t i) { return (whole_open[i] & 2) != 0; });
    std::vector<unsigned char>().swap(whole_open);
    const auto [wx, wy] = uf.windings();
    wraps = (wx ? 1 : 0) | (wy ? 2 : 0);
    parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
      const auto i = static_cast<std::size_t>(ii);
      const std::int32_t r = uf.root(static_cast<std::int32_t>(i));
      const bool still = !(uf.wraps(r, 0) || uf.wraps(r, 1));
      status[i] = static_cast<unsigned char>((still ? kStill : 0) |
                                             ((still || r == static_cast<std::int32_t>(i)) ? kPinned : 0));
    });
  }
  wraps = mpi::from_root(wraps);
  wraps_x = (wraps & 1) != 0;
  wraps_y = (wraps & 2) != 0;
  return mpi::scatter(slab, status);
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
  bool wraps_x = false, wraps_y = false;
  const std::vector<unsigned char> status = label_on_root(g, open, wraps_x, wraps_y);
  if (faces_cut > 0 && !(wraps_x && wraps_y)) {
    // The geometric flags (g > 0), as flow.cpp: from the whole gap on rank 0.
    const RealField whole = mpi::gather(g, gap_here);
    int w = 0;
    if (mpi::root()) {
      const auto [gx, gy] = open_windings(g.whole(), whole.data());
      w = (gx ? 1 : 0) | (gy ? 2 : 0);
    }
    w = mpi::from_root(w);
    wraps_x = (w & 1) != 0;
    wraps_y = (w & 2) != 0;
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
