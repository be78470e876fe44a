// Classical (Ruge-Stueben) algebraic multigrid and AMG-preconditioned CG; see
// include/gfmd/flow/amg.hpp.
#include "gfmd/flow/amg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/reduce.hpp"

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
  // The first bad row (rows checked side by side), then what is wrong with it.
  auto bad = [&](std::size_t i) {
    if (a.ptr[i + 1] <= a.ptr[i] || a.col[a.ptr[i]] != static_cast<Index>(i)) return 1;
    if (!(a.val[a.ptr[i]] > 0.0) || !std::isfinite(a.val[a.ptr[i]])) return 2;
    for (std::size_t k = a.ptr[i]; k < a.ptr[i + 1]; ++k) {
      if (a.col[k] < 0 || static_cast<std::size_t>(a.col[k]) >= a.n) return 3;
      if (!std::isfinite(a.val[k])) return 4;
    }
    return 0;
  };
  std::size_t first = a.n;
#pragma omp parallel for schedule(static) reduction(min : first) if (a.n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(a.n); ++i)
    if (bad(static_cast<std::size_t>(i)) != 0) first = std::min(first, static_cast<std::size_t>(i));
  if (first == a.n) return;
  const std::string row = std::to_string(first);
  switch (bad(first)) {
    case 1:
      throw InputError("amg", "row " + row + " does not start with its diagonal");
    case 2:
      throw SolveError("amg: non-positive or non-finite diagonal in row " + row);
    case 3:
      throw InputError("amg", "column index out of range in row " + row);
    default:
      throw SolveError("amg: non-finite entry in row " + row);
  }
}

}  // namespace

void CsrMatrix::multiply(const double* x, double* y) const {
  const auto rows = static_cast<std::ptrdiff_t>(n);
  const std::size_t* const p = ptr.data();
  const std::int32_t* const c = col.data();
  const double* const v = val.data();
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < rows; ++i) {
    double s = 0.0;
    for (std::size_t k = p[i]; k < p[i + 1]; ++k) s += v[k] * x[c[k]];
    y[i] = s;
  }
}

