// Coulomb's law in the friction fixed point: slip tractions (full slip, regularised) and
// the set-valued law with stick solved by Douglas-Rachford splitting (docs/solver.md).
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

std::string friction_history_evidence(const std::vector<double>& change, const std::vector<double>& force,
                                      bool damped_out) {
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
  char buf[512];
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
  } else if (best_p == 1 && best_d < 0.1 && !damped_out) {
    std::snprintf(buf, sizeof buf,
                  "no limit cycle: over the last %zu friction steps the tangential force drifts slowly "
                  "(range %.2e relative), traction change per step %.2e to %.2e: give it more steps "
                  "(solver.max_outer)",
                  w, 2 * rel, cmin, cmax);
  } else if (best_p == 1 && best_d < 0.1) {
    // The loop gave up because the change stopped falling (damped_mixing), not for want of
    // steps: more steps would not lower it. Where that floor is small, the least change of
    // these steps rounded up to one digit is a tolerance that accepts the state; a floor
    // above 1e-5 is no state to accept.
    const auto first_best = std::min_element(change.begin(), change.begin() + static_cast<std::ptrdiff_t>(n));
    const double scale = cmin > 0 ? std::pow(10.0, std::floor(std::log10(cmin))) : 0.0;
    const double accept = scale > 0 ? std::ceil(cmin / scale * (1.0 - 1e-12)) * scale : 0.0;
    char advice[96] = "";
    if (accept > 0 && accept <= 1e-5)
      std::snprintf(advice, sizeof advice, "; solver.tolerance = %.0e would accept it", accept);
    std::snprintf(buf, sizeof buf,
                  "no limit cycle: over the last %zu friction steps the tangential force drifts slowly "
                  "(range %.2e relative) while the traction change per step stays at %.2e to %.2e, its "
                  "least over the solve %.2e (friction step %td): the change has a floor that more "
                  "steps do not lower%s",
                  w, 2 * rel, cmin, cmax, *first_best, first_best - change.begin() + 1, advice);
  } else {
    std::snprintf(buf, sizeof buf,
                  "no periodic pattern over the last %zu friction steps: tangential force varies by +-%.2e "
                  "(relative), traction change per step %.2e to %.2e",
                  w, rel, cmin, cmax);
  }
  return buf;
}

