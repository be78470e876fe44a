// friction.law = "rate": a coefficient that grows with the slip speed, mu(|v|) = mu_c +
// a ln(1 + |v|/v_c) (rate strengthening, the steady state of rate-and-state friction with
// b < a), mu_c = friction.coefficient at rest. Its stick is set-valued (|tau| <= mu_c p where
// v = 0) and solved as Coulomb's, with the law's resolvent in the splitting.
#include <cmath>

#include "gfmd/contact/friction_law.hpp"

namespace gfmd {

namespace {

std::pair<std::string, std::string> check(const FrictionLaw& law, double) {
  if (!(law.rate_coefficient >= 0) || !std::isfinite(law.rate_coefficient))
    return {"rate_coefficient", "must be a non-negative number (a in mu_c + a ln(1 + |v|/v_c))"};
  if (!(law.velocity_scale > 0) || !std::isfinite(law.velocity_scale))
    return {"velocity_scale", "must be a positive number (v_c / v0 in mu_c + a ln(1 + |v|/v_c))"};
  return {};
}

}  // namespace

const FrictionLawType& rate_friction_law() {
  static const FrictionLawType t{
      .name = "rate",
      .purpose = "rate-strengthening coefficient mu(|v|) = mu_c + a ln(1 + |v|/v_c), stick included",
      .kind = FrictionLawKind::Rate,
      .keys = {{"rate_coefficient", &FrictionLaw::rate_coefficient, 0.0,
                "a, the strengthening per e-fold of speed"},
               {"velocity_scale", &FrictionLaw::velocity_scale, 0.0, "v_c / v0, the speed where it sets in"}},
      // mu grows with the speed: the dissipation potential is convex and the splitting's
      // resolvent is single-valued (FrictionLaw::resolvent).
      .set_valued_stick = true,
      .on_device = true,
      .traction = "(mu_c + a ln(1 + |v|/v_c)) p v/|v|",
      .check = check};
  return t;
}

}  // namespace gfmd
