// The surface stresses on the CUDA device (elastic/device_stress.hpp): stress.cpp's passes --
// the strains from the in-plane displacement spectra, Hooke's law with the free-surface
// relation, Eberly's principal stresses (principal_point.hpp, the host's code), summarize's
// maxima, positions and counts -- with cuFFT and the deterministic reductions of
// core/cuda_kernels.cuh. Memory is freed as the passes go: at most 13 doubles per point plus
// cuFFT's work area.
#include <cuda_runtime.h>
#include <cufft.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "gfmd/core/cuda_kernels.cuh"
#include "gfmd/core/device.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "principal_point.hpp"
#include "stress_detail.hpp"
#include "subsurface_mode.hpp"

namespace gfmd {

using namespace cuda_kernels;

namespace {

using Cplx = cufftDoubleComplex;

// One cell's stress tensor (xx, yy, zz, xy, xz, yz).
struct Tensor {
  double xx, yy, zz, xy, xz, yz;
};
// The six stress spectra of the subsurface pass.
struct Spectra6 {
  Cplx* s[6];
};

// The traction's source: the fields' own (tx, ty, either may be absent), or mu p e.
struct Traction {
  bool from_pressure = false;
  double mu = 0.0, ex = 0.0, ey = 0.0;  // tau = mu p e
};

class StressEval {
 public:
  StressEval(const Grid& g, const DeviceStressRequest& req) : g_(g), req_(req) {
    n_ = g.size();
    ns_ = g.spectral_size();
  }
  StressEval(const StressEval&) = delete;
  StressEval& operator=(const StressEval&) = delete;
  ~StressEval() {
    if (fwd_) cufftDestroy(fwd_);
    if (bwd_) cufftDestroy(bwd_);
  }

  // Whether the evaluation fits the device's free memory (a sixteenth of the card spare).
  [[nodiscard]] bool fits(bool with_modes) const {
    const DeviceStatus dev = cuda_device();
    if (!dev.available) return false;
    std::size_t work = 0, w = 0;
    if (cufftEstimate2d(g_.ny, g_.nx, CUFFT_D2Z, &w) == CUFFT_SUCCESS) work = std::max(work, w);
    if (cufftEstimate2d(g_.ny, g_.nx, CUFFT_Z2D, &w) == CUFFT_SUCCESS) work = std::max(work, w);
    const std::size_t need =
        13 * n_ * sizeof(double) + (with_modes ? ns_ * sizeof(ComplianceMode) : 0) + 2 * work + (64u << 20);
    return need + dev.total_bytes / 16 <= dev.free_bytes;
  }

  void plans() {
    cufft_check(cufftPlan2d(&fwd_, g_.ny, g_.nx, CUFFT_D2Z), "stress: forward plan");
    cufft_check(cufftPlan2d(&bwd_, g_.ny, g_.nx, CUFFT_Z2D), "stress: inverse plan");
    std::size_t w = 0;
    if (cufftGetSize(fwd_, &w) == CUFFT_SUCCESS) bytes_.add(w);
    if (cufftGetSize(bwd_, &w) == CUFFT_SUCCESS) bytes_.add(w);
    red_.init(&bytes_);
  }

  void up(const RealField& h, DevArray<double>& d, const char* what) {
    d.allocate(n_, &bytes_, what);
    cuda_check(cudaMemcpy(d.get(), h.data(), n_ * sizeof(double), cudaMemcpyHostToDevice), what);
  }
  void down(const DevArray<double>& d, RealField& h) const {
    h.resize(n_);
    cuda_check(cudaMemcpy(h.data(), d.get(), n_ * sizeof(double), cudaMemcpyDeviceToHost),
               "stress: reading a field back");
  }
  void forward(const double* in, Cplx* out) {
    cufft_check(cufftExecD2Z(fwd_, const_cast<double*>(in), out), "stress: forward transform");
  }
  // FFT::backward: the spectrum times 1/N (in place), then the inverse transform.
  void backward(Cplx* in, double* out) {
    const double scale = 1.0 / static_cast<double>(n_);
    launch_each(ns_, [=] __device__(std::size_t k) { in[k] = cscale(scale, in[k]); });
    cufft_check(cufftExecZ2D(bwd_, in, out), "stress: inverse transform");
  }

