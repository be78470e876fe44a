// indenter.type = "sphere": a sphere of radius `radius`, not its paraboloid (h = sqrt(R^2 - r^2)
// - R), apex at the cell centre.
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  in.radius = ind.number("radius", 0.0);
  if (!(in.radius > 0)) ind.error("radius", "a sphere needs a positive radius");
}

void write(const IndenterConfig& in, nlohmann::json& out) { out["radius"] = in.radius; }

Topography make(const Config& c, MapReport*) { return make_sphere(c.grid, c.indenter.radius); }

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the sphere's", "indenter.radius = " + g3(c.indenter.radius) + " against " + cell_text(c) +
                              " (its slope is steep near the equator)"};
}

}  // namespace

const IndenterType& sphere_indenter() {
  static const IndenterType t{.name = "sphere",
                              .purpose = "a sphere of radius (its exact profile, not the paraboloid)",
                              .keys = {"radius"},
                              .read = read,
                              .write = write,
                              .make = make,
                              .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
