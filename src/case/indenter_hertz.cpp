// indenter.type = "hertz": a paraboloid with radii of curvature radius_x, radius_y (SPEC §3).
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) { read_radii(ind, r.c, "Hertz indenter"); }

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["radius_x"] = in.radius_x;
  out["radius_y"] = in.radius_y;
  if (in.radius_x == in.radius_y) out["radius"] = in.radius_x;
}

Topography make(const Config& c, MapReport*) {
  return make_hertz(c.grid, c.indenter.radius_x, c.indenter.radius_y);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  const IndenterConfig& in = c.indenter;
  return {"the Hertz indenter's",
          (in.radius_x == in.radius_y
               ? "indenter.radius = " + g3(in.radius_x)
               : "indenter.radius_x, radius_y = " + g3(in.radius_x) + ", " + g3(in.radius_y)) +
              " against " + cell_text(c) + " (a paraboloid is a sphere only where its slope is small)"};
}

}  // namespace

const IndenterType& hertz_indenter() {
  static const IndenterType t{
      .name = "hertz",
      .purpose = "paraboloid (sphere) with radius, or radius_x and radius_y; apex at the cell centre",
      .keys = {"radius", "radius_x", "radius_y"},
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