struct AlgebraicMultigrid::Level {
  CsrMatrix a;
  // Interpolation from the next coarser level (rows: this level, columns: coarse) and its
  // transpose, the restriction; empty on the coarsest level.
  Buffer<std::size_t> p_ptr, r_ptr;
  Buffer<Index> p_col, r_col;
  Buffer<double> p_val, r_val;
  Buffer<double> inv_diag;
  std::size_t blocks = 1;  // Gauss-Seidel blocks (even, or 1)
  // Per row: the couplings with a lower column come first (rows are sorted by column
  // after the diagonal), `lower` of them; `interior` if every coupling stays in the
  // row's Gauss-Seidel block.
  Buffer<std::uint32_t> lower;
  Buffer<std::uint8_t> interior;
  mutable Buffer<double> x, b, r;  // work arrays

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

// Blocks of rows of the coarse/fine splitting (a function of the size only).
std::size_t split_blocks(std::size_t n) { return std::clamp<std::size_t>((n + 32767) / 65536, 1, 16); }

// Ruge-Stueben first pass on the rows [lo, hi), with the strong couplings inside the
// block: repeatedly the undecided point on which most undecided points depend strongly
// becomes coarse and those points fine. A point whose strong couplings all leave the
// block becomes coarse; one without any strong coupling fine.
void first_pass(const CsrMatrix& a, const std::vector<std::uint8_t>& strong, std::size_t lo, std::size_t hi,
                std::vector<std::uint8_t>& state) {
  const std::size_t m = hi - lo;
  const auto ilo = static_cast<Index>(lo), ihi = static_cast<Index>(hi);
  // The strong couplings inside the block in local numbering: S (the points each point
  // depends on strongly) and S^T (the points that depend strongly on it).
  std::vector<Index> sptr(m + 1, 0), tptr(m + 1, 0);
  for (std::size_t i = lo; i < hi; ++i) {
    bool any = false;
    Index in = 0;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
      if (!strong[k]) continue;
      any = true;
      const Index j = a.col[k];
      if (j >= ilo && j < ihi) {
        ++in;
        ++tptr[static_cast<std::size_t>(j - ilo) + 1];
      }
    }
    sptr[i - lo + 1] = in;
    state[i] = !any ? kFine : (in > 0 ? kUndecided : kCoarse);
  }
  std::partial_sum(sptr.begin(), sptr.end(), sptr.begin());
  std::partial_sum(tptr.begin(), tptr.end(), tptr.begin());
  std::vector<Index> sidx(static_cast<std::size_t>(sptr[m])), tidx(static_cast<std::size_t>(tptr[m]));
  {
    std::vector<Index> fill(tptr.begin(), tptr.end() - 1);
    for (std::size_t i = lo; i < hi; ++i) {
      Index q = sptr[i - lo];
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const Index j = a.col[k];
        if (!strong[k] || j < ilo || j >= ihi) continue;
        sidx[static_cast<std::size_t>(q++)] = j - ilo;
        tidx[static_cast<std::size_t>(fill[static_cast<std::size_t>(j - ilo)]++)] =
            static_cast<Index>(i - lo);
      }
    }
  }
  std::uint8_t* const st = state.data() + lo;  // local view
  std::vector<Index> lambda(m);
  Index max_lambda = 0;
  for (std::size_t u = 0; u < m; ++u) {
    lambda[u] = tptr[u + 1] - tptr[u];
    max_lambda = std::max(max_lambda, lambda[u]);
  }
  // Buckets by lambda (doubly linked lists); lambda never exceeds twice its start value.
  const std::size_t nbuckets = 2 * static_cast<std::size_t>(max_lambda) + 2;
  std::vector<Index> head(nbuckets, -1), next(m, -1), prev(m, -1);
  auto insert = [&](Index u) {
    const auto b = static_cast<std::size_t>(lambda[u]);
    prev[u] = -1;
    next[u] = head[b];
    if (head[b] >= 0) prev[head[b]] = u;
    head[b] = u;
  };
  auto remove = [&](Index u) {
    const auto b = static_cast<std::size_t>(lambda[u]);
    if (prev[u] >= 0) {
      next[prev[u]] = next[u];
    } else {
      head[b] = next[u];
    }
    if (next[u] >= 0) prev[next[u]] = prev[u];
  };
  // Inserted from the last point to the first: among equals, the lowest index goes first.
  for (std::size_t u = m; u-- > 0;)
    if (st[u] == kUndecided) insert(static_cast<Index>(u));
  std::size_t top = nbuckets - 1;
  for (;;) {
    while (top > 0 && head[top] < 0) --top;
    if (head[top] < 0) break;
    const Index c = head[top];
    remove(c);
    st[c] = kCoarse;
    for (Index t = tptr[c]; t < tptr[c + 1]; ++t) {
      const Index f = tidx[static_cast<std::size_t>(t)];
      if (st[f] != kUndecided) continue;
      remove(f);
      st[f] = kFine;
      for (Index q = sptr[f]; q < sptr[f + 1]; ++q) {
        const Index u = sidx[static_cast<std::size_t>(q)];
        if (st[u] != kUndecided) continue;
        remove(u);
        ++lambda[u];
        insert(u);
        top = std::max(top, static_cast<std::size_t>(lambda[u]));
      }
    }
    for (Index q = sptr[c]; q < sptr[c + 1]; ++q) {
      const Index u = sidx[static_cast<std::size_t>(q)];
      if (st[u] != kUndecided || lambda[u] == 0) continue;
      remove(u);
      --lambda[u];
      insert(u);
    }
  }
}

// Second pass for the fine point i: every strong fine neighbour k must share a strong
// coarse neighbour with i; otherwise k becomes coarse. stamp[j] == i marks the strong
// coarse neighbours j of i (a scratch array of n entries, initially all -1).
inline void second_pass_row(const CsrMatrix& a, const std::vector<std::uint8_t>& strong, std::size_t i,
                            std::vector<std::uint8_t>& state, Index* stamp) {
  const auto si = static_cast<Index>(i);
  for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k)
    if (strong[k] && state[static_cast<std::size_t>(a.col[k])] == kCoarse) stamp[a.col[k]] = si;
  for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
    const Index f = a.col[k];
    if (!strong[k] || state[static_cast<std::size_t>(f)] != kFine) continue;
    bool shared = false;
    for (std::size_t m = a.ptr[f] + 1; m < a.ptr[f + 1] && !shared; ++m)
      shared = strong[m] && stamp[a.col[m]] == si;
    if (!shared) {
      state[static_cast<std::size_t>(f)] = kCoarse;
      stamp[f] = si;
    }
  }
}

