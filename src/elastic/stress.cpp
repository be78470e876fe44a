// Stresses in the body: surface tensor from a solved state, principal stresses, the
// post-analysis reference, and the exact field below the surface.
//
// Surface (Hooke's law with the free-surface relation). Isotropic Hooke's law,
// sigma_ij = lambda eps_kk delta_ij + 2 G eps_ij with lambda = 2 G nu / (1 - 2 nu). At the
// surface sigma_zz (= -p) is known while eps_zz is not:
//   sigma_zz = lambda (eps_xx + eps_yy) + (lambda + 2G) eps_zz
//   => eps_zz = (sigma_zz - lambda (eps_xx + eps_yy)) / (lambda + 2G).
// Substituting into sigma_xx = (lambda + 2G) eps_xx + lambda eps_yy + lambda eps_zz:
//   sigma_xx = 4G (lambda+G)/(lambda+2G) eps_xx + 2G lambda/(lambda+2G) eps_yy
//              + lambda/(lambda+2G) sigma_zz,
// and with lambda/(lambda+2G) = nu/(1-nu), (lambda+G)/(lambda+2G) = 1/(2(1-nu)):
//   sigma_xx = 2G/(1-nu) (eps_xx + nu eps_yy) + nu/(1-nu) sigma_zz.
// With G = E/(2(1+nu)): 2G/(1-nu) = E/((1+nu)(1-nu)) = E/(1-nu^2) = E*, finite for every
// nu in (-1, 0.5]; at nu = 0.5: sigma_xx = E*(eps_xx + eps_yy/2) + sigma_zz
// (the incompressible limit, lambda -> inf with lambda eps_kk finite). sigma_xy = 2 G eps_xy.
//
// Below the surface (exact spectral solution). Per mode exp(i q x1), q > 0, in the frame
// where q points along axis 1, the problem splits into
//  * antiplane (u2): G u2'' = G q^2 u2, u2 = a e^{qz} (half-space) or a sinh(q(z+h)) (layer,
//    u2 = 0 at z = -h); sigma_23 = G du2/dz fixed by t2, sigma_12 = i q G u2;
//  * plane strain (u1, u3) with u1 = i U, u3 = W, sigma_13 = i S, sigma_33 = N,
//    sigma_11 = X, sigma_22 = Y = nu (X + N). Papkovich-Neuber potentials give four
//    solutions, with E = e^{qz} = e^{-qd} (d = -z the depth) and F = e^{-q(z+h)} =
//    e^{-q(h-d)} (anchored at the base so that every factor is <= 1: no overflow for any qh),
//    delta = qd, eta = q(h-d), kappa = 3 - 4 nu (U, W in units of 1/(2Gq), stresses in 1):
//      phi+ (grad of e^{qz}):        U = E,        W = E,              S = E,  N = E,  X = -E
//      psi+ (4(1-nu)psi - grad(z psi), psi = e^{qz}):
//                                    U = delta E,  W = (kappa+delta) E, S = (1-2nu+delta) E,
//                                    N = (2-2nu+delta) E,  X = (2nu-delta) E
//      phi- (grad of e^{-q(z+h)}):   U = F,        W = -F,             S = -F, N = F,  X = -F
//      psi- (psi = e^{-q(z+h)}, z -> z+h):
//                                    U = -eta F,   W = (kappa+eta) F,   S = (1-2nu+eta) F,
//                                    N = -(2-2nu+eta) F,   X = (eta-2nu) F
//    (each checked against Navier's equations: the state (U, W, S, N) obeys
//    d/d(qz) (U, W, S, N) = (-W + 2S, nu U/(1-nu) + (1-2nu) N/(1-nu), (U - nu N)/(1-nu), S)).
//    Half-space: only the decaying phi+, psi+ terms, fixed by S and N at d = 0.
//    Layer: the four amplitudes are fixed by S, N at the surface and U = W = 0 at the base
//    (a 4x4 system, well conditioned for qh >= 1). For qh < 1 the four functions become
//    nearly dependent, so there the state is propagated from the base instead,
//    w(z) = exp(M q(z+h)) w(-h) with w(-h) = (0, 0, S_b, N_b); M^2 - 1 is nilpotent
//    ((M^2-1)^2 = 0), so exp(M xi) = a + b M + c M^2 + d M^3 with
//    a = cosh - xi sinh/2, b = (3 sinh - xi cosh)/2, c = xi sinh/2, d = (xi cosh - sinh)/2.
//    The surface displacement of both forms reproduces ElasticBody's compliance (SPEC §2),
//    coupling sign included (tests). Back in lab axes with the rotation by (c, s) = q/|q|.
#include "gfmd/elastic/stress.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/elastic/layered.hpp"
#include "principal_point.hpp"
#include "stress_detail.hpp"
namespace gfmd {

using namespace stress_detail;

namespace {
// surface_stress with each mode's strain times factor[k] (null: none), the top layer's
// E(omega)/E0 of a viscoelastic body.
StressField surface_stress_scaled(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                                  const cplx* factor) {
  el.validate();
  const Grid& g = fft.grid();
  const std::size_t n = g.local_size();
  require_size(f.pressure, n, "pressure");
  require_size(f.ux, n, "ux");
  require_size(f.uy, n, "uy");
  const bool has_tx = present(f.tx, g, "tx"), has_ty = present(f.ty, g, "ty");

  SpecField U = fft.spec_field(), V = fft.spec_field(), W = fft.spec_field();
  fft.forward(f.ux.data(), U.data());
  fft.forward(f.uy.data(), V.data());
  const int nxh = g.nxh();
  const cplx i(0.0, 1.0);
  // One strain component at a time: W = its spectrum, synthesised in place.
  const auto strain = [&](int comp, RealField& out) {
    for_rows(g.rows(), [&](int row) {
      const double qy = g.qy_deriv(g.y0 + row);
      for (int ikx = 0; ikx < nxh; ++ikx) {
        const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
        const double qx = g.qx_deriv(ikx);
        W[k] = comp == 0 ? i * qx * U[k] : comp == 1 ? i * qy * V[k] : i * qy * U[k] + i * qx * V[k];
        if (factor) W[k] *= factor[k];
      }
    });
    fft.backward(W.data(), out.data());
  };
  StressField s = make_stress(n);
  strain(0, s.xx);  // eps_xx
  strain(1, s.yy);  // eps_yy
  strain(2, s.xy);  // 2 eps_xy

  const double es = el.contact_modulus, nu = el.poisson;
  const double G = el.shear_modulus(), lat = nu / (1.0 - nu);
  const std::ptrdiff_t nn = static_cast<std::ptrdiff_t>(n);
  parallel_for(nn, [&](std::ptrdiff_t k) {
    const double e_xx = s.xx[k], e_yy = s.yy[k], szz = -f.pressure[k];
    s.zz[k] = szz;
    s.xx[k] = es * (e_xx + nu * e_yy) + lat * szz;
    s.yy[k] = es * (e_yy + nu * e_xx) + lat * szz;
    s.xy[k] = G * s.xy[k];
    s.xz[k] = has_tx ? f.tx[k] : 0.0;
    s.yz[k] = has_ty ? f.ty[k] : 0.0;
  });
  return s;
}
}  // namespace

StressField surface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f) {
  return surface_stress_scaled(fft, el, f, nullptr);
}

