// indenter.type = "file": a measured or saved height map (io/height_map.hpp, every format),
// prepared by surface/measured.hpp (units, missing points, detrending, periodization, crop);
// the grid keys not given in the case come from the map.
#include <algorithm>
#include <filesystem>
#include <tuple>

#include "gfmd/core/error.hpp"
#include "gfmd/io/height_map.hpp"
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

// The grid keys a case leaves out come from the prepared map (read once here; the solve
// reads it again).
void grid_from_map(Section& ind, IndenterRead& r) {
  Config& c = r.c;
  const IndenterConfig& in = c.indenter;
  const GridKeysGiven& given = r.given;
  try {
    MapOptions mo = map_options(c);
    const double k = in.periodize == "none" ? 1.0 : 2.0;  // the cell holds the map k times per side
    mo.lx = given.lx ? c.grid.lx / k : 0.0;
    mo.ly = given.ly ? c.grid.ly / k : 0.0;  // the file's ly, else lx ny / nx (load_height_map)
    mo.nx = mo.ny = 0;
    const Topography t = in_section("indenter", [&] { return load_height_map(in.path, mo); });
    if (!given.nx) c.grid.nx = t.grid.nx;
    if (!given.ny) c.grid.ny = given.nx ? c.grid.nx : t.grid.ny;  // ny defaults to a given nx
    if (c.grid.nx < 2 || c.grid.ny < 2 || c.grid.nx > (1 << 16) || c.grid.ny > (1 << 16))
      ind.error("path", "the height map must have 2 to 65536 points along x and y");
    if (!given.lx) c.grid.lx = t.grid.lx;
    if (!given.ly) c.grid.ly = t.grid.ly;
    if (!(c.grid.lx >= kMinLength && c.grid.lx <= kMaxLength && c.grid.ly >= kMinLength &&
          c.grid.ly <= kMaxLength))
      ind.error("path", "the size of the height map must lie in [1e-30, 1e30]");
  } catch (const InputError& e) {
    const std::string why = e.what();
    if (e.where().starts_with("indenter."))
      r.errors.push_back(why);  // an option of the map, named by in_section
    else
      ind.error("path", why + (why.find("no physical size") != std::string::npos &&
                                       why.find("grid.lx") == std::string::npos
                                   ? " (or give grid.lx)"
                                   : ""));
  }
}

void read(Section& ind, IndenterRead& r) {
  IndenterConfig& in = r.c.indenter;
  in.path = ind.string("path", "");
  if (in.path.empty()) {
    ind.error("path", "a file indenter needs path = \"heights.txt\" (text matrix or NetCDF)");
  } else if (!std::filesystem::path(in.path).is_absolute()) {
    in.path = (std::filesystem::path(r.base_dir) / in.path).lexically_normal().string();
  }
  in.unit = ind.string("unit", "");
  in.missing = ind.string("missing", "error");
  in.detrend = ind.string("detrend", "none");
  in.periodize = ind.string("periodize", "none");
  if (const toml::value* v = ind.raw("crop")) {
    bool ok = v->is_array() && v->as_array().size() == 4;
    for (std::size_t k = 0; ok && k < 4; ++k) {
      const toml::value& e = v->as_array()[k];
      ok = e.is_integer() && e.as_integer() >= 0 && e.as_integer() <= (1LL << 16);
      if (ok) in.crop[k] = e.as_integer();
    }
    if (!ok)
      ind.error("crop", "must be [ix0, iy0, nx, ny]: four integers in [0, 65536] (points of the file)");
  }
  const std::tuple<const char*, const std::string&, const std::vector<std::string>&> choices[] = {
      {"missing", in.missing, kMissingMethods},
      {"detrend", in.detrend, kDetrendMethods},
      {"periodize", in.periodize, kPeriodizeMethods}};
  for (const auto& [key, value, ok] : choices) {
    if (std::find(ok.begin(), ok.end(), value) == ok.end())
      ind.error(key, "\"" + value + "\" is not one of \"" + ok[0] + "\", \"" + ok[1] + "\", \"" + ok[2] +
                         "\"" + did_you_mean(value, ok));
  }
  const bool unit_ok = in.unit.empty() || metres_per_unit(in.unit) != 0.0;
  if (!unit_ok) ind.error("unit", "unknown length unit \"" + in.unit + "\" (m, mm, um, nm, pm or A)");
  const GridKeysGiven& g = r.given;
  if (unit_ok && !in.path.empty() && (!g.nx || !g.ny || !g.lx || !g.ly)) grid_from_map(ind, r);
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  out["path"] = in.path;
  if (!in.unit.empty()) out["unit"] = in.unit;
  out["missing"] = in.missing;
  out["detrend"] = in.detrend;
  out["periodize"] = in.periodize;
  if (in.crop[2] > 0) out["crop"] = in.crop;
}

Topography make(const Config& c, MapReport* report) {
  return load_height_map(c.indenter.path, map_options(c), report);
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport* map) {
  const IndenterConfig& in = c.indenter;
  const bool stated = map != nullptr && map->file_unit == "m" && in.unit.empty();
  return {"the height map's", "indenter.unit (the unit of the file's heights; " +
                                  (stated            ? std::string("the file states its own")
                                   : in.unit.empty() ? std::string("none given")
                                                     : "\"" + in.unit + "\" given") +
                                  ") against the map's size (" + cell_text(c) +
                                  (map != nullptr && map->file_lx > 0
                                       ? "; the file states " + g3(map->file_lx) + " x " + g3(map->file_ly)
                                       : std::string()) +
                                  ")"};
}

}  // namespace

const IndenterType& file_indenter() {
  static const IndenterType t{
      .name = "file",
      .purpose =
          "a measured or saved height map: path (x3p, text, .npy, .gwy, .sur, NetCDF) "
          "and how to prepare it",
      .keys = {"path", "unit", "missing", "detrend", "periodize", "crop"},
      .made_on_slabs = false,
      .rough = true,
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
