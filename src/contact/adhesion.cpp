// The adhesive normal problem: the Maugis-Dugdale cohesive law, each step a repulsive
// Polonsky-Keer solve under a fixed adhesive traction. See solver.hpp and docs/solver.md
// ("Adhesion").
//
// The energy of a state is the elastic energy, the repulsion and the adhesive energy
// sum sigma0 min(g, rho) dA (minus a constant), concave in the gap g. Replacing the adhesive
// term by its tangent at the current gap (the traction a = sigma0 where g < rho, 0 beyond,
// held fixed) gives a convex upper bound that touches the energy there; its minimiser is the
// repulsive problem under that traction (w = C_zz a in the normal solve). Stepping from
// minimiser to minimiser lowers the energy, so a load path follows its branch from its warm
// start (jump-in and jump-off included) instead of being thrown over a barrier.
//
// On the grid the law is integrated over each cell with the gap taken linear across it: the
// cell carries sigma0 times the fraction of its area where g < rho, clamp((rho - g)/s + 1/2,
// 0, 1), s = |g_x| dx + |g_y| dy the gap's spread over the cell (spectral gradient). With the
// law sampled at the cell centres instead (whole cells on or off), the cohesive zone's edge
// moves by whole cells: first-order errors and lattice trapping where the zone is a few cells
// wide (JKR-like contacts: the pull-off 18 % beyond Maugis's at lambda = 2.5 with a 2.5-cell
// zone, 1.0 % with the cell integral; docs/solver.md). The fractions make the steps a fixed
// point that converges linearly; Anderson mixing (solver.anderson) over the traction, clipped
// to [0, sigma0] and safeguarded (below), accelerates it.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

void ContactSolver::gap_spread(const RealField& gap, RealField& gx, RealField& spread) {
  // |g_x| dx + |g_y| dy by one forward and two inverse transforms (s2_, s3_ are free outside
  // the normal solve; the friction loop transforms its tractions again after this). The
  // spectral derivative's symbols are i q_x and i q_y (0 on the Nyquist lines), tabulated once
  // with 1/N folded in.
  const int nxh = grid_.nxh();
  const std::size_t ns = s2_.size();
  if (adh_.qx.size() != ns) {
    adh_.qx.assign(ns, 0.0);
    adh_.qy.assign(ns, 0.0);
    const double inv_n = 1.0 / static_cast<double>(grid_.size());
    for_rows(grid_.rows(), [&](int row) {
      for (int ikx = 0; ikx < nxh; ++ikx) {
        const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
        adh_.qx[k] =
            slip_derivative_symbol(grid_, ikx, grid_.y0 + row, 1.0, 0.0, SlipDerivative::Spectral).imag() *
            inv_n;
        adh_.qy[k] =
            slip_derivative_symbol(grid_, ikx, grid_.y0 + row, 0.0, 1.0, SlipDerivative::Spectral).imag() *
            inv_n;
      }
    });
  }
  fft_.forward(gap.data(), s2_.data());
  parallel_for(static_cast<std::ptrdiff_t>(ns), [&](std::ptrdiff_t k) {
    const cplx iv = cplx(-s2_[k].imag(), s2_[k].real());  // i times the mode
    s3_[k] = iv * adh_.qy[k];
    s2_[k] = iv * adh_.qx[k];
  });
  fft_.backward_unscaled_destroying(s2_.data(), gx.data());
  fft_.backward_unscaled_destroying(s3_.data(), spread.data());
  const double dx = grid_.dx(), dy = grid_.dy();
  parallel_for(static_cast<std::ptrdiff_t>(gap.size()),
               [&](std::ptrdiff_t i) { spread[i] = std::abs(gx[i]) * dx + std::abs(spread[i]) * dy; });
}

