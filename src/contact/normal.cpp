// The normal contact problem: constrained CG (Polonsky & Keer) on the compliance, for a
// hard wall or a harmonic interaction. See include/gfmd/contact/solver.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
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
  if (!inter_.plastic() || load.mode == LoadMode::Approach)
    return solve_normal_pk(load, w, w_zero, p, tol, max_it);
  const double H = inter_.hardness;
  const auto at_cap = [&] {
    return !(grid_max(
                 grid_, [&](std::size_t i) { return p[i]; }, 0.0) < H);
  };
  PKResult trial{0, 1.0, 0.0, false};
  if (!capped_acted_) {
    // The cap did not act in the last solve (or there was none): the uncapped load-controlled solve
    // first. Where its pressure stays below H everywhere it is the capped solution (the cap's
    // constraint inactive, every other condition met), at Polonsky-Keer's cost instead of the
    // bracket's (a Hertz sphere under a cap it never reaches: 38 CG iterations against 410).
    RealField start(p);
    cap_off_ = true;
    trial = solve_normal_pk(load, w, w_zero, p, tol, max_it);
    cap_off_ = false;
    if (trial.converged && !at_cap()) {
      capped_delta_ = trial.delta;
      capped_found_ = true;
      return trial;
    }
    p = std::move(start);  // the bracket starts where this solve did
  }
  PKResult r = solve_normal_capped_load(load, w, w_zero, p, tol, std::max(1, max_it - trial.iterations));
  r.iterations += trial.iterations;
  capped_acted_ = at_cap();
  return r;
}

ContactSolver::PKResult ContactSolver::solve_normal_capped_load(const LoadParams& load, const RealField& w,
                                                                bool w_zero, RealField& p, double tol,
                                                                int max_it) {
  // With a cap Polonsky-Keer's load control (rescaling the pressure) has no hold where every
  // contact point is at the cap; the approach is the Lagrange multiplier instead: the mean
  // pressure of the capped solution at approach d, P(d), is continuous and non-decreasing,
  // and P(d) = pbar is solved for d by regula falsi with the Illinois safeguard.
  const double pbar = load.mode == LoadMode::Force ? load.value / grid_.area() : load.value;
  const double n = static_cast<double>(grid_.size());
  PKResult total{0, 1.0, 0.0, false};
  bool inner_ok = true;
  double inner_err = 0.0;
  double evaluated = std::numeric_limits<double>::quiet_NaN();  // the approach whose solution p holds
  const auto mean_at = [&](double d) {
    evaluated = d;
    const PKResult r = solve_normal_pk(LoadParams{LoadMode::Approach, d}, w, w_zero, p, tol,
                                       std::max(1, max_it - total.iterations));
    total.iterations += r.iterations;
    inner_ok = r.converged;
    inner_err = r.error;
    return grid_sum(grid_, [&](std::size_t i) { return p[i]; }) / n;
  };
  // A bracket [lo, hi] with P(lo) < pbar <= P(hi), from the last approach (or the surface's
  // rms height) outwards in steps that double. With adhesion (w holds the adhesive traction's
  // pull) the approach may be negative: the search crosses zero as any other value.
  const double scale = std::max(g0_rms_, 1e-300);
  double hi = capped_found_ && std::isfinite(capped_delta_) ? capped_delta_ : scale;
  double phi = mean_at(hi);
  double lo = hi, plo = phi;
  // Steps of at least a thousandth of the rms height: an approach found near zero (with
  // adhesion) must not make the search crawl outwards from it.
  double step = std::max(std::abs(hi), 1e-3 * scale);
  const bool met = std::abs(phi - pbar) <= tol * pbar && inner_ok;  // the warm start carries the load
  if (met) {
    // hi is the answer: nothing to bracket, no step below.
  } else if (phi < pbar) {
    for (int k = 0; k < 200 && phi < pbar && total.iterations < max_it; ++k) {
      lo = hi;
      plo = phi;
      hi += step;
      step *= 2.0;
      phi = mean_at(hi);
    }
  } else {
    step *= 0.5;  // first to half the start (the start itself where it is positive)
    for (int k = 0; k < 200 && total.iterations < max_it; ++k) {
      lo -= step;
      step *= 2.0;
      plo = mean_at(lo);
      if (plo < pbar) break;
      hi = lo;
      phi = plo;
    }
  }
  double d = hi, pd = phi;
  int side = 0;  // Illinois: the end kept twice in a row has its residual halved
  for (int k = 0; !met && k < 200 && total.iterations < max_it; ++k) {
    if (std::abs(pd - pbar) <= tol * pbar && inner_ok) break;
    const double flo = plo - pbar, fhi = phi - pbar;
    d = fhi != flo ? hi - fhi * (hi - lo) / (fhi - flo) : 0.5 * (lo + hi);
    if (!(d > lo && d < hi)) d = 0.5 * (lo + hi);
    pd = mean_at(d);
    if (pd < pbar) {
      lo = d;
      plo = pd;
      if (side == -1) phi = pbar + 0.5 * (phi - pbar);
      side = -1;
    } else {
      hi = d;
      phi = pd;
      if (side == 1) plo = pbar + 0.5 * (plo - pbar);
      side = 1;
    }
    if (hi - lo <= 1e-15 * std::max({std::abs(hi), std::abs(lo), scale})) break;
  }
  if (evaluated != d) pd = mean_at(d);  // p must hold d's solution (a bracket found it at once)
  capped_delta_ = d;
  capped_found_ = true;
  total.delta = d;
  const double load_err = std::abs(pd - pbar) / pbar;
  total.error = std::max(inner_err, load_err);
  total.converged = inner_ok && load_err <= tol;
  return total;
}

