// Subsurface stresses and displacements of a layer or half-space under surface tractions
// (SPEC §5): per-mode plane-strain responses (propagator or anchored layer solution), then
// rotated to the lab frame and synthesised. See include/gfmd/elastic/stress.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/stress.hpp"
#include "stress_detail.hpp"

namespace gfmd {

using namespace stress_detail;

namespace {

// Response at depth to unit S0 (column 0) and unit N0 (column 1) at the surface.
// U, W in units of 1/(2 G q) (u1 = i U/(2Gq), u3 = W/(2Gq)); S, N, X, Y are stresses.
struct Plane {
  double U[2], W[2], S[2], N[2], X[2], Y[2];
};

// Basis values of the four Papkovich-Neuber solutions (see the header comment), rows
// U, W, S, N, X, Y, columns phi+, psi+, phi-, psi-.
void basis(double nu, double E, double dl, double F, double et, double B[6][4]) {
  const double kap = 3.0 - 4.0 * nu;
  const double r[6][4] = {
      {E, dl * E, F, -et * F},
      {E, (kap + dl) * E, -F, (kap + et) * F},
      {E, (1.0 - 2.0 * nu + dl) * E, -F, (1.0 - 2.0 * nu + et) * F},
      {E, (2.0 - 2.0 * nu + dl) * E, F, -(2.0 - 2.0 * nu + et) * F},
      {-E, (2.0 * nu - dl) * E, -F, (et - 2.0 * nu) * F},
      {0.0, 2.0 * nu * E, 0.0, -2.0 * nu * F},
  };
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 4; ++j) B[i][j] = r[i][j];
}

Plane from_basis(const double B[6][4], const double b[4][2]) {
  Plane p{};
  double* rows[6] = {p.U, p.W, p.S, p.N, p.X, p.Y};
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 2; ++c) {
      double v = 0.0;
      for (int j = 0; j < 4; ++j) v += B[i][j] * b[j][c];
      rows[i][c] = v;
    }
  return p;
}

Plane plane_half_space(double dl, double nu) {
  // Amplitudes (phi+, psi+) = (b1, b2): S0 = b1 + (1-2nu) b2, N0 = b1 + (2-2nu) b2.
  const double b[4][2] = {{2.0 - 2.0 * nu, -(1.0 - 2.0 * nu)}, {-1.0, 1.0}, {0.0, 0.0}, {0.0, 0.0}};
  double B[6][4];
  basis(nu, std::exp(-dl), dl, 0.0, 0.0, B);
  return from_basis(B, b);
}

// Gaussian elimination with partial pivoting, 4x4 with two right-hand sides.
void solve4(double A[4][4], double b[4][2]) {
  for (int k = 0; k < 4; ++k) {
    int piv = k;
    for (int i = k + 1; i < 4; ++i)
      if (std::abs(A[i][k]) > std::abs(A[piv][k])) piv = i;
    if (piv != k) {
      for (int j = 0; j < 4; ++j) std::swap(A[k][j], A[piv][j]);
      std::swap(b[k][0], b[piv][0]);
      std::swap(b[k][1], b[piv][1]);
    }
    for (int i = k + 1; i < 4; ++i) {
      const double m = A[i][k] / A[k][k];
      for (int j = k; j < 4; ++j) A[i][j] -= m * A[k][j];
      b[i][0] -= m * b[k][0];
      b[i][1] -= m * b[k][1];
    }
  }
  for (int k = 3; k >= 0; --k)
    for (int c = 0; c < 2; ++c) {
      double v = b[k][c];
      for (int j = k + 1; j < 4; ++j) v -= A[k][j] * b[j][c];
      b[k][c] = v / A[k][k];
    }
}

