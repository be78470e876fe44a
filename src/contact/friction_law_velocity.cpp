// friction.law = "velocity": a coefficient that falls (or rises) with the slip speed,
// mu(|v|) = mu_k + (mu_s - mu_k) exp(-|v|/v_c), mu_k = friction.coefficient (as in the paper
// authors' code: a static peak and a velocity threshold). Its stick is set-valued: a point
// sticks while |tau| <= mu_s p, and it is solved as Coulomb's with the law's resolvent in the
// splitting (FrictionLaw::resolvent), or with the regularised law.
#include <cmath>
#include <limits>

#include "gfmd/contact/friction_law.hpp"

namespace gfmd {

namespace {

std::pair<std::string, std::string> check(const FrictionLaw& law, double) {
  if (std::isnan(law.static_coefficient))  // the key's default: not given
    return {"static_coefficient",
            "is required with friction.law = \"velocity\" (mu_s, the coefficient at rest)"};
  if (!(law.static_coefficient >= 0) || !std::isfinite(law.static_coefficient))
    return {"static_coefficient", "must be a non-negative number (mu_s, the coefficient at rest)"};
  if (!(law.velocity_scale > 0) || !std::isfinite(law.velocity_scale))
    return {"velocity_scale",
            "must be a positive number (v_c / v0, the slip speed of the decay from mu_s to mu_k)"};
  return {};
}

}  // namespace

const FrictionLawType& velocity_friction_law() {
  static const FrictionLawType t{
      .name = "velocity",
      .purpose =
          "speed-dependent coefficient mu(|v|) = mu_k + (mu_s - mu_k) exp(-|v|/v_c), mu_k = coefficient",
      .kind = FrictionLawKind::Velocity,
      .keys = {{"static_coefficient", &FrictionLaw::static_coefficient,
                std::numeric_limits<double>::quiet_NaN(), "mu_s, the coefficient at rest"},
               {"velocity_scale", &FrictionLaw::velocity_scale, 0.0,
                "v_c / v0, the slip speed of the decay"}},
      // The resolvent is single-valued outside the disc for either sign of mu_s - mu_k
      // (contact/friction_law.hpp); inside it stick is chosen.
      .set_valued_stick = true,
      .on_device = true,
      .traction = "mu(|v|) p v/|v|, mu(|v|) = mu_k + (mu_s - mu_k) exp(-|v|/v_c)",
      .check = check};
  return t;
}

}  // namespace gfmd
