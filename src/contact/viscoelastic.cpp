// The normal problem of a viscoelastic body in steady sliding: the response per mode
// c C_zz (c = E0/E(omega), complex: the operator is not symmetric) split into a symmetric part
// m C_zz, m = |c| (the elastic compliance at each mode's modulus magnitude |E(omega)|), which
// Polonsky-Keer solves, and the rest (c - m) C_zz, whose displacement from the last pressure is
// held fixed during that solve (w = -(c - m) C_zz p). See solver.hpp and docs/solver.md
// ("Viscoelastic bodies").
//
// On a full contact the plain step multiplies each mode's error by 1 - c/m = 1 - e^{-i delta}
// (delta the loss angle), of modulus 2 sin(delta/2): a contraction for delta < 60 degrees. The
// pressure is Anderson-mixed (safeguarded, as adhesion's traction); on this linear map that acts
// as GMRES, whose rate depends on how far the spectrum e^{-i delta} of the preconditioned
// operator stays from the origin: on the unit circle, within 90 degrees of 1, for every delta.
// (The storage split m = 1/Re(1/c) contracts plainly by sin(delta) for every delta, but puts
// that spectrum on the circle through 0 and 1: with mixing it took twice the iterations at
// E_inf/E0 = 1000.)
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/reduce.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;

double ContactSolver::hysteresis_dissipation(const ContactFields& f, bool friction) {
  // Parseval over the half spectrum: each mode off the kx = 0 and Nyquist columns stands for
  // itself and its conjugate (weight 2). Per mode (q.e_s) Im(t* R t) of the tractions
  // t = (tau_x, tau_y, -p) and the complex response R: on a body alone R = c C with C Hermitian,
  // so Im(t* R t) = Im c (t* C t); an elastic indenter's part of R is Hermitian and adds nothing
  // (it stores, it does not dissipate). The wave numbers are the derivative's (0 on the Nyquist
  // lines), as in the response factors.
  fft_.forward(f.pressure.data(), s1_.data());
  if (friction) {
    fft_.forward(f.tx.data(), s2_.data());
    fft_.forward(f.ty.data(), s3_.data());
  }
  const int nxh = grid_.nxh();
  const double th = body_.visco().direction_deg * std::numbers::pi / 180.0;  // the factors' direction
  const double ex = std::cos(th), ey = std::sin(th);
  std::vector<double> rows(static_cast<std::size_t>(grid_.rows()), 0.0);
  for_rows(grid_.rows(), [&](int row) {
    const int iky = grid_.y0 + row;
    double sum = 0.0;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      const double qs = grid_.qx_deriv(ikx) * ex + grid_.qy_deriv(iky) * ey;
      if (qs == 0.0) continue;
      double loss = body_.normal_response(k).imag() * std::norm(s1_[k]);
      if (friction) {
        const std::array<cplx, 9> c = body_.response_compliance(ikx, iky);
        const std::array<cplx, 3> t{s2_[k], s3_[k], -s1_[k]};
        loss = 0.0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) loss += (std::conj(t[a]) * c[3 * a + b] * t[b]).imag();
      }
      const bool self = ikx == 0 || (grid_.nx % 2 == 0 && ikx == grid_.nx / 2);
      sum += (self ? 1.0 : 2.0) * qs * loss;
    }
    rows[static_cast<std::size_t>(row)] = sum;
  });
  const double n = static_cast<double>(grid_.size());
  return add_rows(grid_, std::move(rows), 1)[0] * grid_.cell_area() / n;
}

