// The indenter types' table (one line per part, indenter_<name>.cpp) and what is built on
// it: reading [indenter], writing it back, making the topography.
#include "indenter_types.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <toml.hpp>

#include "gfmd/core/error.hpp"
#include "gfmd/elastic/body.hpp"

namespace gfmd {

namespace config_detail {

const std::vector<const IndenterType*>& indenter_registry() {
  static const std::vector<const IndenterType*> table = {
      &hertz_indenter(),       //
      &flatpunch_indenter(),   //
      &powerlaw_indenter(),    //
      &sphere_indenter(),      //
      &cylinder_indenter(),    //
      &step_indenter(),        //
      &eggcrate_indenter(),    //
      &selfaffine_indenter(),  //
      &file_indenter(),        //
      &array_indenter(),       //
  };
  return table;
}

const IndenterType* find_indenter_type(const std::string& name) {
  for (const IndenterType* t : indenter_registry())
    if (t->name == name) return t;
  return nullptr;
}

std::vector<std::string> case_indenter_names() {
  std::vector<std::string> names;
  for (const IndenterType* t : indenter_registry())
    if (t->in_case_files) names.push_back(t->name);
  return names;
}

std::string indenter_names_text() { return comma_list(case_indenter_names()); }

std::string g3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string cell_text(const Config& c) {
  return "grid.lx = " + g3(c.grid.lx) + ", grid.ly = " + g3(c.grid.ly);
}

void read_radii(Section& ind, Config& c, const std::string& what) {
  IndenterConfig& in = c.indenter;
  in.radius = ind.number("radius", 0.0);
  in.radius_x = ind.number("radius_x", in.radius);
  in.radius_y = ind.number("radius_y", in.radius);
  if (ind.has("radius"))
    for (const auto& [key, value] : {std::pair{"radius_x", in.radius_x}, std::pair{"radius_y", in.radius_y}})
      if (ind.has(key) && value != in.radius)
        ind.error(key, "conflicts with indenter.radius = " + g3(in.radius) +
                           ": give radius (round), or radius_x and radius_y (elliptic), not both");
  if (!(in.radius_x > 0) || !(in.radius_y > 0))
    ind.error(ind.has("radius") || !ind.has("radius_x") ? "radius" : "radius_x",
              "a " + what + " needs a positive radius (or radius_x and radius_y)");
}

void read_indenter(Section& ind, Config& c, std::vector<std::string>& errors, const GridKeysGiven& given,
                   const std::string& base_dir) {
  IndenterConfig& in = c.indenter;
  in.type = ind.string("type", "hertz");
  const IndenterType* type = find_indenter_type(in.type);
  // "array" is accepted here so that a program's case (gfmd.solve) reads; its topography
  // comes with the run (make_topography refuses it).
  if (type == nullptr) {
    const std::vector<std::string> names = case_indenter_names();
    ind.error("type", "unknown indenter type \"" + in.type + "\"" + did_you_mean(in.type, names) +
                          "; one of " + indenter_names_text());
    std::vector<std::string> every_key;  // no second error for keys of the type meant
    for (const IndenterType* t : indenter_registry())
      every_key.insert(every_key.end(), t->keys.begin(), t->keys.end());
    every_key.insert(every_key.end(), {"contact_modulus", "poisson", "thickness", "substrate_contact_modulus",
                                       "substrate_poisson", "layers", "waviness_amplitude",
                                       "waviness_wavelength", "waviness_axis"});
    ind.finish(every_key);
    return;
  }
  IndenterRead r{c, errors, given, base_dir};
  type->read(ind, r);
  read_indenter_body(ind, c);
  read_waviness(ind, c);
  ind.finish();
}

// An elastic indenter's body (any indenter type): indenter.contact_modulus ("inf" or absent:
// rigid), poisson, thickness ("inf": a half-space), and beneath it, as in [elastic], the
// substrate and layers (a coated indenter).
namespace {
// The keys of an elastic indenter's body besides its contact_modulus (which makes it elastic).
std::vector<std::string> indenter_body_keys() {
  std::vector<std::string> keys = {"poisson", "thickness"};
  for (const BodyKey* k : body_keys()) keys.push_back(k->name);  // a coated indenter's
  return keys;
}
}  // namespace

void read_indenter_body(Section& ind, Config& c) {
  const double es = ind.number_or_inf("contact_modulus", std::numeric_limits<double>::infinity());
  const double nu = ind.number("poisson", 0.25);
  const double h = ind.number_or_inf("thickness", std::numeric_limits<double>::infinity());
  if (es == std::numeric_limits<double>::infinity()) {
    for (const std::string& k : indenter_body_keys())
      if (ind.has(k))
        ind.error(k, "belongs to an elastic indenter: set indenter.contact_modulus (its E*; absent: rigid)");
    return;
  }
  ElasticParams b = homogeneous_body(es, nu, h, c.elastic.coupling);
  read_body_stack(ind, b);
  if (!ind.check([&] { b.validate(); })) return;
  c.indenter.body = b;
}

// A single-wavelength roughness on any type: indenter.waviness_amplitude, waviness_wavelength,
// waviness_axis ("x" or "y").
void read_waviness(Section& ind, Config& c) {
  IndenterConfig& in = c.indenter;
  in.waviness_amplitude = ind.number("waviness_amplitude", 0.0);
  in.waviness_wavelength = ind.number("waviness_wavelength", 0.0);
  const std::string axis = ind.string("waviness_axis", "x");
  if (axis != "x" && axis != "y") {
    ind.error("waviness_axis",
              "must be \"x\" or \"y\" (the direction the wave runs along), got \"" + axis + "\"");
    return;
  }
  in.waviness_axis = axis[0];
  const bool any =
      ind.has("waviness_amplitude") || ind.has("waviness_wavelength") || ind.has("waviness_axis");
  if (!any) return;
  if (!ind.has("waviness_amplitude") || !ind.has("waviness_wavelength")) {
    ind.error(ind.has("waviness_amplitude") ? "waviness_wavelength" : "waviness_amplitude",
              "a waviness needs both waviness_amplitude and waviness_wavelength");
    return;
  }
  const Grid& g = c.grid;
  if (g.nx >= 2 && g.ny >= 2 && g.lx > 0 && g.ly > 0)
    ind.check([&] {  // its checks on one line of the cell along the wave (the periodicity, the resolution)
      const bool along_y = in.waviness_axis == 'y';
      const Grid line{along_y ? 1 : g.nx, along_y ? g.ny : 1, g.lx, g.ly};
      Topography probe{line, RealField(line.size(), 0.0), ""};
      add_waviness(probe, in.waviness_amplitude, in.waviness_wavelength, in.waviness_axis);
    });
}

nlohmann::json indenter_json(const IndenterConfig& in) {
  nlohmann::json out = {{"type", in.type}};
  if (const IndenterType* t = find_indenter_type(in.type)) t->write(in, out);
  if (in.waviness_amplitude > 0) {  // absent: none (as before the keys)
    out["waviness_amplitude"] = in.waviness_amplitude;
    out["waviness_wavelength"] = in.waviness_wavelength;
    out["waviness_axis"] = std::string(1, in.waviness_axis);
  }
  if (in.body) {  // absent: rigid (as before the keys)
    out["contact_modulus"] = in.body->contact_modulus;
    out["poisson"] = in.body->poisson;
    if (in.body->half_space())
      out["thickness"] = "inf";
    else
      out["thickness"] = in.body->thickness;
    write_body_stack(*in.body, out);
  }
  return out;
}

bool rough_indenter(const std::string& type) {
  const IndenterType* t = find_indenter_type(type);
  return t != nullptr && t->rough;
}

std::pair<std::string, std::string> implausible_surface_text(const Config& c, const MapReport* map) {
  const IndenterType* t = find_indenter_type(c.indenter.type);
  if (t == nullptr) t = &array_indenter();
  return t->implausible(c, map);
}

double plausibility_gradient(const Config& c, double rms_gradient) {
  const IndenterType* t = find_indenter_type(c.indenter.type);
  return t != nullptr && t->plausibility_gradient != nullptr ? t->plausibility_gradient(c, rms_gradient)
                                                             : rms_gradient;
}

}  // namespace config_detail

using namespace config_detail;

bool surface_made_on_slabs(const Config& c) {
  const IndenterType* t = find_indenter_type(c.indenter.type);
  return t == nullptr || t->made_on_slabs;
}

Topography make_topography(const Config& c, MapReport* report) {
  const IndenterType* t = find_indenter_type(c.indenter.type);
  if (t == nullptr)
    throw InputError("indenter.type",
                     "unknown indenter type \"" + c.indenter.type + "\"; one of " + indenter_names_text());
  return in_section("indenter", [&] {
    Topography topo = t->make(c, report);
    const IndenterConfig& in = c.indenter;
    if (in.waviness_amplitude > 0)
      add_waviness(topo, in.waviness_amplitude, in.waviness_wavelength, in.waviness_axis);
    return topo;
  });
}

std::vector<IndenterTypeInfo> indenter_types() {
  std::vector<IndenterTypeInfo> out;
  for (const IndenterType* t : indenter_registry())
    if (t->in_case_files) out.push_back({t->name, t->purpose, t->keys});
  return out;
}

Topography make_indenter(const std::string& type, const Grid& grid, const nlohmann::json& keys,
                         const std::string& base_dir) {
  if (!keys.is_object()) throw InputError("indenter", "the keys must be a mapping of key to value");
  toml::table section{{"type", toml::value(type)}};
  // An elastic indenter's keys make a body, not heights: here they would be dropped.
  std::vector<std::string> body = indenter_body_keys();
  body.emplace_back("contact_modulus");
  for (const auto& [k, v] : keys.items()) {
    if (k == "type") throw InputError("indenter.type", "give the type once, as the first argument");
    if (std::find(body.begin(), body.end(), k) != body.end())
      throw InputError("indenter." + k,
                       "describes an elastic indenter's body, not its heights: give the body to the solve "
                       "(Python: indenter_body=gfmd.ElasticBody(...))");
    section[k] = config_detail::toml_from_json(v, "indenter." + k, 1);
  }
  const toml::value root(toml::table{{"indenter", toml::value(section)}});
  Config c;
  c.grid = grid;
  std::vector<std::string> errors;
  Section ind(root, "indenter", errors);
  read_indenter(ind, c, errors, {true, true, true, true}, base_dir);
  if (errors.size() == 1) {  // "indenter.radius: why": the key, and why
    const std::size_t colon = errors[0].find(": ");
    if (colon != std::string::npos) throw InputError(errors[0].substr(0, colon), errors[0].substr(colon + 2));
  }
  if (!errors.empty()) {
    std::string why = std::to_string(errors.size()) + " problems:";
    for (const std::string& e : errors) why += "\n  - " + e;
    throw InputError("indenter", why);
  }
  return make_topography(c);
}

}  // namespace gfmd
