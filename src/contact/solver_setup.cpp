// The contact solver's set-up and its services to the fixed point: the compliance table and
// the device, displacements from the tractions, the independent residual, polls (stop
// requests, progress, checkpoints) and the final checks. The fixed point is src/contact/solver.cpp.
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
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

std::pair<std::string, std::string> device_lacks(const InteractionParams& inter, const FrictionParams& fric,
                                                 bool viscoelastic, bool elastic_indenter) {
  const std::string there =
      " is not implemented on the cuda backend: use solver.backend = \"threads\" (or \"serial\")";
  if (viscoelastic) return {"elastic.viscoelastic", "viscoelastic bodies" + there};
  // The device's slip reads the pair's compliance table; sliding needs the body's own.
  if (elastic_indenter && fric.coefficient > 0)
    return {"indenter.contact_modulus", "friction under an elastic indenter" + there};
  const InteractionType& model = interaction_type(inter);
  if (!model.on_device) return {"interaction.model", "\"" + model.name + "\"" + there};
  if (inter.plastic()) return {"interaction.hardness", "plastic saturation" + there};
  const FrictionLawType& law = friction_law_type(fric.law.kind);
  if (fric.coefficient > 0 && !law.on_device) return {"friction.law", "\"" + law.name + "\"" + there};
  if (fric.stick_acceleration > 0)
    return {"friction.stick_acceleration",
            "is not implemented on the cuda backend: set it to 0 (plain splitting) there"};
  return {};
}

