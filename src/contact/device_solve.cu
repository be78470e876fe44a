// The contact solve on a CUDA device: ContactSolver's algorithm (normal.cpp, friction.cpp,
// solver.cpp) with every field in device memory, cuFFT D2Z/Z2D for the transforms, one
// kernel per fused pass and deterministic block sums (fixed launch shape, partials added in
// block order). The control flow of the friction fixed point is the host's, step for step;
// the host reads back only the few sums each step decides on. See device_solve.hpp.
//
// This file: the set-up, the memory estimate, the transforms and the normal (Polonsky-Keer) solve;
// the class is device_solve_class.cuh.
#include "device_solve_class.cuh"

namespace gfmd {

using namespace contact_detail;
using namespace cuda_kernels;
using namespace contact_device;
using namespace device_solve_detail;

std::size_t device_solve_bytes(const Grid& g, bool friction, bool adhesion, int anderson) {
  const std::size_t n = g.size(), m = spectral_modes(g);
  // cuFFT's estimate of the transforms' work area (one area for both plans).
  std::size_t wf = 0, wb = 0;
  if (cufftEstimate2d(g.ny, g.nx, CUFFT_D2Z, &wf) != CUFFT_SUCCESS) wf = 0;
  if (cufftEstimate2d(g.ny, g.nx, CUFFT_Z2D, &wb) != CUFFT_SUCCESS) wb = 0;
  // g0, p, w, three CG fields; three spectra; C_zz/N and the compliance per mode.
  std::size_t b = 6 * n * sizeof(double) + 3 * m * sizeof(cufftDoubleComplex) +
                  m * (sizeof(double) + sizeof(ComplianceMode));
  // Friction: the iterate and its image (4), the splitting variable and the pressure's slip
  // (4), two flags and the support list per point; the derivative's symbol per mode.
  if (friction)
    b += 8 * n * sizeof(double) + 2 * n + n * sizeof(std::uint32_t) + m * sizeof(cufftDoubleComplex);
  // Adhesion: its traction, image, gap, spread and the friction's displacement; the derivative's
  // two symbols per mode; the mixing's last iterate, residual and kept image and its differences
  // (two floats per point and step of history).
  if (adhesion)
    b += 8 * n * sizeof(double) + 2 * m * sizeof(double) +
         2 * static_cast<std::size_t>(std::max(anderson, 0)) * n * sizeof(float);
  return b + std::max(wf, wb);
}

void require_device_fits(const Grid& grid, bool friction, bool adhesion, int anderson) {
  const DeviceStatus dev = cuda_device();
  if (!dev.available) throw InputError("solver.backend", "\"cuda\": " + dev.reason);
  const std::size_t need = device_solve_bytes(grid, friction, adhesion, anderson);
  // The mixing history grows with the support: a sixteenth of the card is kept for it and
  // the runtime. Said before anything is allocated.
  if (need > dev.free_bytes - std::min(dev.free_bytes, dev.total_bytes / 16)) {
    std::ostringstream os;
    os.precision(3);
    os << "a " << grid.nx << " x " << grid.ny << " solve" << (friction ? " with friction" : "") << " needs "
       << static_cast<double>(need) / (1u << 30) << " GiB on the device (" << dev.name << "), "
       << static_cast<double>(dev.free_bytes) / (1u << 30) << " GiB of its "
       << static_cast<double>(dev.total_bytes) / (1u << 30)
       << " GiB are free: use a smaller grid or solver.backend = \"threads\"";
    throw InputError("grid", os.str());
  }
}

CudaSolve::CudaSolve(const DeviceProblem& pr)
    : grid_(pr.body->grid()),
      fric_(pr.friction),
      sp_(pr.solver),
      k_(pr.stiffness),
      inv_k_(pr.inv_stiffness),
      g0_rms_(pr.g0_rms),
      modulus_dx_(pr.body->params().contact_modulus / pr.body->grid().dx()),
      hard_wall_(pr.hard_wall),
      gamma_(pr.stick_step),
      body_(pr.body),
      gamma_initial_(pr.stick_step),
      gamma_upwind2_(pr.stick_step_upwind2),
      deriv_kind_(pr.friction.derivative()) {
  if (grid_.is_slab())
    throw InputError("solver.backend", "\"cuda\" solves on one process (a distributed run uses \"threads\")");
  n_ = grid_.size();
  ns_ = spectral_modes(grid_);
  const bool friction = fric_.coefficient > 0;
  // Plans first (their work area counts), made without allocating it: one area serves both.
  std::size_t work_f = 0, work_b = 0;
  cufft_check(cufftCreate(&plan_fwd_), "plan");
  cufft_check(cufftCreate(&plan_bwd_), "plan");
  cufft_check(cufftSetAutoAllocation(plan_fwd_, 0), "plan");
  cufft_check(cufftSetAutoAllocation(plan_bwd_, 0), "plan");
  cufft_check(cufftMakePlan2d(plan_fwd_, grid_.ny, grid_.nx, CUFFT_D2Z, &work_f), "plan (D2Z)");
  cufft_check(cufftMakePlan2d(plan_bwd_, grid_.ny, grid_.nx, CUFFT_Z2D, &work_b), "plan (Z2D)");
  const std::size_t work = std::max(work_f, work_b);
  require_device_fits(grid_, friction, pr.adhesive, sp_.anderson);
  fft_work_.allocate(work, &bytes_, "the transforms' work area");
  cufft_check(cufftSetWorkArea(plan_fwd_, fft_work_.get()), "plan");
  cufft_check(cufftSetWorkArea(plan_bwd_, fft_work_.get()), "plan");
  red_.init(&bytes_);
  for (auto* a : {&g0_, &p_, &w_, &cg_g_, &cg_t_, &cg_r_}) a->allocate(n_, &bytes_, "a field");
  for (auto* a : {&s1_, &s2_, &s3_}) a->allocate(ns_, &bytes_, "a spectrum");
  upload(*pr.g0, g0_.get());
  std::vector<double> czz(ns_);
  const auto& modes = pr.body->modes();
  for (std::size_t k = 0; k < ns_; ++k) czz[k] = modes[k].czz / static_cast<double>(n_);
  czz_n_.allocate(ns_, &bytes_, "the compliance table");
  cuda_check(cudaMemcpy(czz_n_.get(), czz.data(), ns_ * sizeof(double), cudaMemcpyHostToDevice), "upload");
  modes_.allocate(ns_, &bytes_, "the compliance table");
  cuda_check(cudaMemcpy(modes_.get(), modes.data(), ns_ * sizeof(ComplianceMode), cudaMemcpyHostToDevice),
             "upload");
  if (pr.adhesive) setup_adhesion(pr);
  if (!friction) return;
  deriv_.allocate(ns_, &bytes_, "the derivative table");
  use_derivative(deriv_kind_);
  for (auto* a : {&tx_, &ty_, &ntx_, &nty_, &zx_, &zy_, &bx_, &by_}) a->allocate(n_, &bytes_, "a field");
  in_supp_.allocate(n_, &bytes_, "the support flags");
  flags_.allocate(n_, &bytes_, "the support flags");
  supp_.allocate(n_, &bytes_, "the support list");
  nsel_.allocate(1, &bytes_, "the support list");
  std::size_t sel = 0;
  thrust::counting_iterator<std::uint32_t> idx(0);
  cuda_check(cub::DeviceSelect::Flagged(nullptr, sel, idx, flags_.get(), supp_.get(), nsel_.get(),
                                        static_cast<std::int64_t>(n_)),
             "support selection");
  select_work_.allocate(std::max<std::size_t>(sel, 1), &bytes_, "the support selection");
}

void CudaSolve::use_derivative(SlipDerivative deriv) {
  // The slip derivative's symbol per mode: the host's table (ElasticBody::slip_symbols).
  const auto dir = direction();
  const std::vector<cplx> sym = body_->slip_symbols(dir.first, dir.second, deriv);
  std::vector<cufftDoubleComplex> dd(ns_);
  for (std::size_t k = 0; k < ns_; ++k) dd[k] = {sym[k].real(), sym[k].imag()};
  cuda_check(cudaMemcpy(deriv_.get(), dd.data(), ns_ * sizeof(cufftDoubleComplex), cudaMemcpyHostToDevice),
             "upload");
  deriv_kind_ = deriv;
  gamma_ = deriv == fric_.derivative() ? gamma_initial_ : gamma_upwind2_;
}

void CudaSolve::poll(bool with_fields, double pressure_scale) {
  bool stop = hooks_->stop && *hooks_->stop && (*hooks_->stop)();
  bool save = false;
  double now = 0.0;
  if (with_fields && hooks_->checkpoint && *hooks_->checkpoint) {
    now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    save = now - last_checkpoint_ >= hooks_->checkpoint_interval_s;
  }
  if (stop || save) {
    // The host sees the state reached: pressure and tractions.
    download(p_.get(), host_->pressure);
    if (pressure_scale != 1.0)
      for (double& v : host_->pressure) v *= pressure_scale;
    // With adhesion the traction that goes with the pressure (a warm start); inside the adhesive
    // steps p_ holds the repulsion: the host sees the net pressure p - a.
    if (adhesive_) download(a_.get(), host_->adhesion);
    if (adhesion_active_)
      for (std::size_t i = 0; i < n_; ++i) host_->pressure[i] -= host_->adhesion[i];
    if (tx_.get()) {
      download(tx_.get(), host_->tx);
      download(ty_.get(), host_->ty);
    }
  }
  if (stop) throw Interrupted("interrupted at iteration " + std::to_string(*total_));
  if (save) {
    last_checkpoint_ = now;
    (*hooks_->checkpoint)(*host_);
  }
}

void CudaSolve::apply_compliance(const double* in, double* out, double scale) {
  forward(in, s1_.get());
  cufftDoubleComplex* s = s1_.get();
  const double* c = czz_n_.get();
  launch_each(ns_, [=] __device__(std::size_t k) { s[k] = cscale(scale * c[k], s[k]); });
  backward(s1_.get(), out);
}

CudaSolve::PK CudaSolve::solve_normal(const LoadParams& load, bool w_zero, double tol, int max_it) {
  // normal.cpp's constrained conjugate gradients, pass for pass.
  const std::size_t n = n_;
  const bool load_ctrl = load.mode != LoadMode::Approach;
  const double pbar = load.mode == LoadMode::Force ? load.value / grid_.area() : load.value;
  const double delta_imp = load_ctrl ? 0.0 : load.value;
  const double ik = inv_k_;
  double* p = p_.get();
  const double* g0 = g0_.get();
  const double* w = w_zero ? nullptr : w_.get();
  double* g = cg_g_.get();
  double* t = cg_t_.get();
  double* r = cg_r_.get();
  double pending = 1.0;
  const double psum = red_.run<1>(n, [=] __device__(std::size_t i, double* acc) { acc[0] += p[i]; })[0];
  if (load_ctrl) {
    if (!(psum > 0))
      launch_each(n, [=] __device__(std::size_t i) { p[i] = pbar; });
    else
      pending = pbar * static_cast<double>(n) / psum;
  } else if (!(psum > 0)) {
    const double kk = hard_wall_ ? modulus_dx_ : k_;
    launch_each(
        n, [=] __device__(std::size_t i) { p[i] = kk * fmax(0.0, delta_imp + (w ? w[i] : 0.0) - g0[i]); });
  }
  bool conjugate = false;
  double gold = 1.0;
  const auto apply_pending = [&] {
    if (pending == 1.0) return;
    const double f = pending;
    launch_each(n, [=] __device__(std::size_t i) { p[i] *= f; });
    pending = 1.0;
  };
  PK res{0, 1.0, 0.0, false};
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    ++*total_;
    apply_compliance(p, g, pending);
    const double ref = gw_mean_ref_;
    const double gref = load_ctrl ? g_mean_ref_ : 0.0;
    const double fp = pending;
    const auto a = red_.run<5>(n, [=] __device__(std::size_t i, double* acc) {
      const double gw = w ? g0[i] - w[i] : g0[i];
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
    pending = 1.0;
    const double ns = a[0];
    if (ns == 0.0) {
      const double minimum = -red_.run<1, true>(
          n, [=] __device__(std::size_t i, double* acc) { acc[0] = fmax(acc[0], -g[i]); })[0];
      if (minimum >= 0.0) {
        res.converged = true;
        res.error = 0.0;
        res.delta = delta_imp;
        return res;
      }
      const double kf = ik > 0 ? k_ : 1.0;
      launch_each(n, [=] __device__(std::size_t i) { p[i] = fmax(0.0, -g[i]) * kf; });
      conjugate = false;
      continue;
    }
    const double shift = a[1] / ns;
    const double gbar = load_ctrl ? gref + shift : 0.0;
    double G = load_ctrl ? std::max(0.0, a[2] - ns * shift * shift) : a[2];
    if (load_ctrl) {
      g_mean_ref_ = gbar;
      if (!(G > 1e-10 * ns * shift * shift)) {
        G = red_.run<1>(n, [=] __device__(std::size_t i, double* acc) {
          const double v = g[i] - gbar;
          if (p[i] > 0) acc[0] += v * v;
        })[0];
      }
    }
    const double s1 = a[3] / ns;
    const double s2 = std::max(0.0, a[4] / ns - s1 * s1);
    gw_mean_ref_ = ref + s1;
    const double beta = conjugate ? G / gold : 0.0;
    gold = G;
    // C and D are read back together: nothing between them needs C's sums.
    red_.launch<3>(0, n, [=] __device__(std::size_t i, double* acc) {
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
    apply_compliance(t, r, 1.0);
    red_.launch<2>(1, n, [=] __device__(std::size_t i, double* acc) {
      if (p[i] > 0) {
        const double v = r[i] + ik * t[i];
        acc[0] += v;
        acc[1] += v * t[i];
      }
    });
    const double* cd = red_.fetch(2);
    const std::array<double, 3> c{cd[0], cd[1], cd[2]};
    const std::array<double, 2> d{cd[kMaxSums], cd[kMaxSums + 1]};
    const double viol = c[2];
    const double scale = std::max(std::sqrt(s2), 1e-3 * g0_rms_) + 1e-300;
    const double gap_residual = std::sqrt((G + viol) / ns) / scale;
    const double num = c[0];
    const double den = load_ctrl ? d[1] - (d[0] / ns) * c[1] : d[1];
    require_finite(num, "the pressure residual", *total_);
    if (den == 0.0 || G == 0.0) {
      res.converged = true;
      res.error = 0.0;
      res.delta = load_ctrl ? gbar : delta_imp;
      return res;
    }
    const double tau = num / den;
    const auto e = red_.run<3>(n, [=] __device__(std::size_t i, double* acc) {
      const double pi = p[i];
      double v = pi > 0 ? fmax(0.0, pi - tau * t[i]) : 0.0;
      const double gi = g[i] - gbar;
      if (v == 0.0 && gi < 0.0) {
        v = -tau * gi;
        acc[0] += 1.0;
      }
      p[i] = v;
      acc[1] += v;
      acc[2] += fabs(v - pi);
    });
    conjugate = (e[0] == 0.0);
    double pnew = e[1];
    double change = e[2];
    if (load_ctrl && pnew > 0) {
      pending = pbar * static_cast<double>(n) / pnew;
      change += std::abs(pending - 1.0) * pnew;
      pnew = pbar * static_cast<double>(n);
    }
    res.error = std::max(gap_residual, pnew > 0 ? change / pnew : (change > 0 ? 1.0 : 0.0));
    res.delta = load_ctrl ? gbar : delta_imp;
    require_finite(res.error, "the pressure", *total_);
    if (hooks_->progress && *hooks_->progress && (*total_ % 50 == 0))
      (*hooks_->progress)(Progress{*total_, 0, res.error});
    if (res.error < tol) {
      apply_pending();
      res.converged = true;
      return res;
    }
    poll(true, pending);
  }
  apply_pending();
  return res;
}

std::unique_ptr<DeviceSolve> make_device_solve(const DeviceProblem& problem) {
  return std::make_unique<CudaSolve>(problem);
}

}  // namespace gfmd