  // post_analysis_stress's displacements: (ux, uy) of the traction (mu p e, -p) through the
  // body's compliance, into ux_, uy_ (the pressure in p_).
  void displacements_from_compliance(const ElasticBody& body, const Traction& t) {
    modes_.allocate(ns_, &bytes_, "stress: compliance");
    cuda_check(
        cudaMemcpy(modes_.get(), body.modes().data(), ns_ * sizeof(ComplianceMode), cudaMemcpyHostToDevice),
        "stress: compliance");
    DevArray<double> r;
    r.allocate(n_, &bytes_, "stress: a traction");
    DevArray<Cplx> TX, TY, TZ;
    for (DevArray<Cplx>* s : {&TX, &TY, &TZ}) s->allocate(ns_, &bytes_, "stress: traction spectra");
    const double* p = p_.get();
    double* rr = r.get();
    const double mu = t.mu, ex = t.ex, ey = t.ey;
    launch_each(n_, [=] __device__(std::size_t k) { rr[k] = mu * p[k] * ex; });
    forward(rr, TX.get());
    launch_each(n_, [=] __device__(std::size_t k) { rr[k] = mu * p[k] * ey; });
    forward(rr, TY.get());
    launch_each(n_, [=] __device__(std::size_t k) { rr[k] = -p[k]; });
    forward(rr, TZ.get());
    r.release();
    // ElasticBody::displacement's in-plane part: u = C_tt t + i c_tz t_z (in place in TX, TY).
    Cplx *X = TX.get(), *Y = TY.get();
    const Cplx* Z = TZ.get();
    const ComplianceMode* m = modes_.get();
    launch_each(ns_, [=] __device__(std::size_t k) {
      const ComplianceMode c = m[k];
      const Cplx x = X[k], y = Y[k], z = Z[k];
      X[k] = {c.cxx * x.x + c.cxy * y.x - c.cxz * z.y, c.cxx * x.y + c.cxy * y.y + c.cxz * z.x};
      Y[k] = {c.cxy * x.x + c.cyy * y.x - c.cyz * z.y, c.cxy * x.y + c.cyy * y.y + c.cyz * z.x};
    });
    TZ.release();
    modes_.release();
    ux_.allocate(n_, &bytes_, "stress: displacements");
    uy_.allocate(n_, &bytes_, "stress: displacements");
    backward(X, ux_.get());
    backward(Y, uy_.get());
  }

  // surface_stress on the device fields p_, ux_, uy_ and the traction, then principal and
  // summarize. tx, ty: the host's tractions (null: zero) unless t.from_pressure.
  DeviceStressResult evaluate(const Traction& t, const RealField* tx, const RealField* ty,
                              const ElasticParams& el) {
    // Strains: eps_xx, eps_yy, 2 eps_xy from the spectra of ux, uy.
    DevArray<Cplx> U, V, W;
    for (DevArray<Cplx>* s : {&U, &V, &W}) s->allocate(ns_, &bytes_, "stress: spectra");
    forward(ux_.get(), U.get());
    forward(uy_.get(), V.get());
    ux_.release();
    uy_.release();
    DevArray<double> qx, qy;
    wave_numbers(true, qx, qy);
    DevArray<double> xx, yy, xy;
    for (DevArray<double>* f : {&xx, &yy, &xy}) f->allocate(n_, &bytes_, "stress: tensor");
    const std::size_t nxh = static_cast<std::size_t>(g_.nxh());
    const Cplx *Us = U.get(), *Vs = V.get();
    Cplx* Ws = W.get();
    const double *qxs = qx.get(), *qys = qy.get();
    for (int comp = 0; comp < 3; ++comp) {
      launch_each(ns_, [=] __device__(std::size_t k) {
        const double ax = qxs[k % nxh], ay = qys[k / nxh];
        const Cplx u = Us[k], v = Vs[k];
        Ws[k] = comp == 0   ? times_i(ax, u)
                : comp == 1 ? times_i(ay, v)
                            : cadd(times_i(ay, u), times_i(ax, v));
      });
      backward(Ws, (comp == 0 ? xx : comp == 1 ? yy : xy).get());
    }
    for (DevArray<Cplx>* s : {&U, &V, &W}) s->release();
    if (!t.from_pressure) {
      if (tx && !tx->empty()) up(*tx, tx_, "stress: tractions");
      if (ty && !ty->empty()) up(*ty, ty_, "stress: tractions");
    }
    // Hooke's law with the free surface (stress.cpp), in place.
    const double es = el.contact_modulus, nu = el.poisson;
    const double G = el.shear_modulus(), lat = nu / (1.0 - nu);
    double *sxx = xx.get(), *syy = yy.get(), *sxy = xy.get();
    const double* p = p_.get();
    launch_each(n_, [=] __device__(std::size_t k) {
      const double e_xx = sxx[k], e_yy = syy[k], szz = -p[k];
      sxx[k] = es * (e_xx + nu * e_yy) + lat * szz;
      syy[k] = es * (e_yy + nu * e_xx) + lat * szz;
      sxy[k] = G * sxy[k];
    });
    DeviceStressResult out;
    if (req_.tensor) {
      down(xx, out.tensor.xx);
      down(yy, out.tensor.yy);
      down(xy, out.tensor.xy);
    }
    const double* txs = tx_.get();
    const double* tys = ty_.get();
    const bool fp = t.from_pressure;
    const double mu = t.mu, ex = t.ex, ey = t.ey;
    principal_and_summary(
        [=] __device__(std::size_t k) {
          const double e = fp ? mu * p[k] * ex : (txs ? txs[k] : 0.0);
          const double f = fp ? mu * p[k] * ey : (tys ? tys[k] : 0.0);
          return Tensor{sxx[k], syy[k], -p[k], sxy[k], e, f};
        },
        out);
    return out;
  }

