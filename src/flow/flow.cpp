// Steady thin-film Reynolds flow (SPEC §6); see include/gfmd/flow/flow.hpp for the
// discretisation. Linear solves by our algebraic multigrid (gfmd/amg.hpp) under CG, or HYPRE.
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#ifndef MPICH_SKIP_MPICXX
#define MPICH_SKIP_MPICXX 1
#endif

#include "gfmd/flow/flow.hpp"

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_utilities.h>
#include <mpi.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(leak_sanitizer)
#define GFMD_LSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) && !defined(GFMD_LSAN)
#define GFMD_LSAN 1
#endif
#ifdef GFMD_LSAN
#include <sanitizer/lsan_interface.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gfmd/core/buffer.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/flow/amg.hpp"

namespace gfmd {

namespace {

// ---------------------------------------------------------------------------------------
// MPI / HYPRE set-up: once per process, lazily.

// OpenMPI keeps (and never frees) bookkeeping from MPI_Init; under LeakSanitizer those
// allocations are excluded so that sanitizer runs report only our own leaks.
struct LeakCheckPause {
#ifdef GFMD_LSAN
  LeakCheckPause() { __lsan_disable(); }
  ~LeakCheckPause() { __lsan_enable(); }
#endif
};

bool g_mpi_initialised_here = false;
std::once_flag g_hypre_once;
std::mutex g_hypre_mutex;  // HYPRE is not thread-safe: one solve at a time

void finalize_hypre_and_mpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  [[maybe_unused]] const LeakCheckPause pause;
  HYPRE_Finalize();
  if (g_mpi_initialised_here) MPI_Finalize();
}

void ensure_hypre() {
  std::call_once(g_hypre_once, [] {
    [[maybe_unused]] const LeakCheckPause pause;
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized) throw SolveError("flow: MPI has already been finalised; HYPRE cannot be used");
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        throw SolveError("flow: MPI_Init_thread failed");
      g_mpi_initialised_here = true;
    }
    HYPRE_Init();
    std::atexit(finalize_hypre_and_mpi);
  });
}

