// A Config written back: its JSON (summary "input") and TOML (fields.nc, checkpoints), and
// the topography it describes.
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <toml.hpp>

#include "config_detail.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/flow/flow.hpp"

namespace gfmd {

using config_detail::kSections;

nlohmann::json Config::to_json() const {
  nlohmann::json j;
  j["grid"] = {{"nx", grid.nx}, {"ny", grid.ny}, {"lx", grid.lx}, {"ly", grid.ly}};
  if (!length_unit.empty()) j["grid"]["unit"] = length_unit;
  j["elastic"] = {{"contact_modulus", elastic.contact_modulus},
                  {"poisson", elastic.poisson},
                  {"coupling", elastic.coupling}};
  if (elastic.half_space())
    j["elastic"]["thickness"] = "inf";
  else
    j["elastic"]["thickness"] = elastic.thickness;
  nlohmann::json ind = {{"type", indenter.type}};
  if (indenter.type == "hertz") {
    ind["radius_x"] = indenter.radius_x;
    ind["radius_y"] = indenter.radius_y;
    if (indenter.radius_x == indenter.radius_y) ind["radius"] = indenter.radius_x;
  } else if (indenter.type == "eggcrate") {
    ind["wavelength"] = indenter.wavelength;
    ind["amplitude"] = indenter.amplitude;
  } else if (indenter.type == "selfaffine") {
    const auto& s = indenter.selfaffine;
    ind["hurst"] = s.hurst;
    ind["lambda_long"] = s.lambda_long;
    ind["lambda_short"] = s.lambda_short;
    if (s.rms_height > 0) ind["rms_height"] = s.rms_height;
    if (s.rms_gradient > 0) ind["rms_gradient"] = s.rms_gradient;
    if (s.lambda_rolloff > 0) ind["lambda_rolloff"] = s.lambda_rolloff;
    ind["seed"] = s.seed;
    if (s.generator != "gfmd") ind["generator"] = s.generator;  // absent: ours (as before the key)
  } else {
    ind["path"] = indenter.path;
    if (!indenter.unit.empty()) ind["unit"] = indenter.unit;
    ind["missing"] = indenter.missing;
    ind["detrend"] = indenter.detrend;
    ind["periodize"] = indenter.periodize;
    if (indenter.crop[2] > 0) ind["crop"] = indenter.crop;
  }
  j["indenter"] = ind;
  const char* lk = load.mode == LoadMode::Force      ? "force"
                   : load.mode == LoadMode::Pressure ? "pressure"
                                                     : "approach";
  j["load"] = {{lk, load.value}};
  j["friction"] = {{"coefficient", friction.coefficient},
                   {"direction", friction.direction_deg},
                   {"regularization", friction.regularization},
                   {"creepage", friction.creepage},
                   {"stick_step", friction.stick_step},
                   {"stick_acceleration", friction.stick_acceleration},
                   {"reference", friction_reference},
                   {"lateral_creepage", friction.lateral_creepage},
                   {"slip_derivative",
                    friction.slip_derivative ? slip_derivative_name(*friction.slip_derivative) : "auto"}};
  j["interaction"] = {{"model", interaction.hard_wall ? "hardwall" : "harmonic"},
                      {"stiffness", interaction.stiffness}};
  j["solver"] = {{"tolerance", solver.tolerance},
                 {"max_iterations", solver.max_iterations},
                 {"max_outer", solver.max_outer},
                 {"max_tangential", solver.max_tangential},
                 {"anderson", solver.anderson},
                 {"mixing", solver.mixing},
                 {"fft_planner", solver.fft_planner == Planner::Measure ? "measure" : "estimate"},
                 {"threads", threads},
                 {"backend", backend}};
  j["output"] = {{"fields", output.fields}, {"png", output.png}, {"analysis", output.analysis}};
  nlohmann::json pa = false;
  if (stress.post_analysis.size() == 1) pa = stress.post_analysis.front();
  if (stress.post_analysis.size() > 1) pa = stress.post_analysis;
  j["stress"] = {{"post_analysis", pa},
                 {"high_tension_fraction", stress.high_tension_fraction},
                 {"depths", stress.depths},
                 {"profiles", stress.profiles}};
  if (flow.enabled)
    j["flow"] = {
        {"angles", flow.angles}, {"tolerance", flow.tolerance}, {"solver", flow_solver_name(flow.solver)}};
  if (sweep.active())
    j["sweep"] = {{"parameter", sweep.parameter}, {"values", sweep.values}, {"plot", sweep.plot}};
  return j;
}

std::string Config::to_toml() const {
  const nlohmann::json j = to_json();
  std::ostringstream os;
  os.precision(17);
  for (const auto& sec : kSections) {
    if (!j.contains(sec)) continue;
    os << "[" << sec << "]\n";
    for (const auto& [k, v] : j[sec].items()) {
      os << k << " = ";
      if (v.is_string())
        os << '"' << v.get<std::string>() << '"';
      else if (v.is_boolean())
        os << (v.get<bool>() ? "true" : "false");
      else if (v.is_number_integer() || v.is_number_unsigned() || v.is_array())
        os << v.dump();
      else
        os << v.get<double>();
      os << "\n";
    }
    os << "\n";
  }
  return os.str();
}

MapOptions map_options(const Config& c) {
  const IndenterConfig& in = c.indenter;
  MapOptions o;
  o.case_unit = c.length_unit;
  o.file_unit = in.unit;
  o.crop = in.crop;
  o.missing = in.missing;
  o.detrend = in.detrend;
  o.periodize = in.periodize;
  const double k = in.periodize == "none" ? 1.0 : 2.0;  // the cell holds the map k times per side
  o.lx = c.grid.lx / k;
  o.ly = c.grid.ly / k;
  o.nx = c.grid.nx;
  o.ny = c.grid.ny;
  return o;
}

bool surface_made_on_slabs(const Config& c) { return c.indenter.type != "file"; }

Topography make_topography(const Config& c, MapReport* report) {
  const IndenterConfig& in = c.indenter;
  if (in.type == "hertz")
    return in_section("indenter", [&] { return make_hertz(c.grid, in.radius_x, in.radius_y); });
  if (in.type == "eggcrate")
    return in_section("indenter", [&] { return make_eggcrate(c.grid, in.wavelength, in.amplitude); });
  if (in.type == "selfaffine")
    return in_section("indenter", [&] { return make_selfaffine(c.grid, in.selfaffine); });
  if (in.type == "array")
    throw InputError("indenter.type",
                     "\"array\" takes its heights from the calling program (Python: gfmd.solve); "
                     "a case file gives type = \"file\" and a path");
  return in_section("indenter", [&] { return load_height_map(in.path, map_options(c), report); });
}

}  // namespace gfmd
