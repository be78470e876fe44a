// The friction laws' table: one line per law (friction_law_<name>.cpp).
#include "gfmd/contact/friction_law.hpp"

#include "gfmd/core/error.hpp"

namespace gfmd {

const std::vector<const FrictionLawType*>& friction_law_types() {
  static const std::vector<const FrictionLawType*> table = {
      &coulomb_friction_law(),   //
      &velocity_friction_law(),  //
      &tresca_friction_law(),    //
      &rate_friction_law(),      //
  };
  return table;
}

const FrictionLawType* find_friction_law(const std::string& name) {
  for (const FrictionLawType* t : friction_law_types())
    if (t->name == name) return t;
  return nullptr;
}

const FrictionLawType& friction_law_type(FrictionLawKind kind) {
  for (const FrictionLawType* t : friction_law_types())
    if (t->kind == kind) return *t;
  throw SolveError("friction law of kind " + std::to_string(static_cast<int>(kind)) + " is not registered");
}

}  // namespace gfmd
