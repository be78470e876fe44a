// friction.law = "tresca": Coulomb's law capped at the interface's shear strength tau_0,
// |tau| = min(mu_c p, tau_0) where slipping, |tau| <= min(mu_c p, tau_0) where stuck (the
// Coulomb-Orowan law; with a large mu_c, Tresca's constant shear stress over the contact).
#include <cmath>

#include "gfmd/contact/friction_law.hpp"

namespace gfmd {

namespace {

std::pair<std::string, std::string> check(const FrictionLaw& law, double) {
  if (!(law.shear_strength > 0) || !std::isfinite(law.shear_strength))
    return {"shear_strength",
            "must be a positive number (tau_0, the interface's shear strength: a stress in the unit of "
            "elastic.contact_modulus)"};
  return {};
}

}  // namespace

const FrictionLawType& tresca_friction_law() {
  static const FrictionLawType t{
      .name = "tresca",
      .purpose = "Coulomb's law capped at the shear strength: |tau| = min(mu_c p, tau_0) (Coulomb-Orowan)",
      .kind = FrictionLawKind::Tresca,
      .keys = {{"shear_strength", &FrictionLaw::shear_strength, 0.0,
                "tau_0, the interface's shear strength (a stress in the unit of elastic.contact_modulus)"}},
      // The bound does not depend on the slip speed: its stick is a disc, as Coulomb's.
      .set_valued_stick = true,
      .on_device = true,
      .traction = "min(mu_c p, tau_0) v/|v|",
      .check = check};
  return t;
}

}  // namespace gfmd
