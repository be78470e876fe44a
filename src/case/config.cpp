#include "gfmd/case/config.hpp"

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
#include <tuple>

#include "config_detail.hpp"
#include "config_section.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/io/height_map.hpp"

namespace gfmd {

using config_detail::require_shallow_nesting;
using config_detail::require_utf8;

const std::vector<std::string> config_detail::kSections = {"grid",     "elastic",     "indenter", "load",
                                                           "friction", "interaction", "solver",   "output",
                                                           "sweep",    "stress",      "flow"};

namespace {

using config_detail::did_you_mean;
using config_detail::read_indenter;
using config_detail::Section;
using config_detail::where;

using config_detail::kSections;

constexpr std::size_t kMaxPronyArms = 64;

// A list of positive numbers at key (at most kMaxPronyArms), or an error naming the entry.
std::vector<double> positive_list(Section& sec, const std::string& key) {
  std::vector<double> out;
  const toml::value* v = sec.raw(key);
  if (!v) return out;
  if (!v->is_array() || v->as_array().empty() || v->as_array().size() > kMaxPronyArms) {
    sec.error(key, "must be a list of 1 to " + std::to_string(kMaxPronyArms) + " positive numbers");
    return out;
  }
  for (const auto& e : v->as_array()) {
    const double d = e.is_floating()  ? e.as_floating()
                     : e.is_integer() ? static_cast<double>(e.as_integer())
                                      : -1.0;
    if (!(d > 0) || !std::isfinite(d)) {
      sec.error(key, "each entry must be a positive finite number" + where(e));
      return {};
    }
    out.push_back(d);
  }
  return out;
}

// elastic.viscoelastic and its keys (the relaxed modulus is elastic.contact_modulus).
void read_viscoelastic(Section& el, ViscoelasticParams& v) {
  using Model = ViscoelasticParams::Model;
  const std::string model = el.string("viscoelastic", "none");
  if (model == "sls")
    v.model = Model::StandardLinearSolid;
  else if (model == "prony")
    v.model = Model::Prony;
  else if (model != "none")
    el.error("viscoelastic", "unknown model \"" + model + "\" (\"none\", \"sls\" or \"prony\")");
  const bool einf = el.has("high_frequency_modulus"), tau = el.has("relaxation_time");
  v.high_frequency_modulus = el.number("high_frequency_modulus", 0.0);
  v.relaxation_time = el.number("relaxation_time", 0.0);
  v.prony_moduli = positive_list(el, "prony_moduli");
  v.prony_times = positive_list(el, "prony_times");
  const auto needs = [&](const char* key, bool given, Model m) {
    if (given && v.model != m)
      el.error(key, std::string("belongs to elastic.viscoelastic = \"") + viscoelastic_model_name(m) + "\"");
    else if (!given && v.model == m)
      el.error(key,
               std::string("is needed with elastic.viscoelastic = \"") + viscoelastic_model_name(m) + "\"");
  };
  needs("high_frequency_modulus", einf, Model::StandardLinearSolid);
  needs("relaxation_time", tau, Model::StandardLinearSolid);
  needs("prony_moduli", !v.prony_moduli.empty(), Model::Prony);
  needs("prony_times", !v.prony_times.empty(), Model::Prony);
}

void apply_override(toml::value& root, const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set " + spec, "expected section.key=value");
  const std::string path = spec.substr(0, eq), text = spec.substr(eq + 1);
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw InputError("--set " + spec, "expected section.key=value");
  const std::string sec = path.substr(0, dot), key = path.substr(dot + 1);
  toml::value val;
  require_shallow_nesting("v = " + text, "--set " + path);
  try {
    std::istringstream is("v = " + text);
    val = toml::parse(is, "--set").as_table().at("v");
  } catch (const std::exception&) {
    // A bare word is a string; it is parsed as one so that a later error about it names
    // "[--set:1]" as it does for any other override.
    try {
      std::istringstream is("v = " + toml::format(toml::value(text)));
      val = toml::parse(is, "--set").as_table().at("v");
    } catch (const std::exception&) {
      val = toml::value(text);  // not valid UTF-8: kept as it is, without a location
    }
  }
  if (!root.is_table()) root = toml::table{};
  auto& tbl = root.as_table();
  if (!tbl.count(sec)) tbl[sec] = toml::table{};
  if (!tbl[sec].is_table()) throw InputError("--set " + spec, "'" + sec + "' is not a table");
  auto& st = tbl[sec].as_table();
  // The load keys exclude each other: setting one replaces the others.
  if (sec == "load" && (key == "force" || key == "pressure" || key == "approach")) {
    st.erase("force");
    st.erase("pressure");
    st.erase("approach");
  }
  st[key] = val;
}

Config build(const toml::value& root, const std::string& name, const std::string& base_dir) {
  std::vector<std::string> errors;
  Config c;
  c.source = name;
  if (root.is_table()) {
    std::vector<std::string> keys;
    for (const auto& kv : root.as_table()) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());
    for (const auto& k : keys)
      if (std::find(kSections.begin(), kSections.end(), k) == kSections.end())
        errors.push_back(k + ": unknown section" + did_you_mean(k, kSections) + where(root.as_table().at(k)));
  }

