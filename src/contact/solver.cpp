#include "gfmd/contact/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>

#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"

namespace gfmd {

namespace {
using Clock = std::chrono::steady_clock;
// Stick-slip (Douglas-Rachford) iteration of the exact law, chosen by measurement (see
// docs/solver.md): step gamma = 1/rho(A), over-relaxation 1.6, no Anderson mixing (it saved
// iterations but not time, and holds 20 single-precision fields); each stick-slip solve
// within a friction step stops at 1e-3 of the friction change.
constexpr double kStickStepFactor = 1.0;
constexpr double kTangentialRelaxation = 1.6;
constexpr double kTangentialTolFactor = 1e-3;

void require_finite(double v, const char* what, int it) {
  if (!std::isfinite(v)) {
    std::ostringstream os;
    os << "solve diverged: " << what << " is not finite at iteration " << it;
    throw SolveError(os.str());
  }
}
// Solves the small (regularised) normal equations of the Anderson least-squares problem.
std::vector<double> solve_small_spd(std::vector<double> M, std::vector<double> rhs) {
  const std::size_t h = rhs.size();
  double trace = 0;
  for (std::size_t a = 0; a < h; ++a) trace += M[a * h + a];
  for (std::size_t a = 0; a < h; ++a) M[a * h + a] += 1e-10 * trace + 1e-300;
  for (std::size_t c = 0; c < h; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < h; ++r)
      if (std::abs(M[r * h + c]) > std::abs(M[piv * h + c])) piv = r;
    if (piv != c) {
      for (std::size_t k = 0; k < h; ++k) std::swap(M[c * h + k], M[piv * h + k]);
      std::swap(rhs[c], rhs[piv]);
    }
    for (std::size_t r = c + 1; r < h; ++r) {
      const double fct = M[r * h + c] / M[c * h + c];
      for (std::size_t k = c; k < h; ++k) M[r * h + k] -= fct * M[c * h + k];
      rhs[r] -= fct * rhs[c];
    }
  }
  std::vector<double> x(h);
  for (std::size_t c = h; c-- > 0;) {
    double v = rhs[c];
    for (std::size_t k = c + 1; k < h; ++k) v -= M[c * h + k] * x[k];
    x[c] = v / M[c * h + c];
  }
  return x;
}
// A point joins the Anderson support of the friction iteration when it is not in it yet
// and the iterate (fx, fy) or its image (x, y) is non-zero there.
bool joins_support(unsigned char in_supp, double x, double y, double fx, double fy) {
  return !in_supp && (x != 0.0 || y != 0.0 || fx != 0.0 || fy != 0.0);
}

// Sums of a friction step at a point with new traction (x, y) and previous (fx, fy): the
// change |new - old|_1, the size |new|_1, and whether the point joins the Anderson support.
void add_change(std::array<double, 3>& acc, unsigned char in_supp, double x, double y, double fx, double fy) {
  acc[0] += std::abs(x - fx) + std::abs(y - fy);
  acc[1] += std::abs(x) + std::abs(y);
  if (joins_support(in_supp, x, y, fx, fy)) acc[2] += 1.0;
}

}  // namespace

std::string friction_history_evidence(const std::vector<double>& change, const std::vector<double>& force) {
  const std::size_t n = std::min(change.size(), force.size());
  const std::size_t w = std::min<std::size_t>(n, 60);
  if (w < 8) return "too few friction steps to tell a limit cycle";
  const std::size_t s = n - w;  // the last w steps
  double fmin = force[s], fmax = force[s], fmean = 0, cmin = change[s], cmax = change[s];
  for (std::size_t t = s; t < n; ++t) {
    fmin = std::min(fmin, force[t]);
    fmax = std::max(fmax, force[t]);
    fmean += force[t] / static_cast<double>(w);
    cmin = std::min(cmin, change[t]);
    cmax = std::max(cmax, change[t]);
  }
  const double range = fmax - fmin;
  char buf[320];
  // The period whose shifted copy matches the force history best (mean mismatch relative to
  // the range), tried up to a third of the window so that at least three periods are seen.
  std::size_t best_p = 0;
  double best_d = std::numeric_limits<double>::infinity();
  if (range > 0)
    for (std::size_t p = 1; p <= w / 3; ++p) {
      double d = 0;
      for (std::size_t t = s + p; t < n; ++t) d += std::abs(force[t] - force[t - p]);
      d /= static_cast<double>(w - p) * range;
      if (d < best_d - 1e-12) {
        best_d = d;
        best_p = p;
      }
    }
  const double rel = std::abs(fmean) > 0 ? 0.5 * range / std::abs(fmean) : 0.5 * range;
  if (best_p >= 2 && best_d < 0.1) {
    std::snprintf(buf, sizeof buf,
                  "a limit cycle over the last %zu friction steps: period %zu steps, tangential force "
                  "oscillating by +-%.2e (relative), traction change per step %.2e to %.2e",
                  w, best_p, rel, cmin, cmax);
  } else if (best_p == 1 && best_d < 0.1) {
    std::snprintf(buf, sizeof buf,
                  "no limit cycle: over the last %zu friction steps the tangential force drifts slowly "
                  "(range %.2e relative), traction change per step %.2e to %.2e: give it more steps",
                  w, 2 * rel, cmin, cmax);
  } else {
    std::snprintf(buf, sizeof buf,
                  "no periodic pattern over the last %zu friction steps: tangential force varies by +-%.2e "
                  "(relative), traction change per step %.2e to %.2e",
                  w, rel, cmin, cmax);
  }
  return buf;
}

