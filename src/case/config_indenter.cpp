// The [indenter] section of a case file: its type and that type's keys, and for a file
// indenter the grid keys its height map supplies. See config_section.hpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "config_section.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/io/height_map.hpp"
#include "gfmd/surface/measured.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::config_detail {

void read_indenter(Section& ind, Config& c, std::vector<std::string>& errors, const GridKeysGiven& given,
                   const std::string& base_dir) {
  const bool grid_nx = given.nx, grid_ny = given.ny, grid_lx = given.lx, grid_ly = given.ly;
  IndenterConfig& in = c.indenter;
  in.type = ind.string("type", "hertz");
  const std::vector<std::string> types = {"hertz", "eggcrate", "selfaffine", "file", "array"};
  std::vector<std::string> extra;
  if (std::find(types.begin(), types.end(), in.type) == types.end()) {
    ind.error("type", "unknown indenter type \"" + in.type + "\"" + did_you_mean(in.type, types) +
                          "; one of hertz, eggcrate, selfaffine, file");
    extra = {"radius",      "radius_x",     "radius_y",   "wavelength",   "amplitude", "hurst",
             "lambda_long", "lambda_short", "rms_height", "rms_gradient", "seed",      "lambda_rolloff",
             "path",        "lx",           "ly",         "generator"};
  } else if (in.type == "hertz") {
    in.radius = ind.number("radius", 0.0);
    in.radius_x = ind.number("radius_x", in.radius);
    in.radius_y = ind.number("radius_y", in.radius);
    if (!(in.radius_x > 0) || !(in.radius_y > 0))
      ind.error(ind.has("radius") || !ind.has("radius_x") ? "radius" : "radius_x",
                "a Hertz indenter needs a positive radius (or radius_x and radius_y)");
  } else if (in.type == "eggcrate") {
    in.wavelength = ind.number("wavelength", c.grid.lx);
    in.amplitude = ind.number("amplitude", in.wavelength / (4 * std::numbers::pi * std::numbers::pi));
    if (!(in.wavelength > 0)) ind.error("wavelength", "must be positive");
    if (!(in.amplitude > 0)) ind.error("amplitude", "must be positive");
    if (in.wavelength > 0 && c.grid.lx > 0) {
      const double rx = c.grid.lx / in.wavelength, ry = c.grid.ly / in.wavelength;
      if (std::abs(rx - std::round(rx)) > 1e-9 * rx || std::abs(ry - std::round(ry)) > 1e-9 * ry)
        ind.error("wavelength", "the cell (grid.lx, grid.ly) must hold a whole number of wavelengths");
    }
  } else if (in.type == "selfaffine") {
    SelfAffineParams& s = in.selfaffine;
    s.hurst = ind.number("hurst", 0.8);
    s.lambda_long = ind.number("lambda_long", c.grid.lx / 2);
    s.lambda_short = ind.number("lambda_short", s.lambda_long / 128);
    s.rms_height = ind.number("rms_height", 0.0);
    s.rms_gradient = ind.number("rms_gradient", 0.0);
    s.lambda_rolloff = ind.number("lambda_rolloff", 0.0);
    s.seed = static_cast<std::uint64_t>(ind.integer("seed", 0, 0, std::numeric_limits<long long>::max()));
    s.generator = ind.string("generator", "gfmd");
    if ((s.rms_height > 0) == (s.rms_gradient > 0)) {
      ind.error("rms_height", "give exactly one of rms_height and rms_gradient (positive)");
    } else {
      // The surface's own checks (band, resolution), here so that they name the line.
      try {
        check_selfaffine(c.grid, s);
      } catch (const ParameterError& e) {
        ind.error(e.where(), e.why());
      }
    }
  } else if (in.type == "array") {
    // Heights handed over by a program (Python's gfmd.solve: RunOptions::topography); no keys.
  } else if (in.type == "file") {
    in.path = ind.string("path", "");
    if (in.path.empty()) {
      ind.error("path", "a file indenter needs path = \"heights.txt\" (text matrix or NetCDF)");
    } else if (!std::filesystem::path(in.path).is_absolute()) {
      in.path = (std::filesystem::path(base_dir) / in.path).lexically_normal().string();
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
    if (unit_ok && !in.path.empty() && (!grid_nx || !grid_ny || !grid_lx || !grid_ly)) {
      // The grid keys not given come from the prepared map (read once here; the solve reads it again).
      try {
        MapOptions mo = map_options(c);
        const double k = in.periodize == "none" ? 1.0 : 2.0;  // the cell holds the map k times per side
        mo.lx = grid_lx ? c.grid.lx / k : 0.0;
        mo.ly = grid_ly ? c.grid.ly / k : 0.0;  // the file's ly, else lx ny / nx (load_height_map)
        mo.nx = mo.ny = 0;
        const Topography t = in_section("indenter", [&] { return load_height_map(in.path, mo); });
        if (!grid_nx) c.grid.nx = t.grid.nx;
        if (!grid_ny) c.grid.ny = grid_nx ? c.grid.nx : t.grid.ny;  // ny defaults to a given nx
        if (c.grid.nx < 2 || c.grid.ny < 2 || c.grid.nx > (1 << 16) || c.grid.ny > (1 << 16))
          ind.error("path", "the height map must have 2 to 65536 points along x and y");
        if (!grid_lx) c.grid.lx = t.grid.lx;
        if (!grid_ly) c.grid.ly = t.grid.ly;
        if (!(c.grid.lx >= kMinLength && c.grid.lx <= kMaxLength && c.grid.ly >= kMinLength &&
              c.grid.ly <= kMaxLength))
          ind.error("path", "the size of the height map must lie in [1e-30, 1e30]");
      } catch (const InputError& e) {
        const std::string why = e.what();
        if (e.where().starts_with("indenter."))
          errors.push_back(why);  // an option of the map, named by in_section
        else
          ind.error("path", why + (why.find("no physical size") != std::string::npos &&
                                           why.find("grid.lx") == std::string::npos
                                       ? " (or give grid.lx)"
                                       : ""));
      }
    }
  }
  ind.finish(extra);
}

}  // namespace gfmd::config_detail