  // A file indenter may leave the grid to the height map: its dimensions and its size
  // header (text) or attributes (NetCDF).
  const bool file_indenter = [&root] {
    if (!root.is_table() || !root.as_table().count("indenter")) return false;
    const toml::value& t = root.as_table().at("indenter");
    return t.is_table() && t.as_table().count("type") && t.as_table().at("type").is_string() &&
           t.as_table().at("type").as_string() == "file";
  }();
  Section grid(root, "grid", errors);
  if (!grid.present() && !file_indenter) errors.push_back("grid: missing section [grid] (nx, lx at least)");
  if (grid.present() && !grid.has("nx") && !file_indenter)
    grid.error("nx", "missing: the number of grid points along x");
  const bool grid_nx = grid.has("nx"), grid_ny = grid.has("ny"), grid_lx = grid.has("lx"),
             grid_ly = grid.has("ly");
  const long long nx = grid.integer("nx", 0, 2, 1 << 16);
  const long long ny = grid.integer("ny", nx, 2, 1 << 16);
  c.grid.lx = grid.number("lx", 0.0);
  c.grid.ly = grid.number("ly", c.grid.lx);
  c.grid.nx = static_cast<int>(nx);
  c.grid.ny = static_cast<int>(ny);
  c.length_unit = grid.string("unit", "");
  if (!c.length_unit.empty() && metres_per_unit(c.length_unit) == 0.0)
    grid.error("unit", "unknown length unit \"" + c.length_unit + "\" (m, mm, um, nm, pm or A)");
  // Lengths are bounded so that areas and volumes stay far from under- and overflow.
  if ((grid_lx || !file_indenter) && !(c.grid.lx >= kMinLength && c.grid.lx <= kMaxLength))
    grid.error("lx", "must be a positive length in [1e-30, 1e30]");
  if ((grid_ly || grid_lx || !file_indenter) && !(c.grid.ly >= kMinLength && c.grid.ly <= kMaxLength))
    grid.error("ly", "must be a positive length in [1e-30, 1e30]");
  grid.finish();

  Section el(root, "elastic", errors);
  c.elastic.contact_modulus = el.number("contact_modulus", 1.0);
  c.elastic.poisson = el.number("poisson", 0.25);
  c.elastic.thickness = el.number_or_inf("thickness", std::numeric_limits<double>::infinity());
  c.elastic.coupling = el.boolean("coupling", true);
  read_viscoelastic(el, c.visco);
  el.finish();
  try {
    c.elastic.validate();
  } catch (const ParameterError& e) {
    errors.push_back("elastic." + e.where() + ": " + e.why() + el.at(e.where()));
  }

  Section ind(root, "indenter", errors);
  if (!ind.present()) errors.push_back("indenter: missing section [indenter] (type = \"hertz\", ...)");
  read_indenter(ind, c, errors, {grid_nx, grid_ny, grid_lx, grid_ly}, base_dir);