// Layer, qh >= 1: amplitudes from the 4x4 system in the anchored basis.
Plane plane_layer_anchored(double x, double dl, double nu) {
  const double e = std::exp(-x);
  double Bb[6][4], Bs[6][4];
  basis(nu, e, x, 1.0, 0.0, Bb);  // at the base: d = h
  basis(nu, 1.0, 0.0, e, x, Bs);  // at the surface: d = 0
  double A[4][4], b[4][2] = {{0, 0}, {0, 0}, {1, 0}, {0, 1}};
  for (int j = 0; j < 4; ++j) {
    A[0][j] = Bb[0][j];  // U = 0 at the base
    A[1][j] = Bb[1][j];  // W = 0 at the base
    A[2][j] = Bs[2][j];  // S = S0 at the surface
    A[3][j] = Bs[3][j];  // N = N0 at the surface
  }
  solve4(A, b);
  const double et = std::max(0.0, x - dl);
  double B[6][4];
  basis(nu, std::exp(-dl), dl, std::exp(-et), et, B);
  return from_basis(B, b);
}

// Columns 2, 3 (unit S and N at the start) of the propagator exp(M xi), state (U, W, S, N).
void propagator_cols(double xi, const double M1[4][4], const double M2[4][4], const double M3[4][4],
                     double P[4][2]) {
  const double ch = std::cosh(xi), sh = std::sinh(xi);
  const double a = ch - 0.5 * xi * sh;
  const double b = 0.5 * (3.0 * sh - xi * ch);
  const double c = 0.5 * xi * sh;
  // d = (xi cosh - sinh)/2 = sum_{k>=1} k xi^(2k+1)/(2k+1)! (no cancellation for small xi).
  double d = 0.0, term = xi;  // term = xi^(2k+1)/(2k+1)!
  for (int k = 1; k < 30; ++k) {
    term *= xi * xi / ((2.0 * k) * (2.0 * k + 1.0));
    d += k * term;
    if (k * term <= 1e-18 * d) break;
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j) {
      const int col = j + 2;
      P[i][j] = (i == col ? a : 0.0) + b * M1[i][col] + c * M2[i][col] + d * M3[i][col];
    }
}

// Layer, qh < 1: propagate the base state (0, 0, S_b, N_b) to the surface and to depth d.
Plane plane_layer_propagator(double x, double dl, double nu) {
  const double om = 1.0 - nu;
  const double M1[4][4] = {{0.0, -1.0, 2.0, 0.0},
                           {nu / om, 0.0, 0.0, (1.0 - 2.0 * nu) / om},
                           {1.0 / om, 0.0, 0.0, -nu / om},
                           {0.0, 0.0, 1.0, 0.0}};
  double M2[4][4] = {}, M3[4][4] = {};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) M2[i][j] += M1[i][k] * M1[k][j];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) M3[i][j] += M2[i][k] * M1[k][j];
  double Px[4][2], Pd[4][2];
  propagator_cols(x, M1, M2, M3, Px);
  propagator_cols(std::max(0.0, x - dl), M1, M2, M3, Pd);
  // (S0, N0) = A (S_b, N_b), A = rows S, N of Px; base tractions = A^-1.
  const double a11 = Px[2][0], a12 = Px[2][1], a21 = Px[3][0], a22 = Px[3][1];
  const double det = a11 * a22 - a12 * a21;
  const double inv[2][2] = {{a22 / det, -a12 / det}, {-a21 / det, a11 / det}};
  Plane p{};
  double* rows[4] = {p.U, p.W, p.S, p.N};
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 2; ++c) rows[i][c] = Pd[i][0] * inv[0][c] + Pd[i][1] * inv[1][c];
  for (int c = 0; c < 2; ++c) {
    p.X[c] = -(p.U[c] - nu * p.N[c]) / om;  // X = -dS/d(qz)
    p.Y[c] = nu * (p.X[c] + p.N[c]);        // plane strain
  }
  return p;
}

void check_depth(const ElasticParams& el, double depth) {
  if (!(depth >= 0.0) || !std::isfinite(depth))
    throw ParameterError("depth", "must be a finite number >= 0 (depth below the surface)");
  if (!el.half_space() && depth > el.thickness * (1.0 + 1e-12))
    throw ParameterError("depth", "is below the rigid base of the layer (depth > thickness)");
}

