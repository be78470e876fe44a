// friction.law = "coulomb": a constant coefficient mu_c, the set-valued law with stick (or, with
// friction.regularization > 0, regularised near stick).
#include "gfmd/contact/friction_law.hpp"

namespace gfmd {

const FrictionLawType& coulomb_friction_law() {
  static const FrictionLawType t{
      .name = "coulomb",
      .purpose = "Coulomb's law: |tau| = mu_c p where slipping, |tau| <= mu_c p where stuck",
      .kind = FrictionLawKind::Coulomb,
      .keys = {},
      .set_valued_stick = true,
      .on_device = true,
      .traction = "mu_c p v/|v|",
      .check = nullptr};
  return t;
}

}  // namespace gfmd