  // An adhesive interaction admits tensile loads and negative approaches (unloading): the
  // load's checks need to know it before [interaction] is read (which sets the value).
  const bool adhesive_model = [&root] {
    if (!root.is_table() || !root.as_table().count("interaction")) return false;
    const toml::value& t = root.as_table().at("interaction");
    return t.is_table() && t.as_table().count("model") && t.as_table().at("model").is_string() &&
           t.as_table().at("model").as_string() == "adhesive";
  }();
  c.interaction.work_of_adhesion = adhesive_model ? 1.0 : 0.0;
  Section load(root, "load", errors);
  const bool hf = load.has("force"), hp = load.has("pressure"), ha = load.has("approach");
  if (int(hf) + int(hp) + int(ha) != 1) {
    std::string at;  // where the loads given are
    for (const char* k : {"force", "pressure", "approach"}) at += load.at(k);
    errors.push_back("load: give exactly one of force, pressure, approach" + at);
  }
  if (hf) {
    c.load = {LoadMode::Force, load.number("force", 0.0)};
  } else if (hp) {
    c.load = {LoadMode::Pressure, load.number("pressure", 0.0)};
  } else if (ha) {
    c.load = {LoadMode::Approach, load.number("approach", 0.0)};
  }
  if (hf || hp || ha)
    if (const auto [key, why] = load_problem(c); !key.empty()) load.error(key, why);
  load.finish();

  Section fr(root, "friction", errors);
  c.friction.coefficient = fr.number("coefficient", 0.0);
  c.friction.direction_deg = fr.number("direction", 0.0);
  c.friction.regularization = fr.number("regularization", 0.0);
  // The sliding speed a viscoelastic body's modes are excited at (omega = -(q.e_s) v0).
  c.visco.velocity = fr.number("velocity", 0.0);
  c.visco.direction_deg = c.friction.direction_deg;
  if (!(c.visco.velocity >= 0))
    fr.error("velocity", "must be a non-negative speed (length per time unit of elastic.relaxation_time)");
  else if (c.visco.velocity != 0 && !c.visco.enabled())
    fr.error("velocity",
             "a sliding speed needs a viscoelastic body (elastic.viscoelastic = \"sls\" or \"prony\"): an "
             "elastic body's steady state does not depend on it");
  try {
    c.visco.validate(c.elastic.contact_modulus);
  } catch (const ParameterError& e) {
    if (e.where() == "velocity")
      fr.error("velocity", e.why());
    else
      el.error(e.where(), e.why());
  }
  if (!(c.friction.regularization >= 0 && c.friction.regularization < 1))
    fr.error("regularization", "must be in [0, 1) (slip speed / v0 below which the traction is regularised)");
  // Section::number has refused nan and inf already (they come back as the default).
  if (!(c.friction.coefficient >= 0)) fr.error("coefficient", "must be a non-negative number");
  c.friction.creepage = fr.number("creepage", 1.0);
  if (!(c.friction.creepage > 0))
    fr.error("creepage", "must be a positive finite number (rigid slip speed / v0; 1 = sliding)");
  else if (c.friction.creepage != 1.0 && !(c.friction.coefficient > 0))
    fr.error("creepage", "rolling with creepage needs friction: set friction.coefficient > 0");
  c.friction.lateral_creepage = fr.number("lateral_creepage", 0.0);
  if (c.friction.lateral_creepage != 0.0 && !(c.friction.coefficient > 0))
    fr.error("lateral_creepage", "rolling with creepage needs friction: set friction.coefficient > 0");
  else if (std::abs(c.friction.lateral_creepage) > 1e6)
    fr.error("lateral_creepage", "must be at most 1e6 in magnitude (rigid slip speed / v0)");
  const std::string deriv = fr.string("slip_derivative", "auto");
  if (deriv == "spectral")
    c.friction.slip_derivative = SlipDerivative::Spectral;
  else if (deriv == "upwind")
    c.friction.slip_derivative = SlipDerivative::Upwind;
  else if (deriv == "upwind2")
    c.friction.slip_derivative = SlipDerivative::Upwind2;
  else if (deriv != "auto")
    fr.error(
        "slip_derivative",
        "unknown discretisation \"" + deriv +
            "\"; one of auto (upwind2 for rolling and where sliding meets stick, else spectral), spectral, "
            "upwind, upwind2");
  c.friction.stick_step = fr.number("stick_step", 0.0);
  if (!(c.friction.stick_step >= 0) || c.friction.stick_step > 1e6)
    fr.error("stick_step", "must be 0 (automatic) or a positive step gamma/E* up to 1e6");
  c.friction.stick_acceleration = static_cast<int>(fr.integer("stick_acceleration", 0, 0, 50));
  if (c.friction.stick_acceleration > 0 && c.friction.slip_derivative == SlipDerivative::Spectral)
    fr.error("stick_acceleration",
             "needs an upwind slip derivative (friction.slip_derivative = \"auto\", \"upwind2\" or "
             "\"upwind\"): with the spectral one its looser inner solves stall the friction iteration "
             "(docs/solver.md)");
  c.friction_reference = fr.boolean("reference", true);
  const std::string law_name = fr.string("law", "coulomb");
  std::vector<std::string> law_keys;  // an unknown law: the keys of every law, no second error
  if (const FrictionLawType* law = find_friction_law(law_name)) {
    c.friction.law.kind = law->kind;
    for (const FrictionLawType::Key& k : law->keys)
      c.friction.law.*k.member = fr.number(k.name, k.default_value);
    if (law->check)
      if (const auto [key, why] = law->check(c.friction.law, c.friction.coefficient); !key.empty())
        fr.error(key, why);
    if (!law->set_valued_stick && c.friction.coefficient > 0 && !c.friction.regularized())
      fr.error("regularization", "must be positive with friction.law = \"" + law->name +
                                     "\" (its stick is solved regularised: e.g. 0.01)");
  } else {
    std::vector<std::string> names;
    for (const FrictionLawType* t : friction_law_types()) {
      names.push_back(t->name);
      for (const auto& k : t->keys) law_keys.push_back(k.name);
    }
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    fr.error("law", "unknown friction law \"" + law_name + "\"" + did_you_mean(law_name, names) +
                        "; one of " + list);
  }
  fr.finish(law_keys);