ContactSolver::PKResult ContactSolver::solve_normal_viscoelastic(const LoadParams& load,
                                                                 const RealField* w_extra, RealField& p,
                                                                 double tol, int max_it, int& steps,
                                                                 std::string& status) {
  const std::size_t n = grid_.local_size();
  static const RealField none;
  if (body_.visco().velocity == 0.0) {
    // At rest every mode is relaxed: the elastic solve with E0, bit for bit.
    ++steps;
    const PKResult pk = w_extra ? solve_normal(load, *w_extra, false, p, tol, max_it)
                                : solve_normal(load, none, true, p, tol, max_it);
    status = pk.converged ? "converged" : "not converged: iteration limit reached";
    return pk;
  }
  if (uses_active_set()) return solve_normal_active_set(load, w_extra, p, tol, max_it, steps, status);
  if (visco_.w.size() != n) visco_.w.assign(n, 0.0);
  RealField& w = visco_.w;
  if (!visco_.mixer) visco_.mixer = std::make_unique<GuardedAnderson>(sp_.anderson, grid_);
  visco_.mixer->restart();
  // The iterate x is the pressure the rest's displacement is taken from; a warm start's
  // pressure is the first.
  RealField x(p.begin(), p.end());
  PKResult pk{0, 1.0, 0.0, false};
  int used = 0;
  double change = 1.0;
  // The repulsion's range: capped at the hardness with plastic saturation (inf: none).
  const double cap = inter_.hardness;
  SolverParams within = sp_;
  within.max_iterations = max_it;
  for (int step = 0;; ++step) {
    ++steps;
    // w = -(c - m) C_zz x (+ the caller's offset: the friction's normal displacement), one
    // spectral pass with the complex table.
    fft_.forward(x.data(), s1_.data());
    const auto ns = static_cast<std::ptrdiff_t>(s1_.size());
    parallel_for(ns, [&](std::ptrdiff_t k) { s1_[k] *= visco_.rest_n[k]; });
    fft_.backward_unscaled_destroying(s1_.data(), w.data());
    if (w_extra)
      parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t i) { w[i] += (*w_extra)[i]; });
    // Each symmetric solve to a tenth of the pressure's last change (no tighter than the
    // tolerance), from the last solution.
    const double inner_tol = std::max(tol, 0.1 * change);
    pk = solve_normal(load, w, false, p, inner_tol, std::max(1, max_it - used));
    used += pk.iterations;
    const auto sums = grid_sums<2>(grid_, [&](std::size_t i, std::array<double, 2>& acc) {
      acc[0] += std::abs(p[i] - x[i]);
      acc[1] += std::abs(p[i]);
    });
    change = relative_change(sums[0], sums[1]);
    // Stopping far from settled with the hard wall: at large loss angles (a stiff glassy modulus
    // near the loss peak) the contact edge's cells switch between contact and gap from one step to
    // the next, which neither more steps nor the mixing cure (docs/solver.md).
    const bool cycling = inter_.hard_wall && change > kViscoStallChange;
    status =
        outer_status(change, tol, pk.converged, inner_tol, used, step, within, "the viscoelastic pressure",
                     cycling ? "with the hard wall at large loss angles the contact edge's cells switch "
                               "between contact and gap from step to step: the active set "
                               "(solver.viscoelastic_method = \"active_set\") or the harmonic interaction "
                               "(interaction.model = \"harmonic\") settles there (docs/solver.md, "
                               "\"Viscoelastic bodies\")"
                             : nullptr);
    if (!status.empty()) break;
    visco_.mixer->advance(x, p, change, 0.0, cap);  // p is the step's image of x
  }
  pk.iterations = used;
  pk.converged = status == "converged";
  return pk;
}

void ContactSolver::apply_normal_response(const RealField& in, RealField& out) {
  if (visco_.rest_n.empty() || body_.visco().velocity == 0.0) {
    apply_compliance(in, out);
    return;
  }
  // c C_zz / N = m C_zz / N (czz_n_) - rest_n: one spectral pass with the complex table.
  fft_.forward(in.data(), s1_.data());
  const auto ns = static_cast<std::ptrdiff_t>(s1_.size());
  parallel_for(ns, [&](std::ptrdiff_t k) { s1_[k] *= czz_n_[k] - visco_.rest_n[k]; });
  fft_.backward_unscaled_destroying(s1_.data(), out.data());
}

ContactSolver::PKResult ContactSolver::solve_repulsive(const LoadParams& load, const RealField& w,
                                                       RealField& p, double tol, int max_it,
                                                       SolveInfo& info) {
  if (!body_.viscoelastic()) return solve_normal(load, w, false, p, tol, max_it);
  std::string why;
  const PKResult pk = solve_normal_viscoelastic(load, &w, p, tol, max_it, info.viscoelastic_steps, why);
  visco_.last_failure = pk.converged ? "" : why;
  return pk;
}

ContactSolver::PKResult ContactSolver::solve_viscoelastic(const LoadParams& load, ContactFields& f,
                                                          double tol, SolveInfo& info) {
  const PKResult pk = solve_normal_viscoelastic(load, nullptr, f.pressure, tol, sp_.max_iterations,
                                                info.viscoelastic_steps, info.status);
  info.converged = info.status == "converged";
  info.hysteresis_dissipation = body_.visco().velocity == 0.0 ? 0.0 : hysteresis_dissipation(f, false);
  return pk;
}

}  // namespace gfmd
