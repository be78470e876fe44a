// Algebraic multigrid set-up: strength of connection, coarse/fine splitting,
// interpolation, Galerkin products, relaxation tables (Ruge-Stueben, as amg.hpp says).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "amg_level.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/reduce.hpp"

namespace gfmd::amg_detail {

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

namespace {

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

}  // namespace

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

}  // namespace gfmd::amg_detail