std::array<double, 4> ContactSolver::slip_tractions(const ContactFields& f, RealField& tx, RealField& ty,
                                                    const std::vector<unsigned char>& in_supp) {
  // Requires s2_/s3_ to hold the spectra of tau_x/tau_y (friction_normal_displacement).
  // One forward FFT (of p; t_z = -p), the slopes (e.grad) u of the in-plane displacement in
  // one spectral pass, two inverse FFTs; leaves (e.grad) u in r1_/r2_.
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const double scale = 1.0 / static_cast<double>(grid_.size());
  fft_.forward(f.pressure.data(), s1_.data());
  const SlipDerivative deriv = deriv_;
  body_.inplane_slope(s2_.data(), s3_.data(), s1_.data(), ex, ey, s1_.data(), s2_.data(), scale, -scale,
                      deriv, slip_symbols());
  fft_.backward_unscaled_destroying(s1_.data(), r1_.data());
  fft_.backward_unscaled_destroying(s2_.data(), r2_.data());
  const double mu = fric_.coefficient;
  const double eps = fric_.regularization;  // tau = mu(|v|) p v / max(|v|, eps)
  const FrictionLaw law = fric_.law;        // |tau| = mu p for Coulomb's law
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];  // plain names: lambdas may capture them
  // Outside the contact set the new traction is zero; outside the Anderson support the
  // traction and its previous image are zero too (see solve), so nothing there is read.
  constexpr double slow2 = kNearStickSpeed * kNearStickSpeed;
  // The law reads the repulsion (with adhesion the net pressure plus the adhesive traction: the
  // compressive part; else the pressure itself); the coupling above, the net pressure.
  return grid_sums<4>(grid_, [&](std::size_t i, std::array<double, 4>& acc) {
    const double p = f.repulsion(i);
    if (p > 0) {
      const double vx = rx + r1_[i], vy = ry + r2_[i];
      const double v2 = vx * vx + vy * vy;
      if (v2 < slow2) acc[3] += 1.0;
      const double speed = std::sqrt(v2);  // |v| = O(1): no hypot needed
      const double norm = std::max(speed, eps);
      const double t = law.bound(mu, p, speed);  // mu p for Coulomb's law
      double x = 0.0, y = 0.0;
      if (norm > 0) {
        x = t * vx / norm;
        y = t * vy / norm;
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

double ContactSolver::stick_step(SlipDerivative deriv) const {
  if (fric_.stick_step > 0) return fric_.stick_step * body_.params().contact_modulus;
  // gamma = c / rho(A): the scale on which the slip operator acts.
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double rho = body_.slip_operator_norm(std::cos(th), std::sin(th), deriv);
  return rho > 0 ? kStickStepFactor / rho : body_.params().contact_modulus;
}

void ContactSolver::use_derivative(SlipDerivative deriv) {
  deriv_ = deriv;
  dsym_.clear();
  if (fric_.coefficient <= 0) return;
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  if (deriv != SlipDerivative::Spectral) dsym_ = body_.slip_symbols(std::cos(th), std::sin(th), deriv);
  if (!fric_.regularized()) gamma_ = stick_step(deriv);
}

ContactSolver::TangentialResult ContactSolver::solve_tangential(const RealField& p, const RealField* adhesion,
                                                                RealField& tx, RealField& ty, double tol,
                                                                int max_it) {
  // Douglas-Rachford on 0 in -v(tau) + N_K(tau), v(tau) = b + A tau with b = xi e_s + b' (b'
  // the slip the pressure causes through the coupling) and A = (e_s.grad) C_tt skew (on a
  // viscoelastic body (e_s.grad) c C_tt, dissipative: ElasticBody::slip_resolvent):
  //   tau = P_K(z);  y = (I - gamma A)^-1 (2 tau - z + gamma b);  z <- z + y - tau.
  // At a fixed point y = tau and z = tau + gamma v(tau), the projection form of Coulomb's
  // law: tau = mu_c p v/|v| where the point slips, |tau| <= mu_c p where v = 0 (stick).
  // Per step: 2 forward and 2 inverse FFTs and two fused passes over the grid.
  const std::size_t n = grid_.local_size();  // points held here
  const double th = fric_.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];  // plain names: lambdas may capture them
  const SlipDerivative deriv = deriv_;
  const double mu = fric_.coefficient;
  // The pressure the law's bound reads: the repulsion p + a with adhesion, p itself otherwise.
  const double* const adh = adhesion && adhesion->size() == n ? adhesion->data() : nullptr;
  const auto law_p = [&](std::size_t i) { return adh ? p[i] + adh[i] : p[i]; };
  // A bound that falls with the speed (the velocity law's static peak): the step stays above its
  // steepest fall at the largest pressure, so that the resolvent is continuous at the disc's edge
  // (friction_law.hpp); raised with headroom (a pressure that creeps up need not restart z), and
  // a raised step starts z afresh.
  if (const double fall = fric_.law.steepest_fall(mu, 1.0); fall > 0) {
    const double need = fall * grid_max(grid_, law_p, 0.0);
    if (kFallingStepMargin * need > gamma_) {
      gamma_ = kFallingStepHeadroom * need;
      have_z_ = false;
    }
  }
  const double gamma = gamma_;
  const double scale = 1.0 / static_cast<double>(grid_.size());
  const bool has_q0 = grid_.y0 == 0 && grid_.rows() > 0;  // the q = 0 mode is held here
  RealField& yx = r1_;
  RealField& yy = r2_;
  // b': slip velocity caused by the pressure (zero without coupling), times gamma.
  for (auto* fld : {&bx_, &by_, &zx_, &zy_})
    if (fld->size() != n) fld->assign(n, 0.0);
  fft_.forward(p.data(), s1_.data());
  body_.inplane_slope(nullptr, nullptr, s1_.data(), ex, ey, s2_.data(), s3_.data(), scale, -scale * gamma,
                      deriv, slip_symbols());
  fft_.backward_unscaled_destroying(s2_.data(), bx_.data());
  fft_.backward_unscaled_destroying(s3_.data(), by_.data());
  if (!have_z_) {
    // z = tau + gamma v(tau) for the traction we start from.
    fft_.forward(tx.data(), s2_.data());
    fft_.forward(ty.data(), s3_.data());
    body_.inplane_slope(s2_.data(), s3_.data(), nullptr, ex, ey, s2_.data(), s3_.data(), scale * gamma, 0.0,
                        deriv, slip_symbols());
    fft_.backward_unscaled_destroying(s2_.data(), yx.data());
    fft_.backward_unscaled_destroying(s3_.data(), yy.data());
    parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t s_i) {
      const auto i = static_cast<std::size_t>(s_i);
      zx_[i] = tx[i] + gamma * rx + bx_[i] + yx[i];
      zy_[i] = ty[i] + gamma * ry + by_[i] + yy[i];
    });
    have_z_ = true;
  }
  // Projection onto the disc of radius mu_c p (the law's bound at rest: a law with a set-valued
  // stick, contact/friction_law.hpp); for a law whose bound grows with the slip speed, its
  // resolvent: tau along z with |tau| + gamma |v| = |z|, |tau| = bound(|v|).
  const FrictionLaw law = fric_.law;
  const bool speed_law = law.speed_dependent();
  const auto project = [&](std::size_t i, double zx, double zy, double& x, double& y) {
    const double pi = law_p(i);
    const double r = law.bound(mu, pi, 0.0);
    if (!(r > 0)) {
      x = y = 0.0;
      return;
    }
    const double m2 = zx * zx + zy * zy;
    if (m2 <= r * r) {
      x = zx;
      y = zy;
    } else {
      const double zm = std::sqrt(m2);
      const double f = (speed_law ? law.resolvent(mu, pi, zm, gamma) : r) / zm;
      x = f * zx;
      y = f * zy;
    }
  };
  // tau = P_K(z); with `rhs` also y <- 2 tau - z + gamma b' (the resolvent's argument).
  const auto project_pass = [&](bool rhs) {
    parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t s_i) {
      const auto i = static_cast<std::size_t>(s_i);
      double x, y;
      project(i, zx_[i], zy_[i], x, y);
      tx[i] = x;
      ty[i] = y;
      if (rhs) {
        yx[i] = 2.0 * x - zx_[i] + bx_[i];
        yy[i] = 2.0 * y - zy_[i] + by_[i];
      }
    });
  };
  TangentialResult res{0, 1.0, false};
  const double cx = gamma * rx, cy = gamma * ry;
  // friction.stick_acceleration: Anderson mixing of z (type II, relaxation inside the map
  // z -> z + beta (y - tau)), with a fresh history per call. An extrapolated z is kept only
  // if the residual |y - tau|_2 there does not exceed the one at the last accepted z (for
  // plain Douglas-Rachford it never grows); otherwise the plain step from that z replaces it.
  const int depth = fric_.stick_acceleration;
  const bool accel = depth > 0;
  const double beta = accel ? kAcceleratedRelaxation : kTangentialRelaxation;
  if (accel) {
    // z over every point held here, its two components interleaved (entry 2i: z_x at i),
    // summed by grid row (the same sums on any number of processes).
    if (!zmix_ || zmix_->size() != 2 * n) {
      zmix_ = std::make_unique<AndersonMixer>(depth);
      zmix_->resize(2 * n);
      const auto rows = static_cast<std::size_t>(grid_.rows());
      zmix_start_.resize(rows + 1);
      for (std::size_t r = 0; r <= rows; ++r)
        zmix_start_[r] = static_cast<std::uint32_t>(2 * r * static_cast<std::size_t>(grid_.nx));
      zmix_order_.resize(2 * n);
      for (std::size_t e = 0; e < 2 * n; ++e) zmix_order_[e] = static_cast<std::uint32_t>(e);
      zmix_->group_by_rows(&grid_, &zmix_start_, &zmix_order_);
    } else {
      zmix_->restart();
    }
  }
  double r2_base = 0.0;    // squared L2 residual at the last accepted z
  bool candidate = false;  // z is an extrapolated iterate, not checked yet
  const auto zref = [&](std::size_t e) -> double& { return (e % 2 == 0 ? zx_ : zy_)[e / 2]; };
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    project_pass(true);
    fft_.forward(yx.data(), s2_.data());
    fft_.forward(yy.data(), s3_.data());
    body_.slip_resolvent(s2_.data(), s3_.data(), ex, ey, gamma, scale, deriv, slip_symbols());
    if (has_q0) {
      s2_[0] += cx;  // the rigid slip gamma (xi e_s + eta e_perp): the q = 0 mode, where the resolvent is 1
      s3_[0] += cy;
    }
    fft_.backward_unscaled_destroying(s2_.data(), yx.data());
    fft_.backward_unscaled_destroying(s3_.data(), yy.data());
    if (!accel) {
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
      continue;
    }
    // Accelerated: y <- d = y - tau; sums |d|_1, |tau|_1 and |d|_2^2.
    const auto sums = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double dx = yx[i] - tx[i], dy = yy[i] - ty[i];
      acc[0] += std::abs(dx) + std::abs(dy);
      acc[1] += std::abs(tx[i]) + std::abs(ty[i]);
      acc[2] += dx * dx + dy * dy;
      yx[i] = dx;
      yy[i] = dy;
    });
    res.error = sums[1] > 0 ? sums[0] / sums[1] : (sums[0] > 0 ? 1.0 : 0.0);
    require_finite(res.error, "the stick-slip traction", total_it_);
    if (candidate && sums[2] > r2_base) {
      // The extrapolated z did not lower the residual: the plain step from the last
      // accepted z instead, with a fresh history.
      zmix_->plain_step(1.0, [&](std::size_t e, double v) { zref(e) = v; });
      zmix_->restart();
      candidate = false;
      continue;
    }
    if (res.error < tol) {
      parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t s_i) {
        const auto i = static_cast<std::size_t>(s_i);
        zx_[i] += beta * yx[i];
        zy_[i] += beta * yy[i];
      });
      res.converged = true;
      break;
    }
    r2_base = sums[2];
    zmix_->step(
        1.0, [&](std::size_t e) { return zref(e); },
        [&](std::size_t e) { return zref(e) + beta * (e % 2 == 0 ? yx : yy)[e / 2]; },
        [&](std::size_t e, double v) { zref(e) = v; });
    candidate = zmix_->history() > 0;
    if (res.iterations % 64 == 0) poll(nullptr);
  }
  project_pass(false);  // tau = P_K(z) for the final z
  return res;
}

void ContactSolver::transform_tractions(const RealField& tx, const RealField& ty) {
  fft_.forward(tx.data(), s2_.data());
  fft_.forward(ty.data(), s3_.data());
}

void ContactSolver::friction_normal_displacement(const RealField& tx, const RealField& ty, RealField& w) {
  transform_tractions(tx, ty);
  body_.displacement(s2_.data(), s3_.data(), nullptr, nullptr, nullptr, s1_.data(),
                     1.0 / static_cast<double>(grid_.size()));
  fft_.backward_unscaled_destroying(s1_.data(), w.data());
}

}  // namespace gfmd