  Section ia(root, "interaction", errors);
  const std::string model = ia.string("model", "harmonic");
  std::vector<std::string> adhesion_keys;
  if (model == "harmonic") {
    c.interaction.hard_wall = false;
  } else if (model == "hardwall" || model == "hard_wall") {
    c.interaction.hard_wall = true;
  } else if (model == "adhesive") {
    // The Maugis-Dugdale cohesive law on a repulsion (hard wall by default, as in the
    // theories it is checked against).
    adhesion_keys = {"work_of_adhesion", "range", "repulsion"};
    // 0: the repulsion alone (the limit of vanishing adhesion, solved as without the model).
    c.interaction.work_of_adhesion = ia.number("work_of_adhesion", 0.0);
    if (!(c.interaction.work_of_adhesion >= 0) || !std::isfinite(c.interaction.work_of_adhesion))
      ia.error("work_of_adhesion",
               "must be zero or positive and finite (the work of adhesion, energy per area in E* x length "
               "units)");
    c.interaction.range = ia.number("range", 0.0);
    if (!(c.interaction.range > 0) || !std::isfinite(c.interaction.range))
      ia.error("range", "must be positive and finite (the range of the cohesive law, a length)");
    const std::string rep = ia.string("repulsion", "hardwall");
    if (rep == "hardwall" || rep == "hard_wall") {
      c.interaction.hard_wall = true;
    } else if (rep == "harmonic") {
      c.interaction.hard_wall = false;
    } else {
      ia.error("repulsion", "unknown repulsion \"" + rep + "\"; one of hardwall, harmonic");
    }
  } else {
    ia.error("model", "unknown model \"" + model + "\"; one of harmonic, hardwall, adhesive");
  }
  c.interaction.stiffness = ia.number("stiffness", 0.0);
  if (!(c.interaction.stiffness >= 0))
    ia.error("stiffness", "must be zero (the default, 2 E*/dx) or positive");
  c.interaction.hardness = ia.number_or_inf("hardness", std::numeric_limits<double>::infinity());
  if (!(c.interaction.hardness > 0))
    ia.error("hardness", "must be positive (the largest local pressure, in units of E*) or \"inf\" (no cap)");
  if (c.interaction.adhesive() && c.friction.coefficient > 0)
    ia.error("model",
             "adhesion with friction is not implemented yet: set friction.coefficient = 0 with "
             "interaction.model = \"adhesive\"");
  if (c.visco.enabled()) {
    if (c.friction.coefficient > 0)
      fr.error("coefficient",
               "a viscoelastic body with Coulomb friction is not implemented yet: set it to 0 "
               "(the hysteresis friction is computed without it)");
    if (c.interaction.adhesive()) ia.error("model", "adhesion on a viscoelastic body is not implemented");
    if (c.interaction.plastic())
      ia.error("hardness", "plastic saturation on a viscoelastic body is not implemented");
  }
  if (c.interaction.adhesive() && c.interaction.plastic())
    ia.error("hardness",
             "adhesion with plastic saturation is not implemented: leave interaction.hardness out "
             "with interaction.model = \"adhesive\"");
  ia.finish(adhesion_keys);
  // A cap below the mean pressure leaves no solution: the load is named.
  if (c.interaction.plastic() && c.interaction.hardness > 0 && (hf || hp))
    if (const auto [key, why] = load_problem(c); !key.empty()) load.error(key, why);

