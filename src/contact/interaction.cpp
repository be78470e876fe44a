// The interaction models' table: one line per model (interaction_<name>.cpp).
#include "gfmd/contact/interaction.hpp"

#include "gfmd/core/error.hpp"

namespace gfmd {

const std::vector<const InteractionType*>& interaction_types() {
  // In the order the docs list them (interaction_type decides which claims a parameter set).
  static const std::vector<const InteractionType*> table = {
      &harmonic_interaction(),  //
      &hardwall_interaction(),  //
      &adhesive_interaction(),  //
  };
  return table;
}

const InteractionType* find_interaction(const std::string& name) {
  const std::string n = name == "hard_wall" ? "hardwall" : name;
  for (const InteractionType* t : interaction_types())
    if (t->name == n) return t;
  return nullptr;
}

const InteractionType& interaction_type(const InteractionParams& p) {
  // The models with keys of their own claim first (adhesion rides on either repulsion).
  for (const InteractionType* t : interaction_types())
    if (!t->keys.empty() && t->claims && t->claims(p)) return *t;
  for (const InteractionType* t : interaction_types())
    if (t->claims && t->claims(p)) return *t;
  throw SolveError("no registered interaction model claims these parameters");
}

}  // namespace gfmd
