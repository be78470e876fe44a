// Principal stresses and von Mises stress of one symmetric tensor, written once for the host
// (stress.cpp) and the CUDA device (device_stress.cu): plain arithmetic, no library types.
#pragma once

#include <cmath>
#include <numbers>

#include "gfmd/core/host_device.hpp"

namespace gfmd::principal_detail {

struct V3 {
  double x, y, z;
};
struct Point {
  double s1, s2, s3;  // s1 >= s2 >= s3
  V3 e1;              // unit eigenvector of s1, its largest component positive
};

GFMD_HD inline V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
GFMD_HD inline double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
GFMD_HD inline V3 scaled(const V3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }

// Symmetric matrix (a00 a01 a02 / . a11 a12 / . . a22).
struct Sym {
  double a00, a01, a02, a11, a12, a22;
  GFMD_HD V3 apply(const V3& v) const {
    return {a00 * v.x + a01 * v.y + a02 * v.z, a01 * v.x + a11 * v.y + a12 * v.z,
            a02 * v.x + a12 * v.y + a22 * v.z};
  }
};

// Unit null vector of the rank-2 matrix A - lambda I from the largest cross product of its
// rows; false if all rows are (nearly) parallel.
GFMD_HD inline bool null_vector(const Sym& A, double lambda, V3& v) {
  const V3 r0{A.a00 - lambda, A.a01, A.a02};
  const V3 r1{A.a01, A.a11 - lambda, A.a12};
  const V3 r2{A.a02, A.a12, A.a22 - lambda};
  const V3 c[3] = {cross(r0, r1), cross(r0, r2), cross(r1, r2)};
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
  v = scaled(c[best], 1.0 / sqrt(bn));
  return true;
}

// The sign convention of the eigenvector: its largest component (the first of equals) positive.
GFMD_HD inline void orient(V3& v) {
  const double a[3] = {fabs(v.x), fabs(v.y), fabs(v.z)};
  const double c[3] = {v.x, v.y, v.z};
  int m = 0;
  for (int k = 1; k < 3; ++k)
    if (a[k] > a[m]) m = k;
  if (c[m] < 0) v = scaled(v, -1.0);
}

GFMD_HD inline double von_mises(double xx, double yy, double zz, double xy, double xz, double yz) {
  const double d1 = xx - yy, d2 = yy - zz, d3 = zz - xx;
  return sqrt(0.5 * (d1 * d1 + d2 * d2 + d3 * d3) + 3.0 * (xy * xy + xz * xz + yz * yz));
}

// Eberly's scheme: the trigonometric formula gives the eigenvalue that is best separated from
// the other two accurately (the cosine is flat there), its eigenvector follows from cross
// products of the rows of A - lambda I; the other two eigenpairs come from the exact 2x2
// problem in the plane orthogonal to it. (The trigonometric values of a nearly repeated pair
// would carry errors of order sqrt(eps).)
GFMD_HD inline Point principal(double xx, double yy, double zz, double xy, double xz, double yz) {
  Point out{0, 0, 0, {1.0, 0.0, 0.0}};
  const double mags[6] = {fabs(xx), fabs(yy), fabs(zz), fabs(xy), fabs(xz), fabs(yz)};
  double scale = mags[0];
  for (int k = 1; k < 6; ++k)
    if (scale < mags[k]) scale = mags[k];
  const bool finite = scale - scale == 0.0;  // false for inf and NaN
  if (!(scale > 0.0) || !finite) {
    if (!finite) out.s1 = out.s2 = out.s3 = static_cast<double>(NAN);
    return out;
  }
  // Work on A / scale (no overflow or underflow in the squares and the determinant).
  const double inv = 1.0 / scale;
  const Sym A{xx * inv, xy * inv, xz * inv, yy * inv, yz * inv, zz * inv};
  const double m = (A.a00 + A.a11 + A.a22) / 3.0;
  const double k00 = A.a00 - m, k11 = A.a11 - m, k22 = A.a22 - m;
  const double off = A.a01 * A.a01 + A.a02 * A.a02 + A.a12 * A.a12;
  const double p2 = (k00 * k00 + k11 * k11 + k22 * k22 + 2.0 * off) / 6.0;
  if (!(p2 > 0.0)) {  // A = m I
    out.s1 = out.s2 = out.s3 = m * scale;
    return out;
  }
  const double p = sqrt(p2);
  // det(K/p)/2 in [-1, 1].
  const double b00 = k00 / p, b11 = k11 / p, b22 = k22 / p;
  const double b01 = A.a01 / p, b02 = A.a02 / p, b12 = A.a12 / p;
  const double det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  double r = 0.5 * det;
  if (r < -1.0) r = -1.0;
  if (r > 1.0) r = 1.0;
  const double phi = acos(r) / 3.0;  // in [0, pi/3]
  // r >= 0: the largest eigenvalue is the best separated one, else the smallest.
  const bool top = r >= 0.0;
  const double ld = top ? m + 2.0 * p * cos(phi) : m + 2.0 * p * cos(phi + 2.0 * std::numbers::pi / 3.0);
  V3 w{1.0, 0.0, 0.0};
  if (!null_vector(A, ld, w)) w = {1.0, 0.0, 0.0};  // cannot happen for p > 0; keep it safe
  const double lw = dot(w, A.apply(w));             // Rayleigh quotient: second-order accurate
  // Orthonormal (u, t) spanning the plane orthogonal to w; 2x2 problem there.
  V3 u = fabs(w.x) > fabs(w.y) ? V3{-w.z, 0.0, w.x} : V3{0.0, w.z, -w.y};
  u = scaled(u, 1.0 / sqrt(dot(u, u)));
  const V3 t = cross(w, u);
  const V3 au = A.apply(u), at = A.apply(t);
  const double c11 = dot(u, au), c22 = dot(t, at), c12 = 0.5 * (dot(u, at) + dot(t, au));
  const double mid = 0.5 * (c11 + c22), rad = hypot(0.5 * (c11 - c22), c12);
  const double lp = mid + rad, lm = mid - rad;
  const double th = 0.5 * atan2(2.0 * c12, c11 - c22);  // eigenvector of lp in (u, t)
  const double ct = cos(th), st = sin(th);
  const V3 vp{ct * u.x + st * t.x, ct * u.y + st * t.y, ct * u.z + st * t.z};
  double l1, l2, l3;
  V3 v1;
  if (lw >= lp) {  // always so when w belongs to the largest eigenvalue (up to rounding)
    l1 = lw, l2 = lp, l3 = lm, v1 = w;
  } else {
    l1 = lp, v1 = vp;
    l2 = lw < lm ? lm : lw;  // std::max(lw, lm)
    l3 = lm < lw ? lm : lw;  // std::min(lw, lm)
  }
  orient(v1);
  out.s1 = l1 * scale;
  out.s2 = l2 * scale;
  out.s3 = l3 * scale;
  out.e1 = v1;
  return out;
}

}  // namespace gfmd::principal_detail
