// The discretised Reynolds system and its linear solvers (private to the flow part): the
// face conductances on the periodic grid, the red-black reduced SPD system, and the two
// solvers of it (our AMG under CG in amg_solve.cpp, HYPRE's BoomerAMG in hypre_solve.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/buffer.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/flow/amg.hpp"
#include "gfmd/flow/flow.hpp"

namespace gfmd::flow_detail {

// ---------------------------------------------------------------------------------------
// The reduced SPD system.

// The operator, independent of the direction of the imposed gradient (G = 1): face
// conductances (weighted by the face length over the centre distance) and the cells that
// are not unknowns. Unknown cell i: diag_i x_i + sum_faces coupling_f x_nb(f) = b_i, with
// diag_i the sum of its four face conductances and coupling_f = -conductance_f, or 0 across
// a closed face and to a pinned neighbour (P~ = 0 there: symmetric elimination).
struct Face {
  std::size_t cell;
  double coupling;
};

struct LinearSystem {
  int nx = 0, ny = 0;
  Buffer<double> kx;                  // face between i and its +x neighbour: (dy/dx) k_f
  Buffer<double> ky;                  // face between i and its +y neighbour: (dx/dy) k_f
  std::vector<unsigned char> pinned;  // not an unknown (gauge cell or no net flow)
  // Periodic neighbours: columns ix -+ 1, row offsets (iy -+ 1) * nx.
  std::vector<std::size_t> xm, xp, ym, yp;