void hypre_check(HYPRE_Int ierr, const char* what) {
  // A convergence failure is judged from the residual by the caller.
  if ((ierr & ~static_cast<HYPRE_Int>(HYPRE_ERROR_CONV)) != 0) {
    char msg[256] = {0};
    HYPRE_DescribeError(ierr, msg);
    HYPRE_ClearAllErrors();
    throw SolveError(std::string("flow: HYPRE ") + what + " failed: " + msg);
  }
  if (ierr != 0) HYPRE_ClearAllErrors();
}

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
  // Calls f(iy) for every grid row, rows shared among the threads.
  template <class F>
  void for_rows(F&& f) const {
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) f(static_cast<std::size_t>(iy));
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
double full_residual_norm(const LinearSystem& sys, const Buffer<double>& b, const Buffer<double>& x) {
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
std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
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
bool finite(const LinearSolution& sol) {
  bool ok = std::isfinite(sol.residual);
  for (double v : sol.x) ok = ok && std::isfinite(v);
  return ok;
}

// What a solve that did not converge reached, for messages.
std::string shortfall(const char* method, const LinearSolution& sol) {
  return std::string(method) + " reached relative residual " + sci(sol.residual) + " after " +
         std::to_string(sol.iterations) + " iterations";
}

// The solutions when no cell is an unknown: zero everywhere.
std::vector<LinearSolution> no_unknowns(std::size_t ncell, std::size_t nrhs) {
  LinearSolution sol;
  sol.x.assign(ncell, 0.0);
  sol.converged = true;
  return std::vector<LinearSolution>(nrhs, sol);
}

// Fills the outcome of a solve whose solution is already in sol.x, from HYPRE's
// iteration count and final relative residual.
void finish(LinearSolution& sol, HYPRE_Int its, HYPRE_Real res, const FlowOptions& opt) {
  sol.iterations = its;
  sol.residual = res;
  sol.converged = finite(sol) && res <= opt.tolerance;
}

// Fills the right-hand side of direction k (on cells, 0 on pinned cells). Built when its
// solve starts, so that it does not hold memory during the set-up.
using RhsFn = std::function<void(std::size_t k, Buffer<double>& b)>;

// Our algebraic multigrid (gfmd/amg.hpp) under CG, one hierarchy for all right-hand sides,
// on the red-black reduced system where the grid allows it. A solve counts as converged
// when CG met the tolerance and the residual of the full system, recomputed, is within
// ten times it.
std::vector<LinearSolution> solve_native(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                         const FlowOptions& opt, int max_iterations) {
  std::vector<LinearSolution> out;
  const auto t0 = std::chrono::steady_clock::now();
  ReducedSystem red(sys, true);
  if (red.size() == 0) return no_unknowns(sys.size(), nrhs);
  const AlgebraicMultigrid amg(red.take_matrix());
  red.release_index();
  const double setup_s = seconds_since(t0);
  if (opt.stop_request && opt.stop_request())
    throw Interrupted("flow solve interrupted after the AMG set-up");
  Buffer<double> b, br, xr;
  for (std::size_t k = 0; k < nrhs; ++k) {
    LinearSolution sol;
    sol.setup_s = k == 0 ? setup_s : 0.0;
    const auto t1 = std::chrono::steady_clock::now();
    make_rhs(k, b);
    const double bnorm =
        std::sqrt(range_sums(b.size(), 1, [&](std::size_t i, double* acc) { acc[0] += b[i] * b[i]; })[0]);
    red.reduce(b, br);
    xr.resize(br.size());
    const CgOutcome cg =
        amg_pcg(amg, br.data(), xr.data(), opt.tolerance, max_iterations, bnorm, opt.stop_request);
    red.expand(b, xr, sol.x);
    sol.solve_s = seconds_since(t1);
    sol.iterations = cg.iterations;
    sol.residual = bnorm > 0.0 ? full_residual_norm(sys, b, sol.x) / bnorm : 0.0;
    sol.converged = finite(sol) && cg.converged && sol.residual <= 10.0 * opt.tolerance;
    out.push_back(std::move(sol));
  }
  return out;
}

std::vector<LinearSolution> solve_boomeramg(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                            const FlowOptions& opt) {
  const MPI_Comm comm = MPI_COMM_SELF;
  const std::size_t ncell = sys.size();

  // Only the free cells are unknowns: pinned and isolated cells (P~ = 0) are dropped,
  // together with their couplings (which are zero in the reduced system anyway).
  ReducedSystem u(sys, false);
  if (u.size() == 0) return no_unknowns(ncell, nrhs);
  const auto n = static_cast<HYPRE_BigInt>(u.size());
  const CsrMatrix a = u.take_matrix();

  HYPRE_IJMatrix A = nullptr;
  HYPRE_IJVector b = nullptr, x = nullptr;
  HYPRE_Solver pcg = nullptr, amg = nullptr;
  struct Cleanup {
    HYPRE_IJMatrix& A;
    HYPRE_IJVector &b, &x;
    HYPRE_Solver &pcg, &amg;
    ~Cleanup() {
      if (amg) HYPRE_BoomerAMGDestroy(amg);
      if (pcg) HYPRE_ParCSRPCGDestroy(pcg);
      if (x) HYPRE_IJVectorDestroy(x);
      if (b) HYPRE_IJVectorDestroy(b);
      if (A) HYPRE_IJMatrixDestroy(A);
      HYPRE_ClearAllErrors();
    }
  } cleanup{A, b, x, pcg, amg};

  std::vector<HYPRE_Int> ncols(static_cast<std::size_t>(n));
  std::vector<HYPRE_BigInt> rows(static_cast<std::size_t>(n)), cols(a.col.begin(), a.col.end());
  const Buffer<double>& vals = a.val;
  Buffer<double> rhs;  // right-hand side of the unknowns
  for (std::size_t r = 0; r < a.n; ++r) {
    rows[r] = static_cast<HYPRE_BigInt>(r);
    ncols[r] = static_cast<HYPRE_Int>(a.ptr[r + 1] - a.ptr[r]);
  }
  hypre_check(HYPRE_IJMatrixCreate(comm, 0, n - 1, 0, n - 1, &A), "IJMatrixCreate");
  hypre_check(HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR), "IJMatrixSetObjectType");
  {
    std::vector<HYPRE_Int> offd(static_cast<std::size_t>(n), 0);
    hypre_check(HYPRE_IJMatrixSetDiagOffdSizes(A, ncols.data(), offd.data()), "IJMatrixSetDiagOffdSizes");
  }
  hypre_check(HYPRE_IJMatrixSetMaxOffProcElmts(A, 0), "IJMatrixSetMaxOffProcElmts");
  hypre_check(HYPRE_IJMatrixInitialize(A), "IJMatrixInitialize");
  hypre_check(HYPRE_IJMatrixSetValues(A, static_cast<HYPRE_Int>(n), ncols.data(), rows.data(), cols.data(),
                                      const_cast<double*>(vals.data())),
              "IJMatrixSetValues");
  hypre_check(HYPRE_IJMatrixAssemble(A), "IJMatrixAssemble");
  HYPRE_ParCSRMatrix parA = nullptr;
  hypre_check(HYPRE_IJMatrixGetObject(A, reinterpret_cast<void**>(&parA)), "IJMatrixGetObject");

  std::vector<double> zero(static_cast<std::size_t>(n), 0.0);
  hypre_check(HYPRE_IJVectorCreate(comm, 0, n - 1, &b), "IJVectorCreate");
  hypre_check(HYPRE_IJVectorSetObjectType(b, HYPRE_PARCSR), "IJVectorSetObjectType");
  hypre_check(HYPRE_IJVectorInitialize(b), "IJVectorInitialize");
  hypre_check(HYPRE_IJVectorSetValues(b, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
              "IJVectorSetValues");
  hypre_check(HYPRE_IJVectorAssemble(b), "IJVectorAssemble");
  hypre_check(HYPRE_IJVectorCreate(comm, 0, n - 1, &x), "IJVectorCreate");
  hypre_check(HYPRE_IJVectorSetObjectType(x, HYPRE_PARCSR), "IJVectorSetObjectType");
  hypre_check(HYPRE_IJVectorInitialize(x), "IJVectorInitialize");
  hypre_check(HYPRE_IJVectorSetValues(x, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
              "IJVectorSetValues");
  hypre_check(HYPRE_IJVectorAssemble(x), "IJVectorAssemble");
  HYPRE_ParVector parb = nullptr, parx = nullptr;
  hypre_check(HYPRE_IJVectorGetObject(b, reinterpret_cast<void**>(&parb)), "IJVectorGetObject");
  hypre_check(HYPRE_IJVectorGetObject(x, reinterpret_cast<void**>(&parx)), "IJVectorGetObject");

  hypre_check(HYPRE_ParCSRPCGCreate(comm, &pcg), "ParCSRPCGCreate");
  HYPRE_PCGSetTol(pcg, opt.tolerance);
  HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
  HYPRE_PCGSetMaxIter(pcg, opt.max_iterations);
  HYPRE_PCGSetTwoNorm(pcg, 1);
  HYPRE_PCGSetRelChange(pcg, 0);
  HYPRE_PCGSetPrintLevel(pcg, 0);
  HYPRE_PCGSetLogging(pcg, 1);

  // Ruge-Stueben coarsening with classical (modified) interpolation: on the 2048^2
  // benchmark gap (bench/bench_flow) its set-up takes about 60 % of that of HMIS +
  // extended+i interpolation at nearly the same iteration count (12 against 11).
  hypre_check(HYPRE_BoomerAMGCreate(&amg), "BoomerAMGCreate");
  HYPRE_BoomerAMGSetPrintLevel(amg, 0);
  HYPRE_BoomerAMGSetMaxIter(amg, 1);
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  HYPRE_BoomerAMGSetCoarsenType(amg, 6);  // Falgout (Ruge-Stueben on one process)
  HYPRE_BoomerAMGSetInterpType(amg, 0);   // classical modified
  HYPRE_BoomerAMGSetPMaxElmts(amg, 4);
  HYPRE_BoomerAMGSetStrongThreshold(amg, 0.25);
  // One forward Gauss-Seidel sweep on the way down and one backward sweep on the way up:
  // a symmetric V-cycle (as PCG needs) at half the smoothing cost of symmetric sweeps at
  // both ends (2048^2 benchmark: 14 instead of 13 iterations, PCG 3.0 s instead of 4.7 s).
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 3, 1);  // down: hybrid forward Gauss-Seidel
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 4, 2);  // up: hybrid backward Gauss-Seidel
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3);  // coarsest: Gaussian elimination
  HYPRE_BoomerAMGSetNumSweeps(amg, 1);
  hypre_check(HYPRE_PCGSetPrecond(pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve),
                                  reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSetup), amg),
              "PCGSetPrecond");

  std::vector<LinearSolution> out;
  Buffer<double> xr(static_cast<std::size_t>(n));
  Buffer<double> full;
  for (std::size_t k = 0; k < nrhs; ++k) {
    make_rhs(k, full);
    u.reduce(full, rhs);
    hypre_check(HYPRE_IJVectorSetValues(b, static_cast<HYPRE_Int>(n), rows.data(), rhs.data()),
                "IJVectorSetValues");
    hypre_check(HYPRE_IJVectorSetValues(x, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
                "IJVectorSetValues");
    LinearSolution sol;
    timed_pcg(
        k == 0, sol, [&] { hypre_check(HYPRE_ParCSRPCGSetup(pcg, parA, parb, parx), "ParCSRPCGSetup"); },
        [&] { hypre_check(HYPRE_ParCSRPCGSolve(pcg, parA, parb, parx), "ParCSRPCGSolve"); });
    HYPRE_Int its = 0;
    HYPRE_Real res = 0.0;
    HYPRE_PCGGetNumIterations(pcg, &its);
    HYPRE_PCGGetFinalRelativeResidualNorm(pcg, &res);
    hypre_check(HYPRE_IJVectorGetValues(x, static_cast<HYPRE_Int>(n), rows.data(), xr.data()),
                "IJVectorGetValues");
    u.expand(full, xr, sol.x);
    finish(sol, its, res, opt);
    out.push_back(std::move(sol));
  }
  return out;
}

