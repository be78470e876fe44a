// Friction laws as parts: the traction magnitude where a point slips (from the pressure and the
// slip speed) and the stick disc's radius, what
// each law's solve can do (capabilities), its keys and how outputs describe it. One file per
// law, src/contact/friction_law_<name>.cpp; the table is src/contact/friction_law.cpp.
//
// Adding a law: a FrictionLawKind, its branch in FrictionLaw::bound (host and device alike:
// GFMD_HD), the file with its FrictionLawType and one line in the table; its keys are
// read and written back from `keys` (case/config), listed in Python (gfmd.friction_laws()).
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/core/host_device.hpp"

namespace gfmd {

enum class FrictionLawKind : int { Coulomb = 0, Velocity = 1, Tresca = 2, Rate = 3 };

// The law's parameters, plain data (the solve copies it into its passes). The kinetic
// coefficient mu_k is FrictionParams::coefficient (friction.coefficient).
struct FrictionLaw {
  FrictionLawKind kind = FrictionLawKind::Coulomb;
  double static_coefficient = 0.0;  // velocity: mu_s, the coefficient at zero slip speed
  double velocity_scale = 0.0;      // velocity: v_c / v0, the slip speed over which mu_s decays to mu_k
  double shear_strength =
      0.0;  // tresca: tau_0, the most shear stress the interface carries (a stress, in the unit of E*)
  double rate_coefficient = 0.0;  // rate: a, mu(|v|) = mu_c + a ln(1 + |v|/v_c)
  // The traction magnitude |tau| where a point with pressure p > 0 slips at the speed
  // |v_slip| / v0 = speed; for a law with a set-valued stick (FrictionLawType::set_valued_stick)
  // bound(mu_k, p, 0) is also the radius of the disc |tau| <= ... where it sticks (mu_s p for
  // the velocity law):
  //   coulomb:  mu_k p;
  //   velocity: (mu_k + (mu_s - mu_k) exp(-speed / v_c)) p   (mu_s at rest, mu_k sliding fast);
  //   tresca:   min(mu_k p, tau_0)                             (Coulomb capped at the shear strength);
  //   rate:     (mu_k + a ln(1 + speed / v_c)) p               (rate strengthening, mu_k at rest).
  [[nodiscard]] GFMD_HD double bound(double mu_k, double p, double speed) const {
    if (kind == FrictionLawKind::Velocity)
      return (mu_k + (static_coefficient - mu_k) * std::exp(-speed / velocity_scale)) * p;
    if (kind == FrictionLawKind::Tresca) return std::fmin(mu_k * p, shear_strength);
    if (kind == FrictionLawKind::Rate)
      return (mu_k + rate_coefficient * std::log1p(speed / velocity_scale)) * p;
    return mu_k * p;
  }
  // Whether the traction's magnitude where a point slips depends on its speed.
  [[nodiscard]] GFMD_HD bool speed_dependent() const {
    return kind == FrictionLawKind::Velocity || (kind == FrictionLawKind::Rate && rate_coefficient != 0.0);
  }
  // d bound / d speed, the law's slope in the slip speed (0 for a speed-independent law).
  [[nodiscard]] GFMD_HD double bound_slope(double mu_k, double p, double speed) const {
    if (kind == FrictionLawKind::Velocity)
      return -(static_coefficient - mu_k) / velocity_scale * std::exp(-speed / velocity_scale) * p;
    if (kind == FrictionLawKind::Rate) return rate_coefficient * p / (velocity_scale + speed);
    return 0.0;
  }
  // The steepest fall of the bound with the speed, max over s of -d bound/ds, at the pressure p:
  // (mu_s - mu_k) p / v_c for a velocity law with a static peak, 0 for a bound that never falls.
  // The splitting's step gamma must exceed it for the resolvent below to be continuous at the
  // disc's edge (otherwise f first falls, and the slip speed jumps from 0 to a finite root).
  [[nodiscard]] GFMD_HD double steepest_fall(double mu_k, double p) const {
    return std::fmax(0.0, -bound_slope(mu_k, p, 0.0));
  }
  // The stick-slip splitting's resolvent, radially: the splitting variable z = tau + gamma v at
  // a point has the magnitude zm; returns |tau|. Inside the disc (zm <= bound at rest) the point
  // sticks, tau = z; outside it slips at the speed s with bound(s) + gamma s = zm, |tau| =
  // bound(s). For a speed-independent bound that is the projection onto the disc. Otherwise
  // f(s) = bound(s) + gamma s - zm has f(0) < 0 outside the disc and exactly one root: it
  // increases where the bound grows with the speed (rate; velocity with mu_s < mu_k), and it is
  // convex where the bound falls exponentially (velocity with mu_s > mu_k: a convex function
  // that starts negative crosses zero once). Newton from the left, kept inside the bracket
  // [0, (zm - least bound)/gamma] by bisection. Inside the disc a falling bound may also admit
  // slip roots (when gamma < steepest_fall): the resolvent then selects stick, the static
  // friction's choice; the solve keeps gamma above steepest_fall at the largest pressure
  // (ContactSolver::solve_tangential; docs/solver.md, "Other friction laws").
  [[nodiscard]] GFMD_HD double resolvent(double mu_k, double p, double zm, double gamma) const {
    const double rest = bound(mu_k, p, 0.0);
    if (zm <= rest) return zm;
    if (!speed_dependent()) return rest;  // the projection
    // The least bound over all speeds: mu_k p for a falling velocity law, the rest value else.
    const double least = kind == FrictionLawKind::Velocity ? std::fmin(rest, mu_k * p) : rest;
    double lo = 0.0, hi = (zm - least) / gamma;  // f < 0 at lo, f >= 0 at hi
    double s = lo;
    for (int k = 0; k < 100; ++k) {
      const double f = bound(mu_k, p, s) + gamma * s - zm;
      if (f < 0) {
        lo = s;
      } else {
        hi = s;
      }
      const double df = bound_slope(mu_k, p, s) + gamma;
      double next = df > 0 ? s - f / df : 0.5 * (lo + hi);  // df <= 0 only left of the root
      if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
      if (std::fabs(next - s) <= 1e-15 * s) {
        s = next;
        break;
      }
      s = next;
    }
    return zm - gamma * s;
  }
};

// A law as a registered part.
struct FrictionLawType {
  std::string name;     // friction.law
  std::string purpose;  // one line (docs, gfmd.friction_laws())
  FrictionLawKind kind = FrictionLawKind::Coulomb;
  using Member = double FrictionLaw::*;
  struct Key {
    std::string name;  // friction.<name>
    Member member;     // where it goes
    double default_value;
    std::string doc;
  };
  std::vector<Key> keys;
  // Capabilities. set_valued_stick: the exact law (friction.regularization = 0), whose stick
  // is set-valued, is solved (Douglas-Rachford splitting); otherwise the law needs
  // regularization > 0. on_device: the cuda backend computes it.
  bool set_valued_stick = true;
  bool on_device = true;
  // The traction the law gives where a point slips, for summary.json ("friction_law_traction")
  // and the dissipation field's description: e.g. "mu_c p v/|v|".
  std::string traction;
  // The law's own checks of its parameters: (key, why), or two empty strings.
  std::pair<std::string, std::string> (*check)(const FrictionLaw& law, double mu_k) = nullptr;
};

const FrictionLawType& coulomb_friction_law();
const FrictionLawType& velocity_friction_law();
const FrictionLawType& tresca_friction_law();
const FrictionLawType& rate_friction_law();

// Every registered law, in the order the docs list them.
const std::vector<const FrictionLawType*>& friction_law_types();
// The law named `name`, or nullptr.
const FrictionLawType* find_friction_law(const std::string& name);
// The law of a kind (always registered).
const FrictionLawType& friction_law_type(FrictionLawKind kind);

}  // namespace gfmd
