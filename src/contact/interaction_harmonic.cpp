// interaction.model = "harmonic": the overlap repulsion p = k max(0, -g), k = interaction.stiffness
// (0: the default 2 E*/dx). The default model.
#include "gfmd/contact/interaction.hpp"

namespace gfmd {

const InteractionType& harmonic_interaction() {
  static const InteractionType t{
      .name = "harmonic",
      .purpose = "repulsion by a harmonic overlap penalty p = k max(0, -g) (k: interaction.stiffness)",
      .keys = {},
      .hard_wall = false,
      .repulsion_key = false,
      .on_device = true,
      .claims = [](const InteractionParams& p) { return !p.hard_wall && !p.adhesive(); },
      .check = nullptr};
  return t;
}

}  // namespace gfmd