std::vector<FlowResult> solve_flow_impl(const Grid& grid, const double* gap,
                                        const std::vector<double>& angles, const FlowOptions& opt) {
  const FlowSolver which = opt.solver;
  check_grid(grid, "flow");
  if (gap == nullptr) throw InputError("flow", "gap field is null");
  if (angles.empty()) throw InputError("flow", "no flow direction given");
  for (double a : angles)
    if (!std::isfinite(a)) throw InputError("flow", "angle must be finite");
  if (!(opt.tolerance > 0.0) || !(opt.tolerance < 1.0))
    throw InputError("flow", "tolerance must be in (0, 1)");
  if (opt.max_iterations < 1) throw InputError("flow", "max_iterations must be >= 1");
  if (opt.amg_iterations_before_fallback < 1)
    throw InputError("flow", "amg_iterations_before_fallback must be >= 1");
  if (!(opt.closed_face_conductance >= 0.0) || !(opt.closed_face_conductance < 1.0))
    throw InputError("flow", "closed_face_conductance must be in [0, 1)");
  const int nx = grid.nx, ny = grid.ny;
  const std::size_t n = grid.size();

  // Every block of the solve comes from the heap, grown once for all of them and advised
  // for transparent huge pages, and is given back when the solve ends: the many grid-sized
  // temporaries (operator, reduction, multigrid set-up, HYPRE's) would otherwise each be
  // mapped and faulted in afresh, 4 KiB at a time (2048^2: seconds in the kernel).
  const HeapAllocationScope heap_only(512 * n);
  double gmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(gap[i])) throw InputError("flow", "non-finite gap at index " + std::to_string(i));
    gmax = std::max(gmax, gap[i]);
  }

  const double dx = grid.dx(), dy = grid.dy();
  const double wx = dy / dx, wy = dx / dy;

  std::vector<FlowResult> results(angles.size());
  const double mean_gap =
      grid_sum(grid, [&](std::size_t i) { return std::max(gap[i], 0.0); }) / static_cast<double>(n);
  const double mean_gap_cubed = grid_sum(grid,
                                         [&](std::size_t i) {
                                           const double g = std::max(gap[i], 0.0);
                                           return g * g * g;
                                         }) /
                                static_cast<double>(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    res.angle_deg = angles[k];
    res.mean_gap = mean_gap;
    res.mean_gap_cubed = mean_gap_cubed;
  }
  if (!(gmax > 0.0)) {  // everything closed: no flow
    for (FlowResult& res : results) {
      res.qx.assign(n, 0.0);
      res.qy.assign(n, 0.0);
    }
    return results;
  }

  // Normalised face conductances (kn = (g / gmax)^3 of the cells, physical k = kscale * kn),
  // weighted by the face length over the centre distance.
  const double kscale = gmax * gmax * gmax;
  LinearSystem sys;
  sys.nx = nx;
  sys.ny = ny;
  sys.make_tables();
  sys.kx.resize(n);
  sys.ky.resize(n);
  auto kcell = [&](std::size_t i) {
    const double g = std::max(gap[i], 0.0) / gmax;
    return g * g * g;
  };
  const double kcut = opt.closed_face_conductance;
  auto harmonic = [kcut](double ki, double kj) {
    const double kf = (ki > 0.0 && kj > 0.0) ? 2.0 * ki * kj / (ki + kj) : 0.0;
    return kf >= kcut ? kf : 0.0;
  };
  // Also counted: faces between two open cells that the cut-off (or underflow of
  // (g / g_max)^3) closed.
  std::size_t faces_cut = 0;
