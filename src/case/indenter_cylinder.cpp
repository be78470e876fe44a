// indenter.type = "cylinder": a (parabolic) cylinder of radius `radius` lying along `axis`
// ("y", default, or "x") through the cell's centre line: a line contact.
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  in.radius = ind.number("radius", 0.0);
  const std::string axis = ind.string("axis", "y");
  if (!(in.radius > 0)) ind.error("radius", "a cylinder needs a positive radius");
  if (axis != "x" && axis != "y")
    ind.error("axis", "must be \"x\" or \"y\" (the direction the cylinder lies along), got \"" + axis + "\"");
  else
    in.axis = axis[0];
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["radius"] = in.radius;
  out["axis"] = std::string(1, in.axis);
}

Topography make(const Config& c, MapReport*) {
  return make_cylinder(c.grid, c.indenter.radius, c.indenter.axis);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the cylinder's", "indenter.radius = " + g3(c.indenter.radius) + " against " + cell_text(c) +
                                " (a parabola is a cylinder only where its slope is small)"};
}

}  // namespace

const IndenterType& cylinder_indenter() {
  static const IndenterType t{
      .name = "cylinder",
      .purpose = "a cylinder of radius lying along axis (\"y\" or \"x\"): a line contact, periodic along it",
      .keys = {"radius", "axis"},
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