// Ruge-Stueben coarse/fine splitting: the first pass in blocks of rows side by side, then
// the second pass, first on the rows whose strong couplings stay inside their block (block
// by block, side by side), then on the others in order. Deterministic for any number of
// threads.
std::vector<std::uint8_t> split(const CsrMatrix& a, const std::vector<std::uint8_t>& strong) {
  const std::size_t n = a.n, nblk = split_blocks(n);
  std::vector<std::uint8_t> state(n, kUndecided);
  std::vector<std::uint8_t> boundary(n, 0);
  const auto nb = static_cast<std::ptrdiff_t>(nblk);
#pragma omp parallel for schedule(dynamic, 1) if (nblk > 1)
  for (std::ptrdiff_t blk = 0; blk < nb; ++blk) {
    const std::size_t lo = n * static_cast<std::size_t>(blk) / nblk,
                      hi = n * static_cast<std::size_t>(blk + 1) / nblk;
    first_pass(a, strong, lo, hi, state);
    for (std::size_t i = lo; i < hi; ++i)
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1] && !boundary[i]; ++k)
        boundary[i] = strong[k] && (a.col[k] < static_cast<Index>(lo) || a.col[k] >= static_cast<Index>(hi));
  }
  // A fine point with a strong neighbour in another block is left to the serial part; so is
  // one with a strong neighbour that has one (its neighbours' rows are read).
  std::vector<std::uint8_t> serial(n, 0);
#pragma omp parallel for schedule(static) if (nblk > 1)
  for (std::ptrdiff_t ii = 0; ii < static_cast<std::ptrdiff_t>(n); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    bool s = boundary[i] != 0;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1] && !s; ++k) s = strong[k] && boundary[a.col[k]];
    serial[i] = s ? 1 : 0;
  }
#pragma omp parallel if (nblk > 1)
  {
    Buffer<Index> stamp(n);
    std::fill(stamp.begin(), stamp.end(), Index{-1});
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t blk = 0; blk < nb; ++blk) {
      const std::size_t lo = n * static_cast<std::size_t>(blk) / nblk,
                        hi = n * static_cast<std::size_t>(blk + 1) / nblk;
      for (std::size_t i = lo; i < hi; ++i)
        if (state[i] == kFine && !serial[i]) second_pass_row(a, strong, i, state, stamp.data());
    }
#pragma omp single
    for (std::size_t i = 0; i < n; ++i)
      if (state[i] == kFine && serial[i]) second_pass_row(a, strong, i, state, stamp.data());
  }
  return state;
}

// Classical modified interpolation (see the header), truncated to max_w weights per row,
// onto the nc coarse points of state. Rows are counted first (a coarse point: 1; a fine
// point: its strong coarse neighbours, at most max_w), then computed straight into place.
void build_interpolation(Level& l, const std::vector<std::uint8_t>& strong,
                         const std::vector<std::uint8_t>& state, int max_w, std::size_t nc) {
  const CsrMatrix& a = l.a;
  const std::size_t n = a.n;
  const auto rows = static_cast<std::ptrdiff_t>(n);
  std::vector<Index> cidx(n, -1);
  for (std::size_t i = 0, next = 0; i < n; ++i)
    if (state[i] == kCoarse) cidx[i] = static_cast<Index>(next++);
  const auto width = static_cast<std::size_t>(max_w);
  l.p_ptr.assign(n + 1, 0);
#pragma omp parallel for schedule(static) if (l.parallel())
  for (std::ptrdiff_t ii = 0; ii < rows; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    std::size_t c = 0;
    if (state[i] == kCoarse) {
      c = 1;
    } else {
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k)
        c += strong[k] && state[static_cast<std::size_t>(a.col[k])] == kCoarse ? 1 : 0;
      c = std::min(c, width);
    }
    l.p_ptr[i + 1] = c;
  }
  for (std::size_t i = 0; i < n; ++i) l.p_ptr[i + 1] += l.p_ptr[i];
  l.p_col.resize(l.p_ptr[n]);
  l.p_val.resize(l.p_ptr[n]);