  // principal() and summarize() of the tensor at(k) of every cell, into out (with the maps
  // the request asks for).
  template <class At>
  void principal_and_summary(At at, DeviceStressResult& out) {
    const bool all = req_.parts == PrincipalParts::All;
    DevArray<double> s1, vm, s2, s3, e1x, e1y, e1z;
    s1.allocate(n_, &bytes_, "stress: principal");
    vm.allocate(n_, &bytes_, "stress: principal");
    if (all)
      for (DevArray<double>* f : {&s2, &s3, &e1x, &e1y, &e1z}) f->allocate(n_, &bytes_, "stress: principal");
    double *o1 = s1.get(), *ov = vm.get(), *o2 = s2.get(), *o3 = s3.get(), *ox = e1x.get(), *oy = e1y.get(),
           *oz = e1z.get();
    launch_each(n_, [=] __device__(std::size_t k) {
      const Tensor v = at(k);
      const principal_detail::Point pt = principal_detail::principal(v.xx, v.yy, v.zz, v.xy, v.xz, v.yz);
      o1[k] = pt.s1;
      ov[k] = principal_detail::von_mises(v.xx, v.yy, v.zz, v.xy, v.xz, v.yz);
      if (all) {
        o2[k] = pt.s2;
        o3[k] = pt.s3;
        ox[k] = pt.e1.x;
        oy[k] = pt.e1.y;
        oz[k] = pt.e1.z;
      }
    });
    // summarize(): maxima, the first cell (row order) holding each, the counts.
    StressSummary& s = out.summary;
    s.high_tension_fraction_of = req_.high_tension_fraction;
    const auto [it, vt] = argmax(o1);
    const auto [iv, vv] = argmax(ov);
    s.max_tensile_stress = vt;
    s.max_tensile_ix = static_cast<int>(it % static_cast<std::size_t>(g_.nx));
    s.max_tensile_iy = static_cast<int>(it / static_cast<std::size_t>(g_.nx));
    s.max_von_mises = vv;
    s.max_von_mises_ix = static_cast<int>(iv % static_cast<std::size_t>(g_.nx));
    s.max_von_mises_iy = static_cast<int>(iv / static_cast<std::size_t>(g_.nx));
    if (vt > 0.0) {
      const double thr = req_.high_tension_fraction * vt, half = 0.5 * vt;
      const auto c = red_.run<2>(n_, [=] __device__(std::size_t i, double* acc) {
        acc[0] += o1[i] >= thr ? 1.0 : 0.0;
        acc[1] += o1[i] >= half ? 1.0 : 0.0;
      });
      s.high_tension_area_fraction = c[0] / static_cast<double>(n_);
      out.above_half = c[1] / static_cast<double>(n_);
    }
    if (all || req_.s1) down(s1, out.principal.s1);
    if (all || req_.von_mises) down(vm, out.principal.von_mises);
    if (all) {
      down(s2, out.principal.s2);
      down(s3, out.principal.s3);
      down(e1x, out.principal.e1x);
      down(e1y, out.principal.e1y);
      down(e1z, out.principal.e1z);
    }
    out.device_bytes = bytes_.peak;
  }