ContactSolver::ContactSolver(const ElasticBody& body, const Topography& topo, const InteractionParams& inter,
                             const FrictionParams& fric, const SolverParams& solver)
    : body_(body),
      grid_(body.grid()),
      fft_(body.grid(), solver.fft_planner),
      inter_(inter),
      fric_(fric),
      sp_(solver),
      g0_(body.grid().size()) {
  if (topo.grid.nx != grid_.nx || topo.grid.ny != grid_.ny)
    throw InputError("indenter", "topography grid does not match the elastic grid");
  if (inter_.hard_wall) {
    k_ = std::numeric_limits<double>::infinity();
    inv_k_ = 0.0;
  } else {
    k_ = inter_.stiffness > 0 ? inter_.stiffness : 2.0 * body.params().contact_modulus / grid_.dx();
    inv_k_ = 1.0 / k_;
  }
  double hmax = -std::numeric_limits<double>::infinity();
  for (double v : topo.h) hmax = std::max(hmax, v);
  for (std::size_t i = 0; i < g0_.size(); ++i) g0_[i] = hmax - topo.h[i];
  double m = 0, m2 = 0;
  for (double v : g0_) {
    m += v;
    m2 += v * v;
  }
  m /= static_cast<double>(g0_.size());
  g0_rms_ = std::sqrt(std::max(0.0, m2 / static_cast<double>(g0_.size()) - m * m));
  for (auto* s : {&s1_, &s2_, &s3_}) s->resize(grid_.spectral_size());
  for (auto* f : {&cg_g_, &cg_t_, &cg_r_}) f->assign(grid_.size(), 0.0);
  czz_n_.resize(body.modes().size());
  for (std::size_t k = 0; k < czz_n_.size(); ++k)
    czz_n_[k] = body.modes()[k].czz / static_cast<double>(grid_.size());
  // Step of the stick-slip iteration (exact law with friction only).
  if (fric_.coefficient > 0 && !fric_.regularized())
    gamma_ = fric_.stick_step > 0 ? fric_.stick_step * body.params().contact_modulus : default_stick_step();
}

void ContactSolver::apply_compliance(const RealField& in, RealField& out, double scale) {
  // out = scale C_zz in (the 1/k term is added by the callers in their fused passes). One
  // spectral pass with the contiguous table C_zz / N, then the inverse transform in place.
  fft_.forward(in.data(), s1_.data());
  const std::ptrdiff_t ns = static_cast<std::ptrdiff_t>(czz_n_.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < ns; ++k) s1_[k] *= scale * czz_n_[k];  // exact for scale = 1
  fft_.backward_unscaled_destroying(s1_.data(), out.data());
}

ContactSolver::PKResult ContactSolver::solve_normal(const LoadParams& load, const RealField& w, bool w_zero,
                                                    RealField& p, double tol, int max_it) {
  // Constrained conjugate gradients (Polonsky & Keer 1999) on (C_zz + 1/k) p = overlap.
  // Per iteration: two compliance products (2 forward + 2 inverse FFTs) and four fused
  // pointwise passes (A, C, D, E below; 17 reads and writes of 8 bytes per point, 16 when
  // w = 0); the work arrays are members (no allocation here).
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(grid_.size());
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
    for (std::ptrdiff_t i = 0; i < n; ++i) p[i] = kk * std::max(0.0, delta_imp + w[i] - g0_[i]);
  }

  RealField& g = cg_g_;
  RealField& t = cg_t_;
  RealField& r = cg_r_;  // C t
  bool conjugate = false;
  double gold = 1.0;
  const auto apply_pending = [&] {
    if (pending == 1.0) return;
    const double f = pending;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) p[i] *= f;
    pending = 1.0;
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
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) p[i] = std::max(0.0, -g[i]) * (ik > 0 ? k_ : 1.0);
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
    // A checkpoint or an interruption sees the rescaled pressure (std::ref: the std::function
    // holds a reference, no allocation per step).
    poll(current_, std::ref(apply_pending));
  }
  apply_pending();
  return res;
}

