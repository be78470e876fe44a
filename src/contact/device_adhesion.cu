// The CUDA contact solve (device_solve_class.cuh): the adhesive normal problem, adhesion.cpp's
// steps on the device, step for step. Each step is a repulsive (Polonsky-Keer) solve under the
// displacement of a held adhesive traction, the traction's image is the cohesive law on the cells
// (contact/cohesive_law.hpp, written once for both backends) and the steps are Anderson-mixed
// with the host's safeguard (DeviceGuarded).

#include "device_solve_class.cuh"

namespace gfmd {

using namespace contact_detail;
using namespace cuda_kernels;
using namespace contact_device;
using namespace device_solve_detail;

void CudaSolve::setup_adhesion(const DeviceProblem& pr) {
  adhesive_ = true;
  s0_ = pr.adhesive_stress;
  range_ = pr.range;
  spread_out_ = pr.adhesive_spread;
  for (auto* a : {&a_, &ad_, &agap_, &aspread_, &awx_}) a->allocate(n_, &bytes_, "an adhesion field");
  // The spectral derivative's symbols i q_x and i q_y (0 on the Nyquist lines) with 1/N folded in:
  // the host's table (ContactSolver::gap_spread).
  const int nxh = grid_.nxh();
  std::vector<double> qx(ns_), qy(ns_);
  const double inv_n = 1.0 / static_cast<double>(n_);
  for (int row = 0; row < grid_.ny; ++row)
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      qx[k] = slip_derivative_symbol(grid_, ikx, row, 1.0, 0.0, SlipDerivative::Spectral).imag() * inv_n;
      qy[k] = slip_derivative_symbol(grid_, ikx, row, 0.0, 1.0, SlipDerivative::Spectral).imag() * inv_n;
    }
  qx_.allocate(ns_, &bytes_, "the derivative table");
  qy_.allocate(ns_, &bytes_, "the derivative table");
  cuda_check(cudaMemcpy(qx_.get(), qx.data(), ns_ * sizeof(double), cudaMemcpyHostToDevice), "upload");
  cuda_check(cudaMemcpy(qy_.get(), qy.data(), ns_ * sizeof(double), cudaMemcpyHostToDevice), "upload");
  if (sp_.anderson > kMaxDepth)
    throw InputError("solver.anderson",
                     "the CUDA backend mixes at most " + std::to_string(kMaxDepth) + " steps");
  amix_.emplace(sp_.anderson, n_, &bytes_);
}

void CudaSolve::gap_spread(const double* gap, double* gx, double* spread) {
  // |g_x| dx + |g_y| dy by one forward and two inverse transforms (adhesion.cpp).
  forward(gap, s2_.get());
  cufftDoubleComplex* s2 = s2_.get();
  cufftDoubleComplex* s3 = s3_.get();
  const double* qx = qx_.get();
  const double* qy = qy_.get();
  launch_each(ns_, [=] __device__(std::size_t k) {
    const cufftDoubleComplex iv{-s2[k].y, s2[k].x};  // i times the mode
    s3[k] = cscale(qy[k], iv);
    s2[k] = cscale(qx[k], iv);
  });
  backward(s2_.get(), gx);
  backward(s3_.get(), spread);
  const double dx = grid_.dx(), dy = grid_.dy();
  launch_each(n_, [=] __device__(std::size_t i) { spread[i] = fabs(gx[i]) * dx + fabs(spread[i]) * dy; });
}

