// Classical (Ruge-Stueben) algebraic multigrid and AMG-preconditioned CG; see
// include/gfmd/amg.hpp.
#include "gfmd/amg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "gfmd/error.hpp"
#include "gfmd/reduce.hpp"

namespace gfmd {

namespace {

// Loops over fewer rows than this run on one thread (a fork/join costs more).
constexpr std::size_t kParallelMin = std::size_t{1} << 13;
// Gauss-Seidel runs in at most kMaxBlocks blocks of at least kBlockRows rows: a function
// of the level size only, so that the results do not depend on the number of threads.
constexpr std::size_t kBlockRows = std::size_t{1} << 13;
constexpr std::size_t kMaxBlocks = 16;
// Coarsest levels up to this size are factorised; larger ones (coarsening stalled) are
// relaxed by kCoarseSweeps symmetric Gauss-Seidel sweeps.
constexpr std::size_t kMaxDense = 1500;
constexpr int kCoarseSweeps = 8;

// Block of row j among nb blocks [n b / nb, n (b + 1) / nb).
inline std::size_t block_of(std::size_t j, std::size_t n, std::size_t nb) { return ((j + 1) * nb - 1) / n; }

enum : std::uint8_t { kUndecided = 0, kCoarse = 1, kFine = 2 };

using Index = std::int32_t;

// An even number of blocks (or one), a function of the level size only.
std::size_t blocks_for(std::size_t n) {
  const std::size_t nb = std::min(n / kBlockRows, kMaxBlocks) & ~std::size_t{1};
  return nb < 2 ? 1 : nb;
}

void check_matrix(const CsrMatrix& a) {
  if (a.n == 0) throw InputError("amg", "empty matrix");
  if (a.n > static_cast<std::size_t>(std::numeric_limits<Index>::max()))
    throw InputError("amg", "matrix too large for 32-bit column indices");
  if (a.ptr.size() != a.n + 1 || a.ptr.front() != 0 || a.ptr.back() != a.col.size() ||
      a.val.size() != a.col.size())
    throw InputError("amg", "inconsistent compressed-row arrays");
  for (std::size_t i = 0; i < a.n; ++i) {
    if (a.ptr[i + 1] <= a.ptr[i] || a.col[a.ptr[i]] != static_cast<Index>(i))
      throw InputError("amg", "row " + std::to_string(i) + " does not start with its diagonal");
    if (!(a.val[a.ptr[i]] > 0.0) || !std::isfinite(a.val[a.ptr[i]]))
      throw SolveError("amg: non-positive or non-finite diagonal in row " + std::to_string(i));
    for (std::size_t k = a.ptr[i]; k < a.ptr[i + 1]; ++k) {
      if (a.col[k] < 0 || static_cast<std::size_t>(a.col[k]) >= a.n)
        throw InputError("amg", "column index out of range in row " + std::to_string(i));
      if (!std::isfinite(a.val[k])) throw SolveError("amg: non-finite entry in row " + std::to_string(i));
    }
  }
}

}  // namespace

void CsrMatrix::multiply(const double* x, double* y) const {
  const auto rows = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < rows; ++i) {
    double s = 0.0;
    for (std::size_t k = ptr[i]; k < ptr[i + 1]; ++k) s += val[k] * x[col[k]];
    y[i] = s;
  }
}

struct AlgebraicMultigrid::Level {
  CsrMatrix a;
  // Interpolation from the next coarser level (rows: this level, columns: coarse) and its
  // transpose, the restriction; empty on the coarsest level.
  std::vector<std::size_t> p_ptr, r_ptr;
  std::vector<Index> p_col, r_col;
  std::vector<double> p_val, r_val;
  std::vector<double> inv_diag;
  std::size_t blocks = 1;  // Gauss-Seidel blocks (even, or 1)
  bool far = false;        // a coupling between two different blocks of the same colour
  mutable std::vector<double> x, b, r, snapshot;  // work arrays

  [[nodiscard]] std::size_t n() const { return a.n; }
  [[nodiscard]] bool parallel() const { return a.n >= kParallelMin; }
};