  Section so(root, "solver", errors);
  c.solver.tolerance = so.number("tolerance", 1e-8);
  c.solver.max_iterations = static_cast<int>(so.integer("max_iterations", 20000, 1, 1000000000));
  c.solver.max_outer = static_cast<int>(so.integer("max_outer", 2000, 1, 1000000000));
  c.solver.max_tangential = static_cast<int>(so.integer("max_tangential", 20000, 1, 100000000));
  c.solver.anderson = static_cast<int>(so.integer("anderson", 10, 0, 50));
  c.solver.mixing = so.number("mixing", 0.5);
  if (!(c.solver.mixing > 0 && c.solver.mixing <= 1)) so.error("mixing", "must be in (0, 1]");
  c.threads = static_cast<int>(so.integer("threads", 0, 0, kMaxThreads));
  c.backend = so.string("backend", c.backend);
  if (find_backend(c.backend) == nullptr) {
    std::string names;
    for (const auto& b : backend_names()) names += (names.empty() ? "\"" : ", \"") + b + "\"";
    so.error("backend", "must be one of " + names + " (got \"" + c.backend + "\")");
  }
  {
    const std::string planner = so.string("fft_planner", "estimate");
    if (planner == "estimate") {
      c.solver.fft_planner = Planner::Estimate;
    } else if (planner == "measure") {
      c.solver.fft_planner = Planner::Measure;
    } else {
      so.error("fft_planner", "must be \"estimate\" or \"measure\" (got \"" + planner + "\")");
    }
  }
  if (!(c.solver.tolerance > 0 && c.solver.tolerance < 1)) so.error("tolerance", "must be in (0, 1)");
  so.finish();