// Lab-frame stress (xx, yy, zz, xy, xz, yz) and displacement of one mode with direction
// (c, s) for lab tractions (tx, ty, tz).
void to_lab(const ModeResponse& r, double c, double s, cplx tx, cplx ty, cplx tz, cplx* sig, cplx* u) {
  const cplx t[3] = {c * tx + s * ty, -s * tx + c * ty, tz};
  cplx sp[6], up[3];
  for (int k = 0; k < 6; ++k) sp[k] = r.stress[k][0] * t[0] + r.stress[k][1] * t[1] + r.stress[k][2] * t[2];
  for (int k = 0; k < 3; ++k) up[k] = r.disp[k][0] * t[0] + r.disp[k][1] * t[1] + r.disp[k][2] * t[2];
  if (sig) {
    const cplx s11 = sp[0], s22 = sp[1], s33 = sp[2], s12 = sp[3], s13 = sp[4], s23 = sp[5];
    sig[0] = c * c * s11 + s * s * s22 - 2.0 * c * s * s12;
    sig[1] = s * s * s11 + c * c * s22 + 2.0 * c * s * s12;
    sig[2] = s33;
    sig[3] = c * s * (s11 - s22) + (c * c - s * s) * s12;
    sig[4] = c * s13 - s * s23;
    sig[5] = s * s13 + c * s23;
  }
  if (u) {
    u[0] = c * up[0] - s * up[1];
    u[1] = s * up[0] + c * up[1];
    u[2] = up[2];
  }
}

// Spectral evaluation of the response on the whole grid; sig (6 spectra) and/or u (3).
void subsurface_spectra(const FFT& fft, const ElasticParams& el, const ContactFields& f, double depth,
                        std::array<SpecField, 6>* sig, std::array<SpecField, 3>* u) {
  el.validate();
  check_depth(el, depth);
  const Grid& g = fft.grid();
  const std::size_t n = g.local_size();
  require_size(f.pressure, n, "pressure");
  const bool has_tx = present(f.tx, g, "tx"), has_ty = present(f.ty, g, "ty");
  RealField tz(n);
  for (std::size_t i = 0; i < n; ++i) tz[i] = -f.pressure[i];
  SpecField TZ = fft.spec_field(), TX, TY;
  fft.forward(tz.data(), TZ.data());
  if (has_tx) {
    TX = fft.spec_field();
    fft.forward(f.tx.data(), TX.data());
  }
  if (has_ty) {
    TY = fft.spec_field();
    fft.forward(f.ty.data(), TY.data());
  }
  if (sig)
    for (auto& s : *sig) s = fft.spec_field();
  if (u)
    for (auto& s : *u) s = fft.spec_field();
  const int nxh = g.nxh();
  const bool evenx = g.nx % 2 == 0, eveny = g.ny % 2 == 0;
  for_rows(g.rows(), [&](int row) {
    const int iky = g.y0 + row;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      const double qx = g.qx(ikx), qy = g.qy(iky), q = std::hypot(qx, qy);
      const ModeResponse r = mode_response(q, depth, el);
      const double c = q > 0 ? qx / q : 1.0, s = q > 0 ? qy / q : 0.0;
      const cplx tx = has_tx ? TX[k] : cplx(0.0), ty = has_ty ? TY[k] : cplx(0.0), tzk = TZ[k];
      // On a Nyquist line the mode q and its mirror are the same mode: keep the part of
      // the response that is even in that component (as ElasticBody does).
      const bool nyx = evenx && ikx == g.nx / 2, nyy = eveny && iky == g.ny / 2;
      cplx sacc[6] = {}, uacc[3] = {};
      int count = 0;
      for (int fx = 0; fx < (nyx ? 2 : 1); ++fx)
        for (int fy = 0; fy < (nyy ? 2 : 1); ++fy) {
          cplx sg[6], ug[3];
          to_lab(r, fx ? -c : c, fy ? -s : s, tx, ty, tzk, sig ? sg : nullptr, u ? ug : nullptr);
          if (sig)
            for (int m = 0; m < 6; ++m) sacc[m] += sg[m];
          if (u)
            for (int m = 0; m < 3; ++m) uacc[m] += ug[m];
          ++count;
        }
      if (sig)
        for (int m = 0; m < 6; ++m) (*sig)[m][k] = sacc[m] / static_cast<double>(count);
      if (u)
        for (int m = 0; m < 3; ++m) (*u)[m][k] = uacc[m] / static_cast<double>(count);
    }
  });
}
}  // namespace