#pragma omp parallel for schedule(static) reduction(+ : faces_cut)
  for (int iy = 0; iy < ny; ++iy) {
    const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
    for (int ix = 0; ix < nx; ++ix) {
      const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
      const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
      const std::size_t ie = static_cast<std::size_t>(iy) * nx + ixe,
                        in = static_cast<std::size_t>(iyn) * nx + ix;
      const double ki = kcell(i);
      sys.kx[i] = wx * harmonic(ki, kcell(ie));
      sys.ky[i] = wy * harmonic(ki, kcell(in));
      faces_cut += static_cast<std::size_t>(gap[i] > 0.0 && gap[ie] > 0.0 && sys.kx[i] == 0.0);
      faces_cut += static_cast<std::size_t>(gap[i] > 0.0 && gap[in] > 0.0 && sys.ky[i] == 0.0);
    }
  }

  // Connected components over open faces; windings give the percolation flags.
  // (Geometric flags, g > 0, are recomputed below where faces were cut.)
  // A component that winds around the cell in no direction (a trapped pocket, an isolated
  // cell) carries no flow: its total pressure is constant. Such "still" cells are not
  // unknowns (their currents are zero); neither is one gauge cell (the root, P~ = 0) of
  // every winding component.
  sys.pinned.resize(n);
  std::vector<unsigned char>& pinned = sys.pinned;
  Buffer<unsigned char> still(n);
  bool wraps_x = false, wraps_y = false;
  {
    WrapUnionFind uf(n);
    unite_open_faces(
        uf, grid, [&](std::size_t i) { return sys.kx[i] > 0.0; },
        [&](std::size_t i) { return sys.ky[i] > 0.0; });
    std::tie(wraps_x, wraps_y) = uf.windings();
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t ii = 0; ii < static_cast<std::ptrdiff_t>(n); ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      const std::int32_t r = uf.root(static_cast<std::int32_t>(i));
      still[i] = !(uf.wraps(r, 0) || uf.wraps(r, 1));
      pinned[i] = still[i] || r == static_cast<std::int32_t>(i);
    }
  }
  // Cutting faces only removes windings: the geometric flags differ only where a direction
  // lost its winding.
  if (faces_cut > 0 && !(wraps_x && wraps_y)) {
    const auto [gx, gy] = open_windings(grid, gap);
    wraps_x = gx;
    wraps_y = gy;
  }

  // Right-hand side of direction d = (cos a, sin a): the divergence of the imposed current,
  // G d_x dx through x faces and G d_y dy through y faces (times the conductance).
  const RhsFn make_rhs = [&](std::size_t k, Buffer<double>& b) {
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    b.resize(n);
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        if (pinned[i]) {
          b[i] = 0.0;
          continue;
        }
        const std::size_t iw = static_cast<std::size_t>(iy) * nx + ixw;
        const std::size_t is = static_cast<std::size_t>(iys) * nx + ix;
        b[i] = dxd * dx * (sys.kx[iw] - sys.kx[i]) + dyd * dy * (sys.ky[is] - sys.ky[i]);
      }
    }
  };

  // Back end: our algebraic multigrid (OpenMP, on the red-black reduced system), with
  // HYPRE's BoomerAMG (serial) as the fallback if it does not converge within its
  // iteration budget; or BoomerAMG alone when asked for. One set-up serves all directions.
  std::vector<LinearSolution> sols;
  std::string failure, solver = "amg";
  double wasted_s = 0.0;  // a failed AMG attempt, counted into the set-up time
  if (which != FlowSolver::BoomerAMG) {
    const int budget = which == FlowSolver::Amg
                           ? opt.max_iterations
                           : std::min(opt.max_iterations, opt.amg_iterations_before_fallback);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      sols = solve_native(sys, angles.size(), make_rhs, opt, budget);
      for (const LinearSolution& sol : sols)
        if (!sol.converged && failure.empty()) failure = shortfall("AMG-PCG", sol);
    } catch (const Interrupted&) {
      throw;
    } catch (const SolveError& e) {
      failure = e.what();
    }
    if (!failure.empty() && which == FlowSolver::Amg)
      throw SolveError("flow: linear solve did not converge to " + sci(opt.tolerance) + ": " + failure);
    wasted_s = failure.empty() ? 0.0 : seconds_since(t0);
  }
  if (which == FlowSolver::BoomerAMG || !failure.empty()) {
    solver = failure.empty() ? "boomeramg" : "boomeramg (fallback)";
    if (opt.stop_request && opt.stop_request()) throw Interrupted("flow solve interrupted before BoomerAMG");
    ensure_hypre();
    std::lock_guard<std::mutex> lock(g_hypre_mutex);
    sols = solve_boomeramg(sys, angles.size(), make_rhs, opt);
    for (const LinearSolution& sol : sols)
      if (!sol.converged) {
        if (!failure.empty()) failure += "; then ";
        failure += shortfall("BoomerAMG-PCG", sol);
        throw SolveError("flow: linear solve did not converge to " + sci(opt.tolerance) + ": " + failure);
      }
    sols.front().setup_s += wasted_s;
  }

  Buffer<double> qxf(n), qyf(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    res.percolates = std::abs(dxd) >= std::abs(dyd) ? wraps_x : wraps_y;
    res.faces_cut = faces_cut;
    res.iterations = sols[k].iterations;
    res.residual = sols[k].residual;
    res.setup_s = sols[k].setup_s;
    res.solve_s = sols[k].solve_s;
    res.solver = solver;
    const Buffer<double>& P = sols[k].x;

    // Face current densities (physical units, G = 1) and cell-centred averages.
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        const std::size_t ie = static_cast<std::size_t>(iy) * nx + ixe;
        const std::size_t in = static_cast<std::size_t>(iyn) * nx + ix;
        // kx / dy = k_f / dx, ky / dx = k_f / dy.
        qxf[i] = (sys.kx[i] > 0.0 && !still[i]) ? -kscale * sys.kx[i] * (P[ie] - P[i] - dxd * dx) / dy : 0.0;
        qyf[i] = (sys.ky[i] > 0.0 && !still[i]) ? -kscale * sys.ky[i] * (P[in] - P[i] - dyd * dy) / dx : 0.0;
      }
    }
    res.qx.resize(n);
    res.qy.resize(n);
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        res.qx[i] = 0.5 * (qxf[i] + qxf[static_cast<std::size_t>(iy) * nx + ixw]);
        res.qy[i] = 0.5 * (qyf[i] + qyf[static_cast<std::size_t>(iys) * nx + ix]);
      }
    }
    const double mqx = grid_sum(grid, [&](std::size_t i) { return qxf[i]; }) / static_cast<double>(n);
    const double mqy = grid_sum(grid, [&](std::size_t i) { return qyf[i]; }) / static_cast<double>(n);
    res.conductivity = mqx * dxd + mqy * dyd;
    res.conductivity_transverse = -mqx * dyd + mqy * dxd;
    res.flow_factor =
        res.mean_gap > 0.0 ? res.conductivity / (res.mean_gap * res.mean_gap * res.mean_gap) : 0.0;

    // Conservation: total current through every column of x faces / row of y faces,
    // expressed as mean current densities (divide by the cross-section length).
    std::vector<double> col(static_cast<std::size_t>(nx), 0.0), row(static_cast<std::size_t>(ny), 0.0);
    for (int iy = 0; iy < ny; ++iy) {
      double r = 0.0;
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        col[ix] += qxf[i];
        r += qyf[i];
      }
      row[iy] = r;
    }
    for (double& c : col) c /= ny;  // = column total / ly
    for (double& r : row) r /= nx;  // = row total / lx
    const double scale = std::max(std::abs(mqx), std::abs(mqy));
    double dev = 0.0;
    for (double c : col) dev = std::max(dev, std::abs(c - mqx));
    for (double r : row) dev = std::max(dev, std::abs(r - mqy));
    res.conservation_error = scale > 0.0 ? dev / scale : 0.0;
  }
  return results;
}

}  // namespace