  void make_tables() {
    const auto unx = static_cast<std::size_t>(nx), uny = static_cast<std::size_t>(ny);
    xm.resize(unx);
    xp.resize(unx);
    ym.resize(uny);
    yp.resize(uny);
    for (std::size_t ix = 0; ix < unx; ++ix) {
      xm[ix] = ix == 0 ? unx - 1 : ix - 1;
      xp[ix] = ix + 1 == unx ? 0 : ix + 1;
    }
    for (std::size_t iy = 0; iy < uny; ++iy) {
      ym[iy] = (iy == 0 ? uny - 1 : iy - 1) * unx;
      yp[iy] = (iy + 1 == uny ? 0 : iy + 1) * unx;
    }
  }
  [[nodiscard]] std::size_t size() const { return kx.size(); }
  [[nodiscard]] std::size_t at(std::size_t ix, std::size_t iy) const {
    return iy * static_cast<std::size_t>(nx) + ix;
  }
  // The four faces (-x, +x, -y, +y) of cell (ix, iy); on grids one or two cells wide a
  // neighbour can appear twice, or be the cell itself.
  [[nodiscard]] std::array<Face, 4> faces(std::size_t ix, std::size_t iy) const {
    const std::size_t row = at(0, iy), i = row + ix, iw = row + xm[ix], ie = row + xp[ix];
    const std::size_t is = ym[iy] + ix, in = yp[iy] + ix;
    std::array<Face, 4> f = {{{iw, -kx[iw]}, {ie, -kx[i]}, {is, -ky[is]}, {in, -ky[i]}}};
    for (Face& e : f)
      if (pinned[i] || pinned[e.cell]) e.coupling = 0.0;
    return f;
  }
  [[nodiscard]] double diag(std::size_t ix, std::size_t iy) const {
    const std::size_t row = at(0, iy);
    return kx[row + xm[ix]] + kx[row + ix] + ky[ym[iy] + ix] + ky[row + ix];
  }
  // Conductance of a cell to its pinned neighbours (the row sum of an unknown's equation).
  [[nodiscard]] double excess(std::size_t ix, std::size_t iy) const {
    const std::size_t row = at(0, iy), i = row + ix, iw = row + xm[ix], ie = row + xp[ix];
    const std::size_t is = ym[iy] + ix, in = yp[iy] + ix;
    return (pinned[iw] ? kx[iw] : 0.0) + (pinned[ie] ? kx[i] : 0.0) + (pinned[is] ? ky[is] : 0.0) +
           (pinned[in] ? ky[i] : 0.0);
  }
  // Calls f(iy) for every grid row (a pass of the current backend).
  template <class F>
  void for_rows(F&& f) const {
    gfmd::for_rows(ny, [&](int iy) { f(static_cast<std::size_t>(iy)); });
  }
};

// The system handed to the linear solvers. All unknowns (cells not pinned, in grid order)
// in general. On grids with even sizes the cells are coloured red ((ix + iy) even) and
// black: a black cell couples to red cells only, so the black unknowns are eliminated
// exactly (the Schur complement S = A_rr - A_rb A_bb^-1 A_br with a diagonal A_bb, nine
// couplings per red row) and recovered after the solve from their own equations.
// S_ij = -sum_k a_ik a_kj / a_kk has no cancellation; its diagonal is taken from its row
// sum (the pinned-cell conductances, eliminated alike) plus the magnitudes of the
// couplings, so that nearly closed cells lose no digits either. Rows are in compressed
// form, diagonal first; couplings to the same neighbour across two faces are merged,
// those of a cell to itself (nx or ny == 1) go to the diagonal.
class ReducedSystem {
 public:
  ReducedSystem(const LinearSystem& sys, bool red_black) : sys_(sys) {
    red_black_ = red_black && sys.nx % 2 == 0 && sys.ny % 2 == 0;
    const auto ny = static_cast<std::size_t>(sys.ny), nx = static_cast<std::size_t>(sys.nx);
    // Unknowns of each grid row, then their numbers.
    row_first_.assign(ny + 1, 0);
    sys.for_rows([&](std::size_t iy) {
      std::size_t c = 0;
      for (std::size_t ix = 0; ix < nx; ++ix) c += kept(ix, iy) ? 1 : 0;
      row_first_[iy + 1] = c;
    });
    for (std::size_t iy = 0; iy < ny; ++iy) row_first_[iy + 1] += row_first_[iy];
    index_.resize(sys.size());
    sys.for_rows([&](std::size_t iy) {
      auto r = static_cast<std::int32_t>(row_first_[iy]);
      for (std::size_t ix = 0; ix < nx; ++ix) index_[sys.at(ix, iy)] = kept(ix, iy) ? r++ : -1;
    });
    // Rows are built twice: to count, then to fill the compressed rows in place.
    const std::size_t m = size();
    std::vector<std::uint8_t> len(m);
    sys.for_rows([&](std::size_t iy) {
      std::array<std::int32_t, kWidth> cols;
      std::array<double, kWidth> vals;
      std::size_t r = row_first_[iy];
      for (std::size_t ix = 0; ix < nx; ++ix)
        if (kept(ix, iy)) len[r++] = static_cast<std::uint8_t>(row(ix, iy, cols, vals));
    });
    matrix_.n = m;
    matrix_.ptr.assign(m + 1, 0);
    for (std::size_t r = 0; r < m; ++r) matrix_.ptr[r + 1] = matrix_.ptr[r] + len[r];
    matrix_.col.resize(matrix_.ptr[m]);
    matrix_.val.resize(matrix_.ptr[m]);
    sys.for_rows([&](std::size_t iy) {
      std::array<std::int32_t, kWidth> cols;
      std::array<double, kWidth> vals;
      std::size_t r = row_first_[iy];
      for (std::size_t ix = 0; ix < nx; ++ix) {
        if (!kept(ix, iy)) continue;
        const std::size_t c = row(ix, iy, cols, vals);
        std::copy_n(cols.data(), c, matrix_.col.data() + matrix_.ptr[r]);
        std::copy_n(vals.data(), c, matrix_.val.data() + matrix_.ptr[r]);
        ++r;
      }
    });
  }

  [[nodiscard]] std::size_t size() const { return row_first_.back(); }
  CsrMatrix take_matrix() { return std::move(matrix_); }
  // The cell -> unknown map is needed to build the matrix only.
  void release_index() { Buffer<std::int32_t>().swap(index_); }

  // The right-hand side of the reduced system for the full one b (on cells).
  void reduce(const Buffer<double>& b, Buffer<double>& br) const {
    br.resize(size());
    const auto nx = static_cast<std::size_t>(sys_.nx);
    sys_.for_rows([&](std::size_t iy) {
      std::size_t r = row_first_[iy];
      for (std::size_t ix = 0; ix < nx; ++ix) {
        if (!kept(ix, iy)) continue;
        double v = b[sys_.at(ix, iy)];
        if (red_black_)
          for (const Face& f : sys_.faces(ix, iy))
            if (f.coupling != 0.0) v -= f.coupling * b[f.cell] / sys_.diag(f.cell % nx, f.cell / nx);
        br[r++] = v;
      }
    });
  }

