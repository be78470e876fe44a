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
#include "stress_detail.hpp"
namespace gfmd {

using namespace stress_detail;

StressField surface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f) {
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

StressField post_analysis_stress(const FFT& fft, const ElasticBody& body, const RealField& pressure,
                                 double mu, double angle_deg) {
  const Grid& g = fft.grid();
  if (g.nx != body.grid().nx || g.ny != body.grid().ny || g.lx != body.grid().lx || g.ly != body.grid().ly)
    throw std::invalid_argument("post_analysis_stress: FFT and body are on different grids");
  const std::size_t n = g.local_size();
  require_size(pressure, n, "pressure");
  const double a = angle_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(a), ey = std::sin(a);
  ContactFields st;
  st.pressure = pressure;
  st.tx = fft.real_field();
  st.ty = fft.real_field();
  RealField tz = fft.real_field();
  for (std::size_t k = 0; k < n; ++k) {
    st.tx[k] = mu * pressure[k] * ex;
    st.ty[k] = mu * pressure[k] * ey;
    tz[k] = -pressure[k];
  }
  SpecField TX = fft.spec_field(), TY = fft.spec_field(), TZ = fft.spec_field();
  fft.forward(st.tx.data(), TX.data());
  fft.forward(st.ty.data(), TY.data());
  fft.forward(tz.data(), TZ.data());
  SpecField UX = fft.spec_field(), UY = fft.spec_field(), UZ = fft.spec_field();
  body.displacement(TX.data(), TY.data(), TZ.data(), UX.data(), UY.data(), UZ.data());
  st.ux = fft.real_field();
  st.uy = fft.real_field();
  st.uz = fft.real_field();
  fft.backward(UX.data(), st.ux.data());
  fft.backward(UY.data(), st.uy.data());
  fft.backward(UZ.data(), st.uz.data());
  return surface_stress(fft, body.params(), st);
}

// ---- principal stresses ----------------------------------------------------------------

double von_mises(double xx, double yy, double zz, double xy, double xz, double yz) {
  const double d1 = xx - yy, d2 = yy - zz, d3 = zz - xx;
  return std::sqrt(0.5 * (d1 * d1 + d2 * d2 + d3 * d3) + 3.0 * (xy * xy + xz * xz + yz * yz));
}

namespace {

using Vec3 = std::array<double, 3>;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Unit null vector of the rank-2 matrix A - lambda I from the largest cross product of
// its rows; false if all rows are (nearly) parallel.
bool null_vector(const double A[3][3], double lambda, Vec3& v) {
  const Vec3 r0{A[0][0] - lambda, A[0][1], A[0][2]};
  const Vec3 r1{A[1][0], A[1][1] - lambda, A[1][2]};
  const Vec3 r2{A[2][0], A[2][1], A[2][2] - lambda};
  const Vec3 c[3] = {cross(r0, r1), cross(r0, r2), cross(r1, r2)};
  int best = 0;
  double bn = dot(c[0], c[0]);
  for (int k = 1; k < 3; ++k) {
    const double nk = dot(c[k], c[k]);
    if (nk > bn) {
      bn = nk;
      best = k;
    }
  }
  if (!(bn > 0.0)) return false;
  const double inv = 1.0 / std::sqrt(bn);
  v = {c[best][0] * inv, c[best][1] * inv, c[best][2] * inv};
  return true;
}

void orient(Vec3& v) {
  int m = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(v[k]) > std::abs(v[m])) m = k;
  if (v[m] < 0)
    for (double& x : v) x = -x;
}

}  // namespace