void ContactSolver::save_adhesive_mixing(AdhesiveRestart& st) const {
  const GuardedAnderson& g = *adh_.mixer;
  const std::size_t n = grid_.local_size();
  st.guard = g.guard().state();
  st.kept = g.kept().size() == n ? g.kept() : RealField(n, 0.0);  // read only after a mixing step
  const AndersonMixer* m = g.mixer();
  st.mixer = m != nullptr;
  if (!m) return;
  st.mixer_have_prev = m->has_previous();
  for (const std::size_t sl : m->slots()) st.mixer_slots.push_back(static_cast<std::int32_t>(sl));
  st.mixer_gram = m->gram();
  st.xprev.assign(m->previous_iterate().begin(), m->previous_iterate().end());
  st.fprev.assign(m->previous_residual().begin(), m->previous_residual().end());
  for (const std::size_t sl : m->slots()) {
    const auto& df = m->residual_differences(sl);
    const auto& dx = m->iterate_differences(sl);
    st.df.emplace_back(df.begin(), df.end());  // floats, exactly
    st.dx.emplace_back(dx.begin(), dx.end());
  }
}

void ContactSolver::restore_adhesive_mixing(const AdhesiveRestart& st) {
  GuardedAnderson& g = *adh_.mixer;
  g.guard().restore(st.guard);
  g.kept() = st.kept;
  AndersonMixer* m = g.mixer();
  if (!m) return;
  const std::vector<std::size_t> slots(st.mixer_slots.begin(), st.mixer_slots.end());
  m->restore(st.mixer_have_prev, slots, st.mixer_gram);
  m->previous_iterate().assign(st.xprev.begin(), st.xprev.end());
  m->previous_residual().assign(st.fprev.begin(), st.fprev.end());
  for (std::size_t k = 0; k < slots.size(); ++k) {
    auto& df = m->residual_differences(slots[k]);
    auto& dx = m->iterate_differences(slots[k]);
    df.resize(st.df[k].size());
    dx.resize(st.dx[k].size());
    for (std::size_t i = 0; i < df.size(); ++i) {
      df[i] = static_cast<float>(st.df[k][i]);
      dx[i] = static_cast<float>(st.dx[k][i]);
    }
  }
}

