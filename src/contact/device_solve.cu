// The contact solve on a CUDA device: ContactSolver's algorithm (normal.cpp, friction.cpp,
// solver.cpp) with every field in device memory, cuFFT D2Z/Z2D for the transforms, one
// kernel per fused pass and deterministic block sums (fixed launch shape, partials added in
// block order). The control flow of the friction fixed point is the host's, step for step;
// the host reads back only the few sums each step decides on. See device_solve.hpp.
#include <cuda_runtime.h>
#include <cufft.h>
#include <thrust/iterator/counting_iterator.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cub/device/device_select.cuh>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "device_anderson.cuh"
#include "device_solve.hpp"
#include "gfmd/contact/anderson.hpp"
#include "gfmd/core/cuda_kernels.cuh"
#include "gfmd/core/device.hpp"
#include "gfmd/core/error.hpp"
#include "solver_detail.hpp"

namespace gfmd {

using namespace contact_detail;
using namespace cuda_kernels;
using namespace contact_device;

namespace {

// solver_detail.hpp's joins_support and add_change, on the device.
__device__ inline bool joins_support_dev(unsigned char in_supp, double x, double y, double fx, double fy) {
  return !in_supp && (x != 0.0 || y != 0.0 || fx != 0.0 || fy != 0.0);
}
__device__ inline void add_change_dev(double* acc, unsigned char in_supp, double x, double y, double fx,
                                      double fy) {
  acc[0] += fabs(x - fx) + fabs(y - fy);
  acc[1] += fabs(x) + fabs(y);
  if (joins_support_dev(in_supp, x, y, fx, fy)) acc[2] += 1.0;
}

class CudaSolve final : public DeviceSolve {
 public:
  explicit CudaSolve(const DeviceProblem& pr);
  ~CudaSolve() override {
    if (plan_fwd_) cufftDestroy(plan_fwd_);
    if (plan_bwd_) cufftDestroy(plan_bwd_);
  }
  SolveInfo solve(const LoadParams& load, ContactFields& f, const DeviceHooks& hooks, int& total) override;
  [[nodiscard]] std::size_t device_bytes() const override { return bytes_.peak; }

  // Public throughout: nvcc's extended lambdas must not sit in private members.
  struct PK {
    int iterations;
    double error;
    double delta;
    bool converged;
  };
  struct Tangential {
    int iterations;
    double error;
    bool converged;
  };
  void forward(const double* in, cufftDoubleComplex* out) {
    cufft_check(cufftExecD2Z(plan_fwd_, const_cast<double*>(in), out), "forward transform");
    ++transforms_;
  }
  void backward(cufftDoubleComplex* in, double* out) {
    cufft_check(cufftExecZ2D(plan_bwd_, in, out), "inverse transform");
    ++transforms_;
  }
  void apply_compliance(const double* in, double* out, double scale);
  PK solve_normal(const LoadParams& load, bool w_zero, double tol, int max_it);
  std::array<double, 4> slip_tractions();
  // Uploads the symbol table of `deriv` and takes its splitting step (ContactSolver::use_derivative).
  void use_derivative(SlipDerivative deriv);
  Tangential solve_tangential(double tol, int max_it);
  void friction_normal_displacement();
  void download(const double* d, RealField& h) const {
    h.resize(n_);
    cuda_check(cudaMemcpy(h.data(), d, n_ * sizeof(double), cudaMemcpyDeviceToHost), "reading a field back");
  }
  void upload(const RealField& h, double* d) const {
    cuda_check(cudaMemcpy(d, h.data(), n_ * sizeof(double), cudaMemcpyHostToDevice), "uploading a field");
  }
  // Stop requests, progress and checkpoints (the host's poll): settle first when one is due.
  // pressure_scale: a pending load rescaling, applied to the host's copy only (the device's
  // state, and so the results, do not depend on when checkpoints fall).
  void poll(bool with_fields, double pressure_scale = 1.0);
  [[nodiscard]] std::pair<double, double> direction() const {
    const double th = fric_.direction_deg * std::numbers::pi / 180.0;
    return {std::cos(th), std::sin(th)};
  }