namespace {

using Level = AlgebraicMultigrid::Level;

// Strong couplings: -a_ij >= theta max_k(-a_ik), off-diagonal and negative.
std::vector<std::uint8_t> strength(const CsrMatrix& a, double theta) {
  std::vector<std::uint8_t> strong(a.nnz(), 0);
  const auto rows = static_cast<std::ptrdiff_t>(a.n);
#pragma omp parallel for schedule(static) if (a.n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < rows; ++i) {
    double m = 0.0;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) m = std::max(m, -a.val[k]);
    if (!(m > 0.0)) continue;
    const double threshold = theta * m;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) strong[k] = -a.val[k] >= threshold ? 1 : 0;
  }
  return strong;
}

// Ruge-Stueben coarse/fine splitting: first pass (greedy maximal set by the number of
// undecided points that depend strongly on a point) and second pass (strongly connected
// fine points share a coarse point). Serial; deterministic.
std::vector<std::uint8_t> split(const CsrMatrix& a, const std::vector<std::uint8_t>& strong) {
  const std::size_t n = a.n;
  // S^T: for each j, the points i that depend strongly on j.
  std::vector<std::size_t> tptr(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k)
      if (strong[k]) ++tptr[static_cast<std::size_t>(a.col[k]) + 1];
  std::partial_sum(tptr.begin(), tptr.end(), tptr.begin());
  std::vector<Index> tidx(tptr[n]);
  {
    std::vector<std::size_t> fill(tptr.begin(), tptr.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k)
        if (strong[k]) tidx[fill[static_cast<std::size_t>(a.col[k])]++] = static_cast<Index>(i);
  }
  std::vector<std::uint8_t> state(n, kUndecided);
  std::vector<Index> lambda(n);
  Index max_lambda = 0;
  for (std::size_t i = 0; i < n; ++i) {
    lambda[i] = static_cast<Index>(tptr[i + 1] - tptr[i]);
    max_lambda = std::max(max_lambda, lambda[i]);
    bool depends = false;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1] && !depends; ++k) depends = strong[k] != 0;
    if (lambda[i] == 0 && !depends) state[i] = kFine;  // no strong coupling at all
  }
  // Buckets by lambda (doubly linked lists); lambda never exceeds twice its start value.
  const std::size_t nbuckets = 2 * static_cast<std::size_t>(max_lambda) + 2;
  std::vector<Index> head(nbuckets, -1), next(n, -1), prev(n, -1);
  auto insert = [&](Index i) {
    const auto b = static_cast<std::size_t>(lambda[i]);
    prev[i] = -1;
    next[i] = head[b];
    if (head[b] >= 0) prev[head[b]] = i;
    head[b] = i;
  };
  auto remove = [&](Index i) {
    const auto b = static_cast<std::size_t>(lambda[i]);
    if (prev[i] >= 0) {
      next[prev[i]] = next[i];
    } else {
      head[b] = next[i];
    }
    if (next[i] >= 0) prev[next[i]] = prev[i];
  };
  // Inserted from the last point to the first: among equals, the lowest index goes first.
  for (std::size_t i = n; i-- > 0;)
    if (state[i] == kUndecided) insert(static_cast<Index>(i));
  std::size_t top = nbuckets - 1;
  for (;;) {
    while (top > 0 && head[top] < 0) --top;
    if (head[top] < 0) break;
    const Index c = head[top];
    remove(c);
    state[c] = kCoarse;
    for (std::size_t t = tptr[c]; t < tptr[c + 1]; ++t) {
      const Index f = tidx[t];
      if (state[f] != kUndecided) continue;
      remove(f);
      state[f] = kFine;
      for (std::size_t k = a.ptr[f] + 1; k < a.ptr[f + 1]; ++k) {
        const Index u = a.col[k];
        if (!strong[k] || state[u] != kUndecided) continue;
        remove(u);
        ++lambda[u];
        insert(u);
        top = std::max(top, static_cast<std::size_t>(lambda[u]));
      }
    }
    for (std::size_t k = a.ptr[c] + 1; k < a.ptr[c + 1]; ++k) {
      const Index u = a.col[k];
      if (!strong[k] || state[u] != kUndecided || lambda[u] == 0) continue;
      remove(u);
      --lambda[u];
      insert(u);
    }
  }
  // Second pass: every strong fine neighbour k of a fine point i must share a coarse
  // point with i; otherwise k becomes coarse.
  std::vector<std::int64_t> stamp(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (state[i] != kFine) continue;
    const auto si = static_cast<std::int64_t>(i);
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k)
      if (strong[k] && state[a.col[k]] == kCoarse) stamp[a.col[k]] = si;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
      const Index f = a.col[k];
      if (!strong[k] || state[f] != kFine) continue;
      bool shared = false;
      for (std::size_t m = a.ptr[f] + 1; m < a.ptr[f + 1] && !shared; ++m)
        shared = strong[m] && stamp[a.col[m]] == si;
      if (!shared) {
        state[f] = kCoarse;
        stamp[f] = si;
      }
    }
  }
  return state;
}