  Section sw(root, "sweep", errors);
  if (sw.present()) {
    c.sweep.parameter = sw.string("parameter", "");
    c.sweep.plot = sw.string("plot", c.sweep.plot);
    if (const toml::value* v = sw.raw("values")) {
      if (!v->is_array()) {
        sw.error("values", "must be an array of numbers");
      } else if (v->as_array().size() > static_cast<std::size_t>(kMaxSweepPoints)) {
        sw.error("values", "at most " + std::to_string(kMaxSweepPoints) + " values, got " +
                               std::to_string(v->as_array().size()));
      } else {
        for (const auto& e : v->as_array()) {
          if (e.is_floating() && std::isfinite(e.as_floating()))
            c.sweep.values.push_back(e.as_floating());
          else if (e.is_integer())
            c.sweep.values.push_back(static_cast<double>(e.as_integer()));
          else
            sw.error("values", "must be an array of finite numbers" + where(e));
        }
      }
    }
    const double from = sw.number("from", 0.0), to = sw.number("to", 0.0);
    const long long points = sw.integer("points", 0, 0, kMaxSweepPoints);
    const std::string spacing = sw.string("spacing", "log");
    if (points > 0) {
      if (!c.sweep.values.empty()) sw.error("points", "give either values or from/to/points, not both");
      if (spacing != "log" && spacing != "linear") sw.error("spacing", "must be \"log\" or \"linear\"");
      if (spacing == "log" && !(from > 0 && to > 0))
        sw.error("from", "log spacing needs positive from and to");
      for (long long i = 0; i < points; ++i) {
        const double t = points == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(points - 1);
        c.sweep.values.push_back(spacing == "log" ? from * std::pow(to / from, t) : from + (to - from) * t);
      }
    }
    if (c.sweep.parameter.empty() || c.sweep.parameter.find('.') == std::string::npos)
      sw.error("parameter", "name the swept key as \"section.key\", e.g. \"load.force\"");
    if (c.sweep.values.empty()) sw.error("values", "give the values (or from, to, points)");
  }
  sw.finish();

  Section st(root, "stress", errors);
  if (const toml::value* v = st.raw("post_analysis")) {
    // false | true (= "consistent") | "paper" | "consistent" | a list of those.
    const auto kind = [&](const toml::value& e) {
      if (e.is_string() && (e.as_string() == "paper" || e.as_string() == "consistent")) {
        const std::string k = e.as_string();
        if (std::find(c.stress.post_analysis.begin(), c.stress.post_analysis.end(), k) ==
            c.stress.post_analysis.end())
          c.stress.post_analysis.push_back(k);
      } else {
        st.error("post_analysis",
                 "must be false, true, \"paper\", \"consistent\" or a list of those" + where(e));
      }
    };
    if (v->is_boolean()) {
      if (v->as_boolean()) c.stress.post_analysis = {"consistent"};
    } else if (v->is_array()) {
      for (const auto& e : v->as_array()) kind(e);
    } else {
      kind(*v);
    }
  }
  if (!c.stress.post_analysis.empty() && c.friction.law.kind != FrictionLawKind::Coulomb &&
      c.friction.coefficient > 0)
    st.error("post_analysis",
             "adds Coulomb's traction mu_c p e_s to the frictionless solution: not defined for "
             "friction.law = \"" +
                 friction_law_type(c.friction.law.kind).name +
                 "\" (the solve's own stresses are: stress.depths, fields.nc)");
  c.stress.high_tension_fraction = st.number("high_tension_fraction", 0.9);
  c.stress.profiles = st.boolean("profiles", true);
  if (!(c.stress.high_tension_fraction > 0 && c.stress.high_tension_fraction <= 1))
    st.error("high_tension_fraction", "must be in (0, 1]");
  if (const toml::value* v = st.raw("depths")) {
    if (!v->is_array()) {
      st.error("depths", "must be an array of depths below the surface");
    } else if (v->as_array().size() > kMaxStressDepths) {
      st.error("depths", "at most " + std::to_string(kMaxStressDepths) + " depths, got " +
                             std::to_string(v->as_array().size()));
    } else {
      for (const auto& e : v->as_array()) {
        const double d = e.is_floating()  ? e.as_floating()
                         : e.is_integer() ? static_cast<double>(e.as_integer())
                                          : -1.0;
        if (!(d >= 0) || !std::isfinite(d) || (!c.elastic.half_space() && d > c.elastic.thickness))
          st.error("depths", "each depth must be a number in [0, thickness]" + where(e));
        else
          c.stress.depths.push_back(d);
      }
    }
  }
  st.finish();