  // The full solution (0 on pinned cells) from that of the reduced system.
  void expand(const Buffer<double>& b, const Buffer<double>& xr, Buffer<double>& x) const {
    x.resize(sys_.size());
    const auto nx = static_cast<std::size_t>(sys_.nx);
    sys_.for_rows([&](std::size_t iy) {
      std::size_t r = row_first_[iy];
      for (std::size_t ix = 0; ix < nx; ++ix) x[sys_.at(ix, iy)] = kept(ix, iy) ? xr[r++] : 0.0;
    });
    if (!red_black_) return;
    sys_.for_rows([&](std::size_t iy) {
      for (std::size_t ix = (iy + 1) % 2; ix < nx; ix += 2) {
        const std::size_t i = sys_.at(ix, iy);
        if (sys_.pinned[i]) continue;
        double v = b[i];
        for (const Face& f : sys_.faces(ix, iy))
          if (f.coupling != 0.0) v -= f.coupling * x[f.cell];
        x[i] = v / sys_.diag(ix, iy);
      }
    });
  }

 private:
  static constexpr std::size_t kWidth = 13;  // diagonal + 4 black neighbours x 3 red cells
  const LinearSystem& sys_;
  bool red_black_ = false;
  std::vector<std::size_t> row_first_;  // first reduced unknown of each grid row (ny + 1)
  Buffer<std::int32_t> index_;          // cell -> reduced unknown, -1 otherwise
  CsrMatrix matrix_;

  [[nodiscard]] bool kept(std::size_t ix, std::size_t iy) const {
    return !sys_.pinned[sys_.at(ix, iy)] && (!red_black_ || (ix + iy) % 2 == 0);
  }

  // Row of the unknown (ix, iy): diagonal first, no zero couplings; returns its length.
  std::size_t row(std::size_t ix, std::size_t iy, std::array<std::int32_t, kWidth>& cols,
                  std::array<double, kWidth>& vals) const {
    if (red_black_ && sys_.nx > 4 && sys_.ny > 4) return row_wide(ix, iy, cols, vals);
    // General case (and grids four cells wide or less, where neighbours coincide): the
    // couplings are merged by column.
    const LinearSystem& sys = sys_;
    const auto nx = static_cast<std::size_t>(sys.nx);
    const std::size_t i = sys.at(ix, iy);
    std::size_t c = 1;
    cols[0] = index_[i];
    auto add = [&](std::size_t cell, double v) {
      const std::int32_t j = index_[cell];
      std::size_t k = 0;
      while (k < c && cols[k] != j) ++k;
      if (k == c) {
        cols[c] = j;
        vals[c] = v;
        ++c;
      } else {
        vals[k] += v;
      }
    };
    if (!red_black_) {
      vals[0] = sys.diag(ix, iy);
      for (const Face& f : sys.faces(ix, iy))
        if (f.coupling != 0.0) add(f.cell, f.coupling);
      return c;
    }
    double rowsum = sys.excess(ix, iy), offsum = 0.0;
    vals[0] = 0.0;
    for (const Face& f : sys.faces(ix, iy)) {
      if (f.coupling == 0.0) continue;
      const std::size_t kx = f.cell % nx, ky = f.cell / nx;
      const double inv = 1.0 / sys.diag(kx, ky);
      rowsum -= f.coupling * sys.excess(kx, ky) * inv;
      for (const Face& g : sys.faces(kx, ky)) {
        if (g.coupling == 0.0 || g.cell == i) continue;
        const double v = -f.coupling * g.coupling * inv;
        offsum -= v;
        add(g.cell, v);
      }
    }
    vals[0] = rowsum + offsum;
    return c;
  }