void ContactSolver::update_displacements(ContactFields& f) {
  // Tractions on the body: (tau_x, tau_y, -p), the sign of -p applied to its spectrum; the
  // displacement spectra replace the traction spectra in place (1/N folded in) and are
  // synthesised destructively.
  const double scale = 1.0 / static_cast<double>(grid_.size());
  fft_.forward(f.pressure.data(), s1_.data());
  fft_.forward(f.tx.data(), s2_.data());
  fft_.forward(f.ty.data(), s3_.data());
  body_.displacement(s2_.data(), s3_.data(), s1_.data(), s2_.data(), s3_.data(), s1_.data(), scale, -scale);
  fft_.backward_unscaled_destroying(s2_.data(), f.ux.data());
  fft_.backward_unscaled_destroying(s3_.data(), f.uy.data());
  fft_.backward_unscaled_destroying(s1_.data(), f.uz.data());
}

std::array<double, 3> ContactSolver::slip_tractions(const ContactFields& f, RealField& tx, RealField& ty,
                                                    const std::vector<unsigned char>& in_supp) {
  // Requires s2_/s3_ to hold the spectra of tau_x/tau_y (friction_normal_displacement).
  // One forward FFT (of p; t_z = -p), the slopes (e.grad) u of the in-plane displacement in
  // one spectral pass, two inverse FFTs; leaves (e.grad) u in r1_/r2_.
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const double scale = 1.0 / static_cast<double>(grid_.size());
  fft_.forward(f.pressure.data(), s1_.data());
  body_.inplane_slope(s2_.data(), s3_.data(), s1_.data(), ex, ey, s1_.data(), s2_.data(), scale, -scale);
  fft_.backward_unscaled_destroying(s1_.data(), r1_.data());
  fft_.backward_unscaled_destroying(s2_.data(), r2_.data());
  const double mu = fric_.coefficient;
  const double eps = fric_.regularization;  // tau = mu p v / max(|v|, eps)
  const double xi = fric_.creepage;
  // Outside the contact set the new traction is zero; outside the Anderson support the
  // traction and its previous image are zero too (see solve), so nothing there is read.
  return grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
    const double p = f.pressure[i];
    if (p > 0) {
      const double vx = xi * ex + r1_[i], vy = xi * ey + r2_[i];
      const double norm = std::max(std::sqrt(vx * vx + vy * vy), eps);  // |v| = O(1): no hypot needed
      double x = 0.0, y = 0.0;
      if (norm > 0) {
        x = mu * p * vx / norm;
        y = mu * p * vy / norm;
      }
      tx[i] = x;
      ty[i] = y;
      add_change(acc, in_supp[i], x, y, f.tx[i], f.ty[i]);
    } else if (in_supp[i]) {
      tx[i] = 0.0;
      ty[i] = 0.0;
      acc[0] += std::abs(f.tx[i]) + std::abs(f.ty[i]);
    }
  });
}

double ContactSolver::default_stick_step() const {
  // gamma = c / rho(A): the scale on which the slip operator acts.
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double rho = body_.slip_operator_norm(std::cos(th), std::sin(th));
  return rho > 0 ? kStickStepFactor / rho : body_.params().contact_modulus;
}

