// indenter.type = "flatpunch": a flat cylindrical punch of radius `radius` whose side drops by
// `depth` (default: the radius), face at the cell centre (Boussinesq's problem).
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  in.radius = ind.number("radius", 0.0);
  in.depth = ind.number("depth", in.radius);
  if (!(in.radius > 0)) {
    ind.error("radius", "a flat punch needs a positive radius (of its face)");
    return;
  }
  if (!(in.depth > 0)) ind.error("depth", "must be positive (how far the punch's side drops)");
  const Grid& g = r.c.grid;
  if (in.depth > 0 && g.nx >= 2 && g.ny >= 2 && g.lx > 0 && g.ly > 0)
    // the punch's own checks (resolution, size against the cell), naming the line
    ind.check([&] { check_flatpunch(r.c.grid, in.radius, in.depth); });
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["radius"] = in.radius;
  out["depth"] = in.depth;
}

Topography make(const Config& c, MapReport*) {
  return make_flatpunch(c.grid, c.indenter.radius, c.indenter.depth);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the flat punch's", "indenter.depth = " + g3(c.indenter.depth) + " against " + cell_text(c) +
                                  " (the step at the punch's edge is one grid spacing wide)"};
}

}  // namespace

const IndenterType& flatpunch_indenter() {
  static const IndenterType t{.name = "flatpunch",
                              .purpose =
                                  "flat cylindrical punch: face of radius `radius`, side dropping by `depth` "
                                  "(default the radius); face at the cell centre",
                              .keys = {"radius", "depth"},
                              .read = read,
                              .write = write,
                              .make = make,
                              .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
