// The CUDA contact solve's class (device_solve.cu): shared by its translation units,
// device_solve.cu (set-up, transforms, the normal solve), device_adhesion.cu (the adhesive
// steps), device_friction.cu (the friction passes and the tangential solve) and
// device_solve_loop.cu (the friction fixed point).
#pragma once

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

namespace device_solve_detail {

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
  // Adhesion (device_adhesion.cu): the fields and tables; |g_x| dx + |g_y| dy; the adhesive
  // normal problem (ContactSolver::solve_adhesive), under the friction's displacement held in
  // w_ where w_extra.
  void setup_adhesion(const DeviceProblem& pr);
  void gap_spread(const double* gap, double* gx, double* spread);
  PK solve_adhesive(const LoadParams& load, double tol, SolveInfo& info, bool w_extra, int max_it);
  // The pressure the friction law's bound reads: the repulsion p + a with adhesion (made in ad_
  // after each adhesive solve of the friction loop), the pressure itself otherwise.
  [[nodiscard]] const double* law_pressure() const { return adhesive_ ? ad_.get() : p_.get(); }
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
  // Adhesion only: sigma0 and the range; the traction, its image, the gap, its spread, the
  // friction's normal displacement; the spectral derivative's symbols; the mixing.
  bool adhesive_ = false;
  double s0_ = 0.0, range_ = 0.0;
  RealField* spread_out_ = nullptr;  // the host's copy of the last step's spread (its residual)
  DevArray<double> a_, ad_, agap_, aspread_, awx_;
  DevArray<double> qx_, qy_;
  std::optional<DeviceGuarded> amix_;
  bool adhesion_active_ = false;  // inside the adhesive steps: p_ holds the repulsion p + a
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

inline std::size_t spectral_modes(const Grid& g) { return g.spectral_size(); }

// In-plane displacement of a mode under the tractions (x, y, z).
__device__ inline void inplane(const ComplianceMode& m, cufftDoubleComplex x, cufftDoubleComplex y,
                               cufftDoubleComplex z, cufftDoubleComplex& ux, cufftDoubleComplex& uy) {
  const cufftDoubleComplex iz1 = times_i(m.cxz, z), iz2 = times_i(m.cyz, z);
  ux = {m.cxx * x.x + m.cxy * y.x + iz1.x, m.cxx * x.y + m.cxy * y.y + iz1.y};
  uy = {m.cxy * x.x + m.cyy * y.x + iz2.x, m.cxy * x.y + m.cyy * y.y + iz2.y};
}

}  // namespace device_solve_detail
}  // namespace gfmd
