// indenter.type = "powerlaw": h = -r_e^n / (n R^(n-1)) with elliptic contours (radius, or
// radius_x and radius_y; exponent n, 2 = Hertz's paraboloid), apex at the cell centre.
#include <cmath>

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
  return {"the power-law indenter's (weighed as the paraboloid of its radius)",
          "indenter.radius = " + g3(c.indenter.radius_x) + " against " + cell_text(c) +
              " (its slope (r/R)^(n-1) reaches 1 at r = R)"};
}

// The paraboloid of the same radii on the cell, sqrt(lx^2/(12 Rx^2) + ly^2/(12 Ry^2)): a
// radius in another unit than the cell shows as for Hertz's, while the far field of an exponent
// above 2, steep by design and away from the contact, does not count.
double paraboloid_gradient(const Config& c, double) {
  const IndenterConfig& in = c.indenter;
  return std::sqrt(c.grid.lx * c.grid.lx / (12 * in.radius_x * in.radius_x) +
                   c.grid.ly * c.grid.ly / (12 * in.radius_y * in.radius_y));
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
      .implausible = implausible,
      .plausibility_gradient = paraboloid_gradient};
  return t;
}

}  // namespace gfmd::config_detail