  // A red row on grids more than four cells wide: the eight red neighbours at (+-2, 0),
  // (0, +-2) (through one black cell) and (+-1, +-1) (through two) are distinct.
  std::size_t row_wide(std::size_t ix, std::size_t iy, std::array<std::int32_t, kWidth>& cols,
                       std::array<double, kWidth>& vals) const {
    const LinearSystem& sys = sys_;
    const std::size_t xm1 = sys.xm[ix], xp1 = sys.xp[ix], xm2 = sys.xm[xm1], xp2 = sys.xp[xp1];
    const auto nx = static_cast<std::size_t>(sys.nx);
    const std::size_t y0 = iy * nx, ym1 = sys.ym[iy], yp1 = sys.yp[iy];
    const std::size_t ym2 = sys.ym[ym1 / nx], yp2 = sys.yp[yp1 / nx];
    const unsigned char* pin = sys.pinned.data();
    const double* kx = sys.kx.data();
    const double* ky = sys.ky.data();
    // Conductance between two cells if both are unknowns (the face is named by its cell
    // on the -x / -y side), 0 otherwise.
    auto cx = [&](std::size_t a, std::size_t b, std::size_t face) {
      return pin[a] || pin[b] ? 0.0 : kx[face];
    };
    auto cy = [&](std::size_t a, std::size_t b, std::size_t face) {
      return pin[a] || pin[b] ? 0.0 : ky[face];
    };
    const std::size_t i = y0 + ix, W = y0 + xm1, E = y0 + xp1, S = ym1 + ix, N = yp1 + ix;
    const double aW = cx(i, W, W), aE = cx(i, E, i), aS = cy(i, S, S), aN = cy(i, N, i);
    const std::size_t sy = ym1 / nx, ny_ = yp1 / nx;
    const double iW = aW > 0.0 ? 1.0 / sys.diag(xm1, iy) : 0.0, iE = aE > 0.0 ? 1.0 / sys.diag(xp1, iy) : 0.0;
    const double iS = aS > 0.0 ? 1.0 / sys.diag(ix, sy) : 0.0, iN = aN > 0.0 ? 1.0 / sys.diag(ix, ny_) : 0.0;
    const std::array<std::size_t, 8> nb = {y0 + xm2,  y0 + xp2,  ym2 + ix,  yp2 + ix,
                                           ym1 + xm1, ym1 + xp1, yp1 + xm1, yp1 + xp1};
    // Products a_ik a_kj / a_kk (>= 0; S_ij is minus their sum).
    const std::array<double, 8> v = {aW * cx(W, nb[0], nb[0]) * iW,
                                     aE * cx(E, nb[1], E) * iE,
                                     aS * cy(S, nb[2], nb[2]) * iS,
                                     aN * cy(N, nb[3], N) * iN,
                                     aW * cy(W, nb[4], nb[4]) * iW + aS * cx(S, nb[4], nb[4]) * iS,
                                     aE * cy(E, nb[5], nb[5]) * iE + aS * cx(S, nb[5], S) * iS,
                                     aW * cy(W, nb[6], W) * iW + aN * cx(N, nb[6], nb[6]) * iN,
                                     aE * cy(E, nb[7], E) * iE + aN * cx(N, nb[7], N) * iN};
    double rowsum = sys.excess(ix, iy);
    if (aW > 0.0) rowsum += aW * sys.excess(xm1, iy) * iW;
    if (aE > 0.0) rowsum += aE * sys.excess(xp1, iy) * iE;
    if (aS > 0.0) rowsum += aS * sys.excess(ix, sy) * iS;
    if (aN > 0.0) rowsum += aN * sys.excess(ix, ny_) * iN;
    std::size_t c = 1;
    double offsum = 0.0;
    cols[0] = index_[i];
    for (std::size_t k = 0; k < 8; ++k) {
      if (v[k] == 0.0) continue;
      cols[c] = index_[nb[k]];
      vals[c] = -v[k];
      offsum += v[k];
      ++c;
    }
    vals[0] = rowsum + offsum;
    return c;
  }
};

// ||b - A x||_2 over the unknowns of the full system.
inline double full_residual_norm(const LinearSystem& sys, const Buffer<double>& b, const Buffer<double>& x) {
  const Grid g{sys.nx, sys.ny, 1.0, 1.0};
  const auto nx = static_cast<std::size_t>(sys.nx);
  return std::sqrt(grid_sum(g, [&](std::size_t i) {
    if (sys.pinned[i]) return 0.0;
    const std::size_t ix = i % nx, iy = i / nx;
    double v = b[i] - sys.diag(ix, iy) * x[i];
    for (const Face& f : sys.faces(ix, iy)) v -= f.coupling * x[f.cell];
    return v * v;
  }));
}

// Solution for one right-hand side; the set-up time is that of the preconditioner,
// counted for the first right-hand side only (the others reuse it).
struct LinearSolution {
  bool converged = false;
  double setup_s = 0.0, solve_s = 0.0;
  int iterations = 0;
  double residual = 0.0;
  Buffer<double> x;
};

// A number in scientific notation with three significant digits, for messages.
inline std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// PCG for one right-hand side: the preconditioner set-up runs for the first one only;
// both phases are timed.
template <class Setup, class Solve>
void timed_pcg(bool first, LinearSolution& sol, Setup&& setup, Solve&& solve) {
  if (first) {
    const auto t0 = std::chrono::steady_clock::now();
    setup();
    sol.setup_s = seconds_since(t0);
  }
  const auto t1 = std::chrono::steady_clock::now();
  solve();
  sol.solve_s = seconds_since(t1);
}

// Whether the residual and every value of the solution are finite.
inline bool finite(const LinearSolution& sol) {
  bool ok = std::isfinite(sol.residual);
  for (double v : sol.x) ok = ok && std::isfinite(v);
  return ok;
}

// What a solve that did not converge reached, for messages.
inline std::string shortfall(const char* method, const LinearSolution& sol) {
  return std::string(method) + " reached relative residual " + sci(sol.residual) + " after " +
         std::to_string(sol.iterations) + " iterations";
}

// The solutions when no cell is an unknown: zero everywhere.
inline std::vector<LinearSolution> no_unknowns(std::size_t ncell, std::size_t nrhs) {
  LinearSolution sol;
  sol.x.assign(ncell, 0.0);
  sol.converged = true;
  return std::vector<LinearSolution>(nrhs, sol);
}

// Fills the right-hand side of direction k (on cells, 0 on pinned cells). Built when its
// solve starts, so that it does not hold memory during the set-up.
using RhsFn = std::function<void(std::size_t k, Buffer<double>& b)>;

// Our algebraic multigrid (gfmd/flow/amg.hpp) under CG, one hierarchy for all right-hand
// sides, on the red-black reduced system where the grid allows it. A solve counts as
// converged when CG met the tolerance and the residual of the full system, recomputed, is
// within ten times it.
std::vector<LinearSolution> solve_native(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                         const FlowOptions& opt, int max_iterations);

// HYPRE's BoomerAMG under its PCG on the free cells (MPI and HYPRE started once per
// process; one solve at a time). Without HYPRE in the build: SolveError.
std::vector<LinearSolution> solve_boomeramg(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                            const FlowOptions& opt);

// The system of a distributed run (a slab of rows per process): the rows of the unknowns
// this process holds, with global column indices (unknowns are numbered process by process,
// row-major within each).
struct SlabSystem {
  std::int64_t first = 0;  // global index of the first unknown held here
  std::int64_t count = 0;  // unknowns held here
  std::int64_t total = 0;  // unknowns of all processes
  std::vector<int> ncols;  // couplings of each row held here (the diagonal included)
  std::vector<std::int64_t> cols;
  std::vector<double> vals;
};

// The results of every direction with their angle, <max(g, 0)> and <max(g, 0)^3> over the
// cell (grid_sum: the same sums on a whole grid and on the slabs of a distributed run).
inline std::vector<FlowResult> results_with_gap_means(const Grid& grid, const double* gap,
                                                      const std::vector<double>& angles) {
  const double n = static_cast<double>(grid.size());
  const double mean_gap = grid_sum(grid, [&](std::size_t i) { return std::max(gap[i], 0.0); }) / n;
  const double mean_gap_cubed = grid_sum(grid,
                                         [&](std::size_t i) {
                                           const double g = std::max(gap[i], 0.0);
                                           return g * g * g;
                                         }) /
                                n;
  std::vector<FlowResult> results(angles.size());
  for (std::size_t k = 0; k < angles.size(); ++k) {
    results[k].angle_deg = angles[k];
    results[k].mean_gap = mean_gap;
    results[k].mean_gap_cubed = mean_gap_cubed;
  }
  return results;
}

// A direction's result takes what its linear solve and the labelling found.
inline void take_solve(FlowResult& res, const LinearSolution& sol, double dxd, double dyd, bool wraps_x,
                       bool wraps_y, std::size_t faces_cut, const std::string& solver) {
  res.percolates = std::abs(dxd) >= std::abs(dyd) ? wraps_x : wraps_y;
  res.faces_cut = faces_cut;
  res.iterations = sol.iterations;
  res.residual = sol.residual;
  res.setup_s = sol.setup_s;
  res.solve_s = sol.solve_s;
  res.solver = solver;
}

// solve_flow on a slab of a distributed run (every process calls it with its rows of the
// gap): flow_slabs.cpp. The currents are the slab's; every figure is the whole cell's.
std::vector<FlowResult> solve_flow_slabs(const Grid& slab, const double* gap,
                                         const std::vector<double>& angles, const FlowOptions& opt);

// HYPRE's BoomerAMG under its PCG over all processes (MPI_COMM_WORLD), the settings of
// solve_boomeramg; rhs[k] holds the right-hand side of this process's unknowns. The
// solutions' x are this process's unknowns. Without HYPRE in the build: SolveError.
std::vector<LinearSolution> solve_boomeramg_slabs(const SlabSystem& sys,
                                                  const std::vector<Buffer<double>>& rhs,
                                                  const FlowOptions& opt);

}  // namespace gfmd::flow_detail