#pragma omp parallel if (l.parallel())
  {
    // stamp[j] == i marks the strong coarse neighbours j of row i, slot[j] their place.
    std::vector<Index> stamp(n, -1);
    std::vector<Index> slot(n, 0);
    std::vector<Index> cj;
    std::vector<double> w;
    std::vector<std::size_t> order;
#pragma omp for schedule(static)
    for (std::ptrdiff_t ii = 0; ii < rows; ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      Index* rc = l.p_col.data() + l.p_ptr[i];
      double* rv = l.p_val.data() + l.p_ptr[i];
      if (state[i] == kCoarse) {
        rc[0] = cidx[i];
        rv[0] = 1.0;
        continue;
      }
      if (l.p_ptr[i + 1] == l.p_ptr[i]) continue;  // no coarse neighbour: left to the smoother
      const auto si = static_cast<Index>(i);
      cj.clear();
      w.clear();
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const Index j = a.col[k];
        if (strong[k] && state[static_cast<std::size_t>(j)] == kCoarse) {
          stamp[static_cast<std::size_t>(j)] = si;
          slot[static_cast<std::size_t>(j)] = static_cast<Index>(cj.size());
          cj.push_back(j);
          w.push_back(a.val[k]);
        }
      }
      double diag = a.val[a.ptr[i]];
      for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1]; ++k) {
        const auto j = static_cast<std::size_t>(a.col[k]);
        if (stamp[j] == si) continue;  // a coarse neighbour of the interpolation
        const double aij = a.val[k];
        if (strong[k] && state[j] == kFine) {
          double den = 0.0;
          for (std::size_t m = a.ptr[j] + 1; m < a.ptr[j + 1]; ++m)
            if (stamp[static_cast<std::size_t>(a.col[m])] == si && a.val[m] < 0.0) den += a.val[m];
          if (den < 0.0) {
            for (std::size_t m = a.ptr[j] + 1; m < a.ptr[j + 1]; ++m)
              if (stamp[static_cast<std::size_t>(a.col[m])] == si && a.val[m] < 0.0)
                w[slot[static_cast<std::size_t>(a.col[m])]] += aij * a.val[m] / den;
            continue;
          }
        }
        diag += aij;  // weak, positive, or a fine neighbour sharing no coarse point
      }
      const std::size_t count = l.p_ptr[i + 1] - l.p_ptr[i];
      if (!(diag > 0.0)) {  // cannot happen for an M-matrix; no interpolation then
        for (std::size_t t = 0; t < count; ++t) {
          rc[t] = cidx[static_cast<std::size_t>(cj[t])];
          rv[t] = 0.0;
        }
        continue;
      }
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
      for (std::size_t t = 0; t < count; ++t) {
        rc[t] = cidx[static_cast<std::size_t>(cj[order[t]])];
        rv[t] = w[order[t]];
      }
    }
  }
  // Restriction R = P^T (each row in increasing fine index): the fine rows in a fixed
  // number of chunks count their entries per coarse column, then each chunk writes its
  // entries after those of the chunks before it.
  const std::size_t nchunks = std::clamp<std::size_t>(n / 8192, 1, 8);
  std::vector<Buffer<Index>> count(nchunks);
  l.r_ptr.assign(nc + 1, 0);
  const auto chunks = static_cast<std::ptrdiff_t>(nchunks);
#pragma omp parallel for schedule(static) if (nchunks > 1)
  for (std::ptrdiff_t t = 0; t < chunks; ++t) {
    const auto ut = static_cast<std::size_t>(t);
    Buffer<Index>& c = count[ut];
    c.assign(nc, 0);
    for (std::size_t k = l.p_ptr[n * ut / nchunks]; k < l.p_ptr[n * (ut + 1) / nchunks]; ++k)
      ++c[static_cast<std::size_t>(l.p_col[k])];
  }
  for (std::size_t J = 0; J < nc; ++J) {
    std::size_t total = 0;
    for (std::size_t t = 0; t < nchunks; ++t) total += static_cast<std::size_t>(count[t][J]);
    l.r_ptr[J + 1] = l.r_ptr[J] + total;
  }
  l.r_col.resize(l.p_col.size());
  l.r_val.resize(l.p_col.size());
