// Shared pieces of the contact solver's parts (private to the contact part): constants of
// the stick-slip iteration, checks and the per-point sums of a friction step.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include "gfmd/core/error.hpp"

namespace gfmd::contact_detail {

using Clock = std::chrono::steady_clock;
// Stick-slip (Douglas-Rachford) iteration of the exact law, chosen by measurement (see
// docs/solver.md): step gamma = 1/rho(A), over-relaxation 1.6, no Anderson mixing by default
// (it saves iterations but not time: its two passes over 2 N entries cost about what the
// step's four transforms do); each stick-slip solve within a friction step stops at 1e-2 of
// the friction change.
inline constexpr double kStickStepFactor = 1.0;
inline constexpr double kTangentialRelaxation = 1.6;
inline constexpr double kTangentialTolFactor = 1e-2;
// With friction.stick_acceleration > 0 (Anderson mixing of z, safeguarded): relaxation 1.4,
// stick-slip solves to 3e-3 of the friction change and, in the stick-slip phase, normal
// solves to 0.3 of it (0.1 otherwise); measured on the thin layer (docs/solver.md).
inline constexpr double kAcceleratedRelaxation = 1.4;
inline constexpr double kAcceleratedTangentialTolFactor = 3e-3;
inline constexpr double kAcceleratedNormalTolFactor = 0.3;
// The full-slip map hands over to the stick-slip solve once contact points slip slower than
// kNearStickSpeed v0 in kNearStickSteps successive friction steps, from friction step
// kNearStickFirst on (the first steps start from a traction the pressure has not met yet).
inline constexpr double kNearStickSpeed = 0.03;
inline constexpr int kNearStickSteps = 2;
inline constexpr int kNearStickFirst = 4;

inline void require_finite(double v, const char* what, int it) {
  if (!std::isfinite(v)) {
    std::ostringstream os;
    os << "solve diverged: " << what << " is not finite at iteration " << it;
    throw SolveError(os.str());
  }
}
// A point joins the Anderson support of the friction iteration when it is not in it yet
// and the iterate (fx, fy) or its image (x, y) is non-zero there.
inline bool joins_support(unsigned char in_supp, double x, double y, double fx, double fy) {
  return !in_supp && (x != 0.0 || y != 0.0 || fx != 0.0 || fy != 0.0);
}

// Sums of a friction step at a point with new traction (x, y) and previous (fx, fy): the
// change |new - old|_1, the size |new|_1, and whether the point joins the Anderson support.
template <std::size_t N>
inline void add_change(std::array<double, N>& acc, unsigned char in_supp, double x, double y, double fx,
                       double fy) {
  acc[0] += std::abs(x - fx) + std::abs(y - fy);
  acc[1] += std::abs(x) + std::abs(y);
  if (joins_support(in_supp, x, y, fx, fy)) acc[2] += 1.0;
}

}  // namespace gfmd::contact_detail