  // subsurface.cpp's subsurface_spectra and subsurface_stress at `depth` (p_ uploaded; tx,
  // ty the host's tractions, either may be empty), then principal_and_summary.
  DeviceStressResult subsurface(double depth, const ElasticParams& el, const RealField& tx,
                                const RealField& ty) {
    DevArray<Cplx> TZ, TX, TY;
    {
      DevArray<double> r;
      r.allocate(n_, &bytes_, "stress: a traction");
      const double* p = p_.get();
      double* rr = r.get();
      launch_each(n_, [=] __device__(std::size_t k) { rr[k] = -p[k]; });
      TZ.allocate(ns_, &bytes_, "stress: traction spectra");
      forward(rr, TZ.get());
      for (const auto& [h, S] : {std::pair{&tx, &TX}, std::pair{&ty, &TY}})
        if (!h->empty()) {
          cuda_check(cudaMemcpy(rr, h->data(), n_ * sizeof(double), cudaMemcpyHostToDevice),
                     "stress: tractions");
          S->allocate(ns_, &bytes_, "stress: traction spectra");
          forward(rr, S->get());
        }
    }
    DevArray<double> qx, qy;
    wave_numbers(false, qx, qy);
    DevArray<Cplx> sig[6];
    for (DevArray<Cplx>& a : sig) a.allocate(ns_, &bytes_, "stress: subsurface spectra");
    Spectra6 out6{};
    for (int m = 0; m < 6; ++m) out6.s[m] = sig[m].get();
    const Cplx *tzs = TZ.get(), *txs = TX.get(), *tys = TY.get();
    const double *qxs = qx.get(), *qys = qy.get();
    const std::size_t nxh = static_cast<std::size_t>(g_.nxh());
    const int nyq_x = g_.nx % 2 == 0 ? g_.nx / 2 : -1, nyq_y = g_.ny % 2 == 0 ? g_.ny / 2 : -1;
    const double nu = el.poisson, om = 1.0 - nu, thickness = el.thickness;
    const bool half = el.half_space();
    launch_each(ns_, [=] __device__(std::size_t k) {
      const int ikx = static_cast<int>(k % nxh), iky = static_cast<int>(k / nxh);
      const double qxv = qxs[ikx], qyv = qys[iky], q = hypot(qxv, qyv);
      const Cplx t1 = txs ? txs[k] : Cplx{0.0, 0.0}, t2 = tys ? tys[k] : Cplx{0.0, 0.0}, t3 = tzs[k];
      if (q == 0.0) {  // uniform traction: uniform stress (mode_response)
        const double l = nu / om;
        const Cplx v[6] = {{l * t3.x, l * t3.y}, {l * t3.x, l * t3.y}, t3, {0.0, 0.0}, t1, t2};
        for (int m = 0; m < 6; ++m) out6.s[m][k] = v[m];
        return;
      }
      const subsurface_detail::Mode md = subsurface_detail::mode_plane(q, depth, nu, half, thickness);
      const subsurface_detail::Plane& P = md.p;
      const double c0 = qxv / q, s0 = qyv / q;
      // On a Nyquist line the mode and its mirror are one mode: the mean over the mirrors.
      const bool nx2 = ikx == nyq_x, ny2 = iky == nyq_y;
      Cplx acc[6] = {};
      int count = 0;
      for (int fx = 0; fx < (nx2 ? 2 : 1); ++fx)
        for (int fy = 0; fy < (ny2 ? 2 : 1); ++fy) {
          const double c = fx ? -c0 : c0, s = fy ? -s0 : s0;
          // The traction in the mode's frame (1 along q, 2 across, 3 = z).
          const Cplx a{c * t1.x + s * t2.x, c * t1.y + s * t2.y};
          const Cplx b{-s * t1.x + c * t2.x, -s * t1.y + c * t2.y};
          // s11 = -i X0 a + X1 t3 (likewise Y, N), s12 = i rho b, s13 = S0 a + i S1 t3, s23 = tau b.
          const Cplx s11{P.X[0] * a.y + P.X[1] * t3.x, -P.X[0] * a.x + P.X[1] * t3.y};
          const Cplx s22{P.Y[0] * a.y + P.Y[1] * t3.x, -P.Y[0] * a.x + P.Y[1] * t3.y};
          const Cplx s33{P.N[0] * a.y + P.N[1] * t3.x, -P.N[0] * a.x + P.N[1] * t3.y};
          const Cplx s12{-md.rho * b.y, md.rho * b.x};
          const Cplx s13{P.S[0] * a.x - P.S[1] * t3.y, P.S[0] * a.y + P.S[1] * t3.x};
          const Cplx s23{md.tau * b.x, md.tau * b.y};
          const double cc = c * c, ss = s * s, cs = c * s;
          const Cplx lab[6] = {
              {cc * s11.x + ss * s22.x - 2.0 * cs * s12.x, cc * s11.y + ss * s22.y - 2.0 * cs * s12.y},
              {ss * s11.x + cc * s22.x + 2.0 * cs * s12.x, ss * s11.y + cc * s22.y + 2.0 * cs * s12.y},
              s33,
              {cs * (s11.x - s22.x) + (cc - ss) * s12.x, cs * (s11.y - s22.y) + (cc - ss) * s12.y},
              {c * s13.x - s * s23.x, c * s13.y - s * s23.y},
              {s * s13.x + c * s23.x, s * s13.y + c * s23.y}};
          for (int m = 0; m < 6; ++m) {
            acc[m].x += lab[m].x;
            acc[m].y += lab[m].y;
          }
          ++count;
        }
      for (int m = 0; m < 6; ++m) out6.s[m][k] = {acc[m].x / count, acc[m].y / count};
    });
    for (DevArray<Cplx>* a : {&TZ, &TX, &TY}) a->release();
    DevArray<double> f[6];
    for (int m = 0; m < 6; ++m) {
      f[m].allocate(n_, &bytes_, "stress: subsurface tensor");
      backward(sig[m].get(), f[m].get());
      sig[m].release();
    }
    const double *a0 = f[0].get(), *a1 = f[1].get(), *a2 = f[2].get(), *a3 = f[3].get(), *a4 = f[4].get(),
                 *a5 = f[5].get();
    DeviceStressResult out;
    principal_and_summary(
        [=] __device__(std::size_t k) { return Tensor{a0[k], a1[k], a2[k], a3[k], a4[k], a5[k]}; }, out);
    return out;
  }

