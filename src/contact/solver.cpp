// The contact solver's friction fixed point with Anderson mixing around the normal solve, and
// the restart point it keeps for checkpoints (set-up and services: solver_setup.cpp). See
// include/gfmd/contact/solver.hpp.
#include "gfmd/contact/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <optional>
#include <sstream>

#include "device_solve.hpp"
#include "gfmd/contact/anderson.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

SolveInfo ContactSolver::solve(const LoadParams& load, ContactFields& f, const FrictionRestart* resume,
                               const AdhesiveRestart* adhesive_resume) {
  restart_.reset();
  adh_restart_.reset();
  adh_.repulsive = false;
  // The device solve resumes from the fields alone (a warm start).
  if (device_) return solve_on_device(load, f);
  const auto t0 = Clock::now();
  const std::uint64_t transforms0 = fft_.transforms();
  const double fft_seconds0 = fft_.seconds();
  current_ = &f;
  last_checkpoint_ = std::chrono::duration<double>(t0.time_since_epoch()).count();
  const std::size_t n = grid_.local_size();  // points held here
  for (auto* fld : {&f.pressure, &f.tx, &f.ty})
    if (fld->size() != n) fld->assign(n, 0.0);
  // The displacements and the gap follow from (p, tau) at the end: their memory is given
  // back during the iterations.
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) RealField().swap(*fld);
  f.stick.clear();
  if (!inter_.adhesive()) RealField().swap(f.adhesion);
  total_it_ = 0;
  SolveInfo info;
  info.stiffness = k_;
  if (deriv_ != fric_.derivative()) use_derivative(fric_.derivative());  // a previous solve met stick
  const double tol = sp_.tolerance;
  const double mu = fric_.coefficient;
  RealField w(n, 0.0);
  PKResult pk{};
  if (mu == 0.0) {
    std::fill(f.tx.begin(), f.tx.end(), 0.0);
    std::fill(f.ty.begin(), f.ty.end(), 0.0);
    if (inter_.adhesive()) {
      // On a viscoelastic body too (its repulsive solves); it keeps a restart point.
      pk = solve_adhesive(load, f, tol, info, nullptr, -1, true, adhesive_resume);
      if (body_.viscoelastic() && body_.visco().velocity != 0.0)
        info.hysteresis_dissipation = hysteresis_dissipation(f, false);
    } else if (body_.viscoelastic()) {
      pk = solve_viscoelastic(load, f, tol, info);
    } else {
      pk = solve_normal(load, w, true, f.pressure, tol, sp_.max_iterations);
      info.converged = pk.converged;
      info.status = pk.converged ? "converged" : "not converged: iteration limit reached";
    }
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
    // order of entry; the mixer's vector holds the two components of each support point
    // interleaved (entry 2j: tau_x at supp[j], 2j + 1: tau_y).
    std::vector<std::uint32_t> supp;
    std::vector<unsigned char> in_supp(n, 0);
    // Where the support grew (a restart point's order): (friction steps done, first entry);
    // the warm start's points come at 0.
    std::vector<std::pair<std::int32_t, std::size_t>> batches;
    if (resume) {
      const std::string why = restart_mismatch(*resume, n, sp_.anderson, fric_.slip_derivative);
      if (!why.empty()) throw ParameterError("resume", "the restart point does not fit this solve: " + why);
      // The support in its order of entry: by the step it joined at, then by grid index.
      std::vector<std::pair<std::int32_t, std::uint32_t>> order;
      for (std::size_t i = 0; i < n; ++i)
        if (resume->support[i] >= 0) {
          order.emplace_back(static_cast<std::int32_t>(resume->support[i]), static_cast<std::uint32_t>(i));
          in_supp[i] = 1;
        }
      std::sort(order.begin(), order.end());
      for (const auto& [step, i] : order) {
        if (batches.empty() || batches.back().first != step) batches.emplace_back(step, supp.size());
        supp.push_back(i);
      }
    } else {
      // A warm start's traction starts the support (the slip pass reads nothing outside it).
      batches.emplace_back(0, 0);
      for (std::size_t i = 0; i < n; ++i)
        if (f.tx[i] != 0.0 || f.ty[i] != 0.0) {
          in_supp[i] = 1;
          supp.push_back(static_cast<std::uint32_t>(i));
        }
    }
    // The mixer's sums go by grid row (the same sums on any number of processes): the
    // support's entries listed row by row, in their order of entry (rebuilt as it grows).
    std::vector<std::uint32_t> row_start, row_order;
    const auto group_support = [&] {
      row_start.assign(static_cast<std::size_t>(grid_.rows()) + 1, 0);
      const auto nx = static_cast<std::uint32_t>(grid_.nx);
      for (const std::uint32_t i : supp) ++row_start[i / nx + 1];
      for (std::size_t r = 1; r < row_start.size(); ++r) row_start[r] += row_start[r - 1];
      row_order.resize(2 * supp.size());
      std::vector<std::uint32_t> next(row_start.begin(), row_start.end() - 1);
      // Entries 2j and 2j + 1 (tau_x and tau_y of support point j) stay together.
      for (std::size_t j = 0; j < supp.size(); ++j) {
        const std::uint32_t at = next[supp[j] / nx]++;
        row_order[2 * at] = static_cast<std::uint32_t>(2 * j);
        row_order[2 * at + 1] = static_cast<std::uint32_t>(2 * j + 1);
      }
      for (auto& v : row_start) v *= 2;
    };
    std::optional<AndersonMixer> mixer;  // none: plain relaxation
    // The history's depth: solver.anderson, deepened once where the fixed point stalls (and
    // so in a restart point made after that).
    int depth = sp_.anderson;
    if (resume && resume->mixer)
      depth = static_cast<int>(std::lround(std::sqrt(static_cast<double>(resume->mixer_gram.size()))));
    if (sp_.anderson > 0) {
      info.history_depth = depth;
      mixer.emplace(depth);
      mixer->resize(2 * supp.size());
      group_support();
      mixer->group_by_rows(&grid_, &row_start, &row_order);
      if (resume && resume->mixer) {
        std::vector<std::size_t> slots(resume->mixer_slots.begin(), resume->mixer_slots.end());
        for (const std::int32_t sl : resume->mixer_slots)
          if (sl < 0) throw ParameterError("resume", "the restart point's mixing history is damaged");
        mixer->restore(resume->mixer_have_prev, slots, resume->mixer_gram);
        auto& xp = mixer->previous_iterate();
        auto& fp = mixer->previous_residual();
        for (std::size_t j = 0; j < supp.size(); ++j) {
          const std::uint32_t i = supp[j];
          xp[2 * j] = resume->xprev_x[i];
          xp[2 * j + 1] = resume->xprev_y[i];
          fp[2 * j] = resume->fprev_x[i];
          fp[2 * j + 1] = resume->fprev_y[i];
        }
        for (std::size_t k = 0; k < slots.size(); ++k) {
          auto& df = mixer->residual_differences(slots[k]);
          auto& dx = mixer->iterate_differences(slots[k]);
          for (std::size_t j = 0; j < supp.size(); ++j) {
            unpack_floats(resume->df[k][supp[j]], df[2 * j], df[2 * j + 1]);
            unpack_floats(resume->dx[k][supp[j]], dx[2 * j], dx[2 * j + 1]);
          }
        }
      }
    }
    double err = 1.0;
    // Per friction step: the traction change and the tangential force (sum of tau_x and of
    // tau_y), the evidence a failure message gives (friction_history_evidence).
    std::vector<double> hist_change, hist_force;
    const double dir_x = std::cos(fric_.direction_deg * std::numbers::pi / 180.0),
                 dir_y = std::sin(fric_.direction_deg * std::numbers::pi / 180.0);
    bool have_slip = false;  // r1_/r2_ hold (e.grad) u of this solve
    // The exact law starts with the full-slip map tau = mu_c p v/|v| (fast, and its fixed
    // point, where every contact point slips, solves the set-valued law too). Where it meets
    // stick (contact points slower than kNearStickSpeed v0 in kNearStickSteps successive
    // friction steps, from step kNearStickFirst on), where it does not settle, or with
    // creepage (rolling: stick is expected), the stick-slip solve takes over from the
    // current traction; the automatic derivative turns with it (FrictionSteps).
    FrictionSteps steps(!fric_.regularized() && fric_.rolling(),
                        !fric_.slip_derivative && deriv_ == SlipDerivative::Spectral);
    // Stick: the splitting variable inside the friction disc (there z = tau, v = 0).
    const auto sticks = [&](std::size_t i) {
      const double r = fric_.law.bound(mu, f.repulsion(i), 0.0);  // the friction disc's radius
      return r > 0 && zx_[i] * zx_[i] + zy_[i] * zy_[i] < r * r;
    };
    double stick_now = 0.0;                    // contact points that stick in the last stick-slip solve
    bool map_changed = false;                  // the slip derivative turned in this friction step
    bool tangential_ok = !steps.stick_mode();  // the last stick-slip solve met the final tolerance
    have_z_ = false;
    const bool accelerated = fric_.stick_acceleration > 0;
    double omega = sp_.mixing;
    int first_outer = 0;
    if (resume) {
      // Where the interrupted solve stood at the start of its step.
      first_outer = resume->outer;
      total_it_ = resume->iterations;
      info.outer_iterations = resume->outer;
      info.tangential_iterations = resume->tangential_iterations;
      err = resume->error;
      if (resume->outer > 0) info.friction_error = err;
      omega = resume->mixing;
      stick_now = resume->stick_points;
      tangential_ok = resume->tangential_ok;
      have_slip = resume->have_slip;
      if (deriv_ != resume->derivative) use_derivative(resume->derivative);
      steps.restore(resume->steps);
      gw_mean_ref_ = resume->gw_mean_ref;
      g_mean_ref_ = resume->g_mean_ref;
      pk = PKResult{resume->pk_iterations, resume->pk_error, resume->pk_delta, resume->pk_converged};
      hist_change = resume->history_change;
      hist_force = resume->history_force;
      have_z_ = resume->have_z;
      info.adhesion_steps = resume->adhesion_steps;
      if (have_z_) {
        zx_ = resume->zx;
        zy_ = resume->zy;
      }
    }
    // The restart point (the start of the step in progress) for a checkpoint or a stop: the
    // loop's numbers and the pressure and splitting variable at the start of the step (the
    // step's solves change them in place); the traction, the support and the mixing change
    // only at the step's end, after its last poll.
    struct Top {
      int outer, iterations, tangential;
      double err, omega, stick_now;
      bool tangential_ok, have_slip, have_z;
      SlipDerivative deriv;
      FrictionStepsState steps;
      double gw, g;
      PKResult pk;
      std::size_t hist;
      int adhesion_steps;
    } top{};
    RealField p_top, a_top, zx_top, zy_top;
    const bool keep_top = static_cast<bool>(stop_) || static_cast<bool>(checkpoint_);
    restart_maker_ = [&] {
      auto rp = std::make_unique<RestartPoint>();
      FrictionRestart& s = rp->state;
      s.outer = top.outer;
      s.iterations = top.iterations;
      s.tangential_iterations = top.tangential;
      s.error = top.err;
      s.mixing = top.omega;
      s.stick_points = top.stick_now;
      s.tangential_ok = top.tangential_ok;
      s.have_slip = top.have_slip;
      s.have_z = top.have_z;
      s.derivative = top.deriv;
      s.steps = top.steps;
      s.gw_mean_ref = top.gw;
      s.g_mean_ref = top.g;
      s.pk_iterations = top.pk.iterations;
      s.pk_error = top.pk.error;
      s.pk_delta = top.pk.delta;
      s.pk_converged = top.pk.converged;
      s.adhesion_steps = top.adhesion_steps;
      s.history_change.assign(hist_change.begin(),
                              hist_change.begin() + static_cast<std::ptrdiff_t>(top.hist));
      s.history_force.assign(hist_force.begin(), hist_force.begin() + static_cast<std::ptrdiff_t>(top.hist));
      rp->fields.pressure = p_top;
      rp->fields.adhesion = a_top;
      rp->fields.tx = f.tx;
      rp->fields.ty = f.ty;
      if (top.have_z) {
        s.zx = zx_top;
        s.zy = zy_top;
      }
      s.support.assign(n, -1.0);
      for (std::size_t b = 0; b < batches.size(); ++b) {
        const std::size_t end = b + 1 < batches.size() ? batches[b + 1].second : supp.size();
        for (std::size_t j = batches[b].second; j < end; ++j) s.support[supp[j]] = batches[b].first;
      }
      s.mixer = mixer.has_value();
      if (mixer) {
        s.mixer_have_prev = mixer->has_previous();
        for (const std::size_t sl : mixer->slots()) s.mixer_slots.push_back(static_cast<std::int32_t>(sl));
        s.mixer_gram = mixer->gram();
        for (RealField* fld : {&s.xprev_x, &s.xprev_y, &s.fprev_x, &s.fprev_y}) fld->assign(n, 0.0);
        const auto& xp = mixer->previous_iterate();
        const auto& fp = mixer->previous_residual();
        for (std::size_t j = 0; j < supp.size(); ++j) {
          const std::uint32_t i = supp[j];
          s.xprev_x[i] = xp[2 * j];
          s.xprev_y[i] = xp[2 * j + 1];
          s.fprev_x[i] = fp[2 * j];
          s.fprev_y[i] = fp[2 * j + 1];
        }
        for (const std::size_t sl : mixer->slots()) {
          const auto& df = mixer->residual_differences(sl);
          const auto& dx = mixer->iterate_differences(sl);
          RealField& pdf = s.df.emplace_back(n, 0.0);
          RealField& pdx = s.dx.emplace_back(n, 0.0);
          for (std::size_t j = 0; j < supp.size(); ++j) {
            pdf[supp[j]] = pack_floats(df[2 * j], df[2 * j + 1]);
            pdx[supp[j]] = pack_floats(dx[2 * j], dx[2 * j + 1]);
          }
        }
      }
      restart_ = std::move(rp);
    };
    // The maker reads this loop's state: it goes with the loop, however the loop ends.
    struct ClearMaker {
      std::function<void()>& maker;
      ~ClearMaker() { maker = nullptr; }
    } clear_maker{restart_maker_};
    info.status = "not converged: friction fixed point did not settle";
    SolveInfo adhesive_step;  // with adhesion: the last friction step's adhesive solve
    bool pulled_off = false;  // it found the load beyond what the adhesion holds
    for (int outer = first_outer; outer < sp_.max_outer; ++outer) {
      info.outer_iterations = outer + 1;
      top = Top{outer,
                total_it_,
                info.tangential_iterations,
                err,
                omega,
                stick_now,
                tangential_ok,
                have_slip,
                have_z_,
                deriv_,
                steps.state(),
                gw_mean_ref_,
                g_mean_ref_,
                pk,
                hist_change.size(),
                info.adhesion_steps};
      if (keep_top) {
        p_top = f.pressure;
        a_top = f.adhesion;  // with adhesion: the traction that goes with the net pressure
        if (have_z_) {
          zx_top = zx_;
          zy_top = zy_;
        }
      }
      // Stop requests and checkpoints between the steps see the restart point as it is.
      poll(&f);
      friction_normal_displacement(f.tx, f.ty, w);
      // The normal solve's tolerance follows the friction change (looser in the accelerated
      // stick-slip phase).
      const double inner_fac = steps.stick_mode() && accelerated ? kAcceleratedNormalTolFactor : 0.1;
      const double inner_tol = std::max(tol, std::min(1e-3, inner_fac * err));
      const int budget = sp_.max_iterations - total_it_;
      if (budget <= 0) {
        info.status = "not converged: iteration limit reached";
        break;
      }
      if (inter_.adhesive()) {
        // The adhesive normal problem under the friction's normal displacement; its traction
        // f.adhesion is kept from step to step (the warm start of the next).
        SolveInfo& step_info = adhesive_step;
        step_info = SolveInfo{};
        pk = solve_adhesive(load, f, inner_tol, step_info, &w, budget);
        info.adhesion_steps += step_info.adhesion_steps;
        info.viscoelastic_steps += step_info.viscoelastic_steps;
        info.elastic_energy = step_info.elastic_energy;
        info.adhesive_energy = step_info.adhesive_energy;
        info.energy = step_info.energy;
        if (step_info.no_state) {  // beyond the pull-off, or beyond the cap
          info.status = step_info.status;
          pulled_off = true;
          break;
        }
        if (!steps.stick_mode()) transform_tractions(f.tx, f.ty);  // the gap spread used s2_/s3_
      } else {
        pk = solve_repulsive(load, w, f.pressure, inner_tol, budget, info);  // elastic or viscoelastic
      }
      // One friction step costs 3 forward + 3 inverse FFTs: tau_x, tau_y and p forward,
      // w and the two slip derivatives back (with adhesion two more forward: the tractions
      // again after the adhesive steps' gap spread).
      // dn[2]: points outside the Anderson support where the iterate or its image is
      // non-zero (they join the support below).
      std::array<double, 4> dn{};
      if (!steps.stick_mode()) {
        dn = slip_tractions(f, tx, ty, in_supp);
        have_slip = true;
        steps.full_slip_step(dn[3]);
      } else {
        if (!have_z_) {
          tx = f.tx;
          ty = f.ty;
        }
        const double ttol = std::max(
            0.1 * tol,
            std::min(1e-3, (accelerated ? kAcceleratedTangentialTolFactor : kTangentialTolFactor) * err));
        const auto tr = solve_tangential(f.pressure, &f.adhesion, tx, ty, ttol, sp_.max_tangential);
        info.tangential_iterations += tr.iterations;
        tangential_ok = tr.converged && ttol <= 0.1 * tol;
        const auto c = grid_sums<4>(grid_, [&](std::size_t i, std::array<double, 4>& acc) {
          add_change(acc, in_supp[i], tx[i], ty[i], f.tx[i], f.ty[i]);
          if (sticks(i)) acc[3] += 1.0;
        });
        dn = {c[0], c[1], c[2], 0.0};
        stick_now = c[3];
        if (steps.settles_upwind(stick_now)) {
          // The spectral continuation meets stick after all: upwind2 for good, z afresh.
          use_derivative(SlipDerivative::Upwind2);
          have_z_ = false;
          tangential_ok = false;
          map_changed = true;
        }
      }
      err = dn[1] > 0 ? dn[0] / dn[1] : 0.0;
      require_finite(err, "the friction traction", total_it_);
      info.friction_error = err;
      hist_change.push_back(err);
      hist_force.push_back(grid_sum(grid_, [&](std::size_t i) { return dir_x * tx[i] + dir_y * ty[i]; }));
      if (progress_) progress_(Progress{total_it_, outer + 1, err});
      const bool done = err < tol && pk.converged && inner_tol <= tol && tangential_ok;
      if (steps.turns_back(done, stick_now)) {
        // Converged with the automatic derivative turned to upwind2, and every contact point
        // slips: continue from here with the spectral one (its answer differs by the
        // discretisation, ~1e-5), z afresh, a fresh mixing history (below).
        use_derivative(SlipDerivative::Spectral);
        have_z_ = false;
        tangential_ok = false;
        map_changed = true;
      } else if (done) {
        f.tx.swap(tx);
        f.ty.swap(ty);
        info.converged = true;
        info.status = "converged";
        break;
      }
      const FrictionSteps::Next next = steps.after(err, outer, !fric_.regularized());
      if (next == FrictionSteps::Next::HandOver) {
        // The full-slip map meets stick or does not settle: continue with the set-valued law
        // from the current traction, with a fresh mixing history (and the upwind derivative
        // where it is automatic: docs/solver.md).
        if (steps.upwind()) use_derivative(SlipDerivative::Upwind2);
        tangential_ok = false;
        if (mixer) mixer->restart();
        continue;
      }
      if (next == FrictionSteps::Next::Damp && mixer && deepened_history(sp_.anderson, depth) != depth) {
        // Stalled: first a longer mixing history (deepened_history), started afresh from
        // the current iterate.
        depth = deepened_history(sp_.anderson, depth);
        mixer.emplace(depth);
        mixer->resize(2 * supp.size());
        mixer->group_by_rows(&grid_, &row_start, &row_order);
        info.history_depth = depth;
      } else if (next == FrictionSteps::Next::Damp) {
        // Stalled (with the longer history too): damp harder and restart the mixing history;
        // give up once damping no longer helps (a limit cycle of the slip field).
        omega = damped_mixing(omega, sp_.mixing, hist_change);
        if (mixer) mixer->clear_history();
        if (omega == 0.0) {
          f.tx.swap(tx);
          f.ty.swap(ty);
          info.status = "not converged: oscillating (friction fixed point does not settle even with damping)";
          break;
        }
      }
      if (dn[2] > 0) {
        // New support points (in grid order, so the layout does not depend on threads):
        // their previous iterate, residual and all stored differences are zero.
        const std::size_t before = supp.size();
        for (std::size_t i = 0; i < n; ++i)
          if (joins_support(in_supp[i], tx[i], ty[i], f.tx[i], f.ty[i])) {
            in_supp[i] = 1;
            supp.push_back(static_cast<std::uint32_t>(i));
          }
        if (supp.size() > before) batches.emplace_back(outer + 1, before);
        if (mixer) {
          mixer->resize(2 * supp.size());
          group_support();
        }
      }
      if (map_changed) {
        // The friction map changed with the slip derivative: this step's residual and the
        // mixing history belong to the old map, and Anderson would read the jump between the
        // two as the response to the last (tiny) step and stay put (measured: ten friction
        // steps without progress). The image becomes the iterate; the mixing starts afresh.
        map_changed = false;
        f.tx.swap(tx);
        f.ty.swap(ty);
        if (mixer) mixer->restart();
        continue;
      }
      // The exact law's splitting variable follows the mixed traction: z <- z + (tau_mixed -
      // tau), so the next stick-slip solve starts from the mixed iterate (z - tau = gamma v
      // is kept).
      const auto follow = [&] {
        if (!steps.stick_mode()) return;
        for (const std::uint32_t i : supp) {
          zx_[i] += f.tx[i] - tx[i];
          zy_[i] += f.ty[i] - ty[i];
        }
      };
      if (!mixer) {
        // Plain relaxation; outside the support both tractions are zero.
        for (const std::uint32_t i : supp) {
          f.tx[i] += omega * (tx[i] - f.tx[i]);
          f.ty[i] += omega * (ty[i] - f.ty[i]);
        }
        follow();
        continue;
      }
      // Anderson mixing (contact/anderson.hpp) of the traction on the support; outside it
      // the iterate, its image and so the update are zero.
      const auto entry = [&](const RealField& ax, const RealField& ay, std::size_t e) {
        return (e % 2 == 0 ? ax : ay)[supp[e / 2]];
      };
      mixer->step(
          omega, [&](std::size_t e) { return entry(f.tx, f.ty, e); },
          [&](std::size_t e) { return entry(tx, ty, e); },
          [&](std::size_t e, double v) { (e % 2 == 0 ? f.tx : f.ty)[supp[e / 2]] = v; });
      follow();
    }
    if (!info.converged && !pulled_off && info.status.rfind("not converged: iteration limit", 0) != 0)
      info.status +=
          "; " + friction_history_evidence(hist_change, hist_force,
                                           info.status.find("even with damping") != std::string::npos);
    // The last adhesive solve's own failure (e.g. cohesive zones too narrow for the grid).
    if (!info.converged && !pulled_off && !adhesive_step.converged && !adhesive_step.status.empty())
      info.status += "; the last adhesive solve: " + adhesive_step.status;
    if (!info.converged && !pulled_off && fric_.law.kind == FrictionLawKind::Tresca &&
        mu > kTrescaSteepCoefficient)
      info.status += kTrescaSteepHint;
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
        if (f.in_contact(i)) {
          const double v = std::hypot(ex + r1_[i], ey + r2_[i]);
          vmin = std::min(vmin, v);
          if (v < slow) ++nslow;
        }
      nslow = mpi::sum_all(grid_, nslow);
      vmin = -mpi::max_all(grid_, -vmin);
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
    if (steps.stick_mode() && have_z_) {
      std::size_t ns = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (sticks(i)) {
          f.stick[i] = 1;
          ++ns;
        }
      info.stick_points = mpi::sum_all(grid_, ns);
    }
    if (!pk.converged && info.converged) {
      info.converged = false;
      info.status = "not converged: iteration limit reached";
    }
    // On a viscoelastic body: why the last normal solve did not settle, if it did not.
    if (!info.converged && !pulled_off && !pk.converged && !inter_.adhesive() && !visco_.last_failure.empty())
      info.status += "; the last viscoelastic solve: " + visco_.last_failure;
  }
  info.iterations = total_it_;
  info.slip_derivative = deriv_;
  info.pk_error = pk.error;
  info.approach = pk.delta;
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) fld->resize(n);
  update_displacements(f);
  if (inter_.adhesive() && mu > 0.0) {
    // The elastic energy with the tractions' share: 1/2 sum (tau.u_t - p u_z) dA (the adhesive
    // steps counted the normal part alone).
    const double e = 0.5 * grid_.cell_area() * grid_sum(grid_, [&](std::size_t i) {
                       return f.tx[i] * f.ux[i] + f.ty[i] * f.uy[i] - f.pressure[i] * f.uz[i];
                     });
    info.energy += e - info.elastic_energy;
    info.elastic_energy = e;
  }
  check_final_state(info, f, pk.delta);
  if (body_.viscoelastic() && mu > 0.0 && body_.visco().velocity != 0.0)
    info.hysteresis_dissipation = hysteresis_dissipation(f, true);
  info.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  info.transforms = fft_.transforms() - transforms0;
  info.fft_seconds = fft_.seconds() - fft_seconds0;
  return info;
}

}  // namespace gfmd
