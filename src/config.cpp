#include "gfmd/config.hpp"

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

#include "gfmd/error.hpp"
#include "gfmd/flow.hpp"

namespace gfmd {

namespace {

using Table = toml::value;

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string did_you_mean(const std::string& key, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t bd = 3;
  for (const auto& a : allowed) {
    const std::size_t d = edit_distance(key, a);
    if (d < bd) {
      bd = d;
      best = a;
    }
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::string where(const toml::value& v) {
  const auto loc = v.location();
  if (loc.file_name() == "unknown file" || loc.line() == 0) return "";
  return " [" + loc.file_name() + ":" + std::to_string(loc.line()) + "]";
}

// One [section] of the case file: typed getters that record problems instead of
// throwing, and a check that every key present was understood.
class Section {
 public:
  Section(const toml::value& root, std::string name, std::vector<std::string>& errors)
      : name_(std::move(name)), errors_(errors) {
    if (root.is_table() && root.as_table().count(name_)) {
      const toml::value& v = root.as_table().at(name_);
      if (!v.is_table()) {
        errors_.push_back(name_ + ": must be a table [" + name_ + "]" + where(v));
      } else {
        tbl_ = &v;
      }
    }
  }
  [[nodiscard]] bool present() const { return tbl_ != nullptr; }
  bool has(const std::string& key) {
    allowed_.push_back(key);
    return tbl_ && tbl_->as_table().count(key);
  }
  const toml::value* raw(const std::string& key) {
    if (!has(key)) return nullptr;
    return &tbl_->as_table().at(key);
  }
  double number(const std::string& key, double def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_floating()) return v->as_floating();
    if (v->is_integer()) return static_cast<double>(v->as_integer());
    error(key, "must be a number, got " + type_name(*v) + where(*v));
    return def;
  }
  // A number that may also be "inf"/"infinity" (string or TOML inf).
  double number_or_inf(const std::string& key, double def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_string()) {
      std::string s = v->as_string();
      std::transform(s.begin(), s.end(), s.begin(), ::tolower);
      if (s == "inf" || s == "infinity" || s == "infinite") return std::numeric_limits<double>::infinity();
      error(key, "must be a number or \"inf\", got \"" + std::string(v->as_string()) + "\"" + where(*v));
      return def;
    }
    return number(key, def);
  }
  long long integer(const std::string& key, long long def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_integer()) return v->as_integer();
    if (v->is_floating() && std::floor(v->as_floating()) == v->as_floating() &&
        std::abs(v->as_floating()) < 1e15)
      return static_cast<long long>(v->as_floating());
    error(key, "must be an integer, got " + type_name(*v) + where(*v));
    return def;
  }
  bool boolean(const std::string& key, bool def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_boolean()) return v->as_boolean();
    error(key, "must be true or false, got " + type_name(*v) + where(*v));
    return def;
  }
  std::string string(const std::string& key, const std::string& def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_string()) return v->as_string();
    error(key, "must be a string, got " + type_name(*v) + where(*v));
    return def;
  }
  int line(const std::string& key) const {
    if (!tbl_ || !tbl_->as_table().count(key)) return 0;
    return static_cast<int>(tbl_->as_table().at(key).location().line());
  }
  std::string at(const std::string& key) const {
    if (!tbl_ || !tbl_->as_table().count(key)) return "";
    return where(tbl_->as_table().at(key));
  }
  void error(const std::string& key, const std::string& why) {
    errors_.push_back(name_ + "." + key + ": " + why);
  }
  // Keys in the file that no getter asked for.
  void finish(const std::vector<std::string>& also_allowed = {}) {
    if (!tbl_) return;
    std::vector<std::string> allowed = allowed_;
    allowed.insert(allowed.end(), also_allowed.begin(), also_allowed.end());
    std::vector<std::string> keys;
    for (const auto& kv : tbl_->as_table()) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());
    for (const auto& k : keys)
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        errors_.push_back(name_ + "." + k + ": unknown key" + did_you_mean(k, allowed) +
                          where(tbl_->as_table().at(k)));
  }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  static std::string type_name(const toml::value& v) {
    std::ostringstream os;
    os << v.type();
    return os.str();
  }
  std::string name_;
  std::vector<std::string>& errors_;
  const toml::value* tbl_ = nullptr;
  std::vector<std::string> allowed_;
};