ModeResponse mode_response(double q, double depth, const ElasticParams& el) {
  const double nu = el.poisson, es = el.contact_modulus, om = 1.0 - nu;
  const double G = el.shear_modulus();
  const bool half = el.half_space();
  const double h = el.thickness;
  const cplx i(0.0, 1.0);
  ModeResponse r;
  if (q == 0.0) {
    // Uniform traction: uniform stress, uniaxial strain (no mean in-plane strain).
    r.stress[0][2] = r.stress[1][2] = nu / om;
    r.stress[2][2] = 1.0;
    r.stress[4][0] = 1.0;
    r.stress[5][1] = 1.0;
    // Uniform strain eps_xz = t1/(2G), eps_zz = t3/(lambda+2G); displacement pinned at the
    // rigid base (layer) or, as in ElasticBody, zero at the surface (half-space).
    const double z = half ? -depth : std::max(0.0, h - depth);
    r.disp[0][0] = r.disp[1][1] = z / G;
    r.disp[2][2] = z * (1.0 - 2.0 * nu) / (om * om * es);
    return r;
  }
  const double dl = q * depth;
  Plane p;
  double tau, rho;  // antiplane: sigma_23 = tau t2, sigma_12 = i rho t2, u2 = rho t2 / (G q)
  if (half) {
    p = plane_half_space(dl, nu);
    tau = rho = std::exp(-dl);
  } else {
    const double x = q * h, et = std::max(0.0, x - dl);
    p = x >= 1.0 ? plane_layer_anchored(x, dl, nu) : plane_layer_propagator(x, dl, nu);
    // cosh(eta)/cosh(x), sinh(eta)/cosh(x) with only decaying exponentials.
    const double ed = std::exp(-dl), den = 1.0 + std::exp(-2.0 * x);
    tau = ed * (1.0 + std::exp(-2.0 * et)) / den;
    rho = -ed * std::expm1(-2.0 * et) / den;
  }
  // Plane strain inputs S0 = -i t1, N0 = t3.
  r.stress[0][0] = -i * p.X[0];
  r.stress[0][2] = p.X[1];
  r.stress[1][0] = -i * p.Y[0];
  r.stress[1][2] = p.Y[1];
  r.stress[2][0] = -i * p.N[0];
  r.stress[2][2] = p.N[1];
  r.stress[4][0] = p.S[0];  // sigma_13 = i S = S_S t1 + i S_N t3
  r.stress[4][2] = i * p.S[1];
  r.stress[3][1] = i * rho;                   // sigma_12
  r.stress[5][1] = tau;                       // sigma_23
  const double u_unit = 1.0 / (2.0 * G * q);  // U, W are 2 G q times the displacement
  r.disp[0][0] = p.U[0] * u_unit;             // u1 = i U
  r.disp[0][2] = i * p.U[1] * u_unit;
  r.disp[2][0] = -i * p.W[0] * u_unit;  // u3 = W
  r.disp[2][2] = p.W[1] * u_unit;
  r.disp[1][1] = rho / (G * q);
  return r;
}

StressField subsurface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f, double depth) {
  std::array<SpecField, 6> sig;
  subsurface_spectra(fft, el, f, depth, &sig, nullptr);
  StressField s = make_stress(fft.grid().local_size());
  RealField* out[6] = {&s.xx, &s.yy, &s.zz, &s.xy, &s.xz, &s.yz};
  for (int m = 0; m < 6; ++m) fft.backward(sig[m].data(), out[m]->data());
  return s;
}

DisplacementField subsurface_displacement(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                                          double depth) {
  std::array<SpecField, 3> u;
  subsurface_spectra(fft, el, f, depth, nullptr, &u);
  DisplacementField d;
  RealField* out[3] = {&d.ux, &d.uy, &d.uz};
  for (int m = 0; m < 3; ++m) {
    out[m]->assign(fft.grid().local_size(), 0.0);
    fft.backward(u[m].data(), out[m]->data());
  }
  return d;
}

}  // namespace gfmd
