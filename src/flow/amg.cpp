// Classical (Ruge-Stueben) algebraic multigrid and AMG-preconditioned CG; see
// include/gfmd/flow/amg.hpp.
#include "gfmd/flow/amg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "amg_level.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/reduce.hpp"

namespace gfmd {

using namespace amg_detail;

namespace {

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

namespace {

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
