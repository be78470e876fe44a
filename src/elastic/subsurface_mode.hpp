// The plane-strain and antiplane response of one surface-traction mode at a depth (the
// solutions of subsurface.cpp's header comment), written once for the host (subsurface.cpp)
// and the CUDA device (device_stress.cu): plain real arithmetic, no library types.
#pragma once

#include <cmath>

#include "gfmd/core/host_device.hpp"

namespace gfmd::subsurface_detail {

// max(0, v) as std::max(0.0, v) gives it (0 for NaN).
GFMD_HD inline double nonneg(double v) { return 0.0 < v ? v : 0.0; }

// Response at depth to unit S0 (column 0) and unit N0 (column 1) at the surface.
// U, W in units of 1/(2 G q) (u1 = i U/(2Gq), u3 = W/(2Gq)); S, N, X, Y are stresses.
struct Plane {
  double U[2], W[2], S[2], N[2], X[2], Y[2];
};

// Basis values of the four Papkovich-Neuber solutions (see subsurface.cpp), rows
// U, W, S, N, X, Y, columns phi+, psi+, phi-, psi-.
GFMD_HD inline void basis(double nu, double E, double dl, double F, double et, double B[6][4]) {
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

GFMD_HD inline Plane from_basis(const double B[6][4], const double b[4][2]) {
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

GFMD_HD inline Plane plane_half_space(double dl, double nu) {
  // Amplitudes (phi+, psi+) = (b1, b2): S0 = b1 + (1-2nu) b2, N0 = b1 + (2-2nu) b2.
  const double b[4][2] = {{2.0 - 2.0 * nu, -(1.0 - 2.0 * nu)}, {-1.0, 1.0}, {0.0, 0.0}, {0.0, 0.0}};
  double B[6][4];
  basis(nu, exp(-dl), dl, 0.0, 0.0, B);
  return from_basis(B, b);
}

// Gaussian elimination with partial pivoting, 4x4 with two right-hand sides.
GFMD_HD inline void solve4(double A[4][4], double b[4][2]) {
  for (int k = 0; k < 4; ++k) {
    int piv = k;
    for (int i = k + 1; i < 4; ++i)
      if (fabs(A[i][k]) > fabs(A[piv][k])) piv = i;
    if (piv != k) {
      for (int j = 0; j < 4; ++j) {
        const double t = A[k][j];
        A[k][j] = A[piv][j];
        A[piv][j] = t;
      }
      for (int c = 0; c < 2; ++c) {
        const double t = b[k][c];
        b[k][c] = b[piv][c];
        b[piv][c] = t;
      }
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
GFMD_HD inline Plane plane_layer_anchored(double x, double dl, double nu) {
  const double e = exp(-x);
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
  const double et = nonneg(x - dl);
  double B[6][4];
  basis(nu, exp(-dl), dl, exp(-et), et, B);
  return from_basis(B, b);
}

// Columns 2, 3 (unit S and N at the start) of the propagator exp(M xi), state (U, W, S, N).
GFMD_HD inline void propagator_cols(double xi, const double M1[4][4], const double M2[4][4],
                                    const double M3[4][4], double P[4][2]) {
  const double ch = cosh(xi), sh = sinh(xi);
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
GFMD_HD inline Plane plane_layer_propagator(double x, double dl, double nu) {
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
  propagator_cols(nonneg(x - dl), M1, M2, M3, Pd);
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

// The response of a mode with q > 0 at depth `depth`: the plane-strain part and the
// antiplane factors (sigma_23 = tau t2, sigma_12 = i rho t2, u2 = rho t2 / (G q)).
struct Mode {
  Plane p;
  double tau, rho;
};
// thickness: the layer's (ignored when half_space).
GFMD_HD inline Mode mode_plane(double q, double depth, double nu, bool half_space, double thickness) {
  const double dl = q * depth;
  Mode m;
  if (half_space) {
    m.p = plane_half_space(dl, nu);
    m.tau = m.rho = exp(-dl);
  } else {
    const double x = q * thickness, et = nonneg(x - dl);
    m.p = x >= 1.0 ? plane_layer_anchored(x, dl, nu) : plane_layer_propagator(x, dl, nu);
    // cosh(eta)/cosh(x), sinh(eta)/cosh(x) with only decaying exponentials.
    const double ed = exp(-dl), den = 1.0 + exp(-2.0 * x);
    m.tau = ed * (1.0 + exp(-2.0 * et)) / den;
    m.rho = -ed * expm1(-2.0 * et) / den;
  }
  return m;
}

}  // namespace gfmd::subsurface_detail