  Grid grid_;
  std::size_t n_ = 0, ns_ = 0;  // points, half-spectrum modes
  FrictionParams fric_;
  SolverParams sp_;
  double k_, inv_k_, g0_rms_, modulus_dx_;
  bool hard_wall_;
  double gamma_;
  const ElasticBody* body_;
  double gamma_initial_, gamma_upwind2_;
  SlipDerivative deriv_kind_;  // the slip derivative in use now
  Tally bytes_;
  cufftHandle plan_fwd_ = 0, plan_bwd_ = 0;
  DevArray<char> fft_work_;
  Reducer red_;
  DevArray<double> g0_, p_, w_, cg_g_, cg_t_, cg_r_;
  DevArray<cufftDoubleComplex> s1_, s2_, s3_;
  DevArray<double> czz_n_;
  // Friction only.
  DevArray<ComplianceMode> modes_;
  DevArray<cufftDoubleComplex> deriv_;  // the symbol D(q) of (e.grad), per mode
  DevArray<double> tx_, ty_, ntx_, nty_, zx_, zy_, bx_, by_;
  DevArray<unsigned char> in_supp_, flags_;
  DevArray<std::uint32_t> supp_, nsel_;
  DevArray<char> select_work_;
  std::size_t supp_len_ = 0;
  bool have_z_ = false;
  double gw_mean_ref_ = 0.0, g_mean_ref_ = 0.0;
  std::uint64_t transforms_ = 0;
  // The solve in progress.
  const DeviceHooks* hooks_ = nullptr;
  ContactFields* host_ = nullptr;
  int* total_ = nullptr;
  double last_checkpoint_ = 0.0;
  // GFMD_CUDA_PROFILE set: seconds per phase (the device synchronised at each boundary, which
  // costs a little): normal solves, slip tractions, stick-slip, mixing, support, rest, results.
  bool profile_ = std::getenv("GFMD_CUDA_PROFILE") != nullptr;
  std::array<double, 7> phase_s_{};
  struct Phase {
    CudaSolve* s;
    int k;
    double t0 = 0.0;
    Phase(CudaSolve* solve, int phase) : s(solve), k(phase) {
      if (s->profile_) t0 = now();
    }
    ~Phase() {
      if (s->profile_) s->phase_s_[static_cast<std::size_t>(k)] += now() - t0;
    }
    static double now() {
      cudaDeviceSynchronize();
      return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    }
  };
};

std::size_t spectral_modes(const Grid& g) { return g.spectral_size(); }

}  // namespace

std::size_t device_solve_bytes(const Grid& g, bool friction) {
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
  return b + std::max(wf, wb);
}

void require_device_fits(const Grid& grid, bool friction) {
  const DeviceStatus dev = cuda_device();
  if (!dev.available) throw InputError("solver.backend", "\"cuda\": " + dev.reason);
  const std::size_t need = device_solve_bytes(grid, friction);
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

namespace {

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
  require_device_fits(grid_, friction);
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

void CudaSolve::friction_normal_displacement() {
  forward(tx_.get(), s2_.get());
  forward(ty_.get(), s3_.get());
  const ComplianceMode* md = modes_.get();
  const cufftDoubleComplex* a = s2_.get();
  const cufftDoubleComplex* b = s3_.get();
  cufftDoubleComplex* out = s1_.get();
  const double scale = 1.0 / static_cast<double>(n_);
  launch_each(ns_, [=] __device__(std::size_t k) {
    const ComplianceMode m = md[k];
    const cufftDoubleComplex x = cscale(scale, a[k]), y = cscale(scale, b[k]);
    const cufftDoubleComplex tx = times_i(m.cxz, x), ty = times_i(m.cyz, y);
    out[k] = {-tx.x - ty.x, -tx.y - ty.y};
  });
  backward(s1_.get(), w_.get());
}

// In-plane displacement of a mode under the tractions (x, y, z).
__device__ inline void inplane(const ComplianceMode& m, cufftDoubleComplex x, cufftDoubleComplex y,
                               cufftDoubleComplex z, cufftDoubleComplex& ux, cufftDoubleComplex& uy) {
  const cufftDoubleComplex iz1 = times_i(m.cxz, z), iz2 = times_i(m.cyz, z);
  ux = {m.cxx * x.x + m.cxy * y.x + iz1.x, m.cxx * x.y + m.cxy * y.y + iz1.y};
  uy = {m.cxy * x.x + m.cyy * y.x + iz2.x, m.cxy * x.y + m.cyy * y.y + iz2.y};
}

std::array<double, 4> CudaSolve::slip_tractions() {
  // friction.cpp's slip_tractions: s2/s3 hold the spectra of tau_x/tau_y.
  const auto dir = direction();
  const double ex = dir.first, ey = dir.second;
  forward(p_.get(), s1_.get());
  {
    const ComplianceMode* md = modes_.get();
    const cufftDoubleComplex* dd = deriv_.get();
    cufftDoubleComplex* a = s1_.get();
    cufftDoubleComplex* b = s2_.get();
    cufftDoubleComplex* c = s3_.get();
    const double scale = 1.0 / static_cast<double>(n_);
    launch_each(ns_, [=] __device__(std::size_t k) {
      cufftDoubleComplex ux, uy;
      inplane(md[k], cscale(scale, b[k]), cscale(scale, c[k]), cscale(-scale, a[k]), ux, uy);
      a[k] = cmul(dd[k], ux);
      b[k] = cmul(dd[k], uy);
    });
  }
  backward(s1_.get(), cg_t_.get());
  backward(s2_.get(), cg_r_.get());
  const double mu = fric_.coefficient, eps = fric_.regularization;
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];
  const double* p = p_.get();
  const double* r1 = cg_t_.get();
  const double* r2 = cg_r_.get();
  const double* fx = tx_.get();
  const double* fy = ty_.get();
  double* tx = ntx_.get();
  double* ty = nty_.get();
  const unsigned char* in_supp = in_supp_.get();
  constexpr double slow2 = kNearStickSpeed * kNearStickSpeed;
  return red_.run<4>(n_, [=] __device__(std::size_t i, double* acc) {
    const double pi = p[i];
    if (pi > 0) {
      const double vx = rx + r1[i], vy = ry + r2[i];
      const double v2 = vx * vx + vy * vy;
      if (v2 < slow2) acc[3] += 1.0;
      const double norm = fmax(sqrt(v2), eps);
      double x = 0.0, y = 0.0;
      if (norm > 0) {
        x = mu * pi * vx / norm;
        y = mu * pi * vy / norm;
      }
      tx[i] = x;
      ty[i] = y;
      add_change_dev(acc, in_supp[i], x, y, fx[i], fy[i]);
    } else if (in_supp[i]) {
      tx[i] = 0.0;
      ty[i] = 0.0;
      acc[0] += fabs(fx[i]) + fabs(fy[i]);
    }
  });
}

CudaSolve::Tangential CudaSolve::solve_tangential(double tol, int max_it) {
  // friction.cpp's Douglas-Rachford iteration; the image tau goes to (ntx, nty).
  const auto dir = direction();
  const double ex = dir.first, ey = dir.second;
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];
  const double mu = fric_.coefficient;
  const double gamma = gamma_;
  const double scale = 1.0 / static_cast<double>(n_);
  const ComplianceMode* md = modes_.get();
  const cufftDoubleComplex* dd = deriv_.get();
  cufftDoubleComplex* a = s1_.get();
  cufftDoubleComplex* b = s2_.get();
  cufftDoubleComplex* c = s3_.get();
  double* yx = cg_t_.get();
  double* yy = cg_r_.get();
  double* bx = bx_.get();
  double* by = by_.get();
  double* zx = zx_.get();
  double* zy = zy_.get();
  double* tx = ntx_.get();
  double* ty = nty_.get();
  const double* p = p_.get();
  forward(p_.get(), s1_.get());
  launch_each(ns_, [=] __device__(std::size_t k) {
    cufftDoubleComplex ux, uy;
    inplane(md[k], {0.0, 0.0}, {0.0, 0.0}, cscale(-scale * gamma, a[k]), ux, uy);
    b[k] = cmul(dd[k], ux);
    c[k] = cmul(dd[k], uy);
  });
  backward(s2_.get(), bx);
  backward(s3_.get(), by);
  if (!have_z_) {
    forward(tx, s2_.get());
    forward(ty, s3_.get());
    launch_each(ns_, [=] __device__(std::size_t k) {
      cufftDoubleComplex ux, uy;
      inplane(md[k], cscale(scale * gamma, b[k]), cscale(scale * gamma, c[k]), {0.0, 0.0}, ux, uy);
      b[k] = cmul(dd[k], ux);
      c[k] = cmul(dd[k], uy);
    });
    backward(s2_.get(), yx);
    backward(s3_.get(), yy);
    launch_each(n_, [=] __device__(std::size_t i) {
      zx[i] = tx[i] + gamma * rx + bx[i] + yx[i];
      zy[i] = ty[i] + gamma * ry + by[i] + yy[i];
    });
    have_z_ = true;
  }
  const auto project_pass = [&](bool rhs) {
    launch_each(n_, [=] __device__(std::size_t i) {
      const double r = mu * p[i];
      double x = 0.0, y = 0.0;
      if (r > 0) {
        const double m2 = zx[i] * zx[i] + zy[i] * zy[i];
        if (m2 <= r * r) {
          x = zx[i];
          y = zy[i];
        } else {
          const double f = r / sqrt(m2);
          x = f * zx[i];
          y = f * zy[i];
        }
      }
      tx[i] = x;
      ty[i] = y;
      if (rhs) {
        yx[i] = 2.0 * x - zx[i] + bx[i];
        yy[i] = 2.0 * y - zy[i] + by[i];
      }
    });
  };
  Tangential res{0, 1.0, false};
  const double cx = gamma * rx, cy = gamma * ry;
  const double beta = kTangentialRelaxation;
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    project_pass(true);
    forward(yx, s2_.get());
    forward(yy, s3_.get());
    launch_each(ns_, [=] __device__(std::size_t k) {
      const ComplianceMode m = md[k];
      const cufftDoubleComplex gd = cscale(gamma, dd[k]);
      const cufftDoubleComplex xa = cscale(scale, b[k]), xb = cscale(scale, c[k]);
      // The adjugate of M = I - gamma D C_tt and 1/det M (slip_resolvent).
      const cufftDoubleComplex m11 = {1.0 - gd.x * m.cyy, -gd.y * m.cyy};
      const cufftDoubleComplex m22 = {1.0 - gd.x * m.cxx, -gd.y * m.cxx};
      const cufftDoubleComplex m12 = cscale(m.cxy, gd);
      const cufftDoubleComplex det = {m11.x * m22.x - m11.y * m22.y - (m12.x * m12.x - m12.y * m12.y),
                                      m11.x * m22.y + m11.y * m22.x - 2.0 * m12.x * m12.y};
      const cufftDoubleComplex inv = cdiv1(det);
      b[k] = cmul(inv, cadd(cmul(m11, xa), cmul(m12, xb)));
      c[k] = cmul(inv, cadd(cmul(m12, xa), cmul(m22, xb)));
      if (k == 0) {
        b[0].x += cx;
        c[0].x += cy;
      }
    });
    backward(s2_.get(), yx);
    backward(s3_.get(), yy);
    const auto sums = red_.run<2>(n_, [=] __device__(std::size_t i, double* acc) {
      const double dx = yx[i] - tx[i], dy = yy[i] - ty[i];
      acc[0] += fabs(dx) + fabs(dy);
      acc[1] += fabs(tx[i]) + fabs(ty[i]);
      zx[i] += beta * dx;
      zy[i] += beta * dy;
    });
    res.error = sums[1] > 0 ? sums[0] / sums[1] : (sums[0] > 0 ? 1.0 : 0.0);
    require_finite(res.error, "the stick-slip traction", *total_);
    if (res.error < tol) {
      res.converged = true;
      break;
    }
    if (res.iterations % 64 == 0) poll(false);
  }
  project_pass(false);
  return res;
}