// Classical modified interpolation (see the header), truncated to max_w weights per row.
void build_interpolation(Level& l, const std::vector<std::uint8_t>& strong,
                         const std::vector<std::uint8_t>& state, int max_w, std::size_t& nc) {
  const CsrMatrix& a = l.a;
  const std::size_t n = a.n;
  std::vector<Index> cidx(n, -1);
  nc = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (state[i] == kCoarse) cidx[i] = static_cast<Index>(nc++);
  const auto width = static_cast<std::size_t>(max_w);
  std::vector<Index> wcol(n * width);
  std::vector<double> wval(n * width);
  std::vector<std::uint8_t> count(n, 0);
#pragma omp parallel if (l.parallel())
  {
    std::vector<std::int64_t> stamp(n, -1);
    std::vector<std::size_t> slot(n, 0);
    std::vector<Index> cj;
    std::vector<double> w;
    std::vector<std::size_t> order;
#pragma omp for schedule(static)
    for (std::ptrdiff_t ii = 0; ii < static_cast<std::ptrdiff_t>(n); ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      Index* rc = wcol.data() + i * width;
      double* rv = wval.data() + i * width;
      if (state[i] == kCoarse) {
        rc[0] = cidx[i];
        rv[0] = 1.0;
        count[i] = 1;
        continue;
      }
      const auto si = static_cast<std::int64_t>(i);
      cj.clear();
      w.clear();
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const Index j = a.col[k];
        if (strong[k] && state[j] == kCoarse) {
          stamp[j] = si;
          slot[j] = cj.size();
          cj.push_back(j);
          w.push_back(a.val[k]);
        }
      }
      if (cj.empty()) continue;  // no coarse neighbour: left to the smoother
      double diag = a.val[a.ptr[i]];
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const Index j = a.col[k];
        if (stamp[j] == si) continue;  // a coarse neighbour of the interpolation
        const double aij = a.val[k];
        if (strong[k] && state[j] == kFine) {
          double den = 0.0;
          for (std::size_t m = a.ptr[j] + 1; m < a.ptr[j + 1]; ++m)
            if (stamp[a.col[m]] == si && a.val[m] < 0.0) den += a.val[m];
          if (den < 0.0) {
            for (std::size_t m = a.ptr[j] + 1; m < a.ptr[j + 1]; ++m)
              if (stamp[a.col[m]] == si && a.val[m] < 0.0) w[slot[a.col[m]]] += aij * a.val[m] / den;
            continue;
          }
        }
        diag += aij;  // weak, positive, or a fine neighbour sharing no coarse point
      }
      if (!(diag > 0.0)) continue;
      for (double& v : w) v = -v / diag;
      // Keep the largest weights (ties: lower column), rescaled to the same sum.
      order.resize(w.size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      if (w.size() > width) {
        std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(width), order.end(),
                          [&](std::size_t p, std::size_t q) {
                            const double ap = std::abs(w[p]), aq = std::abs(w[q]);
                            return ap != aq ? ap > aq : cj[p] < cj[q];
                          });
        double total = 0.0, kept = 0.0;
        for (double v : w) total += v;
        for (std::size_t t = 0; t < width; ++t) kept += w[order[t]];
        const double scale = kept != 0.0 ? total / kept : 1.0;
        order.resize(width);
        std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return cj[p] < cj[q]; });
        for (std::size_t& t : order) w[t] *= scale;
      }
      std::size_t c = 0;
      for (std::size_t t : order) {
        rc[c] = cidx[cj[t]];
        rv[c] = w[t];
        ++c;
      }
      count[i] = static_cast<std::uint8_t>(c);
    }
  }
  l.p_ptr.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) l.p_ptr[i + 1] = l.p_ptr[i] + count[i];
  l.p_col.resize(l.p_ptr[n]);
  l.p_val.resize(l.p_ptr[n]);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < count[i]; ++c) {
      l.p_col[l.p_ptr[i] + c] = wcol[i * width + c];
      l.p_val[l.p_ptr[i] + c] = wval[i * width + c];
    }
  // Restriction R = P^T (rows in increasing fine index).
  l.r_ptr.assign(nc + 1, 0);
  for (Index c : l.p_col) ++l.r_ptr[static_cast<std::size_t>(c) + 1];
  std::partial_sum(l.r_ptr.begin(), l.r_ptr.end(), l.r_ptr.begin());
  l.r_col.resize(l.p_col.size());
  l.r_val.resize(l.p_col.size());
  std::vector<std::size_t> fill(l.r_ptr.begin(), l.r_ptr.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = l.p_ptr[i]; k < l.p_ptr[i + 1]; ++k) {
      const std::size_t pos = fill[static_cast<std::size_t>(l.p_col[k])]++;
      l.r_col[pos] = static_cast<Index>(i);
      l.r_val[pos] = l.p_val[k];
    }
}