Principal3 principal(double xx, double yy, double zz, double xy, double xz, double yz) {
  // Eberly's scheme: the trigonometric formula gives the eigenvalue that is best
  // separated from the other two accurately (the cosine is flat there), its eigenvector
  // follows from cross products of the rows of A - lambda I; the other two eigenpairs
  // come from the exact 2x2 problem in the plane orthogonal to it. (The trigonometric
  // values of a nearly repeated pair would carry errors of order sqrt(eps).)
  Principal3 out{0, 0, 0, {1.0, 0.0, 0.0}};
  const double scale =
      std::max({std::abs(xx), std::abs(yy), std::abs(zz), std::abs(xy), std::abs(xz), std::abs(yz)});
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    if (!std::isfinite(scale)) out.s1 = out.s2 = out.s3 = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  // Work on A / scale (no overflow or underflow in the squares and the determinant).
  const double inv = 1.0 / scale;
  const double A[3][3] = {
      {xx * inv, xy * inv, xz * inv}, {xy * inv, yy * inv, yz * inv}, {xz * inv, yz * inv, zz * inv}};
  const double m = (A[0][0] + A[1][1] + A[2][2]) / 3.0;
  const double k00 = A[0][0] - m, k11 = A[1][1] - m, k22 = A[2][2] - m;
  const double off = A[0][1] * A[0][1] + A[0][2] * A[0][2] + A[1][2] * A[1][2];
  const double p2 = (k00 * k00 + k11 * k11 + k22 * k22 + 2.0 * off) / 6.0;
  if (!(p2 > 0.0)) {  // A = m I
    out.s1 = out.s2 = out.s3 = m * scale;
    return out;
  }
  const double p = std::sqrt(p2);
  // det(K/p)/2 in [-1, 1].
  const double b00 = k00 / p, b11 = k11 / p, b22 = k22 / p;
  const double b01 = A[0][1] / p, b02 = A[0][2] / p, b12 = A[1][2] / p;
  const double det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  const double r = std::clamp(0.5 * det, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;  // in [0, pi/3]
  // r >= 0: the largest eigenvalue is the best separated one, else the smallest.
  const bool top = r >= 0.0;
  const double ld =
      top ? m + 2.0 * p * std::cos(phi) : m + 2.0 * p * std::cos(phi + 2.0 * std::numbers::pi / 3.0);
  Vec3 w{1.0, 0.0, 0.0};
  if (!null_vector(A, ld, w)) w = {1.0, 0.0, 0.0};  // cannot happen for p > 0; keep it safe
  auto apply = [&](const Vec3& a) {
    return Vec3{A[0][0] * a[0] + A[0][1] * a[1] + A[0][2] * a[2],
                A[1][0] * a[0] + A[1][1] * a[1] + A[1][2] * a[2],
                A[2][0] * a[0] + A[2][1] * a[1] + A[2][2] * a[2]};
  };
  const double lw = dot(w, apply(w));  // Rayleigh quotient: second-order accurate
  // Orthonormal (u, t) spanning the plane orthogonal to w; 2x2 problem there.
  Vec3 u = std::abs(w[0]) > std::abs(w[1]) ? Vec3{-w[2], 0.0, w[0]} : Vec3{0.0, w[2], -w[1]};
  const double un = std::sqrt(dot(u, u));
  for (double& x : u) x /= un;
  const Vec3 t = cross(w, u);
  const Vec3 au = apply(u), at = apply(t);
  const double c11 = dot(u, au), c22 = dot(t, at), c12 = 0.5 * (dot(u, at) + dot(t, au));
  const double mid = 0.5 * (c11 + c22), rad = std::hypot(0.5 * (c11 - c22), c12);
  const double lp = mid + rad, lm = mid - rad;
  const double th = 0.5 * std::atan2(2.0 * c12, c11 - c22);  // eigenvector of lp in (u, t)
  const double ct = std::cos(th), st = std::sin(th);
  const Vec3 vp{ct * u[0] + st * t[0], ct * u[1] + st * t[1], ct * u[2] + st * t[2]};
  double l1, l2, l3;
  Vec3 v1;
  if (lw >= lp) {  // always so when w belongs to the largest eigenvalue (up to rounding)
    l1 = lw, l2 = lp, l3 = lm, v1 = w;
  } else {
    l1 = lp, v1 = vp;
    l2 = std::max(lw, lm), l3 = std::min(lw, lm);
  }
  orient(v1);
  out.s1 = l1 * scale;
  out.s2 = l2 * scale;
  out.s3 = l3 * scale;
  out.e1 = v1;
  return out;
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
