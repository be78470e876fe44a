// indenter.type = "step": a raised strip of `width` lying along `axis` ("y", default, or "x")
// through the cell's centre, its sides dropping by `depth` (default: the width): the two steps
// a periodic cell holds; on a flat body a periodic flat punch in plane strain.
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  in.width = ind.number("width", 0.0);
  in.depth = ind.number("depth", in.width);
  const std::string axis = ind.string("axis", "y");
  if (axis != "x" && axis != "y") {
    ind.error("axis", "must be \"x\" or \"y\" (the direction the strip lies along), got \"" + axis + "\"");
    return;
  }
  in.axis = axis[0];
  if (!(in.width > 0)) {
    ind.error("width", "a step needs a positive width (of the raised strip)");
    return;
  }
  if (!(in.depth > 0)) ind.error("depth", "must be positive (how far the step drops)");
  const Grid& g = r.c.grid;
  if (in.depth > 0 && g.nx >= 2 && g.ny >= 2 && g.lx > 0 && g.ly > 0)
    // the step's own checks (resolution, room for the lower terrace), naming the line
    ind.check([&] { check_step(g, in.width, in.depth, in.axis); });
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["width"] = in.width;
  out["depth"] = in.depth;
  out["axis"] = std::string(1, in.axis);
}

Topography make(const Config& c, MapReport*) {
  return make_step(c.grid, c.indenter.width, c.indenter.depth, c.indenter.axis);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the step's", "indenter.depth = " + g3(c.indenter.depth) + " against " + cell_text(c) +
                            " (each step is one grid spacing wide)"};
}

}  // namespace

const IndenterType& step_indenter() {
  static const IndenterType t{
      .name = "step",
      .purpose =
          "a raised strip of width `width` along axis (\"y\" or \"x\"), its sides dropping by `depth` "
          "(default the width): two steps, a periodic flat punch in plane strain",
      .keys = {"width", "depth", "axis"},
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