  // The wave numbers of the half spectrum's columns (qx) and rows (qy) on the device; deriv:
  // those of a derivative (Grid::qx_deriv, zero on the Nyquist lines).
  void wave_numbers(bool deriv, DevArray<double>& qx, DevArray<double>& qy) {
    std::vector<double> hx(static_cast<std::size_t>(g_.nxh())), hy(static_cast<std::size_t>(g_.ny));
    for (int i = 0; i < g_.nxh(); ++i) hx[static_cast<std::size_t>(i)] = deriv ? g_.qx_deriv(i) : g_.qx(i);
    for (int j = 0; j < g_.ny; ++j) hy[static_cast<std::size_t>(j)] = deriv ? g_.qy_deriv(j) : g_.qy(j);
    for (auto& [h, d] : {std::pair{&hx, &qx}, std::pair{&hy, &qy}}) {
      d->allocate(h->size(), &bytes_, "stress: wave numbers");
      cuda_check(cudaMemcpy(d->get(), h->data(), h->size() * sizeof(double), cudaMemcpyHostToDevice),
                 "stress: wave numbers");
    }
  }

  // grid_argmax: the maximum and the first cell (row order) holding it.
  std::pair<std::size_t, double> argmax(const double* v) {
    const double none = -std::numeric_limits<double>::infinity();
    const double mx =
        red_.run<1, true>(n_, [=] __device__(std::size_t i, double* acc) { acc[0] = fmax(acc[0], v[i]); })[0];
    const double neg = red_.run<1, true>(n_, [=] __device__(std::size_t i, double* acc) {
      if (v[i] == mx) acc[0] = fmax(acc[0], -static_cast<double>(i));
    })[0];
    return {neg == none ? 0 : static_cast<std::size_t>(-neg), mx};
  }