CudaSolve::PK CudaSolve::solve_adhesive(const LoadParams& load, double tol, SolveInfo& info, bool w_extra,
                                        int max_it) {
  const std::size_t n = n_;
  const double s0 = s0_, rho = range_, ik = inv_k_;
  double* a = a_.get();
  double* p = p_.get();  // the repulsive pressure during the steps, the net one at the end
  double* d = ad_.get();
  double* gap = agap_.get();
  double* spread = aspread_.get();
  double* w = w_.get();
  double* wx = awx_.get();  // the friction's normal displacement (w_extra)
  const double* g0 = g0_.get();
  if (w_extra) cuda_check(cudaMemcpy(wx, w, n * sizeof(double), cudaMemcpyDeviceToDevice), "a field");
  const auto sum_a = [&] {
    return red_.run<1>(n, [=] __device__(std::size_t i, double* acc) { acc[0] += a[i]; })[0];
  };
  // A tensile (or zero) load under load control starts from the state at first touch.
  PK pre{0, 0.0, 0.0, true};
  if (load.mode != LoadMode::Approach && !(load.value > 0) && !(sum_a() > 0)) {
    pre = solve_adhesive(LoadParams{LoadMode::Approach, 0.0}, tol, info, w_extra, max_it);
    if (!info.converged) return pre;
  }
  launch_each(n, [=] __device__(std::size_t i) { p[i] = fmax(0.0, p[i] + a[i]); });
  adhesion_active_ = true;
  SolverParams within = sp_;
  if (max_it >= 0) within.max_iterations = max_it;
  within.max_iterations = std::max(1, within.max_iterations - pre.iterations);
  amix_->restart();
  PK pk{0, 1.0, 0.0, false};
  int used = 0;
  bool no_state = false;
  double change = 1.0;
  info.status = "";
  const double cell = grid_.cell_area();
  for (int step = 0;; ++step) {
    ++info.adhesion_steps;
    apply_compliance(a, w, 1.0);  // C_zz a
    if (w_extra) launch_each(n, [=] __device__(std::size_t i) { w[i] += wx[i]; });
    LoadParams inner = load;
    if (load.mode != LoadMode::Approach) {
      const double pull = sum_a() * cell;
      inner.value += load.mode == LoadMode::Force ? pull : pull / grid_.area();
      if (!(inner.value > 0)) {
        info.status = kBeyondPullOff;
        no_state = true;
        break;
      }
    }
    const double inner_tol = adhesive_inner_tolerance(tol, change);
    {
      const Phase ph(this, 0);
      pk = solve_normal(inner, false, inner_tol, std::max(1, within.max_iterations - used));
    }
    used += pk.iterations;
    launch_each(n, [=] __device__(std::size_t i) { d[i] = p[i] - a[i]; });
    apply_compliance(d, gap, 1.0);
    const double delta = pk.delta;
    const auto en = red_.run<2>(n, [=] __device__(std::size_t i, double* acc) {
      double v = gap[i];
      if (w_extra) v -= wx[i];
      acc[0] += d[i] * v;
      acc[1] += p[i] * p[i];
      gap[i] = v + ik * p[i] + g0[i] - delta;
    });
    info.elastic_energy = 0.5 * en[0] * cell;
    const double repulsion_energy = 0.5 * en[1] * ik * cell;
    gap_spread(gap, d, spread);
    const auto sums = red_.run<3>(n, [=] __device__(std::size_t i, double* acc) {
      const double an = s0 * adhesive_fraction(gap[i], spread[i], rho);
      acc[0] += fabs(an - a[i]);
      acc[1] += an;
      acc[2] += s0 * adhesive_potential(gap[i], spread[i], rho);
      d[i] = an;
    });
    info.adhesive_energy = sums[2] * cell;
    info.energy = info.elastic_energy + info.adhesive_energy + repulsion_energy;
    change = relative_change(sums[0], sums[1]);
    info.status =
        outer_status(change, tol, pk.converged, inner_tol, used, step, within, "the adhesive traction");
    if (!info.status.empty()) break;
    amix_->advance(red_, a, d, change, 0.0, s0);
  }
  info.converged = info.status == "converged";
  info.no_state = no_state;
  if (!info.converged && !no_state) {
    const auto z = red_.run<2>(n, [=] __device__(std::size_t i, double* acc) {
      if (a[i] > 0 && !(p[i] > 0)) acc[0] += 1.0;
      if (a[i] > 0 && a[i] < s0 * (1.0 - 1e-9)) acc[1] += 1.0;
    });
    if (z[1] > 0) add_cohesive_zones(info.status, z[0] / z[1]);
  }
  launch_each(n, [=] __device__(std::size_t i) { p[i] -= a[i]; });
  adhesion_active_ = false;
  pk.iterations = used + pre.iterations;
  pk.converged = info.converged;
  return pk;
}

}  // namespace gfmd