ContactSolver::TangentialResult ContactSolver::solve_tangential(const RealField& p, RealField& tx,
                                                                RealField& ty, double tol, int max_it) {
  // Douglas-Rachford on 0 in -v(tau) + N_K(tau), v(tau) = b + A tau with b = xi e_s + b' (b'
  // the slip the pressure causes through the coupling) and A = (e_s.grad) C_tt skew:
  //   tau = P_K(z);  y = (I - gamma A)^-1 (2 tau - z + gamma b);  z <- z + y - tau.
  // At a fixed point y = tau and z = tau + gamma v(tau), the projection form of Coulomb's
  // law: tau = mu_c p v/|v| where the point slips, |tau| <= mu_c p where v = 0 (stick).
  // Per step: 2 forward and 2 inverse FFTs and two fused passes over the grid.
  const std::size_t n = grid_.size();
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const double xi = fric_.creepage;
  const double mu = fric_.coefficient;
  const double gamma = gamma_;
  const double scale = 1.0 / static_cast<double>(n);
  RealField& yx = r1_;
  RealField& yy = r2_;
  // b': slip velocity caused by the pressure (zero without coupling), times gamma.
  for (auto* fld : {&bx_, &by_, &zx_, &zy_})
    if (fld->size() != n) fld->assign(n, 0.0);
  fft_.forward(p.data(), s1_.data());
  body_.inplane_slope(nullptr, nullptr, s1_.data(), ex, ey, s2_.data(), s3_.data(), scale, -scale * gamma);
  fft_.backward_unscaled_destroying(s2_.data(), bx_.data());
  fft_.backward_unscaled_destroying(s3_.data(), by_.data());
  if (!have_z_) {
    // z = tau + gamma v(tau) for the traction we start from.
    fft_.forward(tx.data(), s2_.data());
    fft_.forward(ty.data(), s3_.data());
    body_.inplane_slope(s2_.data(), s3_.data(), nullptr, ex, ey, s2_.data(), s3_.data(), scale * gamma, 0.0);
    fft_.backward_unscaled_destroying(s2_.data(), yx.data());
    fft_.backward_unscaled_destroying(s3_.data(), yy.data());
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      zx_[i] = tx[i] + gamma * xi * ex + bx_[i] + yx[i];
      zy_[i] = ty[i] + gamma * xi * ey + by_[i] + yy[i];
    }
    have_z_ = true;
  }
  // Projection onto the disc of radius mu_c p.
  const auto project = [&](std::size_t i, double zx, double zy, double& x, double& y) {
    const double r = mu * p[i];
    if (!(r > 0)) {
      x = y = 0.0;
      return;
    }
    const double m2 = zx * zx + zy * zy;
    if (m2 <= r * r) {
      x = zx;
      y = zy;
    } else {
      const double f = r / std::sqrt(m2);
      x = f * zx;
      y = f * zy;
    }
  };
  // tau = P_K(z); with `rhs` also y <- 2 tau - z + gamma b' (the resolvent's argument).
  const auto project_pass = [&](bool rhs) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      double x, y;
      project(i, zx_[i], zy_[i], x, y);
      tx[i] = x;
      ty[i] = y;
      if (rhs) {
        yx[i] = 2.0 * x - zx_[i] + bx_[i];
        yy[i] = 2.0 * y - zy_[i] + by_[i];
      }
    }
  };
  TangentialResult res{0, 1.0, false};
  const double cx = gamma * xi * ex, cy = gamma * xi * ey;
  const double beta = kTangentialRelaxation;
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    project_pass(true);
    fft_.forward(yx.data(), s2_.data());
    fft_.forward(yy.data(), s3_.data());
    body_.slip_resolvent(s2_.data(), s3_.data(), ex, ey, gamma, scale);
    s2_[0] += cx;  // the rigid slip gamma xi e_s: the q = 0 mode, where the resolvent is 1
    s3_[0] += cy;
    fft_.backward_unscaled_destroying(s2_.data(), yx.data());
    fft_.backward_unscaled_destroying(s3_.data(), yy.data());
    // The change |y - tau| and the size |tau| (L1); the relaxed step z <- z + beta (y - tau).
    const auto sums = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      const double dx = yx[i] - tx[i], dy = yy[i] - ty[i];
      acc[0] += std::abs(dx) + std::abs(dy);
      acc[1] += std::abs(tx[i]) + std::abs(ty[i]);
      zx_[i] += beta * dx;
      zy_[i] += beta * dy;
    });
    res.error = sums[1] > 0 ? sums[0] / sums[1] : (sums[0] > 0 ? 1.0 : 0.0);
    require_finite(res.error, "the stick-slip traction", total_it_);
    if (res.error < tol) {
      res.converged = true;
      break;
    }
    if (res.iterations % 64 == 0) poll(nullptr);
  }
  project_pass(false);  // tau = P_K(z) for the final z
  return res;
}

void ContactSolver::friction_normal_displacement(const RealField& tx, const RealField& ty, RealField& w) {
  fft_.forward(tx.data(), s2_.data());
  fft_.forward(ty.data(), s3_.data());
  body_.displacement(s2_.data(), s3_.data(), nullptr, nullptr, nullptr, s1_.data(),
                     1.0 / static_cast<double>(grid_.size()));
  fft_.backward_unscaled_destroying(s1_.data(), w.data());
}