// Galerkin product R A P of level f (rows in order; the diagonal first in each row). Rows
// are computed in fixed chunks (a function of the size only), shared among the threads.
CsrMatrix galerkin(const Level& f, std::size_t nc) {
  const CsrMatrix& a = f.a;
  CsrMatrix c;
  c.n = nc;
  std::vector<std::size_t> len(nc, 0);
  const std::size_t nchunks = std::clamp<std::size_t>(nc / 4096, 1, 256);
  std::vector<std::vector<Index>> bcol(nchunks);
  std::vector<std::vector<double>> bval(nchunks);
  const auto chunks = static_cast<std::ptrdiff_t>(nchunks);
#pragma omp parallel if (nchunks > 1)
  {
    std::vector<std::int64_t> marker(nc, -1);
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t ch = 0; ch < chunks; ++ch) {
      const auto t = static_cast<std::size_t>(ch);
      std::vector<Index>& cols = bcol[t];
      std::vector<double>& vals = bval[t];
      const std::size_t lo = nc * t / nchunks, hi = nc * (t + 1) / nchunks;
      for (std::size_t I = lo; I < hi; ++I) {
        const auto start = static_cast<std::int64_t>(cols.size());
        for (std::size_t q = f.r_ptr[I]; q < f.r_ptr[I + 1]; ++q) {
          const auto i = static_cast<std::size_t>(f.r_col[q]);
          const double ri = f.r_val[q];
          for (std::size_t k = a.ptr[i]; k < a.ptr[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(a.col[k]);
            const double ra = ri * a.val[k];
            for (std::size_t m = f.p_ptr[j]; m < f.p_ptr[j + 1]; ++m) {
              const auto J = static_cast<std::size_t>(f.p_col[m]);
              if (marker[J] < start) {
                marker[J] = static_cast<std::int64_t>(cols.size());
                cols.push_back(static_cast<Index>(J));
                vals.push_back(ra * f.p_val[m]);
              } else {
                vals[static_cast<std::size_t>(marker[J])] += ra * f.p_val[m];
              }
            }
          }
        }
        // Diagonal first.
        const auto s = static_cast<std::size_t>(start);
        for (std::size_t k = s; k < cols.size(); ++k)
          if (cols[k] == static_cast<Index>(I)) {
            std::swap(cols[k], cols[s]);
            std::swap(vals[k], vals[s]);
            break;
          }
        len[I] = cols.size() - s;
      }
      // Markers of this chunk point into its own buffer: invalidate them for the next one.
      for (Index J : cols) marker[static_cast<std::size_t>(J)] = -1;
    }
  }
  c.ptr.assign(nc + 1, 0);
  for (std::size_t I = 0; I < nc; ++I) c.ptr[I + 1] = c.ptr[I] + len[I];
  c.col.resize(c.ptr[nc]);
  c.val.resize(c.ptr[nc]);
#pragma omp parallel for schedule(static) if (nchunks > 1)
  for (std::ptrdiff_t ch = 0; ch < chunks; ++ch) {
    const auto t = static_cast<std::size_t>(ch);
    const std::size_t lo = nc * t / nchunks;
    std::copy(bcol[t].begin(), bcol[t].end(), c.col.begin() + static_cast<std::ptrdiff_t>(c.ptr[lo]));
    std::copy(bval[t].begin(), bval[t].end(), c.val.begin() + static_cast<std::ptrdiff_t>(c.ptr[lo]));
  }
  return c;
}