StressField paper_post_analysis_stress(const FFT& fft, const ElasticParams& el,
                                       const ContactFields& frictionless, double mu, double angle_deg) {
  const std::size_t n = fft.grid().local_size();
  require_size(frictionless.pressure, n, "pressure");
  require_size(frictionless.ux, n, "ux");
  require_size(frictionless.uy, n, "uy");
  const double a = angle_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(a), ey = std::sin(a);
  ContactFields st;
  st.pressure = frictionless.pressure;
  st.ux = frictionless.ux;
  st.uy = frictionless.uy;
  st.tx.resize(n);
  st.ty.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    st.tx[k] = mu * st.pressure[k] * ex;
    st.ty[k] = mu * st.pressure[k] * ey;
  }
  return surface_stress(fft, el, st);
}

namespace {
// st.ux, st.uy, st.uz: the body's displacement from the tractions of st (tx, ty and -pressure).
void displace_by_tractions(const FFT& fft, const ElasticBody& body, ContactFields& st) {
  const std::size_t n = fft.grid().local_size();
  const bool has_tx = present(st.tx, fft.grid(), "tx"), has_ty = present(st.ty, fft.grid(), "ty");
  RealField tz = fft.real_field();
  for (std::size_t k = 0; k < n; ++k) tz[k] = -st.pressure[k];
  SpecField TX, TY, TZ = fft.spec_field();
  if (has_tx) {
    TX = fft.spec_field();
    fft.forward(st.tx.data(), TX.data());
  }
  if (has_ty) {
    TY = fft.spec_field();
    fft.forward(st.ty.data(), TY.data());
  }
  fft.forward(tz.data(), TZ.data());
  SpecField UX = fft.spec_field(), UY = fft.spec_field(), UZ = fft.spec_field();
  body.displacement(has_tx ? TX.data() : nullptr, has_ty ? TY.data() : nullptr, TZ.data(), UX.data(),
                    UY.data(), UZ.data());
  st.ux = fft.real_field();
  st.uy = fft.real_field();
  st.uz = fft.real_field();
  fft.backward(UX.data(), st.ux.data());
  fft.backward(UY.data(), st.uy.data());
  fft.backward(UZ.data(), st.uz.data());
}

// surface_stress of the state with the tractions of st and the body's displacement from them.
StressField stress_of_tractions(const FFT& fft, const ElasticBody& body, ContactFields& st) {
  displace_by_tractions(fft, body, st);
  return surface_stress(fft, body.params(), st);
}

void check_same_grid(const FFT& fft, const Grid& b, const char* who) {
  const Grid& g = fft.grid();
  if (g.nx != b.nx || g.ny != b.ny || g.lx != b.lx || g.ly != b.ly)
    throw std::invalid_argument(std::string(who) + ": FFT and body are on different grids");
}
}  // namespace