ContactSolver::ContactSolver(const ElasticBody& body, const Topography& topo, const InteractionParams& inter,
                             const FrictionParams& fric, const SolverParams& solver)
    : body_(body),
      grid_(body.grid()),
      fft_(body.grid(), solver.fft_planner),
      inter_(inter),
      fric_(fric),
      sp_(solver),
      g0_(body.grid().local_size()) {
  // On a slab (a distributed run) the topography holds this process's rows of heights.
  if (topo.grid.nx != grid_.nx || topo.grid.ny != grid_.ny || topo.h.size() != grid_.local_size())
    throw ParameterError("topo", "the topography's grid does not match the elastic body's");
  if (inter_.hard_wall) {
    k_ = std::numeric_limits<double>::infinity();
    inv_k_ = 0.0;
  } else {
    k_ = inter_.stiffness_on(body.params().contact_modulus, grid_.dx());
    inv_k_ = 1.0 / k_;
  }
  const double hmax = grid_max(
      grid_, [&](std::size_t i) { return topo.h[i]; }, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < g0_.size(); ++i) g0_[i] = hmax - topo.h[i];
  const auto sums = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
    acc[0] += g0_[i];
    acc[1] += g0_[i] * g0_[i];
  });
  const double points = static_cast<double>(grid_.size());
  const double m = sums[0] / points;
  g0_rms_ = std::sqrt(std::max(0.0, sums[1] / points - m * m));
  deriv_ = fric_.derivative();
  const bool exact_friction = fric_.coefficient > 0 && !fric_.regularized();
  const FrictionLawType& law = friction_law_type(fric_.law.kind);
  if (exact_friction && !law.set_valued_stick)
    throw ParameterError("friction.regularization", "must be positive with friction.law = \"" + law.name +
                                                        "\": its stick is solved regularised (near rest)");
  if (inter_.adhesive()) {
    if (!(inter_.range > 0) || !std::isfinite(inter_.range) || !std::isfinite(inter_.work_of_adhesion))
      throw ParameterError("interaction.range", "must be positive and finite with adhesion");
  }
  if (body.viscoelastic()) {
    // The observables measure along the friction's direction, the body is excited along its own.
    if (body.visco().direction_deg != fric_.direction_deg)
      throw ParameterError("friction.direction", "must be the viscoelastic body's sliding direction");
  }
  if (backend().name() == "cuda") {
    if (const auto [key, why] = device_lacks(inter_, fric_, body.viscoelastic(), body.elastic_indenter());
        !key.empty())
      throw ParameterError(key, why);
    // The fields live on the device; the host keeps only g0 (the final residual check).
    DeviceProblem pr;
    pr.body = &body_;
    pr.g0 = &g0_;
    pr.g0_rms = g0_rms_;
    pr.stiffness = k_;
    pr.inv_stiffness = inv_k_;
    pr.hard_wall = inter_.hard_wall;
    pr.friction = fric_;
    pr.solver = sp_;
    pr.adhesive = inter_.adhesive();
    pr.adhesive_stress = inter_.adhesive_stress();
    pr.range = inter_.range;
    pr.adhesive_spread = &adh_.spread;
    // Steps of the stick-slip iteration (exact law with friction only); the second for an
    // automatic derivative that turns to upwind2.
    if (exact_friction) {
      pr.stick_step = stick_step(deriv_);
      if (!fric_.slip_derivative && deriv_ == SlipDerivative::Spectral)
        pr.stick_step_upwind2 = stick_step(SlipDerivative::Upwind2);
    }
    device_ = make_device_solve(pr);
    return;
  }
  for (auto* s : {&s1_, &s2_, &s3_}) s->resize(grid_.spectral_size());
  for (auto* f : {&cg_g_, &cg_t_, &cg_r_}) f->assign(grid_.local_size(), 0.0);
  czz_n_.resize(body.modes().size());
  for (std::size_t k = 0; k < czz_n_.size(); ++k)
    czz_n_[k] = body.modes()[k].czz / static_cast<double>(grid_.size());
  if (body.viscoelastic()) {
    // The complex normal response Z (c C_zz on a body alone, c = E0/E(omega); under an elastic
    // indenter c C_zz plus the indenter's C_zz) split as |Z| + (Z - |Z|): the elastic compliance
    // at the response's magnitude (docs/solver.md, "Viscoelastic bodies": it beat the storage
    // modulus E0/E', 80 against 168 iterations at E_inf/E0 = 1000, because the mixed steps see the
    // spectrum e^{-i delta} on the unit circle).
    visco_.rest_n.resize(czz_n_.size());
    const double inv_n = 1.0 / static_cast<double>(grid_.size());
    for (std::size_t k = 0; k < czz_n_.size(); ++k) {
      const cplx z = body.normal_response(k);
      const double m = std::abs(z);
      visco_.rest_n[k] = -(z - m) * inv_n;
      czz_n_[k] = m * inv_n;
    }
  }
  use_derivative(deriv_);
}

ContactSolver::~ContactSolver() = default;

SolveInfo ContactSolver::solve_on_device(const LoadParams& load, ContactFields& f) {
  current_ = &f;
  const DeviceHooks hooks{&progress_, &stop_, &checkpoint_, checkpoint_interval_s_};
  SolveInfo info = device_->solve(load, f, hooks, total_it_);
  const auto t0 = Clock::now();
  check_final_state(info, f, info.approach);
  info.device_bytes = device_->device_bytes();
  info.wall_time_s += std::chrono::duration<double>(Clock::now() - t0).count();
  return info;
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

double ContactSolver::residual(const ContactFields& f, double delta) {
  // Independent check of the final state: gap from the full 3D displacement.
  const auto gap = [&](std::size_t i) { return g0_[i] - delta - f.uz[i]; };
  const double H = inter_.hardness;  // inf: no cap (min(x, inf) = x)
  // The repulsion (the pressure; with adhesion p + a) against the interaction.
  double r;
  if (!inter_.hard_wall) {
    const double num = grid_sum(grid_, [&](std::size_t i) {
      const double d = f.repulsion(i) - std::min(k_ * std::max(0.0, -gap(i)), H);
      return d * d;
    });
    const double den = grid_sum(grid_, [&](std::size_t i) { return f.repulsion(i) * f.repulsion(i); });
    r = den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  } else {
    const double num = grid_sum(grid_, [&](std::size_t i) {
      const double g = gap(i), pr = f.repulsion(i);
      if (pr >= H) return g > 0 ? g * g : 0.0;  // at the cap: overlap is plastic flow
      if (pr > 0) return g * g;
      return g < 0 ? g * g : 0.0;
    });
    const double mean =
        grid_sum(grid_, [&](std::size_t i) { return g0_[i]; }) / static_cast<double>(grid_.size());
    const double den = grid_sum(grid_, [&](std::size_t i) { return (g0_[i] - mean) * (g0_[i] - mean); });
    r = den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
  if (!inter_.adhesive()) return r;
  // With adhesion also the adhesive traction a against the cohesive law on the cells
  // (adhesive_fraction with the gap's spread of the last step), relative to the size of the two
  // pressures.
  const double s0 = inter_.adhesive_stress(), rho = inter_.range;
  const auto sums = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
    const double g = gap(i), pr = f.repulsion(i), ai = f.adhesion[i];
    const double law =
        adh_.spread.size() == f.adhesion.size() ? s0 * adhesive_fraction(g, adh_.spread[i], rho) : ai;
    acc[0] += (ai - law) * (ai - law);
    acc[1] += pr * pr + ai * ai;
  });
  return std::max(r, sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) : std::sqrt(sums[0]));
}