ContactSolver::PKResult ContactSolver::solve_normal_pk(const LoadParams& load, const RealField& w,
                                                       bool w_zero, RealField& p, double tol, int max_it) {
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
  // The local stiffness: the interaction's k, or E*/dx for the hard wall (a start without a
  // pressure; capped, the largest step of points outside the CG).
  const double local_k = inter_.hard_wall ? body_.params().contact_modulus / grid_.dx() : k_;
  // Plastic saturation (interaction.hardness), under approach control only (load control
  // with a cap is solve_normal_capped_load): the pressure is capped at H. Points at the cap
  // are fixed loads of the CG (not in its active set): they may overlap (plastic flow) and
  // leave the cap where their gap opens. H = inf: the plain method, bit for bit.
  const double H = cap_off_ ? std::numeric_limits<double>::infinity() : inter_.hardness;
  const bool capped = std::isfinite(H);
  if (capped && load_ctrl) throw SolveError("solve_normal_pk: a capped pressure needs approach control");

  // The load rescaling of a step (a factor on the whole pressure) is applied by the next
  // step's compliance product and pass A, which writes p anyway: `pending` until then.
  double pending = 1.0;
  if (capped) parallel_for(nl, [&](std::ptrdiff_t i) { p[i] = std::min(p[i], H); });
  double psum = grid_sum(grid_, [&](std::size_t i) { return p[i]; });
  if (load_ctrl) {
    if (!(psum > 0)) {
      std::fill(p.begin(), p.end(), pbar);
    } else {
      pending = pbar * static_cast<double>(n) / psum;
    }
  } else if (!(psum > 0)) {
    for (std::ptrdiff_t i = 0; i < nl; ++i)
      p[i] = std::min(local_k * std::max(0.0, delta_imp + (w_zero ? 0.0 : w[i]) - g0_[i]), H);
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
  double last_tau = 0.0;  // the last CG step length (capped: the step of points outside the CG)
  // Capped: the step of points that enter the contact or leave the cap is halved whenever such a
  // step does not shrink the pressure's change (a whole contact at the cap can otherwise jump
  // between all-capped and all-open, each point moved by the local stiffness while the patch
  // responds far more softly: seen on a viscoelastic body, whose glassy modes stiffen the
  // operator unevenly).
  double cap_damping = 1.0, last_cap_change = std::numeric_limits<double>::infinity();
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
        if (pi > 0 && pi < H) {
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
    if (ns == 0.0 && !capped) {
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
    // Capped, every contact point may be at the cap (ns = 0): the separation's reference is then
    // the previous one, and the step below moves the points outside the CG only.
    const double nsd = ns > 0 ? ns : 1.0;
    const double shift = a[1] / nsd;  // gbar - gref
    const double gbar = load_ctrl ? gref + shift : 0.0;
    double G = load_ctrl ? std::max(0.0, a[2] - nsd * shift * shift) : a[2];
    if (load_ctrl) {
      g_mean_ref_ = gbar;
      // Shifted sums lose log10(ns shift^2 / G) digits: recomputed directly when that
      // leaves fewer than about 6 (the reference is the previous mean, so this is rare).
      if (!(G > 1e-10 * ns * shift * shift)) {
        G = grid_sum(grid_, [&](std::size_t i) {
          const double v = g[i] - gbar;
          return p[i] > 0 && p[i] < H ? v * v : 0.0;
        });
      }
    }
    const double s1 = a[3] / nsd;
    const double s2 = std::max(0.0, a[4] / nsd - s1 * s1);  // variance of g0 - w on the contact set
    gw_mean_ref_ = ref + s1;
    const double beta = conjugate ? G / gold : 0.0;
    gold = G;
    // C: conjugate direction on the contact set; squared overlap outside it.
    const auto c = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double gi = g[i] - gbar;
      double v = 0.0;
      if (p[i] > 0 && p[i] < H) {
        v = gi + beta * t[i];
      } else if (p[i] > 0 ? gi > 0 : gi < 0) {
        acc[2] += gi * gi;  // overlap outside the contact, or an opening gap under a point at the cap
      }
      t[i] = v;
      acc[0] += gi * v;
      acc[1] += v;
    });
    const double viol = c[2];
    // Residual of the contact conditions: gap on the contact set and overlap outside,
    // relative to the spread of the separation over the contact set.
    const double scale = std::max(std::sqrt(s2), 1e-3 * g0_rms_) + 1e-300;
    const double gap_residual = std::sqrt((G + viol) / nsd) / scale;
    apply_compliance(t, r);
    // D: r = (C + 1/k) t; with load control the mean of r over the contact set is removed,
    // which changes sum_c r t by rbar sum_c t.
    const auto d = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      if (p[i] > 0 && p[i] < H) {
        const double v = r[i] + ik * t[i];
        acc[0] += v;
        acc[1] += v * t[i];
      }
    });
    const double num = c[0];
    const double den = load_ctrl ? d[1] - (d[0] / nsd) * c[1] : d[1];
    require_finite(num, "the pressure residual", total_it_);
    // Capped: the points below the cap may satisfy their conditions (G = 0, or none of them
    // left) while points outside them do not (viol > 0): the step then moves only those, with
    // the last step length (or the stiffness scale E*/dx, k).
    const bool stalled = den == 0.0 || G == 0.0;
    if (stalled && !(capped && viol > 0.0)) {
      res.converged = true;
      res.error = 0.0;
      res.delta = load_ctrl ? gbar : delta_imp;
      return res;
    }
    const double tau = !stalled ? num / den : (last_tau > 0 ? last_tau : local_k);
    if (!stalled) last_tau = tau;
    // Points that enter the contact or leave the cap move by at most the local stiffness
    // (E*/dx, k) times their gap when capped: the CG's step of a small free set can be far
    // larger and would throw points between 0 and H (without a cap: Polonsky-Keer's tau).
    const double tau_cap = capped ? std::min(tau, local_k) * cap_damping : tau;
    // E: projected step; points that overlap outside the contact set enter it. Sums: the
    // entering points, the new total and the change of the pressure.
    // Capped: steps are clipped at H; a point at the cap whose gap opens leaves it by the same
    // rule as an overlapping point enters the contact.
    const auto e = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double pi = p[i];
      const double gi = g[i] - gbar;
      double v;
      if (pi >= H) {
        v = H;
        if (gi > 0.0) {
          v = std::max(0.0, H - tau_cap * gi);
          acc[0] += 1.0;
        }
      } else {
        v = pi > 0 ? std::min(std::max(0.0, pi - tau * t[i]), H) : 0.0;
        if (v == 0.0 && gi < 0.0) {
          v = std::min(-tau_cap * gi, H);
          acc[0] += 1.0;
        }
      }
      p[i] = v;
      acc[1] += v;
      acc[2] += std::abs(v - pi);
    });
    if (capped && e[0] > 0.0) {
      if (!(e[2] < last_cap_change)) cap_damping *= 0.5;
      last_cap_change = e[2];
    }
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
