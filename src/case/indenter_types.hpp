// Indenter types as parts (private to src/case/): each type is one file, indenter_<name>.cpp,
// that says how its [indenter] keys are read and written back, how its topography is made,
// and what the plausibility warning names; indenter_types.cpp lists them, one line each.
// Config reading, serialisation, the "one of ..." messages, make_topography and the Python
// names (gfmd.indenter_types) all come from that list.
//
// Adding a type: write indenter_<name>.cpp defining `const IndenterType& <name>_indenter()`,
// declare it below and add it to the table in indenter_types.cpp; give IndenterConfig the
// fields it needs (include/gfmd/case/config.hpp); test it (docs/architecture.md, recipes).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "config_section.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/surface/measured.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::config_detail {

// What a type's reader gets besides its section: the whole case (the grid is read before the
// indenter; a file indenter fills the grid keys not given), the error list (for messages
// that are not about one key), which grid keys the file gave, and the case file's folder.
struct IndenterRead {
  Config& c;
  std::vector<std::string>& errors;
  GridKeysGiven given;
  const std::string& base_dir;
};

struct IndenterType {
  std::string name;     // indenter.type
  std::string purpose;  // one line (gfmd.indenter_types(), docs)
  // The type's keys (besides "type"): the keys an unknown type's section may hold without a
  // second error, and the documented list.
  std::vector<std::string> keys;
  bool in_case_files = true;  // false: heights handed over by a program ("array")
  // Each process of a distributed run makes its rows of the surface (analytic, seeded);
  // false: rank 0 makes the whole map and scatters it (a height file).
  bool made_on_slabs = true;
  bool rough = false;  // the analysis treats it as a rough surface (spectrum fit, bands)
  // Reads the type's keys into r.c.indenter, reporting problems through ind.error.
  void (*read)(Section& ind, IndenterRead& r) = nullptr;
  // Adds the type's keys, with defaults filled in, to the indenter's JSON (summary "input").
  void (*write)(const IndenterConfig& in, nlohmann::json& out) = nullptr;
  // The topography on c.grid (a slab grid: this process's rows). Throws ParameterError
  // naming the type's key, or InputError.
  Topography (*make)(const Config& c, MapReport* report) = nullptr;
  // For the warning on an implausibly steep surface: whose rms gradient it is ("the Hertz
  // indenter's") and which keys to check.
  std::pair<std::string, std::string> (*implausible)(const Config& c, const MapReport* map) = nullptr;
  // The slope that warning weighs, from the surface's rms gradient; empty: that rms gradient.
  // (A power law's far field is steep by design, away from any contact: its radius is weighed.)
  double (*plausibility_gradient)(const Config& c, double rms_gradient) = nullptr;
};

// The parts, one file each.
const IndenterType& hertz_indenter();
const IndenterType& flatpunch_indenter();
const IndenterType& powerlaw_indenter();
const IndenterType& sphere_indenter();
const IndenterType& cylinder_indenter();
const IndenterType& step_indenter();
const IndenterType& eggcrate_indenter();
const IndenterType& selfaffine_indenter();
const IndenterType& file_indenter();
const IndenterType& array_indenter();

// Every registered type, in the order the docs and messages list them.
const std::vector<const IndenterType*>& indenter_registry();
// The type named `name`, or nullptr.
const IndenterType* find_indenter_type(const std::string& name);
// The names of the types a case file may give, and "hertz, flatpunch, ..." for messages.
std::vector<std::string> case_indenter_names();
std::string indenter_names_text();
// The indenter's keys as summary.json's "input" records them (type first).
nlohmann::json indenter_json(const IndenterConfig& in);
// indenter.contact_modulus, poisson, thickness: an elastic indenter's body (c.indenter.body).
void read_indenter_body(Section& ind, Config& c);
// indenter.waviness_amplitude, waviness_wavelength, waviness_axis: a single-wavelength roughness
// added to any type's heights.
void read_waviness(Section& ind, Config& c);
// Whether the analysis treats a topography of this kind (Topography::kind) as rough.
bool rough_indenter(const std::string& type);
// The plausibility warning's subject and the keys to check, for the case's type.
std::pair<std::string, std::string> implausible_surface_text(const Config& c, const MapReport* map);
// radius, or radius_x and radius_y (hertz, powerlaw): into c.indenter's radii; a radius_x or
// radius_y given beside a radius must equal it (summary.json's input writes all three when
// equal), a positive radius is needed. `what` names the type in the message.
void read_radii(Section& ind, Config& c, const std::string& what);
// The slope the implausibly-steep warning weighs for the case's type (IndenterType::
// plausibility_gradient, or the surface's rms gradient).
double plausibility_gradient(const Config& c, double rms_gradient);
// "%.3g" of v, for the messages of the parts.
std::string g3(double v);
// "grid.lx = ..., grid.ly = ...": the cell, for the plausibility messages.
std::string cell_text(const Config& c);

}  // namespace gfmd::config_detail