StressField traction_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                            const ViscoelasticParams& visco) {
  require_size(f.pressure, fft.grid().local_size(), "pressure");
  ContactFields st;
  st.pressure = f.pressure;
  st.tx = f.tx;
  st.ty = f.ty;
  using Part = ViscoelasticParams::Part;
  if (!(visco.enabled() && visco.velocity != 0.0 && el.layered() && visco.part != Part::All))
    return stress_of_tractions(fft, ElasticBody(fft.grid(), el), st);
  // A layered body's modes have no common factor: its own complex response, then Hooke's law of
  // the top layer (at each mode's E(omega) = E0 / c if it is a viscoelastic part).
  const ElasticBody body(fft.grid(), el, visco);
  const ViscoelasticStack stack(fft.grid(), el, visco);
  if (!stack.top_viscoelastic()) return stress_of_tractions(fft, body, st);  // an elastic top layer
  displace_by_tractions(fft, body, st);
  std::vector<cplx> modulus(body.modes().size());
  for (std::size_t k = 0; k < modulus.size(); ++k) modulus[k] = 1.0 / stack.top_factor(k);
  return surface_stress_scaled(fft, el, st, modulus.data());
}

ContactFields uniform_slip_tractions(const RealField& pressure, double mu, double angle_deg) {
  const double a = angle_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(a), ey = std::sin(a);
  const std::size_t n = pressure.size();
  ContactFields st;
  st.pressure = pressure;
  st.tx.resize(n);
  st.ty.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    st.tx[k] = mu * pressure[k] * ex;
    st.ty[k] = mu * pressure[k] * ey;
  }
  return st;
}

