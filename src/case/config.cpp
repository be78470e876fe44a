// A case file read into a Config: the sections in order ([grid], [indenter] and [load] here,
// the others in config_physics.cpp and config_run.cpp), their combinations, the load checks and
// command-line overrides.
#include "gfmd/case/config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <toml.hpp>

#include "config_detail.hpp"
#include "config_section.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/io/height_map.hpp"
#include "indenter_types.hpp"

namespace gfmd {

using config_detail::require_shallow_nesting;
using config_detail::require_utf8;

const std::vector<std::string> config_detail::kSections = {"grid",     "elastic",     "indenter", "load",
                                                           "friction", "interaction", "solver",   "output",
                                                           "sweep",    "stress",      "flow"};

namespace {

using config_detail::did_you_mean;
using config_detail::read_elastic;
using config_detail::read_flow;
using config_detail::read_friction;
using config_detail::read_indenter;
using config_detail::read_interaction;
using config_detail::read_output;
using config_detail::read_solver;
using config_detail::read_stress;
using config_detail::read_sweep;
using config_detail::Section;
using config_detail::where;

using config_detail::kSections;

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
    val = toml::parse(is, "--set " + spec).as_table().at("v");
  } catch (const std::exception&) {
    // A bare word is a string; it is parsed as one so that a later error about it names
    // "[--set KEY=VALUE]" as it does for any other override.
    try {
      std::istringstream is("v = " + toml::format(toml::value(text)));
      val = toml::parse(is, "--set " + spec).as_table().at("v");
    } catch (const std::exception&) {
      val = toml::value(text);  // not valid UTF-8: kept as it is, without a location
    }
  }
  if (!root.is_table()) root = toml::table{};
  auto& tbl = root.as_table();
  if (!tbl.count(sec)) tbl[sec] = toml::table{};
  if (!tbl[sec].is_table()) throw InputError("--set " + spec, "'" + sec + "' is not a table");
  auto& st = tbl[sec].as_table();
  // Keys that exclude each other: setting one replaces the others (the load; a round or an
  // elliptic indenter; a surface's rms height or gradient).
  for (const std::vector<std::vector<std::string>>& group :
       {std::vector<std::vector<std::string>>{{"load"}, {"force"}, {"pressure"}, {"approach"}},
        {{"indenter"}, {"radius"}, {"radius_x", "radius_y"}},
        {{"indenter"}, {"rms_height"}, {"rms_gradient"}}}) {
    if (sec != group[0][0]) continue;
    for (std::size_t k = 1; k < group.size(); ++k)
      if (std::find(group[k].begin(), group[k].end(), key) != group[k].end()) {
        // One axis of an ellipse given over a round indenter: the other keeps the radius.
        if (key == "radius_x" || key == "radius_y") {
          const std::string other_axis = key == "radius_x" ? "radius_y" : "radius_x";
          if (st.count("radius") && !st.count(other_axis)) st[other_axis] = st.at("radius");
        }
        for (std::size_t other = 1; other < group.size(); ++other)
          if (other != k)
            for (const std::string& o : group[other]) st.erase(o);
      }
  }
  // Another indenter type or friction law: the keys of the file's (its default where it gives
  // none) that the new one does not have go; the keys every type or law has stay.
  // part_keys(name): the part's own keys, or nullopt for a name that is not registered.
  const auto switch_part = [&](const char* section, const char* name_key, const std::string& fallback,
                               const auto& part_keys) {
    if (sec != section || key != name_key || !val.is_string()) return;
    const std::string before_name =
        st.count(key) && st.at(key).is_string() ? std::string(st.at(key).as_string()) : fallback;
    const auto before = part_keys(before_name), after = part_keys(std::string(val.as_string()));
    if (before_name == val.as_string() || !before || !after) return;
    for (const std::string& k : *before)
      if (std::find(after->begin(), after->end(), k) == after->end()) st.erase(k);
  };
  switch_part("indenter", "type", "hertz",
              [](const std::string& n) -> std::optional<std::vector<std::string>> {
                const config_detail::IndenterType* t = config_detail::find_indenter_type(n);
                return t ? std::optional(t->keys) : std::nullopt;
              });
  switch_part("friction", "law", "coulomb",
              [](const std::string& n) -> std::optional<std::vector<std::string>> {
                const FrictionLawType* t = find_friction_law(n);
                if (!t) return std::nullopt;
                std::vector<std::string> names;
                for (const FrictionLawType::Key& k : t->keys) names.push_back(k.name);
                return names;
              });
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
  read_elastic(el, c, base_dir);
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
  read_friction(fr, c);