FlowResult solve_flow(const Grid& grid, const double* gap, double angle_deg, const FlowOptions& opt) {
  return std::move(solve_flow_impl(grid, gap, {angle_deg}, opt).front());
}

std::vector<FlowResult> solve_flow(const Grid& grid, const double* gap, const std::vector<double>& angles_deg,
                                   const FlowOptions& opt) {
  return solve_flow_impl(grid, gap, angles_deg, opt);
}

bool parse_flow_solver(const std::string& name, FlowSolver& out) {
  if (name == "auto") {
    out = FlowSolver::Auto;
  } else if (name == "amg") {
    out = FlowSolver::Amg;
  } else if (name == "boomeramg") {
    out = FlowSolver::BoomerAMG;
  } else {
    return false;
  }
  return true;
}

std::string flow_solver_name(FlowSolver solver) {
  switch (solver) {
    case FlowSolver::Amg:
      return "amg";
    case FlowSolver::BoomerAMG:
      return "boomeramg";
    case FlowSolver::Auto:
      break;
  }
  return "auto";
}

double bruggeman_2d(const std::vector<double>& k) {
  if (k.empty()) throw InputError("bruggeman_2d", "empty list of conductivities");
  std::size_t zeros = 0;
  double kmin = std::numeric_limits<double>::infinity(), kmax = 0.0;
  for (double v : k) {
    if (!std::isfinite(v) || v < 0.0)
      throw InputError("bruggeman_2d", "conductivities must be finite and >= 0");
    if (v == 0.0) {
      ++zeros;
    } else {
      kmin = std::min(kmin, v);
      kmax = std::max(kmax, v);
    }
  }
  if (2 * zeros >= k.size()) return 0.0;
  if (kmin == kmax && zeros == 0) return kmax;
  // f(K) = sum (K_i - K)/(K_i + K) decreases strictly from n_pos - n_zero > 0 (K -> 0+)
  // to -n (K -> inf); f(kmax) <= 0. Find a lower bracket, then bisect in log K.
  // Written without the cancellation between terms near +1 and -1: a term with K_i > K
  // is 1 - 2K/(K_i + K), one with K_i <= K is -1 + 2K_i/(K_i + K); the +-1 are counted.
  auto f = [&](double K) {
    long count = 0;
    double s = 0.0;
    for (double v : k) {
      if (v > K) {
        ++count;
        s -= 2.0 * K / (v + K);
      } else {
        --count;
        s += 2.0 * v / (v + K);
      }
    }
    return static_cast<double>(count) + s;
  };
  double hi = kmax, lo = kmin;
  while (f(lo) <= 0.0) lo *= 0.5;  // terminates: f(0+) > 0
  if (f(hi) >= 0.0) return hi;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    if (!(mid > lo && mid < hi)) break;
    if (f(mid) > 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  // Final secant step between the brackets for full precision.
  const double flo = f(lo), fhi = f(hi);
  const double K = (flo - fhi) != 0.0 ? lo + (hi - lo) * flo / (flo - fhi) : 0.5 * (lo + hi);
  return std::clamp(K, lo, hi);
}

bool percolates(const Grid& grid, const double* gap, int axis) {
  check_grid(grid, "percolates");
  if (gap == nullptr) throw InputError("percolates", "gap field is null");
  if (axis != 0 && axis != 1) throw InputError("percolates", "axis must be 0 (x) or 1 (y)");
  const auto [wx, wy] = open_windings(grid, gap);
  return axis == 0 ? wx : wy;
}

}  // namespace gfmd
