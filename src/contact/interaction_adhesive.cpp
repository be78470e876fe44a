// interaction.model = "adhesive": the Maugis-Dugdale cohesive law, a tensile traction sigma0 =
// work_of_adhesion / range wherever the gap is below the range, on a repulsion (the hard wall by
// default, as in the theories it is checked against; interaction.repulsion). A zero work of
// adhesion is the repulsion alone (written back as that model). The solve's adhesive steps are
// src/contact/adhesion.cpp, on the CUDA device src/contact/device_adhesion.cu.
#include <cmath>

#include "gfmd/contact/interaction.hpp"

namespace gfmd {

namespace {

std::vector<std::pair<std::string, std::string>> check(const InteractionParams& p) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!(p.work_of_adhesion >= 0) || !std::isfinite(p.work_of_adhesion))
    out.emplace_back(
        "work_of_adhesion",
        "must be zero or positive and finite (the work of adhesion, energy per area in E* x length "
        "units)");
  if (!(p.range > 0) || !std::isfinite(p.range))
    out.emplace_back("range", "must be positive and finite (the range of the cohesive law, a length)");
  return out;
}

}  // namespace

const InteractionType& adhesive_interaction() {
  static const InteractionType t{
      .name = "adhesive",
      .purpose =
          "Maugis-Dugdale adhesion: a tensile stress work_of_adhesion / range where the gap is below "
          "range, on a repulsion (interaction.repulsion)",
      .keys = {{"work_of_adhesion", &InteractionParams::work_of_adhesion, 0.0,
                "the work of adhesion, energy per area (E* x length)"},
               {"range", &InteractionParams::range, 0.0, "the range of the cohesive law (a length)"}},
      .hard_wall = true,
      .repulsion_key = true,
      .on_device = true,
      .claims = [](const InteractionParams& p) { return p.adhesive(); },
      .check = check};
  return t;
}

}  // namespace gfmd
