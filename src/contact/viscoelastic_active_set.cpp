// The normal problem of a sliding viscoelastic body on its non-symmetric operator K = c C_zz
// itself (solver.viscoelastic_method = "active_set"; "auto", the default, takes it for the
// frictionless solve): a primal-dual active set. On
// the contact set A the gap vanishes (the hard wall) or equals -p/k (the harmonic interaction),
// off it the pressure does. That linear system, (K + 1/k) p = w - g0 + delta on A with p = 0 off
// A (and sum p = N pbar under load control, delta its multiplier), is solved by restarted GMRES,
// whose one product is a spectral pass with the complex table; its vectors live on the set's
// points only. Then the set is updated: points whose pressure came out negative leave, points
// outside it that overlap join. The solve ends when the set no longer changes and the linear
// residual meets the tolerance. See docs/solver.md ("Viscoelastic bodies").
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/contact/solver.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

namespace {
// GMRES restart length: the Krylov basis holds this many vectors on the set (plus one). On the
// viscoelastic sphere the linear solves take 20-100 products, within one or two restarts.
constexpr int kKrylovRestart = kActiveSetKrylov;
// Steps without fewer points joining or leaving than before, after which the set is taken to
// cycle: its linear solves are then exact (a loose solve's error can decide an edge point's sign).
constexpr int kCycleSteps = 3;
}  // namespace

bool ContactSolver::uses_active_set() const {
  // A hardness cap needs a third state per point (at the cap): the splitting handles it.
  if (inter_.plastic() || sp_.visco_method == ViscoMethod::Splitting) return false;
  return sp_.visco_method == ViscoMethod::ActiveSet || fric_.coefficient == 0.0;
}