  const Grid& g_;
  DeviceStressRequest req_;
  std::size_t n_ = 0, ns_ = 0;
  Tally bytes_;
  cufftHandle fwd_ = 0, bwd_ = 0;
  Reducer red_;
  DevArray<double> p_, ux_, uy_, tx_, ty_;
  DevArray<ComplianceMode> modes_;
};

Traction traction_of(double mu, double angle_deg) {
  const double a = angle_deg * std::numbers::pi / 180.0;
  return {true, mu, std::cos(a), std::sin(a)};
}

// The host's side of the tensor: zz = -p, xz and yz the tractions.
void complete_tensor(DeviceStressResult& r, const RealField& p, const RealField* tx, const RealField* ty,
                     const Traction& t) {
  if (r.tensor.xx.empty()) return;
  const std::size_t n = p.size();
  StressField& s = r.tensor;
  s.zz.resize(n);
  s.xz.assign(n, 0.0);
  s.yz.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    s.zz[k] = -p[k];
    if (t.from_pressure) {
      s.xz[k] = t.mu * p[k] * t.ex;
      s.yz[k] = t.mu * p[k] * t.ey;
    } else {
      if (tx && !tx->empty()) s.xz[k] = (*tx)[k];
      if (ty && !ty->empty()) s.yz[k] = (*ty)[k];
    }
  }
}

bool usable(const Grid& g) { return !g.is_slab() && g.size() > 0; }

// The surface stresses from the fields' pressure and in-plane displacements with the traction
// t (the fields' own tx, ty unless t.from_pressure).
std::optional<DeviceStressResult> surface_from_displacements(const Grid& g, const ElasticParams& el,
                                                             const ContactFields& f, const Traction& t,
                                                             const DeviceStressRequest& req) {
  el.validate();
  if (!usable(g)) return std::nullopt;
  StressEval e(g, req);
  if (!e.fits(false)) return std::nullopt;
  e.plans();
  e.up(f.pressure, e.p_, "stress: pressure");
  e.up(f.ux, e.ux_, "stress: displacements");
  e.up(f.uy, e.uy_, "stress: displacements");
  const RealField* tx = t.from_pressure ? nullptr : &f.tx;
  const RealField* ty = t.from_pressure ? nullptr : &f.ty;
  DeviceStressResult r = e.evaluate(t, tx, ty, el);
  complete_tensor(r, f.pressure, tx, ty, t);
  return r;
}

}  // namespace

std::optional<DeviceStressResult> device_surface_stress(const Grid& g, const ElasticParams& el,
                                                        const ContactFields& f,
                                                        const DeviceStressRequest& req) {
  return surface_from_displacements(g, el, f, Traction{}, req);
}

std::optional<DeviceStressResult> device_paper_post_analysis_stress(const Grid& g, const ElasticParams& el,
                                                                    const ContactFields& frictionless,
                                                                    double mu, double angle_deg,
                                                                    const DeviceStressRequest& req) {
  return surface_from_displacements(g, el, frictionless, traction_of(mu, angle_deg), req);
}

std::optional<DeviceStressResult> device_post_analysis_stress(const ElasticBody& body,
                                                              const RealField& pressure, double mu,
                                                              double angle_deg,
                                                              const DeviceStressRequest& req) {
  const Grid& g = body.grid();
  if (!usable(g) || body.modes().size() != g.spectral_size()) return std::nullopt;
  StressEval e(g, req);
  if (!e.fits(true)) return std::nullopt;
  e.plans();
  e.up(pressure, e.p_, "stress: pressure");
  const Traction t = traction_of(mu, angle_deg);
  e.displacements_from_compliance(body, t);
  DeviceStressResult r = e.evaluate(t, nullptr, nullptr, body.params());
  complete_tensor(r, pressure, nullptr, nullptr, t);
  return r;
}

std::optional<DeviceStressResult> device_subsurface_stress(const Grid& g, const ElasticParams& el,
                                                           const ContactFields& f, double depth,
                                                           const DeviceStressRequest& req) {
  el.validate();
  stress_detail::check_depth(el, depth);
  if (!usable(g) || el.layered()) return std::nullopt;  // a layered body's planes: the host's
  if (f.pressure.size() != g.size() || (!f.tx.empty() && f.tx.size() != g.size()) ||
      (!f.ty.empty() && f.ty.size() != g.size()))
    return std::nullopt;  // the host's checks say what is wrong
  StressEval e(g, req);
  if (!e.fits(false)) return std::nullopt;
  e.plans();
  e.up(f.pressure, e.p_, "stress: pressure");
  return e.subsurface(depth, el, f.tx, f.ty);
}

}  // namespace gfmd