double ContactSolver::residual(const ContactFields& f, double delta) {
  // Independent check of the final state: gap from the full 3D displacement.
  const auto gap = [&](std::size_t i) { return g0_[i] - delta - f.uz[i]; };
  if (!inter_.hard_wall) {
    const double num = grid_sum(grid_, [&](std::size_t i) {
      const double d = f.pressure[i] - k_ * std::max(0.0, -gap(i));
      return d * d;
    });
    const double den = grid_sum(grid_, [&](std::size_t i) { return f.pressure[i] * f.pressure[i]; });
    return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
  const double num = grid_sum(grid_, [&](std::size_t i) {
    const double g = gap(i);
    if (f.pressure[i] > 0) return g * g;
    return g < 0 ? g * g : 0.0;
  });
  const double mean =
      grid_sum(grid_, [&](std::size_t i) { return g0_[i]; }) / static_cast<double>(grid_.size());
  const double den = grid_sum(grid_, [&](std::size_t i) { return (g0_[i] - mean) * (g0_[i] - mean); });
  return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
}

void ContactSolver::poll(const ContactFields* f, const std::function<void()>& settle) {
  const bool stop = stop_ && stop_();
  bool save = false;
  double now = 0.0;
  if (checkpoint_ && f) {
    now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    save = now - last_checkpoint_ >= checkpoint_interval_s_;
  }
  if ((stop || save) && settle) settle();
  if (stop) throw Interrupted("interrupted at iteration " + std::to_string(total_it_));
  if (save) {
    last_checkpoint_ = now;
    checkpoint_(*f);
  }
}

SolveInfo ContactSolver::solve(const LoadParams& load, ContactFields& f) {
  const auto t0 = Clock::now();
  const std::uint64_t transforms0 = fft_.transforms();
  const double fft_seconds0 = fft_.seconds();
  current_ = &f;
  last_checkpoint_ = std::chrono::duration<double>(t0.time_since_epoch()).count();
  const std::size_t n = grid_.size();
  for (auto* fld : {&f.pressure, &f.tx, &f.ty})
    if (fld->size() != n) fld->assign(n, 0.0);
  // The displacements and the gap follow from (p, tau) at the end: their memory is given
  // back during the iterations.
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) RealField().swap(*fld);
  f.stick.clear();
  total_it_ = 0;
  SolveInfo info;
  info.stiffness = k_;
  const double tol = sp_.tolerance;
  const double mu = fric_.coefficient;
  RealField w(n, 0.0);
  PKResult pk{};
  if (mu == 0.0) {
    std::fill(f.tx.begin(), f.tx.end(), 0.0);
    std::fill(f.ty.begin(), f.ty.end(), 0.0);
    pk = solve_normal(load, w, true, f.pressure, tol, sp_.max_iterations);
    info.converged = pk.converged;
    info.status = pk.converged ? "converged" : "not converged: iteration limit reached";
  } else {
    // Friction fixed point on the traction tau = (tau_x, tau_y): G(tau) = mu_c p s(u), with
    // p the normal solution for w = C_z.tau and u the displacement of (tau, -p). The plain
    // map contracts slowly where mu_c p/E* is large (the transverse slip feeds back on
    // itself through the in-plane compliance) and on thin, nearly incompressible layers,
    // so it is accelerated by Anderson mixing over the last `anderson` steps.
    RealField tx(n), ty(n);
    // Anderson state, kept on the support of the traction only: the points where the
    // iterate or its image has been non-zero since the solve began (the contact set and
    // the points that left it; elsewhere every difference is exactly zero). supp lists them in
    // order of entry; per support point the previous iterate and residual (double) and
    // the ring buffers of their differences (float) hold two interleaved components.
    std::vector<std::uint32_t> supp;
    // Zero-extends v to len with 25 % headroom (the support grows in small steps; the
    // default doubling would hold up to twice the memory).
    const auto grow = [](auto& v, std::size_t len) {
      if (v.capacity() < len) v.reserve(len + len / 4);
      v.resize(len, 0);
    };
    std::vector<unsigned char> in_supp(n, 0);
    std::vector<double> xprev, fprev;
    // A warm start's traction starts the support (the slip pass reads nothing outside it).
    for (std::size_t i = 0; i < n; ++i)
      if (f.tx[i] != 0.0 || f.ty[i] != 0.0) {
        in_supp[i] = 1;
        supp.push_back(static_cast<std::uint32_t>(i));
      }
    grow(xprev, 2 * supp.size());
    grow(fprev, 2 * supp.size());
    const int m = std::max(0, sp_.anderson);
    and_df_.assign(static_cast<std::size_t>(m), {});
    and_dx_.assign(static_cast<std::size_t>(m), {});
    std::vector<double> gram(static_cast<std::size_t>(m) * m, 0.0);
    std::vector<int> slots;  // ring slots in use, oldest first
    bool have_prev = false;
    double err = 1.0, best = std::numeric_limits<double>::infinity();
    int since_best = 0;
    // Per friction step: the traction change and the tangential force (sum of tau_x and of
    // tau_y), the evidence a failure message gives (friction_history_evidence).
    std::vector<double> hist_change, hist_force;
    const double dir_x = std::cos(fric_.direction_deg * std::numbers::pi / 180.0),
                 dir_y = std::sin(fric_.direction_deg * std::numbers::pi / 180.0);
    bool have_slip = false;  // r1_/r2_ hold (e.grad) u of this solve
    // The exact law starts with the full-slip map tau = mu_c p v/|v| (fast, and its fixed
    // point, where every contact point slips, solves the set-valued law too). Where it does
    // not settle (points near stick) or with creepage (rolling: stick is expected), the
    // stick-slip solve takes over from the current traction.
    bool stick_mode = !fric_.regularized() && fric_.creepage != 1.0;
    bool tangential_ok = !stick_mode;  // the last stick-slip solve met the final tolerance
    have_z_ = false;
    double omega = sp_.mixing;
    // Stall test: the best change must improve by 10 % within 20 steps. Slow but steady
    // progress (stiff slip feedback near stick) is not a stall; a limit cycle is.
    constexpr double stall_gain = 0.9;
    constexpr int stall_steps = 20;
    info.status = "not converged: friction fixed point did not settle";
    for (int outer = 0; outer < sp_.max_outer; ++outer) {
      info.outer_iterations = outer + 1;
      friction_normal_displacement(f.tx, f.ty, w);
      const double inner_tol = std::max(tol, std::min(1e-3, 0.1 * err));
      const int budget = sp_.max_iterations - total_it_;
      if (budget <= 0) {
        info.status = "not converged: iteration limit reached";
        break;
      }
      pk = solve_normal(load, w, false, f.pressure, inner_tol, budget);
      // One friction step costs 3 forward + 3 inverse FFTs: tau_x, tau_y and p forward,
      // w and the two slip derivatives back.
      // dn[2]: points outside the Anderson support where the iterate or its image is
      // non-zero (they join the support below).
      std::array<double, 3> dn{};
      if (!stick_mode) {
        dn = slip_tractions(f, tx, ty, in_supp);
        have_slip = true;
      } else {
        if (!have_z_) {
          tx = f.tx;
          ty = f.ty;
        }
        const double ttol = std::max(0.1 * tol, std::min(1e-3, kTangentialTolFactor * err));
        const auto tr = solve_tangential(f.pressure, tx, ty, ttol, sp_.max_tangential);
        info.tangential_iterations += tr.iterations;
        tangential_ok = tr.converged && ttol <= 0.1 * tol;
        dn = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
          add_change(acc, in_supp[i], tx[i], ty[i], f.tx[i], f.ty[i]);
        });
      }
      err = dn[1] > 0 ? dn[0] / dn[1] : 0.0;
      require_finite(err, "the friction traction", total_it_);
      info.friction_error = err;
      hist_change.push_back(err);
      hist_force.push_back(grid_sum(grid_, [&](std::size_t i) { return dir_x * tx[i] + dir_y * ty[i]; }));
      if (progress_) progress_(Progress{total_it_, outer + 1, err});
      poll(&f);
      if (err < tol && pk.converged && inner_tol <= tol && tangential_ok) {
        f.tx.swap(tx);
        f.ty.swap(ty);
        info.converged = true;
        info.status = "converged";
        break;
      }
      if (err < stall_gain * best) {
        best = err;
        since_best = 0;
      } else if (++since_best >= stall_steps && !fric_.regularized() && !stick_mode) {
        // The full-slip map does not settle: continue with the set-valued law (stick) from
        // the current traction, with a fresh mixing history.
        stick_mode = true;
        tangential_ok = false;
        slots.clear();
        have_prev = false;
        since_best = 0;
        best = std::numeric_limits<double>::infinity();
        continue;
      } else if (since_best >= stall_steps) {
        // Stalled: damp harder and restart the mixing history; give up once damping
        // no longer helps (a limit cycle of the slip field).
        omega *= 0.5;
        slots.clear();
        since_best = 0;
        best = err;
        if (omega < 0.04) {
          f.tx.swap(tx);
          f.ty.swap(ty);
          info.status = "not converged: oscillating (friction fixed point does not settle even with damping)";
          break;
        }
      }
      if (dn[2] > 0) {
        // New support points (in grid order, so the layout does not depend on threads):
        // their previous iterate, residual and all stored differences are zero.
        for (std::size_t i = 0; i < n; ++i)
          if (joins_support(in_supp[i], tx[i], ty[i], f.tx[i], f.ty[i])) {
            in_supp[i] = 1;
            supp.push_back(static_cast<std::uint32_t>(i));
          }
        const std::size_t len = 2 * supp.size();
        grow(xprev, len);
        grow(fprev, len);
        for (int sl : slots) {
          grow(and_df_[static_cast<std::size_t>(sl)], len);
          grow(and_dx_[static_cast<std::size_t>(sl)], len);
        }
      }
      // The exact law's splitting variable follows the mixed traction: z <- z + (tau_mixed -
      // tau), so the next stick-slip solve starts from the mixed iterate (z - tau = gamma v
      // is kept).
      const auto follow = [&] {
        if (!stick_mode) return;
        for (const std::uint32_t i : supp) {
          zx_[i] += f.tx[i] - tx[i];
          zy_[i] += f.ty[i] - ty[i];
        }
      };
      if (m == 0) {
        // Plain relaxation; outside the support both tractions are zero.
        for (const std::uint32_t i : supp) {
          f.tx[i] += omega * (tx[i] - f.tx[i]);
          f.ty[i] += omega * (ty[i] - f.ty[i]);
        }
        follow();
        continue;
      }
      // Anderson mixing with relaxation (Walker & Ni 2011): with x the traction, f = G(x) - x,
      // gamma = argmin |f - dF gamma|, x <- x - dX gamma + omega (f - dF gamma).
      // omega < 1 damps the rotating (imaginary-eigenvalue) modes of the slip feedback.
      // One pass stores the new differences and forms the new Gram row and dF^T f.
      const std::size_t ns = supp.size();
      std::vector<double> rhs;
      if (!have_prev) {
#pragma omp parallel for schedule(static)
        for (std::size_t j = 0; j < ns; ++j) {
          const std::size_t i = supp[j];
          xprev[2 * j] = f.tx[i];
          xprev[2 * j + 1] = f.ty[i];
          fprev[2 * j] = tx[i] - f.tx[i];
          fprev[2 * j + 1] = ty[i] - f.ty[i];
        }
        have_prev = true;
      } else {
        int slot = 0;
        if (static_cast<int>(slots.size()) == m) {
          slot = slots.front();
          slots.erase(slots.begin());
        } else {
          std::vector<bool> used(static_cast<std::size_t>(m), false);
          for (int sl : slots) used[static_cast<std::size_t>(sl)] = true;
          while (used[static_cast<std::size_t>(slot)]) ++slot;
        }
        slots.push_back(slot);
        auto& dfs = and_df_[static_cast<std::size_t>(slot)];
        auto& dxs = and_dx_[static_cast<std::size_t>(slot)];
        grow(dfs, 2 * ns);
        grow(dxs, 2 * ns);
        const std::size_t h = slots.size();
        std::vector<const float*> hist(h);
        for (std::size_t r = 0; r < h; ++r) hist[r] = and_df_[static_cast<std::size_t>(slots[r])].data();
        // Over both components of every support point: acc[0..h-1] = <dF_r, dF_new>,
        // acc[h..2h-1] = <dF_r, f>.
        const auto sums = range_sums(2 * ns, 2 * h, [&](std::size_t e, double* acc) {
          const std::size_t i = supp[e / 2];
          const double xi = (e % 2 == 0) ? f.tx[i] : f.ty[i];
          const double fi = ((e % 2 == 0) ? tx[i] : ty[i]) - xi;
          const float dfi = static_cast<float>(fi - fprev[e]);
          dfs[e] = dfi;
          dxs[e] = static_cast<float>(xi - xprev[e]);
          xprev[e] = xi;
          fprev[e] = fi;
          for (std::size_t r = 0; r < h; ++r) {
            const double hr = hist[r][e];
            acc[r] += hr * static_cast<double>(dfi);
            acc[h + r] += hr * fi;
          }
        });
        for (std::size_t r = 0; r < h; ++r) {
          const auto a = static_cast<std::size_t>(slots[r]), b = static_cast<std::size_t>(slot);
          gram[a * m + b] = gram[b * m + a] = sums[r];
        }
        rhs.assign(sums.begin() + static_cast<std::ptrdiff_t>(h), sums.end());
      }
      const std::size_t h = rhs.size();
      std::vector<double> gamma;
      if (h > 0) {
        std::vector<double> M(h * h);
        for (std::size_t r = 0; r < h; ++r)
          for (std::size_t c = 0; c < h; ++c)
            M[r * h + c] = gram[static_cast<std::size_t>(slots[r]) * m + static_cast<std::size_t>(slots[c])];
        gamma = solve_small_spd(M, rhs);
      }
      std::vector<const float*> hf(h), hx(h);
      for (std::size_t r = 0; r < h; ++r) {
        hf[r] = and_df_[static_cast<std::size_t>(slots[r])].data();
        hx[r] = and_dx_[static_cast<std::size_t>(slots[r])].data();
      }
      // Outside the support the iterate and its image are zero, and so is the update.
      const std::ptrdiff_t nsp = static_cast<std::ptrdiff_t>(ns);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t j = 0; j < nsp; ++j) {
        const std::size_t ex = 2 * static_cast<std::size_t>(j), ey = ex + 1;
        double xx = xprev[ex], xy = xprev[ey], fx = fprev[ex], fy = fprev[ey];
        for (std::size_t r = 0; r < h; ++r) {
          xx -= gamma[r] * hx[r][ex];
          xy -= gamma[r] * hx[r][ey];
          fx -= gamma[r] * hf[r][ex];
          fy -= gamma[r] * hf[r][ey];
        }
        const std::size_t i = supp[static_cast<std::size_t>(j)];
        f.tx[i] = xx + omega * fx;
        f.ty[i] = xy + omega * fy;
      }
      follow();
    }
    and_df_.clear();
    and_dx_.clear();
    if (!info.converged && info.status.rfind("not converged: iteration limit", 0) != 0)
      info.status += "; " + friction_history_evidence(hist_change, hist_force);
    if (!info.converged && have_slip && fric_.regularized()) {
      // Near stick the slip direction of the exact Coulomb law is ill-conditioned (the
      // usual cause of a friction fixed point that does not settle): say so. r1_/r2_ hold
      // the last (e.grad) u.
      const double th = fric_.direction_deg * std::numbers::pi / 180.0;
      const double ex = std::cos(th), ey = std::sin(th);
      constexpr double slow = 0.1;
      std::size_t nslow = 0;
      double vmin = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < n; ++i)
        if (f.pressure[i] > 0) {
          const double v = std::hypot(ex + r1_[i], ey + r2_[i]);
          vmin = std::min(vmin, v);
          if (v < slow) ++nslow;
        }
      if (nslow > 0 && fric_.regularization < slow) {
        std::ostringstream os;
        os << info.status << "; " << nslow << " contact points slip slower than " << slow << " v0 (minimum "
           << vmin
           << " v0): near stick the friction step converges slowly; raise solver.max_outer or "
              "solver.max_tangential, or set friction.stick_step";
        info.status = os.str();
      }
    }
    if (!fric_.regularized()) f.stick.assign(n, 0);
    if (stick_mode && have_z_) {
      // Stick: the splitting variable inside the friction disc (there z = tau, v = 0).
      std::size_t ns = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const double r = mu * f.pressure[i];
        if (r > 0 && zx_[i] * zx_[i] + zy_[i] * zy_[i] < r * r) {
          f.stick[i] = 1;
          ++ns;
        }
      }
      info.stick_points = ns;
    }
    if (!pk.converged && info.converged) {
      info.converged = false;
      info.status = "not converged: iteration limit reached";
    }
  }
  info.iterations = total_it_;
  info.pk_error = pk.error;
  info.approach = pk.delta;
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) fld->resize(n);
  update_displacements(f);
  for (std::size_t i = 0; i < n; ++i) f.gap[i] = std::max(0.0, g0_[i] - pk.delta - f.uz[i]);
  info.residual = residual(f, pk.delta);
  require_finite(info.residual, "the final residual", total_it_);
  // The stopping tests watch changes between iterates; only a state that also satisfies the
  // contact conditions within the stated bound counts as a solution.
  info.residual_bound = std::max(1e-5, 1e3 * sp_.tolerance);
  if (info.converged && !(info.residual <= info.residual_bound)) {
    info.converged = false;
    char why[160];
    std::snprintf(why, sizeof why, "not converged: the independent residual %.3g exceeds its bound %.3g",
                  info.residual, info.residual_bound);
    info.status = why;
  }
  info.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  info.transforms = fft_.transforms() - transforms0;
  info.fft_seconds = fft_.seconds() - fft_seconds0;
  return info;
}

}  // namespace gfmd
