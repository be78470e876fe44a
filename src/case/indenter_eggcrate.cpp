// indenter.type = "eggcrate": h0 [cos(2 pi x/lambda) + cos(2 pi y/lambda)] (SPEC §3).
#include <cmath>
#include <numbers>

#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  const Grid& g = r.c.grid;
  in.wavelength = ind.number("wavelength", g.lx);
  in.amplitude = ind.number("amplitude", in.wavelength / (4 * std::numbers::pi * std::numbers::pi));
  if (!(in.wavelength > 0)) ind.error("wavelength", "must be positive");
  if (!(in.amplitude > 0)) ind.error("amplitude", "must be positive");
  if (in.wavelength > 0 && g.lx > 0) {
    const double rx = g.lx / in.wavelength, ry = g.ly / in.wavelength;
    if (std::abs(rx - std::round(rx)) > 1e-9 * rx || std::abs(ry - std::round(ry)) > 1e-9 * ry)
      ind.error("wavelength", "the cell (grid.lx, grid.ly) must hold a whole number of wavelengths");
  }
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["wavelength"] = in.wavelength;
  out["amplitude"] = in.amplitude;
}

Topography make(const Config& c, MapReport*) {
  return make_eggcrate(c.grid, c.indenter.wavelength, c.indenter.amplitude);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the egg-crate's", "indenter.amplitude = " + g3(c.indenter.amplitude) +
                                 " against indenter.wavelength = " + g3(c.indenter.wavelength)};
}

}  // namespace

const IndenterType& eggcrate_indenter() {
  static const IndenterType t{
      .name = "eggcrate",
      .purpose = "egg-crate amplitude [cos(2 pi x/wavelength) + cos(2 pi y/wavelength)]",
      .keys = {"wavelength", "amplitude"},
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