  Section fl(root, "flow", errors);
  if (fl.present()) {
    c.flow.enabled = fl.boolean("enabled", true);
    c.flow.tolerance = fl.number("tolerance", 1e-10);
    if (!(c.flow.tolerance > 0 && c.flow.tolerance < 1)) fl.error("tolerance", "must be in (0, 1)");
    const std::string solver = fl.string("solver", "auto");
    if (!parse_flow_solver(solver, c.flow.solver))
      fl.error("solver", "must be \"auto\", \"amg\" or \"boomeramg\", got \"" + solver + "\"");
    // "x", "y", "both", or an angle in degrees (a number, or a string holding one).
    const std::string expected = "must be \"x\", \"y\", \"both\" or an angle in degrees, got ";
    const toml::value* dv = fl.raw("direction");
    if (dv && (dv->is_floating() || dv->is_integer())) {
      const double a = fl.number("direction", 0.0);
      if (std::isfinite(a)) c.flow.angles = {a};
    } else if (dv && !dv->is_string()) {
      fl.error("direction", expected + Section::type_name(*dv));
    } else {
      const std::string dir = fl.string("direction", "both");
      c.flow.angles = parse_flow_directions(dir);
      if (c.flow.angles.empty()) fl.error("direction", expected + "\"" + dir + "\"");
    }
  }
  fl.finish();

  Section out(root, "output", errors);
  c.output.fields = out.boolean("fields", true);
  c.output.png = out.boolean("png", true);
  c.output.analysis = out.boolean("analysis", true);
  out.finish();

  // Combinations.
  if (errors.empty()) {
    // A layer much thinner than the cell: its uniaxial stiffness ~ E*/h leaves the range in
    // which the layer's Green's tensor and the solve are computed (h = 1e-310 overflows).
    if (const double l = std::max(c.grid.lx, c.grid.ly);
        !c.elastic.half_space() && c.elastic.thickness < kMinThicknessRatio * l) {
      std::ostringstream os;
      os << "must be at least " << kMinThicknessRatio << " of the cell size (" << l << "), got "
         << c.elastic.thickness;
      errors.push_back("elastic.thickness: " + os.str() + el.at("thickness"));
    }
    // (Adhesion holds a contact at no load or in tension: the Hertz estimate does not apply.)
    if (c.indenter.type == "hertz" && c.load.mode == LoadMode::Force && !c.interaction.adhesive()) {
      const double r = std::sqrt(c.indenter.radius_x * c.indenter.radius_y);
      const double a = std::cbrt(3 * c.load.value * r / (4 * c.elastic.contact_modulus));
      const double l = std::min(c.grid.lx, c.grid.ly);
      if (2 * a > 0.5 * l) {
        std::ostringstream os;
        os << "the Hertz contact radius a = " << a << " makes the contact wider than half the cell (L = " << l
           << "): periodic images would interfere; enlarge grid.lx or lower the load";
        errors.push_back("load.force: " + os.str() + load.at("force"));
      } else if (a < 2 * c.grid.dx()) {
        std::ostringstream os;
        os << "the Hertz contact radius a = " << a
           << " spans fewer than 2 grid spacings (dx = " << c.grid.dx() << "); refine the grid";
        errors.push_back("load.force: " + os.str() + load.at("force"));
      }
    }
    if (mpi::size() > c.grid.ny)
      errors.push_back("grid.ny: the grid has " + std::to_string(c.grid.ny) + " rows but the run has " +
                       std::to_string(mpi::size()) +
                       " processes (mpirun -np): each process needs at least one row; run with at most " +
                       std::to_string(c.grid.ny) + " processes");
    const double mem = estimated_memory_bytes(c.grid, mpi::size(), !surface_made_on_slabs(c));
    MemoryLimit lim = memory_limit();
    // The processes of a distributed run on this machine share its memory (and its cgroup);
    // a per-process limit (ulimit) applies to each alone.
    const int here = mpi::processes_on_this_machine();
    if (here > 1 && lim.source.find("ulimit") == std::string::npos) {
      lim.bytes /= here;
      lim.source += ", shared by " + std::to_string(here) + " processes";
    }
    if (lim.bytes > 0 && mem > lim.bytes) {
      std::ostringstream os;
      os << "a " << c.grid.nx << " x " << c.grid.ny << " grid needs about " << mem / 1e9 << " GB"
         << (mpi::size() > 1 ? " per process (over " + std::to_string(mpi::size()) + ")" : std::string())
         << ", more than the " << lim.bytes / 1e9 << " GB allowed here (" << lim.source << ")";
      errors.push_back("grid.nx: " + os.str());
    }
  }

