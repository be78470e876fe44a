// indenter.type = "powerlaw": h = -r_e^n / (n R^(n-1)) with elliptic contours (radius, or
// radius_x and radius_y; exponent n, 2 = Hertz's paraboloid), apex at the cell centre.
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  read_radii(ind, r.c, "power-law indenter");
  in.exponent = ind.number("exponent", 2.0);
  if (!(in.exponent >= 1.0 && in.exponent <= 20.0))
    ind.error("exponent", "must be in [1, 20] (1: a cone, 2: the paraboloid)");
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["radius_x"] = in.radius_x;
  out["radius_y"] = in.radius_y;
  if (in.radius_x == in.radius_y) out["radius"] = in.radius_x;
  out["exponent"] = in.exponent;
}

Topography make(const Config& c, MapReport*) {
  return make_powerlaw(c.grid, c.indenter.radius_x, c.indenter.radius_y, c.indenter.exponent);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the power-law indenter's", "indenter.radius = " + g3(c.indenter.radius_x) +
                                          " and exponent = " + g3(c.indenter.exponent) + " against " +
                                          cell_text(c) + " (its slope (r/R)^(n-1) reaches 1 at r = R)"};
}

}  // namespace

const IndenterType& powerlaw_indenter() {
  static const IndenterType t{
      .name = "powerlaw",
      .purpose = "axisymmetric power law -r^n/(n R^(n-1)) with radius (or radius_x, radius_y) and exponent",
      .keys = {"radius", "radius_x", "radius_y", "exponent"},
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
