// The normal contact problem: constrained CG (Polonsky & Keer) on the compliance, for a
// hard wall or a harmonic interaction. See include/gfmd/contact/solver.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>

#include "gfmd/contact/solver.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

void ContactSolver::apply_compliance(const RealField& in, RealField& out, double scale) {
  // out = scale C_zz in (the 1/k term is added by the callers in their fused passes). One
  // spectral pass with the contiguous table C_zz / N, then the inverse transform in place.
  fft_.forward(in.data(), s1_.data());
  const std::ptrdiff_t ns = static_cast<std::ptrdiff_t>(czz_n_.size());
  parallel_for(ns, [&](std::ptrdiff_t k) { s1_[k] *= scale * czz_n_[k]; });  // exact for scale = 1
  fft_.backward_unscaled_destroying(s1_.data(), out.data());
}

ContactSolver::PKResult ContactSolver::solve_normal(const LoadParams& load, const RealField& w, bool w_zero,
                                                    RealField& p, double tol, int max_it) {
  // Constrained conjugate gradients (Polonsky & Keer 1999) on (C_zz + 1/k) p = overlap.
  // Per iteration: two compliance products (2 forward + 2 inverse FFTs) and four fused
  // pointwise passes (A, C, D, E below; 17 reads and writes of 8 bytes per point, 16 when
  // w = 0); the work arrays are members (no allocation here).
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(grid_.size());         // points of the cell
  const std::ptrdiff_t nl = static_cast<std::ptrdiff_t>(grid_.local_size());  // points held here
  const bool load_ctrl = load.mode != LoadMode::Approach;
  const double pbar = load.mode == LoadMode::Force ? load.value / grid_.area() : load.value;
  const double delta_imp = load_ctrl ? 0.0 : load.value;
  const double ik = inv_k_;

  // The load rescaling of a step (a factor on the whole pressure) is applied by the next
  // step's compliance product and pass A, which writes p anyway: `pending` until then.
  double pending = 1.0;
  double psum = grid_sum(grid_, [&](std::size_t i) { return p[i]; });
  if (load_ctrl) {
    if (!(psum > 0)) {
      std::fill(p.begin(), p.end(), pbar);
    } else {
      pending = pbar * static_cast<double>(n) / psum;
    }
  } else if (!(psum > 0)) {
    const double kk = inter_.hard_wall ? body_.params().contact_modulus / grid_.dx() : k_;
    for (std::ptrdiff_t i = 0; i < nl; ++i) p[i] = kk * std::max(0.0, delta_imp + w[i] - g0_[i]);
  }

  RealField& g = cg_g_;
  RealField& t = cg_t_;
  RealField& r = cg_r_;  // C t
  bool conjugate = false;
  double gold = 1.0;
  const auto apply_pending = [&] {
    if (pending == 1.0) return;
    const double f = pending;
    parallel_for(nl, [&](std::ptrdiff_t i) { p[i] *= f; });
    pending = 1.0;
  };
  RealField unscaled;  // the pressure before a checkpoint's rescaling, and its factor
  double held = 1.0;
  const auto settle = [&] {
    if (pending == 1.0) return;
    unscaled.assign(p.begin(), p.end());
    held = pending;
    apply_pending();
  };
  const auto unsettle = [&] {
    if (held == 1.0) return;
    std::copy(unscaled.begin(), unscaled.end(), p.begin());
    pending = held;
    held = 1.0;
    unscaled = RealField();
  };
  PKResult res{0, 1.0, 0.0, false};
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    ++total_it_;
    apply_compliance(p, g, pending);
    // A: pressure rescaled, separation g = C p + p/k + g0 - w - delta; sums over the contact
    // set: its size; of g - gref and its square, with gref the previous mean of g there
    // (load control; 0 otherwise), so that the squared residual below does not cancel; of
    // g0 - w and its square about its previous mean, gw_mean_ref_, likewise.
    const double ref = gw_mean_ref_;
    const double gref = load_ctrl ? g_mean_ref_ : 0.0;
    const double fp = pending;
    const auto pass_a = [&]<bool WZero>() {
      return grid_sums<5>(grid_, [&](std::size_t i, std::array<double, 5>& acc) {
        const double gw = WZero ? g0_[i] : g0_[i] - w[i];
        double pi = p[i];
        if (fp != 1.0) {
          pi *= fp;
          p[i] = pi;
        }
        const double v = g[i] + ik * pi + gw - delta_imp;
        g[i] = v;
        if (pi > 0) {
          const double d = gw - ref, e = v - gref;
          acc[0] += 1.0;
          acc[1] += e;
          acc[2] += e * e;
          acc[3] += d;
          acc[4] += d * d;
        }
      });
    };
    const auto a = w_zero ? pass_a.template operator()<true>() : pass_a.template operator()<false>();
    pending = 1.0;
    const double ns = a[0];
    if (ns == 0.0) {
      // Approach control with no contact at all: p = 0 is the solution if nothing overlaps.
      const double minimum = -grid_max(
          grid_, [&](std::size_t i) { return -g[i]; }, -1e300);
      if (minimum >= 0.0) {
        res.converged = true;
        res.error = 0.0;
        res.delta = delta_imp;
        return res;
      }
      parallel_for(nl, [&](std::ptrdiff_t i) { p[i] = std::max(0.0, -g[i]) * (ik > 0 ? k_ : 1.0); });
      conjugate = false;
      continue;
    }
    // With load control the separation is measured from its mean on the contact set, gbar:
    // g - gbar below (g itself is not rewritten). G: squared residual on the contact set.
    const double shift = a[1] / ns;  // gbar - gref
    const double gbar = load_ctrl ? gref + shift : 0.0;
    double G = load_ctrl ? std::max(0.0, a[2] - ns * shift * shift) : a[2];
    if (load_ctrl) {
      g_mean_ref_ = gbar;
      // Shifted sums lose log10(ns shift^2 / G) digits: recomputed directly when that
      // leaves fewer than about 6 (the reference is the previous mean, so this is rare).
      if (!(G > 1e-10 * ns * shift * shift)) {
        G = grid_sum(grid_, [&](std::size_t i) {
          const double v = g[i] - gbar;
          return p[i] > 0 ? v * v : 0.0;
        });
      }
    }
    const double s1 = a[3] / ns;
    const double s2 = std::max(0.0, a[4] / ns - s1 * s1);  // variance of g0 - w on the contact set
    gw_mean_ref_ = ref + s1;
    const double beta = conjugate ? G / gold : 0.0;
    gold = G;
    // C: conjugate direction on the contact set; squared overlap outside it.
    const auto c = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double gi = g[i] - gbar;
      double v = 0.0;
      if (p[i] > 0) {
        v = gi + beta * t[i];
      } else if (gi < 0) {
        acc[2] += gi * gi;
      }
      t[i] = v;
      acc[0] += gi * v;
      acc[1] += v;
    });
    const double viol = c[2];
    // Residual of the contact conditions: gap on the contact set and overlap outside,
    // relative to the spread of the separation over the contact set.
    const double scale = std::max(std::sqrt(s2), 1e-3 * g0_rms_) + 1e-300;
    const double gap_residual = std::sqrt((G + viol) / ns) / scale;
    apply_compliance(t, r);
    // D: r = (C + 1/k) t; with load control the mean of r over the contact set is removed,
    // which changes sum_c r t by rbar sum_c t.
    const auto d = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      if (p[i] > 0) {
        const double v = r[i] + ik * t[i];
        acc[0] += v;
        acc[1] += v * t[i];
      }
    });
    const double num = c[0];
    const double den = load_ctrl ? d[1] - (d[0] / ns) * c[1] : d[1];
    require_finite(num, "the pressure residual", total_it_);
    if (den == 0.0 || G == 0.0) {
      res.converged = true;
      res.error = 0.0;
      res.delta = load_ctrl ? gbar : delta_imp;
      return res;
    }
    const double tau = num / den;
    // E: projected step; points that overlap outside the contact set enter it. Sums: the
    // entering points, the new total and the change of the pressure.
    const auto e = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double pi = p[i];
      double v = pi > 0 ? std::max(0.0, pi - tau * t[i]) : 0.0;
      const double gi = g[i] - gbar;
      if (v == 0.0 && gi < 0.0) {
        v = -tau * gi;
        acc[0] += 1.0;
      }
      p[i] = v;
      acc[1] += v;
      acc[2] += std::abs(v - pi);
    });
    conjugate = (e[0] == 0.0);
    double pnew = e[1];
    // Load control rescales the new pressure by f (pending until the next pass A). The
    // change |f v - p| summed is bounded by sum |v - p| + |f - 1| sum v: the bound is what
    // the convergence test uses (exact when f = 1).
    double change = e[2];
    if (load_ctrl && pnew > 0) {
      pending = pbar * static_cast<double>(n) / pnew;
      change += std::abs(pending - 1.0) * pnew;
      pnew = pbar * static_cast<double>(n);
    }
    res.error = std::max(gap_residual, pnew > 0 ? change / pnew : (change > 0 ? 1.0 : 0.0));
    res.delta = load_ctrl ? gbar : delta_imp;
    require_finite(res.error, "the pressure", total_it_);
    if (progress_ && (total_it_ % 50 == 0)) progress_(Progress{total_it_, 0, res.error});
    if (res.error < tol) {
      apply_pending();
      res.converged = true;
      return res;
    }
    // A checkpoint or an interruption sees the rescaled pressure; after a checkpoint the
    // solve goes on from its own unscaled pressure and pending factor, so that its bits do
    // not depend on when checkpoints fall (wall-clock time, hence the process count).
    // (std::ref: the std::function holds a reference, no allocation per step.)
    poll(current_, std::ref(settle), std::ref(unsettle));
  }
  apply_pending();
  return res;
}

}  // namespace gfmd