ContactSolver::PKResult ContactSolver::solve_adhesive(const LoadParams& load, ContactFields& f, double tol,
                                                      SolveInfo& info, const RealField* w_extra, int max_it,
                                                      bool restartable, const AdhesiveRestart* resume) {
  const std::size_t n = grid_.local_size();
  const auto nl = static_cast<std::ptrdiff_t>(n);
  const double s0 = inter_.adhesive_stress();
  const double rho = inter_.range;
  RealField& a = f.adhesion;
  RealField& p = f.pressure;  // the repulsive pressure during the steps, the net one at the end
  if (a.size() != n) a.assign(n, 0.0);
  if (resume) {
    const std::string why = adhesive_restart_mismatch(*resume, n, sp_.anderson);
    if (!why.empty()) throw ParameterError("resume", "the restart point does not fit this solve: " + why);
  }
  // A tensile (or zero) load under load control needs an adhesive state to start from: a cold
  // start has no pull to hold it. The state at first touch (approach 0) is made first.
  PKResult pre{0, 0.0, 0.0, true};
  if (resume) {
    pre.iterations = resume->pre_iterations;  // done before the restart point
  } else if (load.mode != LoadMode::Approach && !(load.value > 0) &&
             !(grid_sum(grid_, [&](std::size_t i) { return a[i]; }) > 0)) {
    pre = solve_adhesive(LoadParams{LoadMode::Approach, 0.0}, f, tol, info, w_extra, max_it);
    if (!info.converged) return pre;
  }
  // A warm start holds the net pressure: its repulsive part is p + a (held in the fields until
  // the end; pressure_is_repulsive says so to a checkpoint). A restart point has its own.
  if (resume)
    p = resume->repulsion;
  else
    parallel_for(nl, [&](std::ptrdiff_t i) { p[i] = std::max(0.0, p[i] + a[i]); });
  adh_.repulsive = true;
  // The budget: all of solver.max_iterations, or the caller's, less what the pre-solve took.
  SolverParams within = sp_;
  if (max_it >= 0) within.max_iterations = max_it;
  within.max_iterations = std::max(1, within.max_iterations - pre.iterations);
  for (RealField* fld : {&adh_.w, &adh_.d, &adh_.gap, &adh_.spread})
    if (fld->size() != n) fld->assign(n, 0.0);
  RealField &w = adh_.w, &d = adh_.d, &gap = adh_.gap;
  // Anderson mixing of the traction (made once, restarted for each solve).
  if (!adh_.mixer) adh_.mixer = std::make_unique<GuardedAnderson>(sp_.anderson, grid_);
  adh_.mixer->restart();
  PKResult pk{0, 1.0, 0.0, false};
  int used = 0;
  bool no_state = false;  // the load has no state (beyond the pull-off, or beyond the cap)
  double change = 1.0;    // relative change of the traction in the last step
  int first_step = 0;
  if (resume) {
    // Where the interrupted solve stood at the start of its step.
    first_step = resume->step;
    used = resume->used;
    change = resume->change;
    total_it_ = resume->iterations;
    info.adhesion_steps = resume->adhesion_steps;
    info.viscoelastic_steps = resume->viscoelastic_steps;
    capped_found_ = resume->capped_found;
    capped_acted_ = resume->capped_acted;
    capped_delta_ = resume->capped_delta;
    gw_mean_ref_ = resume->gw_mean_ref;
    g_mean_ref_ = resume->g_mean_ref;
    restore_adhesive_mixing(*resume);
  }
  // The restart point (the start of the step in progress) for a checkpoint or a stop: the loop's
  // numbers and the repulsive pressure at the start of the step (its solve changes it in place);
  // the traction and the mixing change only at the step's end, after its last poll.
  struct Top {
    int step, used, iterations, adhesion_steps, viscoelastic_steps;
    double change;
    bool capped_found, capped_acted;
    double capped_delta, gw, g;
  } top{};
  RealField p_top;
  const bool keep_top = restartable && (static_cast<bool>(stop_) || static_cast<bool>(checkpoint_));
  struct ClearMaker {
    std::function<void()>* maker;
    ~ClearMaker() {
      if (maker) *maker = nullptr;
    }
  } clear_maker{keep_top ? &restart_maker_ : nullptr};
  if (keep_top)
    restart_maker_ = [&] {
      auto rp = std::make_unique<AdhesiveRestartPoint>();
      AdhesiveRestart& st = rp->state;
      st.step = top.step;
      st.used = top.used;
      st.pre_iterations = pre.iterations;
      st.iterations = top.iterations;
      st.adhesion_steps = top.adhesion_steps;
      st.viscoelastic_steps = top.viscoelastic_steps;
      st.change = top.change;
      st.capped_found = top.capped_found;
      st.capped_acted = top.capped_acted;
      st.capped_delta = top.capped_delta;
      st.gw_mean_ref = top.gw;
      st.g_mean_ref = top.g;
      save_adhesive_mixing(st);
      st.repulsion = p_top;
      rp->fields.pressure.resize(n);
      parallel_for(nl, [&](std::ptrdiff_t i) { rp->fields.pressure[i] = p_top[i] - a[i]; });
      rp->fields.adhesion = a;
      rp->fields.tx.assign(n, 0.0);
      rp->fields.ty.assign(n, 0.0);
      adh_restart_ = std::move(rp);
    };
  info.status = "";
  for (int step = first_step;; ++step) {
    if (keep_top) {
      top = Top{step,       used,          total_it_,     info.adhesion_steps, info.viscoelastic_steps,
                change,     capped_found_, capped_acted_, capped_delta_,       gw_mean_ref_,
                g_mean_ref_};
      p_top = p;
    }
    ++info.adhesion_steps;
    apply_normal_response(a, w);  // the normal displacement the adhesive traction causes (C_zz a)
    if (w_extra)                  // and the friction's (C_z.tau)
      parallel_for(nl, [&](std::ptrdiff_t i) { w[i] += (*w_extra)[i]; });
    LoadParams inner = load;
    if (load.mode != LoadMode::Approach) {
      // The repulsion carries the load plus the adhesive pull.
      const double pull = grid_sum(grid_, [&](std::size_t i) { return a[i]; }) * grid_.cell_area();
      inner.value += load.mode == LoadMode::Force ? pull : pull / grid_.area();
      if (!(inner.value > 0)) {
        info.status = kBeyondPullOff;
        no_state = true;
        break;
      }
      // Capped (plastic saturation), the repulsion can carry at most H over the cell: a load
      // and pull beyond it have no state (e.g. sigma0 >= H, where the pull grows with the
      // contact as fast as the repulsion can).
      const double inner_mean = load.mode == LoadMode::Force ? inner.value / grid_.area() : inner.value;
      if (inter_.plastic() && !(inner_mean < inter_.hardness)) {
        info.status =
            "not converged: the load plus the adhesive pull reach interaction.hardness over the whole cell "
            "(with sigma0 = work_of_adhesion / range near or above the hardness the pull grows with the "
            "contact as fast as the repulsion can carry it); follow the path under approach control "
            "(load.approach, gfmd curve --approaches)";
        no_state = true;
        break;
      }
    }
    // Each repulsive solve to the traction's last change (no tighter than the tolerance): the
    // steps are as many either way (the cohesive zones move over them), tighter solves only cost.
    const double inner_tol = adhesive_inner_tolerance(tol, change);
    pk = solve_repulsive(inner, w, p, inner_tol, std::max(1, within.max_iterations - used), info);
    used += pk.iterations;
    // The gap of this step's state, C_zz (p - a) - C_z.tau + p/k + g0 - delta, and the law on it.
    parallel_for(nl, [&](std::ptrdiff_t i) { d[i] = p[i] - a[i]; });
    apply_normal_response(d, gap);
    if (w_extra) parallel_for(nl, [&](std::ptrdiff_t i) { gap[i] -= (*w_extra)[i]; });
    // In one pass with the gap: the elastic energy 1/2 sum (p - a) C_zz (p - a) dA of this step's
    // state (gap holds C_zz (p - a), less the friction's displacement, until it is completed
    // here; with friction solve() makes the elastic energy again from the displacements) and
    // the harmonic repulsion's 1/2 sum p^2 / k dA.
    const double ik = inv_k_, delta = pk.delta;
    const auto en = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      acc[0] += d[i] * gap[i];
      acc[1] += p[i] * p[i];
      gap[i] += ik * p[i] + g0_[i] - delta;
    });
    info.elastic_energy = 0.5 * en[0] * grid_.cell_area();
    const double repulsion_energy = 0.5 * en[1] * inv_k_ * grid_.cell_area();
    gap_spread(gap, d, adh_.spread);
    // The adhesive energy goes with the traction this step used (a): its cell law's spread is
    // the one it was made from, so the energy of a converged state is its own.
    const auto sums = grid_sums<3>(grid_, [&](std::size_t i, std::array<double, 3>& acc) {
      const double an = s0 * adhesive_fraction(gap[i], adh_.spread[i], rho);
      acc[0] += std::abs(an - a[i]);
      acc[1] += an;
      acc[2] += s0 * adhesive_potential(gap[i], adh_.spread[i], rho);
      d[i] = an;
    });
    info.adhesive_energy = sums[2] * grid_.cell_area();
    info.energy = info.elastic_energy + info.adhesive_energy + repulsion_energy;
    change = relative_change(sums[0], sums[1]);
    info.status =
        outer_status(change, tol, pk.converged, inner_tol, used, step, within, "the adhesive traction");
    if (!info.status.empty()) break;
    // The safeguard (GuardedAnderson): near an instability (the jump-off) an unguarded
    // extrapolation throws the state over the barrier onto the other branch (out of contact
    // early: at lambda = 2.5 it left at P = -1.24 pi w R where the plain steps follow Maugis's
    // branch to -0.87).
    adh_.mixer->advance(a, d, change, 0.0, s0);
  }
  info.converged = info.status == "converged";
  info.no_state = no_state;
  // On a viscoelastic body: why its last repulsive solve did not settle, if it did not.
  if (!info.converged && !no_state && !pk.converged && !visco_.last_failure.empty())
    info.status += "; the last viscoelastic solve: " + visco_.last_failure;
  if (!info.converged && !no_state) {
    // The usual cause: cohesive zones narrower than a cell or two, whose edges the grid traps.
    const auto z = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      if (a[i] > 0 && !(p[i] > 0)) acc[0] += 1.0;
      if (a[i] > 0 && a[i] < s0 * (1.0 - 1e-9)) acc[1] += 1.0;
    });
    if (z[1] > 0) add_cohesive_zones(info.status, z[0] / z[1]);
  }
  parallel_for(nl, [&](std::ptrdiff_t i) { p[i] -= a[i]; });
  adh_.repulsive = false;
  pk.iterations = used + pre.iterations;
  pk.converged = info.converged;
  return pk;
}

}  // namespace gfmd
