// A Config written back: its JSON (summary "input") and TOML (fields.nc, checkpoints), and
// the map options of a file indenter.
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <toml.hpp>

#include "config_detail.hpp"
#include "config_section.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/flow/flow.hpp"
#include "indenter_types.hpp"

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
  config_detail::write_body_stack(elastic, j["elastic"]);
  // A viscoelastic part's keys (the same in [elastic] and in each of its viscoelastic_parts).
  const auto part_keys = [](const ViscoelasticParams& v, nlohmann::json& out, bool name_part) {
    out["viscoelastic"] = viscoelastic_model_name(v.model);
    if (name_part || v.part != ViscoelasticParams::Part::Top)  // absent: the top layer (as before the key)
      out["viscoelastic_part"] = v.part_name();
    if (v.model == ViscoelasticParams::Model::StandardLinearSolid) {
      out["high_frequency_modulus"] = v.high_frequency_modulus;
      out["relaxation_time"] = v.relaxation_time;
    } else if (v.model == ViscoelasticParams::Model::Prony) {
      out["prony_moduli"] = v.prony_moduli;
      out["prony_times"] = v.prony_times;
    } else {
      out["master_curve"] = v.curve_file;
      for (const auto& [k, x] : v.shift_keys) out[k] = x;
    }
  };
  if (visco.enabled()) {  // absent: elastic (as before the key)
    part_keys(visco, j["elastic"], false);
    for (const ViscoelasticParams& f : visco.further) {
      nlohmann::json one;
      part_keys(f, one, true);
      j["elastic"]["viscoelastic_parts"].push_back(one);
    }
  }
  j["indenter"] = config_detail::indenter_json(indenter);
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
  if (visco.enabled()) j["friction"]["velocity"] = visco.velocity;
  if (friction.law.kind != FrictionLawKind::Coulomb) {  // absent: Coulomb's (as before the key)
    const FrictionLawType& law = friction_law_type(friction.law.kind);
    j["friction"]["law"] = law.name;
    for (const FrictionLawType::Key& k : law.keys) j["friction"][k.name] = friction.law.*k.member;
  }
  // The model and its own keys from the registry (contact/interaction.hpp).
  const InteractionType& model = interaction_type(interaction);
  j["interaction"] = {{"model", model.name}, {"stiffness", interaction.stiffness}};
  if (interaction.plastic()) j["interaction"]["hardness"] = interaction.hardness;  // absent: no cap
  if (model.repulsion_key)
    j["interaction"]["repulsion"] =
        (interaction.hard_wall ? hardwall_interaction() : harmonic_interaction()).name;
  for (const InteractionType::Key& k : model.keys) j["interaction"][k.name] = interaction.*k.member;
  j["solver"] = {{"tolerance", solver.tolerance},
                 {"max_iterations", solver.max_iterations},
                 {"max_outer", solver.max_outer},
                 {"max_tangential", solver.max_tangential},
                 {"anderson", solver.anderson},
                 {"mixing", solver.mixing},
                 {"fft_planner", solver.fft_planner == Planner::Measure ? "measure" : "estimate"},
                 {"viscoelastic_method", solver.visco_method == ViscoMethod::Splitting   ? "splitting"
                                         : solver.visco_method == ViscoMethod::ActiveSet ? "active_set"
                                                                                         : "auto"},
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

namespace {

// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (ch == '\n') {
      out += "\\n";
    } else if (ch == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// A key: bare where TOML allows it, quoted otherwise.
std::string toml_key(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  return bare ? key : toml_string(key);
}

// A value of the JSON form as TOML: numbers to 17 digits (read back exactly), arrays, and
// tables inline ({k = v, ...}: a layer, a viscoelastic part).
std::string toml_value(const nlohmann::json& v) {
  std::ostringstream os;
  os.precision(17);
  if (v.is_string()) {
    os << toml_string(v.get<std::string>());
  } else if (v.is_boolean()) {
    os << (v.get<bool>() ? "true" : "false");
  } else if (v.is_number_integer() || v.is_number_unsigned()) {
    os << v.dump();
  } else if (v.is_number()) {
    os << v.get<double>();
  } else if (v.is_array()) {
    os << "[";
    for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << toml_value(v[i]);
    os << "]";
  } else if (v.is_object()) {
    os << "{";
    bool first = true;
    for (const auto& [k, x] : v.items()) {
      os << (first ? "" : ", ") << toml_key(k) << " = " << toml_value(x);
      first = false;
    }
    os << "}";
  } else {
    os << "\"\"";  // null: not written by to_json
  }
  return os.str();
}

}  // namespace

std::string Config::to_toml(const std::string& heights) const {
  nlohmann::json j = to_json();
  // A program's heights: a height file the caller writes (the JSON form keeps "array", which
  // a case file cannot give).
  const bool given = indenter.type == "array" && j.contains("indenter");
  if (given) {
    j["indenter"]["type"] = "file";
    j["indenter"]["path"] = heights;
  }
  // The JSON form's keys a case file reads otherwise: the flow's directions (flow.direction:
  // "both", or one angle).
  if (j.contains("flow")) {
    nlohmann::json& f = j["flow"];
    const std::vector<double> a = flow.angles;
    if (a == std::vector<double>{0.0, 90.0})
      f["direction"] = "both";
    else if (a.size() == 1)
      f["direction"] = a.front();
    f.erase("angles");
  }
  std::ostringstream os;
  for (const auto& sec : kSections) {
    if (!j.contains(sec)) continue;
    os << "[" << sec << "]\n";
    if (given && sec == "indenter")
      os << "# the heights were given by the calling program: they are read from " << heights
         << " beside this file (Python: Result.save_case writes both; or numpy.save(\"" << heights
         << "\", result.fields[\"topography\"]))\n";
    for (const auto& [k, v] : j[sec].items()) os << toml_key(k) << " = " << toml_value(v) << "\n";
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

}  // namespace gfmd