SolveInfo CudaSolve::solve(const LoadParams& load, ContactFields& f, const DeviceHooks& hooks, int& total) {
  // solver.cpp's solve: the friction fixed point with Anderson mixing around the normal solve.
  const auto t0 = Clock::now();
  const std::uint64_t transforms0 = transforms_;
  hooks_ = &hooks;
  host_ = &f;
  total_ = &total;
  total = 0;
  last_checkpoint_ = std::chrono::duration<double>(t0.time_since_epoch()).count();
  const std::size_t n = n_;
  for (auto* fld : {&f.pressure, &f.tx, &f.ty})
    if (fld->size() != n) fld->assign(n, 0.0);
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) RealField().swap(*fld);
  f.stick.clear();
  SolveInfo info;
  info.stiffness = k_;
  const double tol = sp_.tolerance;
  const double mu = fric_.coefficient;
  if (mu > 0 && deriv_kind_ != fric_.derivative())
    use_derivative(fric_.derivative());  // a previous solve met stick
  upload(f.pressure, p_.get());
  cuda_check(cudaMemset(w_.get(), 0, n * sizeof(double)), "clearing a field");
  PK pk{};
  if (mu == 0.0) {
    std::fill(f.tx.begin(), f.tx.end(), 0.0);
    std::fill(f.ty.begin(), f.ty.end(), 0.0);
    {
      const Phase ph(this, 0);
      pk = solve_normal(load, true, tol, sp_.max_iterations);
    }
    info.converged = pk.converged;
    info.status = pk.converged ? "converged" : "not converged: iteration limit reached";
  } else {
    upload(f.tx, tx_.get());
    upload(f.ty, ty_.get());
    double* ftx = tx_.get();
    double* fty = ty_.get();
    double* tx = ntx_.get();
    double* ty = nty_.get();
    unsigned char* in_supp = in_supp_.get();
    unsigned char* flags = flags_.get();
    std::uint32_t* supp = supp_.get();
    // The support: points where the iterate or its image has been non-zero (solver.cpp),
    // listed in order of entry, each entry's points in grid order.
    const auto add_support = [&](bool warm) {
      launch_each(n, [=] __device__(std::size_t i) {
        flags[i] = warm ? (ftx[i] != 0.0 || fty[i] != 0.0)
                        : joins_support_dev(in_supp[i], tx[i], ty[i], ftx[i], fty[i]);
      });
      std::size_t sel = select_work_.size();
      thrust::counting_iterator<std::uint32_t> idx(0);
      cuda_check(cub::DeviceSelect::Flagged(select_work_.get(), sel, idx, flags, supp + supp_len_,
                                            nsel_.get(), static_cast<std::int64_t>(n)),
                 "support selection");
      std::uint32_t added = 0;
      cuda_check(cudaMemcpy(&added, nsel_.get(), sizeof added, cudaMemcpyDeviceToHost), "support selection");
      launch_each(n, [=] __device__(std::size_t i) {
        if (flags[i]) in_supp[i] = 1;
      });
      supp_len_ += added;
    };
    cuda_check(cudaMemset(in_supp, 0, n), "clearing the support");
    supp_len_ = 0;
    add_support(true);
    std::optional<DeviceAnderson> mixer;
    int depth = sp_.anderson;  // deepened once where the fixed point stalls (as on the host)
    if (sp_.anderson > 0) {
      if (sp_.anderson > kMaxDepth)
        throw InputError("solver.anderson",
                         "the CUDA backend mixes at most " + std::to_string(kMaxDepth) + " steps");
      info.history_depth = depth;
      mixer.emplace(sp_.anderson, 2 * n, &bytes_);
      mixer->resize(2 * supp_len_);
    }
    double err = 1.0;
    std::vector<double> hist_change, hist_force;
    const auto dir = direction();
    const double dir_x = dir.first, dir_y = dir.second;
    FrictionSteps steps(!fric_.regularized() && fric_.rolling(),
                        !fric_.slip_derivative && deriv_kind_ == SlipDerivative::Spectral);
    bool tangential_ok = !steps.stick_mode();
    double stick_now = 0.0;
    bool map_changed = false;  // the slip derivative turned in this friction step (solver.cpp)
    have_z_ = false;
    double omega = sp_.mixing;
    info.status = "not converged: friction fixed point did not settle";
    for (int outer = 0; outer < sp_.max_outer; ++outer) {
      info.outer_iterations = outer + 1;
      {
        const Phase ph(this, 1);
        friction_normal_displacement();
      }
      const double inner_tol = std::max(tol, std::min(1e-3, 0.1 * err));
      const int budget = sp_.max_iterations - total;
      if (budget <= 0) {
        info.status = "not converged: iteration limit reached";
        break;
      }
      {
        const Phase ph(this, 0);
        pk = solve_normal(load, false, inner_tol, budget);
      }
      std::array<double, 4> dn{};
      if (!steps.stick_mode()) {
        const Phase ph(this, 1);
        dn = slip_tractions();
        steps.full_slip_step(dn[3]);
      } else {
        if (!have_z_) {
          cuda_check(cudaMemcpy(tx, ftx, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
          cuda_check(cudaMemcpy(ty, fty, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        }
        const double ttol = std::max(0.1 * tol, std::min(1e-3, kTangentialTolFactor * err));
        const Phase ph(this, 2);
        const auto tr = solve_tangential(ttol, sp_.max_tangential);
        info.tangential_iterations += tr.iterations;
        tangential_ok = tr.converged && ttol <= 0.1 * tol;
        const double* pp = p_.get();
        const double* zxs = zx_.get();
        const double* zys = zy_.get();
        const auto c = red_.run<4>(n, [=] __device__(std::size_t i, double* acc) {
          add_change_dev(acc, in_supp[i], tx[i], ty[i], ftx[i], fty[i]);
          const double r = mu * pp[i];
          if (r > 0 && zxs[i] * zxs[i] + zys[i] * zys[i] < r * r) acc[3] += 1.0;
        });
        dn = {c[0], c[1], c[2], 0.0};
        stick_now = c[3];
        if (steps.settles_upwind(stick_now)) {
          use_derivative(SlipDerivative::Upwind2);
          have_z_ = false;
          tangential_ok = false;
          map_changed = true;
        }
      }
      err = dn[1] > 0 ? dn[0] / dn[1] : 0.0;
      require_finite(err, "the friction traction", total);
      info.friction_error = err;
      hist_change.push_back(err);
      const double ddx = dir_x, ddy = dir_y;
      hist_force.push_back(red_.run<1>(
          n, [=] __device__(std::size_t i, double* acc) { acc[0] += ddx * tx[i] + ddy * ty[i]; })[0]);
      if (hooks.progress && *hooks.progress) (*hooks.progress)(Progress{total, outer + 1, err});
      poll(true);
      const bool done = err < tol && pk.converged && inner_tol <= tol && tangential_ok;
      if (steps.turns_back(done, stick_now)) {
        use_derivative(SlipDerivative::Spectral);
        have_z_ = false;
        tangential_ok = false;
        map_changed = true;
      } else if (done) {
        tx_.swap(ntx_);
        ty_.swap(nty_);
        info.converged = true;
        info.status = "converged";
        break;
      }
      const FrictionSteps::Next next = steps.after(err, outer, !fric_.regularized());
      if (next == FrictionSteps::Next::HandOver) {
        if (steps.upwind()) use_derivative(SlipDerivative::Upwind2);
        tangential_ok = false;
        if (mixer) mixer->restart();
        continue;
      }
      if (next == FrictionSteps::Next::Damp && mixer && deepened_history(sp_.anderson, depth) != depth) {
        // As on the host: a longer mixing history first, started afresh.
        depth = deepened_history(sp_.anderson, depth);
        mixer.emplace(depth, 2 * n, &bytes_);
        mixer->resize(2 * supp_len_);
        info.history_depth = depth;
      } else if (next == FrictionSteps::Next::Damp) {
        omega *= 0.5;
        if (mixer) mixer->clear_history();
        if (omega < 0.04) {
          tx_.swap(ntx_);
          ty_.swap(nty_);
          info.status = "not converged: oscillating (friction fixed point does not settle even with damping)";
          break;
        }
      }
      if (dn[2] > 0) {
        const Phase ph(this, 4);
        add_support(false);
        if (mixer) mixer->resize(2 * supp_len_);
      }
      if (map_changed) {
        // As on the host: the image becomes the iterate, the mixing starts afresh.
        map_changed = false;
        cuda_check(cudaMemcpy(ftx, tx, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        cuda_check(cudaMemcpy(fty, ty, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        if (mixer) mixer->restart();
        continue;
      }
      double* zx = zx_.get();
      double* zy = zy_.get();
      const bool follow = steps.stick_mode();
      const std::size_t len = supp_len_;
      if (!mixer) {
        const double om = omega;
        launch_each(len, [=] __device__(std::size_t j) {
          const std::uint32_t i = supp[j];
          const double ox = ftx[i], oy = fty[i];
          ftx[i] = ox + om * (tx[i] - ox);
          fty[i] = oy + om * (ty[i] - oy);
          if (follow) {
            zx[i] += ftx[i] - tx[i];
            zy[i] += fty[i] - ty[i];
          }
        });
        continue;
      }
      const Phase ph(this, 3);
      mixer->step(red_, omega, MixTarget{ftx, fty, tx, ty, supp});
      if (follow)
        launch_each(len, [=] __device__(std::size_t j) {
          const std::uint32_t i = supp[j];
          zx[i] += ftx[i] - tx[i];
          zy[i] += fty[i] - ty[i];
        });
    }
    if (!info.converged && info.status.rfind("not converged: iteration limit", 0) != 0)
      info.status += "; " + friction_history_evidence(hist_change, hist_force);
    if (!fric_.regularized()) f.stick.assign(n, 0);
    if (steps.stick_mode() && have_z_) {
      const double* p = p_.get();
      const double* zx = zx_.get();
      const double* zy = zy_.get();
      unsigned char* fl = flags_.get();
      const auto ns = red_.run<1>(n, [=] __device__(std::size_t i, double* acc) {
        const double r = mu * p[i];
        const bool s = r > 0 && zx[i] * zx[i] + zy[i] * zy[i] < r * r;
        fl[i] = s ? 1 : 0;
        if (s) acc[0] += 1.0;
      })[0];
      cuda_check(cudaMemcpy(f.stick.data(), fl, n, cudaMemcpyDeviceToHost), "reading the stick mask");
      info.stick_points = static_cast<std::size_t>(ns);
    }
    if (!pk.converged && info.converged) {
      info.converged = false;
      info.status = "not converged: iteration limit reached";
    }
  }
  info.iterations = total;
  info.slip_derivative = deriv_kind_;
  info.pk_error = pk.error;
  info.approach = pk.delta;
  // The displacements of (tau, -p) and the gap, then everything back to the host.
  {
    const Phase ph(this, 6);
    forward(p_.get(), s1_.get());
    const bool fr = mu > 0;
    if (fr) {
      forward(tx_.get(), s2_.get());
      forward(ty_.get(), s3_.get());
    }
    const double scale = 1.0 / static_cast<double>(n_);
    const ComplianceMode* md = modes_.get();
    cufftDoubleComplex* a = s1_.get();
    cufftDoubleComplex* b = s2_.get();
    cufftDoubleComplex* c = s3_.get();
    launch_each(ns_, [=] __device__(std::size_t k) {
      const ComplianceMode m = md[k];
      const cufftDoubleComplex z = cscale(-scale, a[k]);
      const cufftDoubleComplex x = fr ? cscale(scale, b[k]) : cufftDoubleComplex{0.0, 0.0};
      const cufftDoubleComplex y = fr ? cscale(scale, c[k]) : cufftDoubleComplex{0.0, 0.0};
      cufftDoubleComplex ux, uy;
      inplane(m, x, y, z, ux, uy);
      const cufftDoubleComplex ix = times_i(m.cxz, x), iy = times_i(m.cyz, y);
      a[k] = {m.czz * z.x - ix.x - iy.x, m.czz * z.y - ix.y - iy.y};
      b[k] = ux;
      c[k] = uy;
    });
    backward(s1_.get(), cg_g_.get());
    backward(s2_.get(), cg_t_.get());
    backward(s3_.get(), cg_r_.get());
    download(cg_g_.get(), f.uz);
    download(cg_t_.get(), f.ux);
    download(cg_r_.get(), f.uy);
    if (fr) {
      download(tx_.get(), f.tx);
      download(ty_.get(), f.ty);
    }
    download(p_.get(), f.pressure);
  }
  info.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (profile_) {
    const auto& t = phase_s_;
    std::fprintf(stderr,
                 "cuda profile: %.4f s in all; normal %.4f (%d iterations), slip %.4f, stick-slip %.4f, "
                 "mixing %.4f, support %.4f, results %.4f, other %.4f; %llu transforms\n",
                 info.wall_time_s, t[0], info.iterations, t[1], t[2], t[3], t[4], t[6],
                 info.wall_time_s - (t[0] + t[1] + t[2] + t[3] + t[4] + t[6]),
                 static_cast<unsigned long long>(transforms_ - transforms0));
    phase_s_.fill(0.0);
  }
  info.transforms = transforms_ - transforms0;
  hooks_ = nullptr;
  host_ = nullptr;
  total_ = nullptr;
  return info;
}

}  // namespace

std::unique_ptr<DeviceSolve> make_device_solve(const DeviceProblem& problem) {
  return std::make_unique<CudaSolve>(problem);
}

}  // namespace gfmd