  Section ia(root, "interaction", errors);
  read_interaction(ia, c);
  // A cap below the mean pressure leaves no solution: the load is named.
  if (c.interaction.plastic() && c.interaction.hardness > 0 && (hf || hp))
    if (const auto [key, why] = load_problem(c); !key.empty()) load.error(key, why);

  Section so(root, "solver", errors);
  read_solver(so, c);

  Section sw(root, "sweep", errors);
  read_sweep(sw, c);

  Section st(root, "stress", errors);
  read_stress(st, c);

  Section fl(root, "flow", errors);
  read_flow(fl, c);

  Section out(root, "output", errors);
  read_output(out, c);

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
    const bool active_set =
        c.visco.enabled() && c.visco.velocity != 0.0 && c.solver.visco_method != ViscoMethod::Splitting;
    const double mem = estimated_memory_bytes(c.grid, mpi::size(), !surface_made_on_slabs(c), active_set);
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
  Config c = build(root, name, base_dir);
  c.source_text = text;
  c.source_dir = base_dir;
  return c;
}

toml::value config_detail::toml_from_json(const nlohmann::json& j, const std::string& key, int depth) {
  if (depth > kMaxTomlNesting)
    throw InputError(key, "nested deeper than " + std::to_string(kMaxTomlNesting) + " levels");
  switch (j.type()) {
    case nlohmann::json::value_t::boolean:
      return toml::value(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return toml::value(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: {
      const auto u = j.get<std::uint64_t>();
      if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        throw InputError(key, "an integer beyond the 64-bit range");
      return toml::value(static_cast<std::int64_t>(u));
    }
    case nlohmann::json::value_t::number_float: {
      const double v = j.get<double>();
      if (std::isnan(v)) throw InputError(key, "must not be NaN");
      return toml::value(v);
    }
    case nlohmann::json::value_t::string:
      return toml::value(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      toml::array a;
      std::size_t i = 0;
      for (const auto& e : j)
        a.push_back(toml_from_json(e, key + "[" + std::to_string(i++) + "]", depth + 1));
      return toml::value(std::move(a));
    }
    case nlohmann::json::value_t::object: {
      toml::table t;
      for (const auto& [k, v] : j.items())
        t[k] = toml_from_json(v, key.empty() ? k : key + "." + k, depth + 1);
      return toml::value(std::move(t));
    }
    default:
      throw InputError(key.empty() ? "case" : key,
                       "not a value a case file can hold (a number, string, "
                       "boolean, list or table)");
  }
}

Config config_from_tables(const nlohmann::json& tables, const std::string& name,
                          const std::vector<std::string>& overrides, const std::string& base_dir) {
  if (!tables.is_object()) throw InputError(name, "the case must be a table of sections");
  toml::value root = config_detail::toml_from_json(tables, "", 0);
  for (const auto& o : overrides) apply_override(root, o);
  return build(root, name, base_dir);
}

Config reparse_config(const Config& base, const std::vector<std::string>& overrides) {
  if (base.source_text.empty())
    throw InputError(base.source.empty() ? "case" : base.source, "not read from a case file's text");
  return parse_config(base.source_text, base.source, overrides, base.source_dir);
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string text = read_regular_file(path, kMaxCaseFileBytes, "case file");
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_config(text, path, overrides, base.empty() ? "." : base);
}

}  // namespace gfmd