void ContactSolver::poll(const ContactFields* f, const std::function<void()>& settle,
                         const std::function<void()>& unsettle) {
  bool stop = stop_ && stop_();
  bool save = false;
  double now = 0.0;
  if (checkpoint_ && f) {
    now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    save = now - last_checkpoint_ >= checkpoint_interval_s_;
  }
  // Every process polls at the same steps: a stop request seen by one stops them all, and
  // rank 0's clock says when a checkpoint is due (saving one is a collective).
  if (grid_.is_slab()) {
    const unsigned all = mpi::any_bits((stop ? 1u : 0u) | (save && mpi::root() ? 2u : 0u));
    stop = (all & 1u) != 0;
    save = (all & 2u) != 0;
  }
  if ((stop || save) && settle) settle();
  // In the friction loop: its restart point (what the checkpoint holds; kept after a stop).
  if ((stop || save) && restart_maker_) restart_maker_();
  if (stop) throw Interrupted("interrupted at iteration " + std::to_string(total_it_));
  if (save) {
    last_checkpoint_ = now;
    checkpoint_(*f);
    restart_.reset();
    adh_restart_.reset();
    if (unsettle) unsettle();
  }
}

bool ContactSolver::finish(ContactFields& f, SolveInfo& info) {
  if (device_) return false;
  const std::size_t n = grid_.local_size();
  for (auto* fld : {&f.pressure, &f.tx, &f.ty})
    if (fld->size() != n) fld->assign(n, 0.0);
  if (fric_.coefficient == 0.0) f.stick.clear();
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) fld->resize(n);
  update_displacements(f);
  if (inter_.adhesive() && f.adhesion.size() == n) {
    // The residual's cell law reads the gap's spread over each cell, which a solve leaves from its
    // last step: made here from the given state (the law's gap, g0 - delta - u_z + p_rep/k).
    for (RealField* fld : {&adh_.gap, &adh_.d, &adh_.spread})
      if (fld->size() != n) fld->assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      adh_.gap[i] = g0_[i] - info.approach - f.uz[i] + inv_k_ * f.repulsion(i);
    gap_spread(adh_.gap, adh_.d, adh_.spread);
  }
  check_final_state(info, f, info.approach);
  return true;
}

void ContactSolver::check_final_state(SolveInfo& info, ContactFields& f, double delta) {
  f.gap.resize(f.uz.size());
  for (std::size_t i = 0; i < f.gap.size(); ++i) f.gap[i] = std::max(0.0, g0_[i] - delta - f.uz[i]);
  info.residual = residual(f, delta);
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
}

}  // namespace gfmd