#pragma omp parallel for schedule(static) if (nchunks > 1)
  for (std::ptrdiff_t t = 0; t < chunks; ++t) {
    const auto ut = static_cast<std::size_t>(t);
    // Where this chunk's entries of each column start.
    Buffer<std::size_t> fill(nc);
    for (std::size_t J = 0; J < nc; ++J) {
      std::size_t pos = l.r_ptr[J];
      for (std::size_t q = 0; q < ut; ++q) pos += static_cast<std::size_t>(count[q][J]);
      fill[J] = pos;
    }
    for (std::size_t i = n * ut / nchunks; i < n * (ut + 1) / nchunks; ++i)
      for (std::size_t k = l.p_ptr[i]; k < l.p_ptr[i + 1]; ++k) {
        const std::size_t pos = fill[static_cast<std::size_t>(l.p_col[k])]++;
        l.r_col[pos] = static_cast<Index>(i);
        l.r_val[pos] = l.p_val[k];
      }
  }
}

// Galerkin product R A P of level f (rows in order; the diagonal first in each row). Rows
// are computed in fixed chunks (a function of the size only), shared among the threads,
// each with a dense accumulator over the coarse columns.
CsrMatrix galerkin(const Level& f, std::size_t nc) {
  const CsrMatrix& a = f.a;
  CsrMatrix c;
  c.n = nc;
  Buffer<std::size_t> len(nc);
  const std::size_t nchunks = std::clamp<std::size_t>(nc / 4096, 1, 256);
  std::vector<std::vector<Index>> bcol(nchunks);
  std::vector<std::vector<double>> bval(nchunks);
  const auto chunks = static_cast<std::ptrdiff_t>(nchunks);
#pragma omp parallel if (nchunks > 1)
  {
    std::vector<Index> marker(nc, -1);
    std::vector<double> acc(nc, 0.0);
    std::vector<Index> touched;
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t ch = 0; ch < chunks; ++ch) {
      const auto t = static_cast<std::size_t>(ch);
      std::vector<Index>& cols = bcol[t];
      std::vector<double>& vals = bval[t];
      const std::size_t lo = nc * t / nchunks, hi = nc * (t + 1) / nchunks;
      cols.reserve((hi - lo) * 12);
      vals.reserve((hi - lo) * 12);
      const std::size_t* const rp = f.r_ptr.data();
      const Index* const rc = f.r_col.data();
      const double* const rv = f.r_val.data();
      const std::size_t* const ap = a.ptr.data();
      const Index* const ac = a.col.data();
      const double* const av = a.val.data();
      const std::size_t* const pp = f.p_ptr.data();
      const Index* const pc = f.p_col.data();
      const double* const pv = f.p_val.data();
      Index* const mk = marker.data();
      double* const ac_sum = acc.data();
      for (std::size_t I = lo; I < hi; ++I) {
        const auto row = static_cast<Index>(I);
        touched.clear();
        mk[I] = row;  // the diagonal first
        touched.push_back(row);
        ac_sum[I] = 0.0;
        for (std::size_t q = rp[I]; q < rp[I + 1]; ++q) {
          const auto i = static_cast<std::size_t>(rc[q]);
          const double ri = rv[q];
          for (std::size_t k = ap[i]; k < ap[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(ac[k]);
            const double ra = ri * av[k];
            for (std::size_t m = pp[j]; m < pp[j + 1]; ++m) {
              const auto J = static_cast<std::size_t>(pc[m]);
              const double v = ra * pv[m];
              if (mk[J] != row) {
                mk[J] = row;
                touched.push_back(static_cast<Index>(J));
                ac_sum[J] = v;
              } else {
                ac_sum[J] += v;
              }
            }
          }
        }
        for (Index J : touched) {
          cols.push_back(J);
          vals.push_back(ac_sum[static_cast<std::size_t>(J)]);
        }
        len[I] = touched.size();
      }
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
    std::vector<Index>().swap(bcol[t]);
    std::vector<double>().swap(bval[t]);
  }
  return c;
}

// fine = P coarse (add: fine += P coarse), P the interpolation of level f.
void prolong(const Level& f, const double* coarse, double* fine, bool add) {
  const auto rows = static_cast<std::ptrdiff_t>(f.n());
#pragma omp parallel for schedule(static) if (f.parallel())
  for (std::ptrdiff_t i = 0; i < rows; ++i) {
    double s = 0.0;
    for (std::size_t k = f.p_ptr[i]; k < f.p_ptr[i + 1]; ++k) s += f.p_val[k] * coarse[f.p_col[k]];
    fine[i] = add ? fine[i] + s : s;
  }
}

void finish_level(Level& l) {
  const std::size_t n = l.n();
  const auto rows = static_cast<std::ptrdiff_t>(n);
  const CsrMatrix& a = l.a;
  l.inv_diag.resize(n);
#pragma omp parallel for schedule(static) if (l.parallel())
  for (std::ptrdiff_t i = 0; i < rows; ++i) l.inv_diag[static_cast<std::size_t>(i)] = 1.0 / a.val[a.ptr[i]];
  l.blocks = blocks_for(n);
  const std::size_t nb = l.blocks;
  int far = 0;
#pragma omp parallel for schedule(static) reduction(| : far) if (nb > 1)
  for (std::ptrdiff_t blk = 0; blk < static_cast<std::ptrdiff_t>(nb); ++blk) {
    const auto ub = static_cast<std::size_t>(blk);
    const std::size_t lo = n * ub / nb, hi = n * (ub + 1) / nb;
    for (std::size_t k = a.ptr[lo]; k < a.ptr[hi]; ++k) {
      const std::size_t cb = block_of(static_cast<std::size_t>(a.col[k]), n, nb);
      if (cb != ub && ((cb ^ ub) & 1) == 0) {
        far = 1;
        break;
      }
    }
  }
  // Two blocks of the same colour coupled (rows coupling to rows far away): the blocks
  // cannot be relaxed side by side, so the level is relaxed in one sequential sweep.
  if (far != 0) l.blocks = 1;
  l.r.resize(n);
}

// Once the hierarchy is built (the coarsening reads the rows in their given order): the
// couplings of every row sorted by column after the diagonal, the number of lower ones,
// and whether they all stay in the row's Gauss-Seidel block.
void prepare_relaxation(Level& l) {
  const std::size_t n = l.n(), nb = l.blocks;
  CsrMatrix& a = l.a;
  l.lower.resize(n);
  l.interior.resize(n);
#pragma omp parallel for schedule(static) if (l.parallel())
  for (std::ptrdiff_t ii = 0; ii < static_cast<std::ptrdiff_t>(n); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    for (std::size_t k = a.ptr[i] + 2; k < a.ptr[i + 1]; ++k) {  // insertion sort: rows are short
      const Index c = a.col[k];
      const double v = a.val[k];
      std::size_t m = k;
      for (; m > a.ptr[i] + 1 && a.col[m - 1] > c; --m) {
        a.col[m] = a.col[m - 1];
        a.val[m] = a.val[m - 1];
      }
      a.col[m] = c;
      a.val[m] = v;
    }
    std::uint32_t low = 0;
    for (std::size_t k = a.ptr[i] + 1; k < a.ptr[i + 1] && static_cast<std::size_t>(a.col[k]) < i; ++k) ++low;
    l.lower[i] = low;
    const std::size_t blk = block_of(i, n, nb), lo = n * blk / nb, hi = n * (blk + 1) / nb;
    const bool inside =
        a.ptr[i + 1] == a.ptr[i] + 1 || (static_cast<std::size_t>(a.col[a.ptr[i] + 1]) >= lo &&
                                         static_cast<std::size_t>(a.col[a.ptr[i + 1] - 1]) < hi);
    l.interior[i] = inside ? 1 : 0;
  }
}

// One Gauss-Seidel sweep, forward or backward. With several blocks of rows (an even number;
// a block couples only to blocks of the other colour) the even blocks are relaxed first,
// side by side, then the odd ones (backward: odd first): Gauss-Seidel in that order of the
// rows, whatever the number of threads. zero_guess (a forward sweep from x = 0): x is
// overwritten, and values not yet relaxed in this sweep count as 0 without being read.
void relax(const Level& l, const double* b, double* x, bool forward, bool zero_guess) {
  const CsrMatrix& a = l.a;
  const std::size_t n = a.n, nb = l.blocks;
  auto sweep_block = [&](std::size_t blk) {
    const std::size_t lo = n * blk / nb, hi = n * (blk + 1) / nb;
    // zero_guess: the other colour has been relaxed already only if this block is odd.
    const bool other_done = (blk & 1) != 0;
    const std::size_t* const ap = a.ptr.data();
    const Index* const ac = a.col.data();
    const double* const av = a.val.data();
    const double* const id = l.inv_diag.data();
    const std::uint8_t* const interior = l.interior.data();
    const std::uint32_t* const lower = l.lower.data();
    for (std::size_t t = lo; t < hi; ++t) {
      const std::size_t i = forward ? t : hi - 1 - (t - lo);
      double s = b[i];
      if (!zero_guess) {
        for (std::size_t k = ap[i] + 1; k < ap[i + 1]; ++k) s -= av[k] * x[ac[k]];
      } else if (interior[i]) {  // every coupling in this block: the lower ones are relaxed
        for (std::size_t k = ap[i] + 1; k < ap[i] + 1 + lower[i]; ++k) s -= av[k] * x[ac[k]];
      } else {
        for (std::size_t k = ap[i] + 1; k < ap[i + 1]; ++k) {
          const auto j = static_cast<std::size_t>(ac[k]);
          const bool own = j >= lo && j < hi;
          if ((own && j < i) || (!own && other_done)) s -= av[k] * x[j];
        }
      }
      x[i] = s * id[i];
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
  // The set-up makes many short-lived allocations of up to the matrix size: from the heap,
  // grown once and advised for huge pages (see HeapAllocationScope), not mapped one by one.
  const HeapAllocationScope heap_only(40 * a.nnz());
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
    c->x.resize(nc);
    c->b.resize(nc);
    levels_.push_back(std::move(c));
  }
  for (auto& l : levels_) prepare_relaxation(*l);
  const Level& cl = *levels_.back();
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
  prolong(*levels_[static_cast<std::size_t>(level)], coarse, fine, false);
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
  const std::size_t n = f.n(), nc = c.n();
  const auto rows = static_cast<std::ptrdiff_t>(n), crows = static_cast<std::ptrdiff_t>(nc);
  double* r = f.r.data();
  {
    // Residual after the sweep. A row whose couplings all stay in its block satisfied its
    // equation with the lower couplings when it was relaxed: what is left is minus its
    // upper couplings (half a product); the other rows are computed in full.
    const std::size_t* const ap = f.a.ptr.data();
    const Index* const ac = f.a.col.data();
    const double* const av = f.a.val.data();
#pragma omp parallel for schedule(static) if (f.parallel())
    for (std::ptrdiff_t ii = 0; ii < rows; ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      double s = 0.0;
      if (f.interior[i]) {
        for (std::size_t k = ap[i] + 1 + f.lower[i]; k < ap[i + 1]; ++k) s -= av[k] * x[ac[k]];
      } else {
        s = b[i];
        for (std::size_t k = ap[i]; k < ap[i + 1]; ++k) s -= av[k] * x[ac[k]];
      }
      r[i] = s;
    }
  }
  double* bc = c.b.data();
#pragma omp parallel for schedule(static) if (c.parallel())
  for (std::ptrdiff_t I = 0; I < crows; ++I) {
    double s = 0.0;
    for (std::size_t k = f.r_ptr[I]; k < f.r_ptr[I + 1]; ++k) s += f.r_val[k] * r[f.r_col[k]];
    bc[I] = s;
  }
  cycle(l + 1, bc, c.x.data());
  prolong(f, c.x.data(), x, true);
  relax(f, b, x, false, false);
}

void AlgebraicMultigrid::precondition(const double* r, double* z) const { cycle(0, r, z); }

CgOutcome amg_pcg(const AlgebraicMultigrid& mg, const double* b, double* x, double tolerance,
                  int max_iterations, double reference_norm, const std::function<bool()>& stop_request) {
  const std::size_t n = mg.size();
  const CsrMatrix& a = mg.matrix();
  auto dot = [n](auto&& f) { return range_sums(n, 1, [&](std::size_t i, double* s) { s[0] += f(i); })[0]; };
  CgOutcome out;
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) x[i] = 0.0;
  const double bnorm = std::sqrt(dot([&](std::size_t i) { return b[i] * b[i]; }));
  const double ref = reference_norm > 0.0 ? reference_norm : bnorm;
  if (!std::isfinite(bnorm)) return out;
  if (bnorm == 0.0) {
    out.converged = true;
    return out;
  }
  Buffer<double> r(n), z(n), p(n), q(n);
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) r[static_cast<std::size_t>(i)] = b[i];
  mg.precondition(r.data(), z.data());
#pragma omp parallel for schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i)
    p[static_cast<std::size_t>(i)] = z[static_cast<std::size_t>(i)];
  double rz = dot([&](std::size_t i) { return r[i] * z[i]; });
  const auto rows = static_cast<std::ptrdiff_t>(n);
  for (int it = 1; it <= max_iterations; ++it) {
    if (stop_request && stop_request())
      throw Interrupted("flow solve interrupted at PCG iteration " + std::to_string(it));
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