void finish_level(Level& l) {
  const std::size_t n = l.n();
  l.inv_diag.resize(n);
  for (std::size_t i = 0; i < n; ++i) l.inv_diag[i] = 1.0 / l.a.val[l.a.ptr[i]];
  l.blocks = blocks_for(n);
  l.far = false;
  if (l.blocks > 1) {
    const std::size_t nb = l.blocks;
    for (std::size_t blk = 0; blk < nb && !l.far; ++blk) {
      const std::size_t lo = n * blk / nb, hi = n * (blk + 1) / nb;
      for (std::size_t k = l.a.ptr[lo]; k < l.a.ptr[hi] && !l.far; ++k) {
        const std::size_t cb = block_of(static_cast<std::size_t>(l.a.col[k]), n, nb);
        l.far = cb != blk && ((cb ^ blk) & 1) == 0;
      }
    }
  }
  l.r.assign(n, 0.0);
  if (l.far) l.snapshot.assign(n, 0.0);
}

// One Gauss-Seidel sweep, forward or backward. With several blocks of rows (an even number)
// the even blocks are relaxed first, side by side, then the odd ones (backward: odd first):
// Gauss-Seidel in that order of the rows, whatever the number of threads. A coupling to
// another block of the same colour (rare: rows couple to nearby rows) reads the value from
// before the sweep, since that block is being relaxed at the same time. zero_guess: x is
// overwritten (taken as 0 before the sweep).
void relax(const Level& l, const double* b, double* x, bool forward, bool zero_guess) {
  const CsrMatrix& a = l.a;
  const std::size_t n = a.n, nb = l.blocks;
  if (zero_guess) {
    std::fill(x, x + n, 0.0);
  } else if (l.far) {
    std::copy(x, x + n, l.snapshot.begin());
  }
  auto sweep_block = [&](std::size_t blk) {
    const std::size_t lo = n * blk / nb, hi = n * (blk + 1) / nb;
    // Rows of the neighbouring blocks (the other colour): [near_lo, near_hi).
    const std::size_t near_lo = blk == 0 ? 0 : n * (blk - 1) / nb;
    const std::size_t near_hi = blk + 1 == nb ? n : n * (blk + 2) / nb;
    for (std::size_t t = lo; t < hi; ++t) {
      const std::size_t i = forward ? t : hi - 1 - (t - lo);
      double s = b[i];
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const auto j = static_cast<std::size_t>(a.col[k]);
        if ((j >= near_lo && j < near_hi) || ((block_of(j, n, nb) ^ blk) & 1) != 0) {
          s -= a.val[k] * x[j];  // this block (current values) or the other colour (fixed now)
        } else if (!zero_guess) {
          s -= a.val[k] * l.snapshot[j];  // another block of this colour
        }
      }
      x[i] = s * l.inv_diag[i];
    }
  };
  if (nb == 1) {
    sweep_block(0);
    return;
  }
  const auto half = static_cast<std::ptrdiff_t>(nb / 2);
  for (int phase = 0; phase < 2; ++phase) {
    const std::size_t colour =
        forward ? static_cast<std::size_t>(phase) : static_cast<std::size_t>(1 - phase);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t q = 0; q < half; ++q) sweep_block(2 * static_cast<std::size_t>(q) + colour);
  }
}

}  // namespace