const std::vector<std::string> kSections = {"grid",     "elastic",     "indenter", "load",
                                            "friction", "interaction", "solver",   "output",
                                            "sweep",    "stress",      "flow"};

void apply_override(toml::value& root, const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set " + spec, "expected section.key=value");
  const std::string path = spec.substr(0, eq), text = spec.substr(eq + 1);
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw InputError("--set " + spec, "expected section.key=value");
  const std::string sec = path.substr(0, dot), key = path.substr(dot + 1);
  toml::value val;
  try {
    std::istringstream is("v = " + text);
    val = toml::parse(is, "--set").as_table().at("v");
  } catch (const std::exception&) {
    val = toml::value(text);  // a bare word: a string
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

  Section grid(root, "grid", errors);
  if (!grid.present()) errors.push_back("grid: missing section [grid] (nx, lx at least)");
  const long long nx = grid.integer("nx", 0);
  const long long ny = grid.integer("ny", nx);
  c.grid.lx = grid.number("lx", 0.0);
  c.grid.ly = grid.number("ly", c.grid.lx);
  if (nx < 2 || nx > (1 << 16))
    grid.error("nx", "must be an integer in [2, 65536], got " + std::to_string(nx));
  if (ny < 2 || ny > (1 << 16))
    grid.error("ny", "must be an integer in [2, 65536], got " + std::to_string(ny));
  c.grid.nx = static_cast<int>(std::clamp<long long>(nx, 0, 1 << 16));
  c.grid.ny = static_cast<int>(std::clamp<long long>(ny, 0, 1 << 16));
  if (!(c.grid.lx > 0) || !std::isfinite(c.grid.lx)) grid.error("lx", "must be a positive length");
  if (!(c.grid.ly > 0) || !std::isfinite(c.grid.ly)) grid.error("ly", "must be a positive length");
  grid.finish();

  Section el(root, "elastic", errors);
  c.elastic.contact_modulus = el.number("contact_modulus", 1.0);
  c.elastic.poisson = el.number("poisson", 0.25);
  c.elastic.thickness = el.number_or_inf("thickness", std::numeric_limits<double>::infinity());
  c.elastic.coupling = el.boolean("coupling", true);
  el.finish();
  try {
    c.elastic.validate();
  } catch (const InputError& e) {
    const std::string key = e.where().substr(e.where().find('.') + 1);
    errors.push_back(e.where() + ": " + e.why() + el.at(key));
  }

  Section ind(root, "indenter", errors);
  if (!ind.present()) errors.push_back("indenter: missing section [indenter] (type = \"hertz\", ...)");
  IndenterConfig& in = c.indenter;
  in.type = ind.string("type", "hertz");
  const std::vector<std::string> types = {"hertz", "eggcrate", "selfaffine", "file"};
  std::vector<std::string> extra;
  if (std::find(types.begin(), types.end(), in.type) == types.end()) {
    ind.error("type", "unknown indenter type \"" + in.type + "\"" + did_you_mean(in.type, types) +
                          "; one of hertz, eggcrate, selfaffine, file" + ind.at("type"));
    extra = {"radius", "radius_x",       "radius_y",     "wavelength", "amplitude",
             "hurst",  "lambda_long",    "lambda_short", "rms_height", "rms_gradient",
             "seed",   "lambda_rolloff", "path",         "lx",         "ly"};
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
    const long long seed = ind.integer("seed", 0);
    if (seed < 0) ind.error("seed", "must be a non-negative integer");
    s.seed = static_cast<std::uint64_t>(std::max<long long>(seed, 0));
    if ((s.rms_height > 0) == (s.rms_gradient > 0))
      ind.error("rms_height", "give exactly one of rms_height and rms_gradient (positive)");
  } else if (in.type == "file") {
    in.path = ind.string("path", "");
    if (in.path.empty()) {
      ind.error("path", "a file indenter needs path = \"heights.txt\" (text matrix or NetCDF)");
    } else if (!std::filesystem::path(in.path).is_absolute()) {
      in.path = (std::filesystem::path(base_dir) / in.path).lexically_normal().string();
    }
  }
  ind.finish(extra);

  Section load(root, "load", errors);
  const bool hf = load.has("force"), hp = load.has("pressure"), ha = load.has("approach");
  if (int(hf) + int(hp) + int(ha) != 1) {
    errors.push_back("load: give exactly one of force, pressure, approach");
  }
  if (hf) {
    c.load = {LoadMode::Force, load.number("force", 0.0)};
    if (!(c.load.value > 0)) load.error("force", "must be positive" + load.at("force"));
  } else if (hp) {
    c.load = {LoadMode::Pressure, load.number("pressure", 0.0)};
    if (!(c.load.value > 0)) load.error("pressure", "must be positive" + load.at("pressure"));
  } else if (ha) {
    c.load = {LoadMode::Approach, load.number("approach", 0.0)};
    if (!(c.load.value >= 0)) load.error("approach", "must be zero or positive" + load.at("approach"));
  }
  load.finish();

  Section fr(root, "friction", errors);
  c.friction.coefficient = fr.number("coefficient", 0.0);
  c.friction.direction_deg = fr.number("direction", 0.0);
  c.friction.regularization = fr.number("regularization", 0.0);
  if (!(c.friction.regularization >= 0 && c.friction.regularization < 1))
    fr.error("regularization", "must be in [0, 1) (slip speed / v0 below which the traction is regularised)");
  if (!(c.friction.coefficient >= 0) || !std::isfinite(c.friction.coefficient))
    fr.error("coefficient", "must be a non-negative number" + fr.at("coefficient"));
  if (!std::isfinite(c.friction.direction_deg)) fr.error("direction", "must be finite (degrees from +x)");
  c.friction.creepage = fr.number("creepage", 1.0);
  if (!(c.friction.creepage > 0) || !std::isfinite(c.friction.creepage))
    fr.error("creepage",
             "must be a positive finite number (rigid slip speed / v0; 1 = sliding)" + fr.at("creepage"));
  else if (c.friction.creepage != 1.0 && !(c.friction.coefficient > 0))
    fr.error("creepage",
             "rolling with creepage needs friction: set friction.coefficient > 0" + fr.at("creepage"));
  c.friction.stick_step = fr.number("stick_step", 0.0);
  if (!(c.friction.stick_step >= 0) || !std::isfinite(c.friction.stick_step) || c.friction.stick_step > 1e6)
    fr.error("stick_step",
             "must be 0 (automatic) or a positive step gamma/E* up to 1e6" + fr.at("stick_step"));
  c.friction_reference = fr.boolean("reference", true);
  fr.finish();

  Section ia(root, "interaction", errors);
  const std::string model = ia.string("model", "harmonic");
  if (model == "harmonic") {
    c.interaction.hard_wall = false;
  } else if (model == "hardwall" || model == "hard_wall") {
    c.interaction.hard_wall = true;
  } else {
    ia.error("model", "unknown model \"" + model + "\"; one of harmonic, hardwall" + ia.at("model"));
  }
  c.interaction.stiffness = ia.number("stiffness", 0.0);
  if (c.interaction.stiffness < 0) ia.error("stiffness", "must be positive (0 = default 2 E*/dx)");
  ia.finish();

  Section so(root, "solver", errors);
  c.solver.tolerance = so.number("tolerance", 1e-8);
  c.solver.max_iterations = static_cast<int>(so.integer("max_iterations", 20000));
  c.solver.max_outer = static_cast<int>(so.integer("max_outer", 2000));
  {
    const auto mt = so.integer("max_tangential", 20000);
    if (mt < 1 || mt > 100000000) so.error("max_tangential", "must be in [1, 1e8]" + so.at("max_tangential"));
    c.solver.max_tangential = static_cast<int>(std::clamp<decltype(mt)>(mt, 1, 100000000));
  }
  c.solver.anderson = static_cast<int>(so.integer("anderson", 10));
  c.solver.mixing = so.number("mixing", 0.5);
  if (!(c.solver.mixing > 0 && c.solver.mixing <= 1)) so.error("mixing", "must be in (0, 1]");
  if (c.solver.anderson < 0 || c.solver.anderson > 50) so.error("anderson", "must be in [0, 50]");
  c.threads = static_cast<int>(so.integer("threads", 0));
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
  if (c.solver.max_iterations < 1) so.error("max_iterations", "must be at least 1");
  if (c.solver.max_outer < 1) so.error("max_outer", "must be at least 1");
  if (c.threads < 0) so.error("threads", "must be >= 0 (0 = all cores)");
  so.finish();

  Section sw(root, "sweep", errors);
  if (sw.present()) {
    c.sweep.parameter = sw.string("parameter", "");
    c.sweep.plot = sw.string("plot", c.sweep.plot);
    if (const toml::value* v = sw.raw("values")) {
      if (!v->is_array()) {
        sw.error("values", "must be an array of numbers" + where(*v));
      } else {
        for (const auto& e : v->as_array()) {
          if (e.is_floating())
            c.sweep.values.push_back(e.as_floating());
          else if (e.is_integer())
            c.sweep.values.push_back(static_cast<double>(e.as_integer()));
          else
            sw.error("values", "must be an array of numbers" + where(e));
        }
      }
    }
    const double from = sw.number("from", 0.0), to = sw.number("to", 0.0);
    const long long points = sw.integer("points", 0);
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
  c.stress.post_analysis = st.boolean("post_analysis", false);
  c.stress.high_tension_fraction = st.number("high_tension_fraction", 0.9);
  c.stress.profiles = st.boolean("profiles", true);
  if (!(c.stress.high_tension_fraction > 0 && c.stress.high_tension_fraction <= 1))
    st.error("high_tension_fraction", "must be in (0, 1]");
  if (const toml::value* v = st.raw("depths")) {
    if (!v->is_array()) {
      st.error("depths", "must be an array of depths below the surface" + where(*v));
    } else {
      for (const auto& e : v->as_array()) {
        const double d = e.is_floating()  ? e.as_floating()
                         : e.is_integer() ? static_cast<double>(e.as_integer())
                                          : -1.0;
        if (!(d >= 0) || (!c.elastic.half_space() && d > c.elastic.thickness))
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
    const std::string dir = fl.string("direction", "both");
    c.flow.angles = parse_flow_directions(dir);
    if (c.flow.angles.empty())
      fl.error("direction", "must be \"x\", \"y\", \"both\" or an angle in degrees, got \"" + dir + "\"");
  }
  fl.finish();

  Section out(root, "output", errors);
  c.output.fields = out.boolean("fields", true);
  c.output.png = out.boolean("png", true);
  out.finish();

  // Combinations.
  if (errors.empty()) {
    if (c.indenter.type == "hertz" && c.load.mode == LoadMode::Force) {
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
    const double mem = estimated_memory_bytes(c.grid);
    const double phys =
        static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    if (phys > 0 && mem > 0.8 * phys) {
      std::ostringstream os;
      os << "a " << c.grid.nx << " x " << c.grid.ny << " grid needs about " << mem / 1e9
         << " GB, more than 80% of this machine's " << phys / 1e9 << " GB";
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

double estimated_memory_bytes(const Grid& grid) {
  // Peak of a sliding solve (BENCHMARKS.md, memory budget): topography, pressure and two
  // tractions, g0, w, the traction image, three CG fields (11 real fields), three complex
  // half-spectra, the compliance tables (56 B/mode) and the Anderson history on the
  // traction's support (196 B per support point; allowance: half the grid in contact).
  const double n = static_cast<double>(grid.size());
  const double ns = static_cast<double>(grid.spectral_size());
  return n * (8.0 * 11.0 + 0.5 * 196.0) + ns * (3.0 * 16.0 + 56.0);
}

namespace {
// TOML is UTF-8 text. Checking it first also keeps malformed bytes away from toml11
// (3.7 reads past the end of some invalid sequences; found by fuzz/fuzz_config).
void require_utf8(const std::string& s, const std::string& name) {
  std::size_t i = 0, line = 1;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = 0;
    if (c == '\n') ++line;
    if (c < 0x80) {
      len = 1;
      if (c == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c == 0x7f)
        throw InputError(name + ":" + std::to_string(line), "control character in the case file");
    } else if ((c & 0xe0) == 0xc0 && c >= 0xc2) {
      len = 2;
    } else if ((c & 0xf0) == 0xe0) {
      len = 3;
    } else if ((c & 0xf8) == 0xf0 && c <= 0xf4) {
      len = 4;
    } else {
      throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    }
    if (i + len > s.size()) throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    for (std::size_t k = 1; k < len; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80)
        throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    i += len;
  }
}
}  // namespace

Config parse_config(const std::string& text, const std::string& name,
                    const std::vector<std::string>& overrides, const std::string& base_dir) {
  require_utf8(text, name);
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
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open the case file");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_config(ss.str(), path, overrides, base.empty() ? "." : base);
}

nlohmann::json Config::to_json() const {
  nlohmann::json j;
  j["grid"] = {{"nx", grid.nx}, {"ny", grid.ny}, {"lx", grid.lx}, {"ly", grid.ly}};
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
  } else {
    ind["path"] = indenter.path;
  }
  j["indenter"] = ind;
  const char* lk = load.mode == LoadMode::Force      ? "force"
                   : load.mode == LoadMode::Pressure ? "pressure"
                                                     : "approach";
  j["load"] = {{lk, load.value}};
  j["friction"] = {{"coefficient", friction.coefficient},       {"direction", friction.direction_deg},
                   {"regularization", friction.regularization}, {"creepage", friction.creepage},
                   {"stick_step", friction.stick_step},         {"reference", friction_reference}};
  j["interaction"] = {{"model", interaction.hard_wall ? "hardwall" : "harmonic"},
                      {"stiffness", interaction.stiffness}};
  j["solver"] = {{"tolerance", solver.tolerance},
                 {"max_iterations", solver.max_iterations},
                 {"max_outer", solver.max_outer},
                 {"max_tangential", solver.max_tangential},
                 {"anderson", solver.anderson},
                 {"mixing", solver.mixing},
                 {"fft_planner", solver.fft_planner == Planner::Measure ? "measure" : "estimate"},
                 {"threads", threads}};
  j["output"] = {{"fields", output.fields}, {"png", output.png}};
  j["stress"] = {{"post_analysis", stress.post_analysis},
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

Topography make_topography(const Config& c) {
  const IndenterConfig& in = c.indenter;
  if (in.type == "hertz") return make_hertz(c.grid, in.radius_x, in.radius_y);
  if (in.type == "eggcrate") return make_eggcrate(c.grid, in.wavelength, in.amplitude);
  if (in.type == "selfaffine") return make_selfaffine(c.grid, in.selfaffine);
  Topography t = read_topography(in.path, c.grid.lx, c.grid.ly);
  if (t.grid.nx != c.grid.nx || t.grid.ny != c.grid.ny) {
    std::ostringstream os;
    os << "the height map is " << t.grid.nx << " x " << t.grid.ny << " but [grid] asks for " << c.grid.nx
       << " x " << c.grid.ny;
    throw InputError(in.path, os.str());
  }
  return t;
}

}  // namespace gfmd