StressField post_analysis_stress(const FFT& fft, const ElasticBody& body, const RealField& pressure,
                                 double mu, double angle_deg) {
  check_same_grid(fft, body.grid(), "post_analysis_stress");
  require_size(pressure, fft.grid().local_size(), "pressure");
  ContactFields st = uniform_slip_tractions(pressure, mu, angle_deg);
  return stress_of_tractions(fft, body, st);
}

// ---- principal stresses ----------------------------------------------------------------

double von_mises(double xx, double yy, double zz, double xy, double xz, double yz) {
  return principal_detail::von_mises(xx, yy, zz, xy, xz, yz);
}

Principal3 principal(double xx, double yy, double zz, double xy, double xz, double yz) {
  const principal_detail::Point e = principal_detail::principal(xx, yy, zz, xy, xz, yz);
  return {e.s1, e.s2, e.s3, {e.e1.x, e.e1.y, e.e1.z}};
}

PrincipalField principal(const StressField& s, PrincipalParts parts) {
  const std::size_t n = s.xx.size();
  for (const RealField* f : {&s.yy, &s.zz, &s.xy, &s.xz, &s.yz})
    if (f->size() != n) throw std::invalid_argument("principal: stress components of different sizes");
  PrincipalField p;
  const bool all = parts == PrincipalParts::All;
  for (RealField* f : {&p.s1, &p.von_mises}) f->assign(n, 0.0);
  if (all)
    for (RealField* f : {&p.s2, &p.s3, &p.e1x, &p.e1y, &p.e1z}) f->assign(n, 0.0);
  const std::ptrdiff_t nn = static_cast<std::ptrdiff_t>(n);
  parallel_for(nn, [&](std::ptrdiff_t k) {
    const Principal3 e = principal(s.xx[k], s.yy[k], s.zz[k], s.xy[k], s.xz[k], s.yz[k]);
    p.s1[k] = e.s1;
    p.von_mises[k] = von_mises(s.xx[k], s.yy[k], s.zz[k], s.xy[k], s.xz[k], s.yz[k]);
    if (all) {
      p.s2[k] = e.s2;
      p.s3[k] = e.s3;
      p.e1x[k] = e.e1[0];
      p.e1y[k] = e.e1[1];
      p.e1z[k] = e.e1[2];
    }
  });
  return p;
}

StressSummary summarize(const Grid& g, const PrincipalField& p, double high_tension_fraction) {
  const std::size_t n = g.local_size();
  if (p.s1.size() != n || p.von_mises.size() != n)
    throw std::invalid_argument("summarize: principal field does not match the grid");
  StressSummary s;
  s.high_tension_fraction_of = high_tension_fraction;
  if (g.size() == 0) return s;
  const auto [it, vt] = grid_argmax(g, [&](std::size_t k) { return p.s1[k]; });
  const auto [iv, vv] = grid_argmax(g, [&](std::size_t k) { return p.von_mises[k]; });
  s.max_tensile_stress = vt;
  s.max_tensile_ix = static_cast<int>(it % g.nx);
  s.max_tensile_iy = static_cast<int>(it / g.nx);
  s.max_von_mises = vv;
  s.max_von_mises_ix = static_cast<int>(iv % g.nx);
  s.max_von_mises_iy = static_cast<int>(iv / g.nx);
  if (s.max_tensile_stress > 0.0) {
    const double thr = high_tension_fraction * s.max_tensile_stress;
    const double count = grid_sum(g, [&](std::size_t k) { return p.s1[k] >= thr ? 1.0 : 0.0; });
    s.high_tension_area_fraction = count / static_cast<double>(g.size());
  }
  return s;
}

// ---- below the surface -----------------------------------------------------------------

}  // namespace gfmd