AlgebraicMultigrid::AlgebraicMultigrid(CsrMatrix a, const AmgOptions& opt) {
  check_matrix(a);
  if (!(opt.strength > 0.0 && opt.strength < 1.0))
    throw InputError("amg", "strength threshold must be in (0, 1)");
  if (opt.max_interpolation < 1 || opt.max_interpolation > 64)
    throw InputError("amg", "max_interpolation must be in [1, 64]");
  auto fine = std::make_unique<Level>();
  fine->a = std::move(a);
  finish_level(*fine);
  levels_.push_back(std::move(fine));
  while (levels_.size() < static_cast<std::size_t>(std::max(opt.max_levels, 1))) {
    Level& f = *levels_.back();
    if (f.n() <= opt.max_coarsest) break;
    const std::vector<std::uint8_t> strong = strength(f.a, opt.strength);
    const std::vector<std::uint8_t> state = split(f.a, strong);
    std::size_t nc = 0;
    for (std::uint8_t s : state) nc += s == kCoarse ? 1 : 0;
    if (nc == 0 || nc * 10 > f.n() * 9) break;  // nothing to coarsen, or coarsening stalled
    build_interpolation(f, strong, state, opt.max_interpolation, nc);
    auto c = std::make_unique<Level>();
    c->a = galerkin(f, nc);
    finish_level(*c);
    c->x.assign(nc, 0.0);
    c->b.assign(nc, 0.0);
    levels_.push_back(std::move(c));
  }
  // The coarsest level loses its (unused) interpolation arrays.
  Level& cl = *levels_.back();
  cl.p_ptr.clear();
  cl.p_col.clear();
  cl.p_val.clear();
  cl.r_ptr.clear();
  cl.r_col.clear();
  cl.r_val.clear();
  const std::size_t m = cl.n();
  if (m <= kMaxDense) {
    // Dense Cholesky; a pivot that rounding made tiny or negative is replaced by a small
    // multiple of the diagonal (the factor stays that of a positive definite matrix).
    chol_.assign(m * m, 0.0);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = cl.a.ptr[i]; k < cl.a.ptr[i + 1]; ++k)
        chol_[i * m + static_cast<std::size_t>(cl.a.col[k])] += cl.a.val[k];
    for (std::size_t k = 0; k < m; ++k) {
      const double orig = chol_[k * m + k];
      double d = orig;
      for (std::size_t j = 0; j < k; ++j) d -= chol_[k * m + j] * chol_[k * m + j];
      if (!(d > 1e-14 * orig)) d = 1e-14 * orig;
      const double lkk = std::sqrt(d);
      chol_[k * m + k] = lkk;
      for (std::size_t i = k + 1; i < m; ++i) {
        double v = chol_[i * m + k];
        for (std::size_t j = 0; j < k; ++j) v -= chol_[i * m + j] * chol_[k * m + j];
        chol_[i * m + k] = v / lkk;
      }
    }
  }
}

AlgebraicMultigrid::~AlgebraicMultigrid() = default;

std::size_t AlgebraicMultigrid::size() const { return levels_.front()->n(); }
int AlgebraicMultigrid::levels() const { return static_cast<int>(levels_.size()); }
std::size_t AlgebraicMultigrid::level_size(int level) const {
  return levels_.at(static_cast<std::size_t>(level))->n();
}
std::size_t AlgebraicMultigrid::level_nnz(int level) const {
  return levels_.at(static_cast<std::size_t>(level))->a.nnz();
}
double AlgebraicMultigrid::operator_complexity() const {
  double total = 0.0;
  for (const auto& l : levels_) total += static_cast<double>(l->a.nnz());
  return total / static_cast<double>(levels_.front()->a.nnz());
}
const CsrMatrix& AlgebraicMultigrid::matrix() const { return levels_.front()->a; }
const CsrMatrix& AlgebraicMultigrid::level_matrix(int level) const {
  return levels_.at(static_cast<std::size_t>(level))->a;
}

void AlgebraicMultigrid::interpolate(int level, const double* coarse, double* fine) const {
  if (level < 0 || level + 1 >= levels())
    throw InputError("amg", "no coarser level below " + std::to_string(level));
  const Level& f = *levels_[static_cast<std::size_t>(level)];
  for (std::size_t i = 0; i < f.n(); ++i) {
    double s = 0.0;
    for (std::size_t k = f.p_ptr[i]; k < f.p_ptr[i + 1]; ++k) s += f.p_val[k] * coarse[f.p_col[k]];
    fine[i] = s;
  }
}

void AlgebraicMultigrid::coarse_solve(const double* b, double* x) const {
  const Level& cl = *levels_.back();
  const std::size_t m = cl.n();
  if (chol_.empty()) {
    relax(cl, b, x, true, true);
    for (int s = 0; s < kCoarseSweeps; ++s) {
      if (s > 0) relax(cl, b, x, true, false);
      relax(cl, b, x, false, false);
    }
    return;
  }
  for (std::size_t i = 0; i < m; ++i) {
    double v = b[i];
    for (std::size_t j = 0; j < i; ++j) v -= chol_[i * m + j] * x[j];
    x[i] = v / chol_[i * m + i];
  }
  for (std::size_t i = m; i-- > 0;) {
    double v = x[i];
    for (std::size_t j = i + 1; j < m; ++j) v -= chol_[j * m + i] * x[j];
    x[i] = v / chol_[i * m + i];
  }
}

