// Interactions as parts: the model of the gap's law between the indenter and the body
// (interaction.model), its keys, its checks and what each backend computes. One file per model,
// src/contact/interaction_<name>.cpp; the table is src/contact/interaction.cpp.
//
// The solve reads InteractionParams (a repulsion: the hard wall or a harmonic overlap penalty;
// optionally Maugis-Dugdale adhesion and a hardness cap); a model is a way to set them from a
// case. Adding a model: its file with an InteractionType (its keys into InteractionParams, its
// checks) and one line in the table; the case reads and writes its keys from there
// (case/config_physics.cpp, config_out.cpp), Python lists it (gfmd.interaction_models()). A
// model whose physics the solve does not have yet also needs its branch in the solve (the
// adhesive steps are src/contact/adhesion.cpp).
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace gfmd {

struct InteractionParams {
  bool hard_wall = false;
  double stiffness = 0.0;  // k_if; 0 means the default 2 E* / dx
  // Plastic saturation: the local pressure is capped at the hardness H (a perfectly plastic
  // surface flows where the elastic solution would press harder; there the indenter overlaps
  // the undeformed surface by the plastic displacement). inf: no cap.
  double hardness = std::numeric_limits<double>::infinity();
  [[nodiscard]] bool plastic() const { return hardness < std::numeric_limits<double>::infinity(); }
  // Adhesion (interaction.model = "adhesive"): the Maugis-Dugdale cohesive law on top of the
  // repulsion. A tensile traction sigma0 = work_of_adhesion / range pulls the body towards the
  // indenter wherever the gap is below the range (inside the contact too), none beyond; the
  // work of separating a unit area is work_of_adhesion. 0: no adhesion (the repulsive solve).
  double work_of_adhesion = 0.0;
  double range = 0.0;
  [[nodiscard]] bool adhesive() const { return work_of_adhesion > 0; }
  [[nodiscard]] double adhesive_stress() const { return adhesive() ? work_of_adhesion / range : 0.0; }
  // k_if on a grid of spacing dx: inf for the hard wall, else stiffness or its default 2 E*/dx.
  [[nodiscard]] double stiffness_on(double contact_modulus, double dx) const {
    if (hard_wall) return std::numeric_limits<double>::infinity();
    return stiffness > 0 ? stiffness : 2.0 * contact_modulus / dx;
  }
};

// A model as a registered part.
struct InteractionType {
  std::string name;     // interaction.model
  std::string purpose;  // one line (docs, gfmd.interaction_models())
  // Its own keys besides the common `stiffness` and `hardness` (numbers into InteractionParams).
  using Member = double InteractionParams::*;
  struct Key {
    std::string name;  // interaction.<name>
    Member member;
    double default_value;
    std::string doc;
  };
  std::vector<Key> keys;
  // The repulsion it sets: the hard wall (true) or the harmonic penalty (false). With
  // repulsion_key the model takes interaction.repulsion (the name of a model without keys of its
  // own: "hardwall" or "harmonic"), this being its default.
  bool hard_wall = false;
  bool repulsion_key = false;
  // A repulsion: a model without keys of its own (what interaction.repulsion names).
  [[nodiscard]] bool repulsion() const { return keys.empty() && !repulsion_key; }
  // Capabilities: the cuda backend computes it.
  bool on_device = true;
  // Whether a parameter set is this model's (how a case is written back): the first model in the
  // table that claims it names it.
  bool (*claims)(const InteractionParams& p) = nullptr;
  // The model's own checks of its keys: (key, why) for each problem.
  std::vector<std::pair<std::string, std::string>> (*check)(const InteractionParams& p) = nullptr;
};

const InteractionType& harmonic_interaction();
const InteractionType& hardwall_interaction();
const InteractionType& adhesive_interaction();

// Every registered model, in the order the docs list them.
const std::vector<const InteractionType*>& interaction_types();
// The model named `name` ("hard_wall" is an old spelling of "hardwall"), or nullptr.
const InteractionType* find_interaction(const std::string& name);
// The model a parameter set is (for writing a case back).
const InteractionType& interaction_type(const InteractionParams& p);

}  // namespace gfmd
