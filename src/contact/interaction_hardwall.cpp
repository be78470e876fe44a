// interaction.model = "hardwall": no overlap, p >= 0 where the gap closes (the limit k -> inf of
// the harmonic repulsion). "hard_wall" is read as its old spelling.
#include "gfmd/contact/interaction.hpp"

namespace gfmd {

const InteractionType& hardwall_interaction() {
  static const InteractionType t{
      .name = "hardwall",
      .purpose = "the hard wall: no overlap, a pressure p >= 0 where the gap is closed",
      .keys = {},
      .hard_wall = true,
      .repulsion_key = false,
      .on_device = true,
      .claims = [](const InteractionParams& p) { return p.hard_wall && !p.adhesive(); },
      .check = nullptr};
  return t;
}

}  // namespace gfmd
