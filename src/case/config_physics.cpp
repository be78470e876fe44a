// The physics sections of a case file: [elastic] (with a viscoelastic body's keys),
// [friction] and [interaction], each read into the Config and checked key by key (private to
// the config part; src/case/config.cpp runs them in order).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <toml.hpp>
#include <vector>

#include "config_section.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "gfmd/contact/interaction.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/layered.hpp"

namespace gfmd::config_detail {

namespace {

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

// A master curve's file (elastic.master_curve, relative to the case file) and its temperature
// shift: WLF (wlf_c1, wlf_c2) or Arrhenius (activation_temperature), from reference_temperature
// to temperature.
void read_master_curve(Section& el, ViscoelasticParams& v, const std::string& base_dir) {
  const bool wlf = el.has("wlf_c1") || el.has("wlf_c2"), arr = el.has("activation_temperature");
  const bool temp = el.has("temperature"), ref = el.has("reference_temperature");
  const std::string path = el.string("master_curve", "");
  const double t = el.number("temperature", 0.0), tr = el.number("reference_temperature", 0.0);
  const double c1 = el.number("wlf_c1", 0.0), c2 = el.number("wlf_c2", 0.0);
  const double a = el.number("activation_temperature", 0.0);
  if (v.model != ViscoelasticParams::Model::MasterCurve) {
    for (const char* k : {"master_curve", "temperature", "reference_temperature", "wlf_c1", "wlf_c2",
                          "activation_temperature"})
      if (el.has(k)) el.error(k, "belongs to " + el.name() + ".viscoelastic = \"master_curve\"");
    return;
  }
  if (path.empty()) {
    el.error("master_curve",
             "is needed with " + el.name() + ".viscoelastic = \"master_curve\" (a file of omega, E', E'')");
    return;
  }
  const std::string file = (std::filesystem::path(base_dir) / path).lexically_normal().string();
  try {
    parse_master_curve(read_regular_file(file, kMaxCaseFileBytes * 16, "master curve"), file, v);
  } catch (const InputError& e) {
    el.error("master_curve", e.what());
    return;
  }
  if (wlf && arr)
    el.error("activation_temperature", "give one shift: wlf_c1 and wlf_c2 (WLF) or this (Arrhenius)");
  if (wlf && !(el.has("wlf_c1") && el.has("wlf_c2"))) {
    el.error(el.has("wlf_c1") ? "wlf_c2" : "wlf_c1", "the WLF shift needs both wlf_c1 and wlf_c2");
    return;
  }
  if ((wlf || arr) != (temp && ref) || (temp != ref)) {
    el.error("temperature",
             "a temperature shift needs temperature, reference_temperature and one shift law "
             "(wlf_c1 and wlf_c2, or activation_temperature)");
    return;
  }
  v.curve_file = file;
  if (wlf) {
    if (!(c2 + t - tr > 0))
      el.error("wlf_c2", "c2 + temperature - reference_temperature must be positive");
    else
      v.shift_factor = wlf_shift(t, tr, c1, c2);
    v.shift_keys = {{"temperature", t}, {"reference_temperature", tr}, {"wlf_c1", c1}, {"wlf_c2", c2}};
  } else if (arr) {
    if (!(t > 0 && tr > 0))
      el.error("temperature", "Arrhenius's shift needs absolute temperatures (kelvin, > 0)");
    else
      v.shift_factor = arrhenius_shift(t, tr, a);
    v.shift_keys = {{"temperature", t}, {"reference_temperature", tr}, {"activation_temperature", a}};
  }
}

// "layers[i]" (i a decimal index below 1000) -> i, else -1.
int layer_index(const std::string& s) {
  if (s.size() < 9 || s.rfind("layers[", 0) != 0 || s.back() != ']') return -1;
  const std::string digits = s.substr(7, s.size() - 8);
  if (digits.empty() || digits.size() > 3 ||
      !std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
    return -1;
  return std::stoi(digits);
}

// elastic.viscoelastic and its keys (the relaxed modulus is elastic.contact_modulus); `further`:
// a table of elastic.viscoelastic_parts (its viscoelastic_part needed).
void read_viscoelastic(Section& el, ViscoelasticParams& v, const std::string& base_dir,
                       bool further = false) {
  using Model = ViscoelasticParams::Model;
  const std::string model = el.string("viscoelastic", "none");
  if (model == "sls")
    v.model = Model::StandardLinearSolid;
  else if (model == "prony")
    v.model = Model::Prony;
  else if (model == "master_curve")
    v.model = Model::MasterCurve;
  else if (model != "none")
    el.error("viscoelastic",
             "unknown model \"" + model + "\" (\"none\", \"sls\", \"prony\" or \"master_curve\")");
  read_master_curve(el, v, base_dir);
  const bool einf = el.has("high_frequency_modulus"), tau = el.has("relaxation_time");
  v.high_frequency_modulus = el.number("high_frequency_modulus", 0.0);
  v.relaxation_time = el.number("relaxation_time", 0.0);
  v.prony_moduli = positive_list(el, "prony_moduli");
  v.prony_times = positive_list(el, "prony_times");
  const auto needs = [&](const char* key, bool given, Model m) {
    if (given && v.model != m)
      el.error(key, "belongs to " + el.name() + ".viscoelastic = \"" + viscoelastic_model_name(m) + "\"");
    else if (!given && v.model == m)
      el.error(key, "is needed with " + el.name() + ".viscoelastic = \"" + viscoelastic_model_name(m) + "\"");
  };
  needs("high_frequency_modulus", einf, Model::StandardLinearSolid);
  needs("relaxation_time", tau, Model::StandardLinearSolid);
  needs("prony_moduli", !v.prony_moduli.empty(), Model::Prony);
  needs("prony_times", !v.prony_times.empty(), Model::Prony);
  if (el.has("viscoelastic_part") || further) {
    const std::string part = el.string("viscoelastic_part", "top");
    if (further && !el.has("viscoelastic_part"))
      el.error("viscoelastic_part",
               "is needed: which part this model makes viscoelastic (\"top\", "
               "\"layers[i]\" or \"substrate\")");
    if (!v.enabled())
      el.error("viscoelastic_part", "belongs to a viscoelastic body (elastic.viscoelastic)");
    else if (part == "substrate")
      v.part = ViscoelasticParams::Part::Substrate;
    else if (part == "all")
      v.part = ViscoelasticParams::Part::All;
    else if (const int i = layer_index(part); i >= 0) {
      v.part = ViscoelasticParams::Part::Layer;
      v.layer = i;
    } else if (part != "top")
      el.error("viscoelastic_part",
               "must be \"top\", \"layers[i]\" (a layer beneath it), \"substrate\" or \"all\", got \"" +
                   part + "\"");
  }
}

// elastic.viscoelastic_parts: further viscoelastic parts of a layered body, an array of tables
// with the viscoelastic keys of [elastic] (viscoelastic, viscoelastic_part, high_frequency_modulus,
// relaxation_time, prony_*, master_curve and its shift), one part each.
// Returns false where a part was left out for its problems (the list's places no longer hold).
bool read_further_parts(Section& el, ViscoelasticParams& v, const std::string& base_dir) {
  const toml::value* parts = el.raw("viscoelastic_parts");
  if (!parts) return true;
  bool whole = true;
  const std::string what =
      "must be an array of tables, each with the viscoelastic keys of [elastic] "
      "(viscoelastic, viscoelastic_part and its model's keys)";
  if (!v.enabled()) {
    el.error("viscoelastic_parts", "further viscoelastic parts need a first one (elastic.viscoelastic)");
  } else if (!parts->is_array()) {
    el.error("viscoelastic_parts", what + where(*parts));
  } else if (parts->as_array().size() > kMaxLayers + 1) {
    el.error("viscoelastic_parts", "at most " + std::to_string(kMaxLayers + 1) + " further parts, got " +
                                       std::to_string(parts->as_array().size()));
  } else {
    std::size_t i = 0;
    for (const toml::value& t : parts->as_array()) {
      const std::string name = "viscoelastic_parts[" + std::to_string(i++) + "]";
      if (!t.is_table()) {
        el.error(name, what + where(t));
        return false;
      }
      Section part = el.child(t, name);
      ViscoelasticParams p;
      const std::size_t problems = part.problems();
      read_viscoelastic(part, p, base_dir, true);
      if (!p.enabled()) part.error("viscoelastic", "is needed: \"sls\", \"prony\" or \"master_curve\"");
      part.finish();
      // A part with problems is not kept, and the body's checks (validate_viscoelastic_parts)
      // wait for a list without: they would report its defaults (say the top for a misspelt
      // viscoelastic_part) as conflicts the file does not have, and name the parts after it
      // by the wrong places.
      if (part.problems() != problems)
        whole = false;
      else
        v.further.push_back(std::move(p));
    }
  }
  return whole;
}

}  // namespace

namespace {
// <section>.<key> of BodyKey::Kind::Tables: an array of tables whose values are the key's fields
// (numbers; the required ones given, no other keys), at most kMaxLayers of them.
void read_tables(Section& el, const BodyKey& k, ElasticParams& e) {
  const toml::value* v = el.raw(k.name);
  if (!v) return;
  std::vector<std::string> names;
  std::string shape;
  for (const BodyTableField& f : k.fields) {
    names.push_back(f.name);
    shape += (shape.empty() ? "{" : ", ") + f.name;
  }
  shape += "}";
  if (!v->is_array()) {
    el.error(k.name, "must be an array of tables " + shape);
    return;
  }
  if (v->as_array().size() > kMaxLayers) {
    el.error(k.name, "at most " + std::to_string(kMaxLayers) + " tables, got " +
                         std::to_string(v->as_array().size()));
    return;
  }
  std::vector<std::vector<double>> rows;
  std::size_t i = 0;
  for (const auto& t : v->as_array()) {
    const std::string name = k.name + "[" + std::to_string(i++) + "]";
    if (!t.is_table()) {
      el.error(name, "must be a table " + shape + where(t));
      return;
    }
    std::vector<double> row;
    std::vector<bool> given(k.fields.size(), false);
    for (const BodyTableField& f : k.fields) row.push_back(f.default_value);
    for (const auto& [key, x] : t.as_table()) {
      const auto at = std::find(names.begin(), names.end(), key);
      if (at == names.end()) {
        el.error(name + "." + key, "unknown key" + did_you_mean(key, names) + where(x));
        return;
      }
      if (!x.is_floating() && !x.is_integer()) {
        el.error(name + "." + key, "must be a number, got " + Section::type_name(x) + where(x));
        return;
      }
      const auto j = static_cast<std::size_t>(at - names.begin());
      row[j] = x.is_floating() ? x.as_floating() : static_cast<double>(x.as_integer());
      given[j] = true;
    }
    for (std::size_t j = 0; j < k.fields.size(); ++j)
      if (k.fields[j].required && !given[j]) {
        el.error(name, "needs " + k.fields[j].name + where(t));
        return;
      }
    rows.push_back(std::move(row));
  }
  k.set_rows(e, rows);
}
}  // namespace

// The keys of the kinds of body (elastic/body.hpp's BodyKey), read and written by their kind.
void read_body_stack(Section& s, ElasticParams& e) {
  for (const BodyKey* k : body_keys()) {
    switch (k->kind) {
      case BodyKey::Kind::Number:
        e.*(k->member) = s.number(k->name, k->default_value);
        break;
      case BodyKey::Kind::NumberOrInf:
        e.*(k->member) = s.number_or_inf(k->name, k->default_value);
        break;
      case BodyKey::Kind::Tables:
        read_tables(s, *k, e);
        break;
    }
    if (!k->needs.empty() && s.has(k->name) && !s.has(k->needs))
      s.error(k->name, "is used only with " + k->needs + ": set " + k->needs + " too");
  }
}

void write_body_stack(const ElasticParams& e, nlohmann::json& out) {
  for (const BodyKey* k : body_keys()) {
    if (k->written && !k->written(e)) continue;
    switch (k->kind) {
      case BodyKey::Kind::Number:
      case BodyKey::Kind::NumberOrInf:
        out[k->name] = e.*(k->member);
        break;
      case BodyKey::Kind::Tables:
        for (const std::vector<double>& row : k->rows(e)) {
          nlohmann::json t = nlohmann::json::object();
          for (std::size_t j = 0; j < k->fields.size(); ++j) t[k->fields[j].name] = row[j];
          out[k->name].push_back(std::move(t));
        }
        break;
    }
  }
}

void read_elastic(Section& el, Config& c, const std::string& base_dir) {
  c.elastic.contact_modulus = el.number("contact_modulus", 1.0);
  c.elastic.poisson = el.number("poisson", 0.25);
  c.elastic.thickness = el.number_or_inf("thickness", std::numeric_limits<double>::infinity());
  c.elastic.coupling = el.boolean("coupling", true);
  read_body_stack(el, c.elastic);
  read_viscoelastic(el, c.visco, base_dir);
  const bool parts_whole = read_further_parts(el, c.visco, base_dir);
  using Part = ViscoelasticParams::Part;
  for (const ViscoelasticParams& p : c.visco.parts())
    if (p.model == ViscoelasticParams::Model::MasterCurve && p.master_relaxed_modulus() > 0 &&
        (p.part == Part::Top || p.part == Part::All)) {
      // The table's relaxed modulus is the body's E0* (the unit of pressures). (A viscoelastic
      // substrate's or layer's is its own contact modulus, given and checked against the table.)
      const double e0 = p.master_relaxed_modulus();
      if (el.has("contact_modulus") && !(std::abs(c.elastic.contact_modulus - e0) <= 1e-12 * e0))
        el.error("contact_modulus", "is set by the master curve (its first storage modulus, " +
                                        format_number(e0) + "): leave it out");
      c.elastic.contact_modulus = e0;
    }
  el.finish();
  // Each part in the body and its model checked against its relaxed modulus (its speed is
  // [friction]'s).
  // The body's checks name parts by their place in the list: with a part left out (its own
  // problems reported) they would name the wrong one, so they wait for a list without problems.
  if (parts_whole) el.check([&] { validate_viscoelastic_parts(c.elastic, c.visco); });
}

void read_friction(Section& fr, Config& c) {
  c.friction.coefficient = fr.number("coefficient", 0.0);
  c.friction.direction_deg = fr.number("direction", 0.0);
  c.friction.regularization = fr.number("regularization", 0.0);
  // The sliding speed a viscoelastic body's modes are excited at (omega = -(q.e_s) v0).
  c.velocity_given = fr.has("velocity");
  c.visco.velocity = fr.number("velocity", 0.0);
  c.visco.direction_deg = c.friction.direction_deg;
  if (!(c.visco.velocity >= 0))
    fr.error("velocity", "must be a non-negative speed (length per time unit of elastic.relaxation_time)");
  else if (c.visco.velocity != 0 && !c.visco.enabled())
    fr.error("velocity",
             "a sliding speed needs a viscoelastic body (elastic.viscoelastic = \"sls\", \"prony\" or "
             "\"master_curve\"): an "
             "elastic body's steady state does not depend on it");
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
    // friction.coefficient > 0 switches the friction on: a law whose traction is not zero at
    // mu_c = 0 (a static peak mu_s, a rate term a) would otherwise be dropped without a word.
    if (!(c.friction.coefficient > 0) &&
        (c.friction.law.bound(0.0, 1.0, 0.0) > 0 || c.friction.law.bound(0.0, 1.0, 1.0) > 0))
      fr.error("coefficient", "must be positive with friction.law = \"" + law->name +
                                  "\": friction.coefficient > 0 switches the friction on, and without it the "
                                  "law's traction (" +
                                  law->traction +
                                  ") would be ignored; for a law that vanishes at rest give a small mu_c, "
                                  "e.g. 1e-9");
    if (!law->set_valued_stick && c.friction.coefficient > 0 && !c.friction.regularized())
      fr.error("regularization", "must be positive with friction.law = \"" + law->name +
                                     "\" (its stick is solved regularised: e.g. 0.01)");
  } else {
    std::vector<std::string> names;
    for (const FrictionLawType* t : friction_law_types()) {
      names.push_back(t->name);
      for (const auto& k : t->keys) law_keys.push_back(k.name);
    }
    fr.error("law", "unknown friction law \"" + law_name + "\"" + did_you_mean(law_name, names) +
                        "; one of " + comma_list(names));
  }
  fr.finish(law_keys);
}

void read_interaction(Section& ia, Config& c) {
  // The model and its own keys from the registry (contact/interaction.hpp).
  const std::string model = ia.string("model", "harmonic");
  std::vector<std::string> own_keys;
  const InteractionType* t = find_interaction(model);
  if (!t) {
    std::vector<std::string> names;
    for (const InteractionType* m : interaction_types()) names.push_back(m->name);
    ia.error("model", "unknown model \"" + model + "\"" + did_you_mean(model, names) + "; one of " +
                          comma_list(names));
  } else {
    c.interaction.hard_wall = t->hard_wall;
    for (const InteractionType::Key& k : t->keys) {
      own_keys.push_back(k.name);
      c.interaction.*k.member = ia.number(k.name, k.default_value);
    }
    if (t->repulsion_key) {
      own_keys.emplace_back("repulsion");
      const std::string rep = ia.string("repulsion", t->hard_wall ? "hardwall" : "harmonic");
      const InteractionType* r = find_interaction(rep);
      if (r && r->repulsion()) {
        c.interaction.hard_wall = r->hard_wall;
      } else {
        std::vector<std::string> repulsions;
        for (const InteractionType* m : interaction_types())
          if (m->repulsion()) repulsions.push_back(m->name);
        ia.error("repulsion", "unknown repulsion \"" + rep + "\"; one of " + comma_list(repulsions));
      }
    }
    if (t->check)
      for (const auto& [key, why] : t->check(c.interaction)) ia.error(key, why);
    // A key of another model is named as such (a work of adhesion under "hardwall" is not an
    // unknown key: the model is what is missing).
    for (const InteractionType* m : interaction_types()) {
      std::vector<std::string> keys;
      for (const InteractionType::Key& k : m->keys) keys.push_back(k.name);
      if (m->repulsion_key) keys.emplace_back("repulsion");
      for (const std::string& k : keys)
        if (m != t && ia.find(k) && std::find(own_keys.begin(), own_keys.end(), k) == own_keys.end()) {
          ia.error(k, "belongs to interaction.model = \"" + std::string(m->name) + "\" (this case's is \"" +
                          model + "\")");
          own_keys.push_back(k);
        }
    }
  }
  c.interaction.stiffness = ia.number("stiffness", 0.0);
  if (!(c.interaction.stiffness >= 0))
    ia.error("stiffness", "must be zero (the default, 2 E*/dx) or positive");
  else if (c.interaction.stiffness > 0 && c.interaction.hard_wall)
    ia.error("stiffness",
             "belongs to the harmonic repulsion (interaction.model = \"harmonic\", or repulsion = "
             "\"harmonic\" with adhesion); this case's is a hard wall, which has none");
  c.interaction.hardness = ia.number_or_inf("hardness", std::numeric_limits<double>::infinity());
  if (!(c.interaction.hardness > 0))
    ia.error("hardness", "must be positive (the largest local pressure, in units of E*) or \"inf\" (no cap)");
  ia.finish(own_keys);
}

}  // namespace gfmd::config_detail