ContactSolver::PKResult ContactSolver::solve_normal_active_set(const LoadParams& load,
                                                               const RealField* w_extra, RealField& p,
                                                               double tol, int max_it, int& steps,
                                                               std::string& status) {
  const std::size_t nl = grid_.local_size();
  const auto nli = static_cast<std::ptrdiff_t>(nl);
  const double n = static_cast<double>(grid_.size());
  const bool load_ctrl = load.mode != LoadMode::Approach;
  const double pbar = load.mode == LoadMode::Force ? load.value / grid_.area() : load.value;
  const double ik = inv_k_;
  ActiveSetWork& ws = visco_.active;
  ws.rhs.resize(nl);
  ws.kp.resize(nl);
  ws.full.resize(nl);
  ws.in.assign(nl, 0);
  RealField& rhs = ws.rhs;
  RealField& kp = ws.kp;
  std::vector<unsigned char>& in = ws.in;
  // rhs = w - g0: on the contact set (K + 1/k) p - delta = rhs.
  parallel_for(nli, [&](std::ptrdiff_t i) { rhs[i] = (w_extra ? (*w_extra)[i] : 0.0) - g0_[i]; });

  PKResult res{0, 1.0, 0.0, false};
  int used = 0;  // operator products (each a forward and an inverse transform)
  // The first set's solve: to the tolerance from a warm start (its set is likely the answer, as
  // in the friction loop's calls), loose from a cold one.
  double violation = 0.0;
  const bool warm = grid_sum(grid_, [&](std::size_t i) { return p[i]; }) > 0.0;
  if (!warm) {
    violation = 1.0;
    // No pressure to start from: the first contact set is that of the symmetric part |c| C_zz
    // (the elastic solve at each mode's modulus magnitude), to 1e-4.
    static const RealField none;
    const PKResult pk = w_extra ? solve_normal(load, *w_extra, false, p, std::max(tol, 1e-4), max_it)
                                : solve_normal(load, none, true, p, std::max(tol, 1e-4), max_it);
    used += 2 * pk.iterations;
    total_it_ += pk.iterations;  // (Polonsky-Keer counted each once; each is two products)
  }
  parallel_for(nli, [&](std::ptrdiff_t i) {
    p[i] = std::max(p[i], 0.0);
    in[i] = p[i] > 0.0 ? 1 : 0;
  });

  // The set's points held here, row by row (idx; row r's are entries start[r] .. start[r+1]-1),
  // so that its sums add in the grid's row order: the same bits on any number of processes.
  std::vector<std::uint32_t>& idx = ws.idx;
  std::vector<std::uint32_t>& start = ws.start;
  std::vector<std::uint32_t>& order = ws.order;
  const auto index_set = [&] {
    idx.clear();
    start.assign(static_cast<std::size_t>(grid_.rows()) + 1, 0);
    for (int r = 0; r < grid_.rows(); ++r) {
      start[static_cast<std::size_t>(r)] = static_cast<std::uint32_t>(idx.size());
      const std::size_t base = static_cast<std::size_t>(r) * static_cast<std::size_t>(grid_.nx);
      for (int ix = 0; ix < grid_.nx; ++ix)
        if (in[base + static_cast<std::size_t>(ix)]) idx.push_back(static_cast<std::uint32_t>(base + ix));
    }
    start[static_cast<std::size_t>(grid_.rows())] = static_cast<std::uint32_t>(idx.size());
    order.resize(idx.size());
    for (std::size_t e = 0; e < order.size(); ++e) order[e] = static_cast<std::uint32_t>(e);
  };
  const auto set_sums = [&](std::size_t k, auto&& f) { return row_grouped_sums(grid_, start, order, k, f); };

  // The operator on the set: out = P ((K + 1/k) v) over its entries; P removes the mean under
  // load control (the multiplier delta absorbs it, and v keeps its zero sum there).
  double n_in = 0.0;
  RealField& full = ws.full;
  const auto op = [&](const std::vector<double>& v, std::vector<double>& out, double kp_factor = 0.0) {
    // kp_factor > 0: kp already holds K v / kp_factor (the last product's response to a pressure
    // v is a multiple of), no transform.
    const auto m = static_cast<std::ptrdiff_t>(idx.size());
    double f = kp_factor;
    if (f == 0.0) {
      std::fill(full.begin(), full.end(), 0.0);
      parallel_for(m, [&](std::ptrdiff_t e) { full[idx[e]] = v[e]; });
      apply_normal_response(full, kp);
      ++used;
      ++total_it_;
      poll(current_);  // once per product, as Polonsky-Keer polls once per iteration
      f = 1.0;
    }
    out.resize(idx.size());
    parallel_for(m, [&](std::ptrdiff_t e) { out[e] = f * kp[idx[e]] + ik * v[e]; });
    if (load_ctrl) {
      const double mean = set_sums(1, [&](std::size_t e, double* acc) { acc[0] += out[e]; })[0] / n_in;
      parallel_for(m, [&](std::ptrdiff_t e) { out[e] -= mean; });
    }
  };

  std::vector<std::vector<double>>& basis = ws.basis;
  basis.resize(static_cast<std::size_t>(kKrylovRestart) + 1);
  std::vector<double> h(static_cast<std::size_t>(kKrylovRestart + 1) * kKrylovRestart);
  std::vector<double> cs(kKrylovRestart), sn(kKrylovRestart), gv(kKrylovRestart + 1), y(kKrylovRestart);
  const auto H = [&](int row, int col) -> double& {
    return h[static_cast<std::size_t>(row) * kKrylovRestart + static_cast<std::size_t>(col)];
  };
  std::vector<double> x, r;  // the pressure on the set and the residual
  double delta = load_ctrl ? 0.0 : load.value;
  bool exact = false;
  bool kp_is_p = false;  // kp holds K p: the last product's input was p, which no clip changed since
  int fewest = std::numeric_limits<int>::max(), since_fewest = 0;
  RealField old;
  for (int step = 0;; ++step) {
    ++steps;
    n_in = grid_sum(grid_, [&](std::size_t i) { return in[i] ? 1.0 : 0.0; });
    if (n_in == 0.0) {
      // Approach control with nothing in contact: done where nothing overlaps, else the overlapping
      // points are the set. Load control: every point, which the steps thin.
      const auto overlaps = [&](std::size_t i) { return load_ctrl || -rhs[i] - delta < 0.0; };
      if (grid_sum(grid_, [&](std::size_t i) { return overlaps(i) ? 1.0 : 0.0; }) == 0.0) {
        status = "converged";
        res = {used, 0.0, delta, true};
        return res;
      }
      parallel_for(nli, [&](std::ptrdiff_t i) { in[i] = overlaps(static_cast<std::size_t>(i)) ? 1 : 0; });
      n_in = grid_sum(grid_, [&](std::size_t i) { return in[i] ? 1.0 : 0.0; });
    }
    index_set();
    const auto m = static_cast<std::ptrdiff_t>(idx.size());
    old.assign(p.begin(), p.end());
    x.resize(idx.size());
    parallel_for(m, [&](std::ptrdiff_t e) { x[e] = p[idx[e]]; });
    double x_factor = 1.0;  // x = x_factor p on the set (0: not so)
    if (load_ctrl) {
      // The load on the set: the pressure rescaled to it (uniform where it has none yet).
      const double s = set_sums(1, [&](std::size_t e, double* acc) { acc[0] += x[e]; })[0];
      x_factor = s > 0.0 ? pbar * n / s : 0.0;
      parallel_for(m, [&](std::ptrdiff_t e) { x[e] = s > 0.0 ? x[e] * x_factor : pbar * n / n_in; });
    }
    // The residual's scale: the spread of w - g0 over the set (as Polonsky-Keer's), no smaller
    // than 1e-3 of the surface's rms height.
    const auto sm = set_sums(2, [&](std::size_t e, double* acc) {
      acc[0] += rhs[idx[e]];
      acc[1] += rhs[idx[e]] * rhs[idx[e]];
    });
    const double mean_rhs = sm[0] / n_in;
    const double spread = std::sqrt(std::max(0.0, sm[1] / n_in - mean_rhs * mean_rhs));
    const double scale = std::sqrt(n_in) * (std::max(spread, 1e-3 * g0_rms_) + 1e-300);
    // Each linear solve to a tenth of the last set's violation (the negative pressures in it,
    // the overlap outside it; no tighter than the tolerance): the signs that decide the next set
    // must not be the solve's error. Exact once the set cycles.
    const double inner_tol = exact ? tol : std::max(tol, std::min(1e-2, 0.1 * violation));
    // GMRES(m) on the set from the current pressure. It ends when its residual meets the target
    // (GMRES's own estimate; the set's update below measures the true one) and, in a call from a
    // warm start, the pressure's error does too: estimated after each cycle as the cycle's
    // relative update times its residual reduction. The gap residual alone can be met by a
    // pressure that has not moved (the friction loop's next call, whose right-hand side changed
    // little); that pressure lagged the traction's change and the friction loop took 296 steps
    // for the splitting's 72 on the rolling sphere (docs/solver.md).
    double rnorm = 0.0;
    bool inner_ok = false;
    double p_err = warm ? -1.0 : 0.0;  // -1: no cycle yet
    double target = inner_tol * scale;
    const auto pressure_ok = [&] { return p_err >= 0.0 && p_err <= inner_tol; };
    // The step's first residual from the last product where that was the response to this
    // pressure (the set only grew: nothing was clipped): K (f p) = f K p, no transform. Within
    // one call only, so that a resumed solve (which starts a call afresh) repeats its bits.
    bool from_kp = kp_is_p && x_factor > 0.0;
    while (used < max_it) {
      // The residual b - A x, b = rhs (its mean removed) or rhs + delta.
      op(x, r, from_kp ? x_factor : 0.0);
      from_kp = false;
      parallel_for(m, [&](std::ptrdiff_t e) {
        r[e] = (load_ctrl ? rhs[idx[e]] - mean_rhs : rhs[idx[e]] + delta) - r[e];
      });
      rnorm = std::sqrt(set_sums(1, [&](std::size_t e, double* acc) { acc[0] += r[e] * r[e]; })[0]);
      require_finite(rnorm, "the viscoelastic gap residual", total_it_);
      if (rnorm == 0.0 || (rnorm <= target && (!warm || pressure_ok()))) {
        inner_ok = true;
        break;
      }
      const double r_before = rnorm;
      basis[0].resize(idx.size());
      parallel_for(m, [&](std::ptrdiff_t e) { basis[0][e] = r[e] / rnorm; });
      std::fill(gv.begin(), gv.end(), 0.0);
      gv[0] = rnorm;
      int k = 0;
      while (k < kKrylovRestart && used < max_it) {
        std::vector<double>& w = basis[static_cast<std::size_t>(k) + 1];
        op(basis[static_cast<std::size_t>(k)], w);
        // Classical Gram-Schmidt twice (one sum of k + 1 dot products per pass).
        for (int pass = 0; pass < 2; ++pass) {
          const std::vector<double> d =
              set_sums(static_cast<std::size_t>(k) + 1, [&](std::size_t e, double* acc) {
                for (int j = 0; j <= k; ++j) acc[j] += w[e] * basis[static_cast<std::size_t>(j)][e];
              });
          for (int j = 0; j <= k; ++j) H(j, k) = (pass == 0 ? 0.0 : H(j, k)) + d[static_cast<std::size_t>(j)];
          parallel_for(m, [&](std::ptrdiff_t e) {
            double v = w[e];
            for (int j = 0; j <= k; ++j)
              v -= d[static_cast<std::size_t>(j)] * basis[static_cast<std::size_t>(j)][e];
            w[e] = v;
          });
        }
        const double hk =
            std::sqrt(set_sums(1, [&](std::size_t e, double* acc) { acc[0] += w[e] * w[e]; })[0]);
        H(k + 1, k) = hk;
        if (hk > 0.0) parallel_for(m, [&](std::ptrdiff_t e) { w[e] /= hk; });
        for (int j = 0; j < k; ++j) {  // the earlier rotations on the new column
          const double a = H(j, k), b = H(j + 1, k);
          H(j, k) = cs[j] * a + sn[j] * b;
          H(j + 1, k) = -sn[j] * a + cs[j] * b;
        }
        const double a = H(k, k), b = H(k + 1, k);
        const double rr = std::hypot(a, b);
        cs[k] = rr > 0.0 ? a / rr : 1.0;
        sn[k] = rr > 0.0 ? b / rr : 0.0;
        H(k, k) = rr;
        H(k + 1, k) = 0.0;
        gv[k + 1] = -sn[k] * gv[k];
        gv[k] = cs[k] * gv[k];
        ++k;
        if (std::abs(gv[k]) <= target || hk == 0.0) break;
      }
      // x += V y, y from the rotated triangle; the update's size for the pressure's error.
      for (int j = k - 1; j >= 0; --j) {
        double s = gv[j];
        for (int l = j + 1; l < k; ++l) s -= H(j, l) * y[l];
        y[j] = H(j, j) != 0.0 ? s / H(j, j) : 0.0;
      }
      const auto upd = set_sums(2, [&](std::size_t e, double* acc) {
        double v = x[e];
        for (int j = 0; j < k; ++j) v += y[j] * basis[static_cast<std::size_t>(j)][e];
        acc[0] += std::abs(v - x[e]);
        acc[1] += std::abs(v);
        x[e] = v;
      });
      rnorm = std::abs(gv[k]);
      if (warm) p_err = relative_change(upd[0], upd[1]) * rnorm / r_before;
      if (rnorm <= target && (!warm || pressure_ok())) {
        inner_ok = true;
        break;
      }
      // The residual met its target but the pressure's error did not: the next cycle aims lower
      // by their ratio.
      if (rnorm <= target) target = rnorm * inner_tol / p_err;
    }
    // The pressure, the gap everywhere, and the multiplier delta under load control.
    std::fill(p.begin(), p.end(), 0.0);
    parallel_for(m, [&](std::ptrdiff_t e) { p[idx[e]] = x[e]; });
    apply_normal_response(p, kp);
    ++used;
    ++total_it_;
    if (load_ctrl)
      delta = set_sums(
                  1, [&](std::size_t e, double* acc) { acc[0] += kp[idx[e]] + ik * x[e] - rhs[idx[e]]; })[0] /
              n_in;
    // The set's update: a negative pressure leaves, an overlap outside joins. Sums: the points
    // that would leave and join, the pressure's size, the negative pressure, the overlap's
    // square and the linear residual's (the gap on the set: its mean is zero under load control).
    const auto gap_at = [&](std::size_t i) { return kp[i] + ik * p[i] - rhs[i] - delta; };
    const auto mv = grid_sums<6>(grid_, [&](std::size_t i, std::array<double, 6>& acc) {
      if (in[i]) {
        const double g = gap_at(i);
        acc[5] += g * g;
        acc[3] += std::abs(p[i]);
        if (p[i] <= 0.0) {
          acc[0] += 1.0;
          acc[2] -= p[i];
        }
      } else if (const double g = gap_at(i); g < 0.0) {
        acc[1] += 1.0;
        acc[4] += g * g;
      }
    });
    const int moves = static_cast<int>(mv[0] + mv[1]);
    // The true residual: GMRES's estimate ended the solve.
    rnorm = std::sqrt(mv[5]);
    inner_ok = inner_ok && rnorm <= inner_tol * scale;
    violation = std::max(relative_change(mv[2], mv[3]), std::sqrt(mv[4]) / scale);
    // Converged: the linear solve and the set's violation within the tolerance (a point left
    // with a negative pressure below it is clipped, an overlap below it counts as contact,
    // as Polonsky-Keer's projection does).
    const bool done = inner_ok && inner_tol <= tol && violation <= tol;
    const auto ch = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      if (in[i] && p[i] <= 0.0) {
        if (p[i] < 0.0) acc[2] += 1.0;
        p[i] = 0.0;
        if (!done) in[i] = 0;
      } else if (!done && !in[i] && gap_at(i) < 0.0) {
        in[i] = 1;
      }
      acc[0] += std::abs(p[i] - old[i]);
      acc[1] += std::abs(p[i]);
    });
    const double change = relative_change(ch[0], ch[1]);
    kp_is_p = ch[2] == 0.0;
    res.error = std::max(rnorm / scale, std::max(change, violation));
    res.delta = delta;
    if (progress_) progress_(Progress{total_it_, 0, res.error});
    if (done) {
      status = "converged";
      break;
    }
    if (used >= max_it) {
      status = "not converged: iteration limit reached";
      break;
    }
    if (step + 1 >= sp_.max_outer) {
      std::ostringstream os;
      os << "not converged: the viscoelastic contact set did not settle in solver.max_outer = "
         << sp_.max_outer << " steps (" << moves << " points joined or left it in the last)";
      status = os.str();
      break;
    }
    if (!exact) {
      if (moves < fewest) {
        fewest = moves;
        since_fewest = 0;
      } else if (++since_fewest >= kCycleSteps) {
        exact = true;
      }
    }
  }
  res.iterations = used;
  res.converged = status == "converged";
  return res;
}

}  // namespace gfmd