void AlgebraicMultigrid::cycle(std::size_t l, const double* b, double* x) const {
  if (l + 1 == levels_.size()) {
    coarse_solve(b, x);
    return;
  }
  const Level& f = *levels_[l];
  const Level& c = *levels_[l + 1];
  relax(f, b, x, true, true);
  f.a.multiply(x, f.r.data());
  const std::size_t n = f.n(), nc = c.n();
  const auto rows = static_cast<std::ptrdiff_t>(n), crows = static_cast<std::ptrdiff_t>(nc);
  double* r = f.r.data();
#pragma omp parallel for schedule(static) if (f.parallel())
  for (std::ptrdiff_t i = 0; i < rows; ++i) r[i] = b[i] - r[i];
  double* bc = c.b.data();
#pragma omp parallel for schedule(static) if (c.parallel())
  for (std::ptrdiff_t I = 0; I < crows; ++I) {
    double s = 0.0;
    for (std::size_t k = f.r_ptr[I]; k < f.r_ptr[I + 1]; ++k) s += f.r_val[k] * r[f.r_col[k]];
    bc[I] = s;
  }
  cycle(l + 1, bc, c.x.data());
  const double* xc = c.x.data();
#pragma omp parallel for schedule(static) if (f.parallel())
  for (std::ptrdiff_t i = 0; i < rows; ++i) {
    double s = 0.0;
    for (std::size_t k = f.p_ptr[i]; k < f.p_ptr[i + 1]; ++k) s += f.p_val[k] * xc[f.p_col[k]];
    x[i] += s;
  }
  relax(f, b, x, false, false);
}

void AlgebraicMultigrid::precondition(const double* r, double* z) const { cycle(0, r, z); }

CgOutcome amg_pcg(const AlgebraicMultigrid& mg, const double* b, double* x, double tolerance,
                  int max_iterations, double reference_norm) {
  const std::size_t n = mg.size();
  const CsrMatrix& a = mg.matrix();
  auto dot = [n](auto&& f) { return range_sums(n, 1, [&](std::size_t i, double* s) { s[0] += f(i); })[0]; };
  CgOutcome out;
  std::fill(x, x + n, 0.0);
  const double bnorm = std::sqrt(dot([&](std::size_t i) { return b[i] * b[i]; }));
  const double ref = reference_norm > 0.0 ? reference_norm : bnorm;
  if (!std::isfinite(bnorm)) return out;
  if (bnorm == 0.0) {
    out.converged = true;
    return out;
  }
  std::vector<double> r(b, b + n), z(n), p(n), q(n);
  mg.precondition(r.data(), z.data());
  p = z;
  double rz = dot([&](std::size_t i) { return r[i] * z[i]; });
  const auto rows = static_cast<std::ptrdiff_t>(n);
  for (int it = 1; it <= max_iterations; ++it) {
    a.multiply(p.data(), q.data());
    const double pq = dot([&](std::size_t i) { return p[i] * q[i]; });
    if (!(pq > 0.0) || !std::isfinite(pq) || !(rz > 0.0)) break;  // breakdown
    const double alpha = rz / pq;
    const double rr = dot([&](std::size_t i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
      return r[i] * r[i];
    });
    out.iterations = it;
    if (!std::isfinite(rr)) break;
    if (std::sqrt(rr) <= tolerance * ref) {
      out.converged = true;
      break;
    }
    mg.precondition(r.data(), z.data());
    const double rz_new = dot([&](std::size_t i) { return r[i] * z[i]; });
    const double beta = rz_new / rz;
    rz = rz_new;
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
    for (std::ptrdiff_t i = 0; i < rows; ++i) p[i] = z[i] + beta * p[i];
  }
  // The residual of the returned x, recomputed (the recursive one drifts by rounding).
  a.multiply(x, q.data());
  const double res = std::sqrt(dot([&](std::size_t i) { return (b[i] - q[i]) * (b[i] - q[i]); }));
  out.residual = res / ref;
  if (!std::isfinite(out.residual)) out.converged = false;
  return out;
}

}  // namespace gfmd