  if (!errors.empty()) {
    std::ostringstream os;
    os << errors.size() << " problem" << (errors.size() > 1 ? "s" : "") << " in the case:";
    for (const auto& e : errors) os << "\n  - " << e;
    throw InputError(name, os.str());
  }
  return c;
}

}  // namespace

std::vector<double> parse_flow_directions(const std::string& text) {
  if (text == "x") return {0.0};
  if (text == "y") return {90.0};
  if (text == "both") return {0.0, 90.0};
  char* end = nullptr;
  const double a = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(a)) return {};
  return {a};
}

std::pair<std::string, std::string> load_problem(const Config& c) {
  const LoadParams& l = c.load;
  const char* key = l.mode == LoadMode::Force      ? "force"
                    : l.mode == LoadMode::Pressure ? "pressure"
                                                   : "approach";
  if (!std::isfinite(l.value)) return {key, "must be a finite number"};
  if (l.mode == LoadMode::Approach) {
    // With adhesion the indenter may be pulled back beyond first touch (unloading).
    if (!(l.value >= 0) && !c.interaction.adhesive())
      return {key, "must be zero or positive (negative only with interaction.model = \"adhesive\")"};
    if (std::abs(l.value) > kMaxLength) return {key, "must be at most 1e30 in size (a length)"};
    return {};
  }
  // With adhesion a load may be tensile (negative) up to the pull-off.
  if (!(l.value > 0) && !c.interaction.adhesive())
    return {key, "must be positive (negative, tensile, only with interaction.model = \"adhesive\")"};
  const double e = c.elastic.contact_modulus;
  if (l.mode == LoadMode::Force && e > 0 && c.grid.lx > 0 && c.grid.ly > 0 &&
      l.value / (e * c.grid.lx * c.grid.ly) > kMaxPressureOverModulus)
    return {key, "the mean pressure force / (lx ly) exceeds 1000 E*: not a contact problem"};
  if (l.mode == LoadMode::Pressure && l.value / e > kMaxPressureOverModulus)
    return {key, "exceeds 1000 E*: not a contact problem"};
  const double mean = l.mode == LoadMode::Force ? l.value / (c.grid.lx * c.grid.ly) : l.value;
  if (c.interaction.plastic() && !(mean < c.interaction.hardness))
    return {key,
            "the mean pressure reaches interaction.hardness: the whole cell would flow plastically "
            "(lower the load or raise the hardness)"};
  return {};
}

void check_load(const Config& c) {
  if (const auto [key, why] = load_problem(c); !key.empty()) throw InputError("load." + key, why);
}

Config parse_config(const std::string& text, const std::string& name,
                    const std::vector<std::string>& overrides, const std::string& base_dir) {
  require_utf8(text, name);
  require_shallow_nesting(text, name);
  toml::value root;
  try {
    std::istringstream is(text);
    root = toml::parse(is, name);
  } catch (const toml::syntax_error& e) {
    throw InputError(name, std::string("not valid TOML:\n") + e.what());
  } catch (const std::exception& e) {
    throw InputError(name, std::string("not valid TOML: ") + e.what());
  }
  for (const auto& o : overrides) apply_override(root, o);
  return build(root, name, base_dir);
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string text = read_regular_file(path, kMaxCaseFileBytes, "case file");
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_config(text, path, overrides, base.empty() ? "." : base);
}

}  // namespace gfmd
