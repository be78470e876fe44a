// Maugis's (1992) adhesive sphere, the reference of the adhesion tests (Dugdale's cohesive
// law; its DMT and JKR limits): the force and contact radius along the curve, the pull-off.
#pragma once

#include <algorithm>
#include <cmath>

namespace gfmd::testing {

// Maugis (1992) in Johnson & Greenwood's (1997) variables, K = 4E*/3: lambda =
// 2 sigma0 (R/(pi w K^2))^(1/3), A = a (K/(pi w R^2))^(1/3), P = F/(pi w R), m = c/a (c the
// cohesive zone's outer radius). For each m the zone condition is a quadratic in A:
//   (lambda A^2/2) [s + (m^2 - 2) atan s] + (4 lambda^2 A/3) [s atan s - m + 1] = 1, s = sqrt(m^2 - 1),
//   P = A^3 - lambda A^2 [s + m^2 atan s].
struct MaugisPoint {
  double A, P;
};
inline MaugisPoint maugis(double lambda, double m) {
  const double s = std::sqrt(m * m - 1), at = std::atan(s);
  const double al = lambda / 2 * (s + (m * m - 2) * at);
  const double be = 4 * lambda * lambda / 3 * (s * at - m + 1);
  const double A = (-be + std::sqrt(be * be + 4 * al)) / (2 * al);
  return {A, A * A * A - lambda * A * A * (s + m * m * at)};
}
// The pull-off (the least P over the curve, load control's) by a fine scan of m.
inline double maugis_pull_off(double lambda) {
  double best = 0;
  for (int k = 0; k <= 200000; ++k)
    best = std::min(best, maugis(lambda, 1 + std::pow(10.0, -8 + 11e-5 * k)).P);
  return best;
}
// The contact radius A at force P on the stable branch (A above the pull-off's), by bisection in m
// (A falls as m grows).
inline double maugis_radius(double lambda, double P) {
  double lo = 1 + 1e-10, hi = 1e3;
  // the pull-off's m bounds the stable branch
  double best = 0, mbest = hi;
  for (int k = 0; k <= 20000; ++k) {
    const double m = 1 + std::pow(10.0, -8 + 11e-4 * k);
    if (const double p = maugis(lambda, m).P; p < best) best = p, mbest = m;
  }
  hi = mbest;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (maugis(lambda, mid).P > P ? lo : hi) = mid;
  }
  return maugis(lambda, std::sqrt(lo * hi)).A;
}

}  // namespace gfmd::testing
