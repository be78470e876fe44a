// Load curves: area, gap, friction and leakage against the mean pressure, and the
// percolation threshold. See include/gfmd/studies/curve.hpp.
#include "gfmd/studies/curve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>

#include "gfmd/case/leakage.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPointsDir = "points";

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// A whole token as a double (no trailing characters); nullopt otherwise.
std::optional<double> to_number(const std::string& tok) {
  if (tok.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(tok.c_str(), &end);
  if (end != tok.c_str() + tok.size()) return std::nullopt;
  return v;
}

// The point's load as the sweep passes it on (%.17g reads back exactly).
std::string load_override(const std::string& parameter, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "=%.17g", v);
  return parameter + buf;
}

std::string csv_number(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_float()) return format_number(v.get<double>());
  return v.dump();
}

// The leakage's direction tags (x, y, <angle>deg) in the case's order.
std::vector<std::string> direction_tags(const Config& cfg) {
  std::vector<std::string> tags;
  for (double a : cfg.flow.angles) tags.push_back(direction_tag(a));
  return tags;
}

// One row of curve.csv from a point's summary.json.
nlohmann::json curve_row(const nlohmann::json& p, const std::string& branch, const nlohmann::json& s,
                         const std::vector<std::string>& tags) {
  const auto get = [&s](const char* k) { return s.contains(k) ? s[k] : nlohmann::json(); };
  nlohmann::json row = nlohmann::json::object();
  row["branch"] = branch;
  row["pressure"] = p;
  row["normal_force"] = get("normal_force");
  row["adhesive_force"] = get("adhesive_force");
  row["relative_contact_area"] = get("relative_contact_area");
  row["mean_gap"] = get("mean_gap");
  row["approach"] = get("approach");
  row["friction_coefficient"] = get("friction_coefficient");
  row["friction_coefficient_downhill"] = get("friction_coefficient_downhill");
  const nlohmann::json flow = s.contains("flow") ? s["flow"] : nlohmann::json::object();
  bool open = false;
  for (const auto& t : tags) {
    const auto f = [&flow](const std::string& k) { return flow.contains(k) ? flow[k] : nlohmann::json(); };
    row["conductivity_" + t] = f("conductivity_" + t);
    row["flow_factor_" + t] = f("flow_factor_" + t);
    const bool perc = flow.value("percolates_" + t, false);
    row["percolates_" + t] = perc;
    open = open || perc;
  }
  row["open"] = open;
  row["iterations"] = get("iterations");
  return row;
}

std::vector<std::string> curve_columns(const std::vector<std::string>& tags) {
  std::vector<std::string> c = {"pressure", "relative_contact_area", "mean_gap",
                                "approach", "friction_coefficient",  "friction_coefficient_downhill"};
  for (const auto& t : tags) {
    c.push_back("conductivity_" + t);
    c.push_back("flow_factor_" + t);
    c.push_back("percolates_" + t);
  }
  c.emplace_back("open");
  c.emplace_back("iterations");
  // Added for approach paths (adhesion), after the columns older tables have.
  for (const char* k : {"branch", "normal_force", "adhesive_force"}) c.emplace_back(k);
  return c;
}

nlohmann::json column_meanings(const std::vector<std::string>& tags) {
  nlohmann::json m = {
      {"branch", "load (the load or approach grows from the previous point) or unload (it falls)"},
      {"pressure",
       "mean pressure (E*): imposed (pressures), or the solution's (approaches; negative in tension)"},
      {"normal_force", "net normal force on the indenter (E* length^2; negative in tension)"},
      {"adhesive_force", "adhesive pull sum a dA (E* length^2); empty without adhesion"},
      {"relative_contact_area", "contact area fraction A/A0 (1)"},
      {"mean_gap", "mean gap between indenter and deformed surface (length)"},
      {"approach", "indenter displacement towards the body from first touch (length; imposed by approaches)"},
      {"friction_coefficient", "friction coefficient mu from the dissipation (1); empty when frictionless"},
      {"friction_coefficient_downhill", "mu from mu_c F + downhill force (1); empty when frictionless"},
      {"open", "1 if the gap percolates along any direction (leakage > 0), else 0"},
      {"iterations", "iterations of the contact solve"}};
  for (const auto& t : tags) {
    m["conductivity_" + t] = "leakage: effective conductivity K_eff = <current . d>/|grad p| along " + t +
                             " with local conductivity g^3 (length^3); 0 when sealed";
    m["flow_factor_" + t] = "K_eff / <g>^3 along " + t + " (1)";
    m["percolates_" + t] = "1 if the open gap wraps around the cell along " + t + ", else 0";
  }
  return m;
}

// The summaries of the curve's finished points, in order, up to the first one missing.
std::vector<nlohmann::json> finished_points(const Config& cfg, const std::vector<std::string>& user_sets,
                                            const std::string& pdir) {
  std::vector<nlohmann::json> out;
  std::vector<std::string> sets = user_sets;
  for (const auto& s : curve_overrides()) sets.push_back(s);
  sets.emplace_back();
  for (std::size_t i = 0; i < cfg.sweep.values.size(); ++i) {
    sets.back() = load_override(cfg.sweep.parameter, cfg.sweep.values[i]);
    auto s = finished_summary((fs::path(pdir) / sweep_point_name(i)).string(), reparse_config(cfg, sets));
    if (!s) break;
    out.push_back(std::move(*s));
  }
  return out;
}

nlohmann::json write_curve_tables(const std::string& case_path, const Config& cfg, const std::string& dir,
                                  const std::vector<std::string>& user_sets) {
  const std::string pdir = (fs::path(dir) / kPointsDir).string();
  const std::vector<nlohmann::json> summaries = finished_points(cfg, user_sets, pdir);
  const std::vector<std::string> tags = direction_tags(cfg);
  const std::vector<std::string> cols = curve_columns(tags);
  const std::vector<double>& ps = cfg.sweep.values;

  std::ostringstream csv;
  for (std::size_t k = 0; k < cols.size(); ++k) csv << (k ? "," : "") << cols[k];
  csv << "\n";
  nlohmann::json points = nlohmann::json::array();
  std::vector<double> pressures, areas;
  std::vector<bool> open;
  const bool by_approach = cfg.sweep.parameter == "load.approach";
  const std::vector<std::string> branches = curve_branches(ps);
  // The pull-off: the most tensile force on the path (an approach-controlled path passes the
  // force minimum before it jumps off), and where the unloading branch lost contact.
  nlohmann::json pull_off = nullptr, pull_off_approach = nullptr, jump_off_approach = nullptr;
  double fmin = 0.0;
  std::size_t imin = 0;
  bool contact_before = false;
  for (std::size_t i = 0; i < summaries.size(); ++i) {
    const nlohmann::json& si = summaries[i];
    const nlohmann::json p =
        by_approach ? si.value("mean_pressure", nlohmann::json()) : nlohmann::json(ps[i]);
    const nlohmann::json row = curve_row(p, branches[i], si, tags);
    for (std::size_t k = 0; k < cols.size(); ++k) csv << (k ? "," : "") << csv_number(row[cols[k]]);
    csv << "\n";
    points.push_back(row);
    const double area =
        row["relative_contact_area"].is_number() ? row["relative_contact_area"].get<double>() : 0.0;
    if (row["normal_force"].is_number() && row["normal_force"].get<double>() < fmin) {
      fmin = row["normal_force"].get<double>();
      pull_off = fmin;
      pull_off_approach = row["approach"];
      imin = i;
    }
    if (branches[i] == "unload" && contact_before && !(area > 0) && jump_off_approach.is_null())
      jump_off_approach = ps[i];
    contact_before = area > 0;
    // The percolation threshold over the loading branch at positive pressures (ascending).
    if (branches[i] != "load" || !p.is_number() || !(p.get<double>() > 0)) continue;
    if (!pressures.empty() && !(p.get<double>() > pressures.back())) continue;
    pressures.push_back(p.get<double>());
    areas.push_back(area);
    open.push_back(row["open"].get<bool>());
  }

  nlohmann::json j;
  j["case"] = case_path;
  j["overrides"] = user_sets;
  j["curve_overrides"] = curve_overrides();
  j["curve_overrides"].push_back(by_approach ? "load.approach=<each approach>"
                                             : "load.pressure=<each pressure>");
  j["parameter"] = cfg.sweep.parameter;
  // What the case itself asks for, without the curve's overrides.
  const Config asked = load_config(case_path, user_sets);
  j["leakage_switched_on"] = !asked.flow.enabled;
  const LoadMode own = by_approach ? LoadMode::Approach : LoadMode::Pressure;
  if (asked.load.mode == own)
    j["load_replaced"] = nullptr;
  else
    j["load_replaced"] = std::string(asked.load.mode == LoadMode::Force      ? "load.force"
                                     : asked.load.mode == LoadMode::Pressure ? "load.pressure"
                                                                             : "load.approach") +
                         " = " + format_number(asked.load.value);
  j[by_approach ? "approaches" : "pressures"] = ps;
  j["pull_off_force"] = pull_off;
  j["pull_off_approach"] = pull_off_approach;
  j["jump_off_approach"] = jump_off_approach;
  // The most tensile force at the path's last point or where it turns back (the last loading
  // point of a load-unload path) need not be the pull-off: the force may fall further beyond.
  j["pull_off_at_path_end"] = pull_off.is_null() ? nlohmann::json()
                                                 : nlohmann::json(imin + 1 == summaries.size() ||
                                                                  branches[imin + 1] != branches[imin]);
  j["pull_off_note"] =
      "pull_off_force: the most tensile normal force on the path (null if none is tensile); an "
      "approach-controlled path resolves it to its point spacing; pull_off_at_path_end: it is the path's "
      "last "
      "point or its turning point, where the force may fall further (extend the path). jump_off_approach: "
      "the "
      "first unloading point without contact (null if contact never ended while unloading)";
  j["completed"] = summaries.size();
  j["total"] = ps.size();
  j["columns"] = column_meanings(tags);
  j["column_order"] = cols;
  j["points"] = points;
  nlohmann::json perc = curve_threshold(pressures, areas, open);
  if (by_approach && pressures.empty() && !summaries.empty())
    perc["message"] =
        "no point of the loading branch at a positive mean pressure (the threshold is sought there)";
  perc["criterion"] =
      "the leakage stops: the open gap (g > 0) wraps around the cell along no direction, i.e. the contact "
      "percolates";
  perc["directions"] = nlohmann::json::object();
  for (const auto& t : tags) {
    std::vector<bool> o;
    for (const auto& row : points) o.push_back(row["percolates_" + t].get<bool>());
    perc["directions"][t] = curve_threshold(pressures, areas, o);
  }
  j["percolation"] = perc;
  j["points_dir"] = kPointsDir;
  j["units"] =
      "lengths in the unit of grid.lx; pressures in the unit of elastic.contact_modulus (E*); conductivity "
      "in length^3";
  if (!summaries.empty() && summaries.front().contains("input"))
    j["input_first_point"] = summaries.front()["input"];
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  write_text_atomic((fs::path(dir) / "curve.csv").string(), csv.str());
  write_text_atomic((fs::path(dir) / "curve.json").string(), j.dump(2) + "\n");
  return j;
}

// A list of values from text (parse_pressures, parse_approaches): comma-separated items, each a
// number or FROM:TO:N, N values from FROM to TO (both included) log-spaced (pressures: FROM and
// TO positive) or evenly spaced (approaches: any finite values). Errors name `key`.
struct ValueList {
  const char* key;      // "pressures" or "approaches"
  const char* one;      // "pressure" or "approach"
  const char* example;  // "P1,P2,..."
  bool log_spaced;      // pressures' ranges; approaches' are linear and their values finite
};
std::vector<double> parse_value_list(const std::string& text, const ValueList& l) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  const auto bad = [&l](const std::string& why) { throw InputError(l.key, why); };
  if (trim(text).empty()) bad(std::string("give at least one ") + l.one + ": " + l.example + " or FROM:TO:N");
  if (trim(text).back() == ',') bad("an empty item in '" + text + "' (two commas, or one at an end)");
  const std::string spacing = l.log_spaced ? "log-spaced" : "evenly spaced";
  while (std::getline(ss, item, ',')) {
    item = trim(item);
    if (item.empty()) bad("an empty item in '" + text + "' (two commas, or one at an end)");
    if (item.find(':') == std::string::npos) {
      const auto v = to_number(item);
      // Pressures are checked as a whole later (curve_pressures); approaches here.
      if (!v || (!l.log_spaced && !std::isfinite(*v)))
        bad("'" + item + "' is not " + (l.log_spaced ? "a number" : "a finite number"));
      out.push_back(*v);
      continue;
    }
    std::vector<std::string> parts;
    std::stringstream is(item);
    std::string part;
    while (std::getline(is, part, ':')) parts.push_back(trim(part));
    if (parts.size() != 3 || item.back() == ':')
      bad("'" + item + "': a range is FROM:TO:N (N " + spacing + " values from FROM to TO)");
    const auto from = to_number(parts[0]), to = to_number(parts[1]);
    const auto n = to_number(parts[2]);
    if (l.log_spaced) {
      if (!from || !to || !n) bad("'" + item + "': FROM, TO and N must be numbers");
      if (!(*from > 0 && *to > 0 && std::isfinite(*from) && std::isfinite(*to)))
        bad("'" + item + "': a log-spaced range needs positive, finite FROM and TO");
    } else if (!from || !to || !n || !std::isfinite(*from) || !std::isfinite(*to)) {
      bad("'" + item + "': FROM and TO must be finite numbers and N a number");
    }
    if (!(*n >= 2 && *n <= static_cast<double>(kMaxSweepPoints) && *n == std::floor(*n)))
      bad("'" + item + "': N must be an integer in [2, " + std::to_string(kMaxSweepPoints) + "]");
    const int count = static_cast<int>(*n);
    if (out.size() + static_cast<std::size_t>(count) > static_cast<std::size_t>(kMaxSweepPoints))
      bad("more than " + std::to_string(kMaxSweepPoints) + " " + l.key);
    for (int i = 0; i < count; ++i) {
      if (i == 0 || i == count - 1) {
        out.push_back(i == 0 ? *from : *to);
      } else if (l.log_spaced) {
        out.push_back(*from * std::pow(*to / *from, static_cast<double>(i) / (count - 1)));
      } else {
        out.push_back(*from + (*to - *from) * static_cast<double>(i) / (count - 1));
      }
    }
  }
  return out;
}

}  // namespace

std::vector<double> parse_pressures(const std::string& text) {
  return parse_value_list(text, {"pressures", "pressure", "P1,P2,...", true});
}

std::vector<double> curve_pressures(std::vector<double> ps) {
  if (ps.empty()) throw InputError("pressures", "give at least one pressure");
  if (ps.size() > static_cast<std::size_t>(kMaxSweepPoints))
    throw InputError("pressures", "at most " + std::to_string(kMaxSweepPoints) + " pressures, got " +
                                      std::to_string(ps.size()));
  for (double p : ps)
    if (!(p > 0) || !std::isfinite(p))
      throw InputError("pressures", "every pressure must be positive and finite, got " + format_number(p));
  std::sort(ps.begin(), ps.end());
  for (std::size_t i = 1; i < ps.size(); ++i)
    if (ps[i] == ps[i - 1])
      throw InputError("pressures", "the pressure " + format_number(ps[i]) + " is given twice");
  return ps;
}

std::vector<double> parse_approaches(const std::string& text) {
  return parse_value_list(text, {"approaches", "approach", "D1,D2,...", false});
}

std::vector<double> approach_path(std::vector<double> approaches, bool unload) {
  if (approaches.empty()) throw InputError("approaches", "give at least one approach");
  if (unload)
    for (std::size_t k = approaches.size() - 1; k-- > 0;) approaches.push_back(approaches[k]);
  if (approaches.size() > static_cast<std::size_t>(kMaxSweepPoints))
    throw InputError("approaches", "at most " + std::to_string(kMaxSweepPoints) + " points, got " +
                                       std::to_string(approaches.size()));
  return approaches;
}

std::vector<std::string> curve_branches(const std::vector<double>& values) {
  std::vector<std::string> b(values.size(), "load");
  for (std::size_t i = 1; i < values.size(); ++i)
    b[i] = values[i] < values[i - 1] ? "unload" : values[i] > values[i - 1] ? "load" : b[i - 1];
  return b;
}

std::vector<std::string> curve_overrides() { return {"flow.enabled=true", "output.png=false"}; }

namespace {
// The user's overrides checked (the curve sets the load, named by `load`, and needs the flow),
// followed by curve_overrides().
std::vector<std::string> curve_sets(const std::vector<std::string>& overrides, const std::string& load) {
  for (const auto& s : overrides) {
    const auto eq = s.find('=');
    const std::string key = trim(s.substr(0, eq));
    if (key.rfind("load.", 0) == 0)
      throw InputError("--set " + s, "the curve sets the load itself (" + load + ")");
    if (key == "flow.enabled" && (eq == std::string::npos || trim(s.substr(eq + 1)) != "true"))
      throw InputError("--set " + s, "the curve needs the leakage: it switches the flow on itself");
  }
  std::vector<std::string> sets = overrides;
  for (const auto& s : curve_overrides()) sets.push_back(s);
  return sets;
}
}  // namespace

Config curve_config(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::vector<double>& pressures_in) {
  const std::vector<double> pressures = curve_pressures(pressures_in);
  const std::vector<std::string> sets = curve_sets(overrides, "load.pressure from the pressures");
  // The pressures against this case's E* before any is applied (the case's own load stands
  // in: a pressure above the limit would otherwise be reported as the key load.pressure).
  Config probe = load_config(case_path, sets);
  const double limit = kMaxPressureOverModulus * probe.elastic.contact_modulus;
  if (pressures.back() > limit)
    throw InputError("pressures", "the pressure " + format_number(pressures.back()) + " exceeds 1000 E* (" +
                                      format_number(limit) + "): not a contact problem");
  // Each pressure against the case (e.g. below interaction.hardness), named as the option,
  // before the curve's directory is made.
  for (double p : pressures) {
    probe.load = {LoadMode::Pressure, p};
    if (const auto [key, why] = load_problem(probe); !key.empty())
      throw InputError("pressures", "the pressure " + format_number(p) + ": " + why);
  }
  return sweep_config(case_path, sets, "load.pressure", pressures);
}

Config curve_config_approaches(const std::string& case_path, const std::vector<std::string>& overrides,
                               const std::vector<double>& path) {
  const std::vector<std::string> sets = curve_sets(overrides, "load.approach from the approaches");
  // Each approach against the case (negative ones need adhesion), named as the option.
  Config probe = load_config(case_path, sets);
  for (double d : path) {
    probe.load = {LoadMode::Approach, d};
    if (const auto [key, why] = load_problem(probe); !key.empty())
      throw InputError("approaches", "the approach " + format_number(d) + ": " + why);
  }
  return sweep_config(case_path, sets, "load.approach", path);
}

nlohmann::json curve_threshold(const std::vector<double>& p, const std::vector<double>& a,
                               const std::vector<bool>& open) {
  nlohmann::json j;
  j["reached"] = false;
  j["pressure"] = nullptr;
  j["relative_contact_area"] = nullptr;
  j["bracket"] = nullptr;
  const std::size_t n = std::min({p.size(), a.size(), open.size()});
  bool monotonic = true;
  for (std::size_t i = 1; i < n; ++i)
    if (open[i] && !open[i - 1]) monotonic = false;
  j["monotonic"] = monotonic;
  j["method"] =
      "midpoint on a log axis (geometric mean) of the last open and the first sealed pressure; contact area "
      "interpolated linearly in log p";
  if (n == 0) {
    j["status"] = "no_points";
    j["message"] = "no finished points";
    return j;
  }
  const std::string range = format_number(p.front()) + " .. " + format_number(p[n - 1]);
  // The last open point; the threshold lies between it and the next (sealed) one.
  std::size_t last_open = n;
  for (std::size_t i = 0; i < n; ++i)
    if (open[i]) last_open = i;
  if (last_open == n) {
    j["status"] = "sealed_throughout";
    j["message"] = "not reached in the range " + range +
                   ": the gap is already sealed at the smallest pressure (the threshold lies below " +
                   format_number(p.front()) + ")";
    return j;
  }
  if (last_open == n - 1) {
    j["status"] = "not_reached";
    j["message"] = "not reached in the range " + range +
                   ": the gap still leaks at the largest pressure (the threshold lies above " +
                   format_number(p[n - 1]) + ")";
    return j;
  }
  const std::size_t lo = last_open, hi = last_open + 1;
  const double ps = std::sqrt(p[lo] * p[hi]);
  const double t = std::log(ps / p[lo]) / std::log(p[hi] / p[lo]);
  const double as = a[lo] + t * (a[hi] - a[lo]);
  j["status"] = "bracketed";
  j["reached"] = true;
  j["pressure"] = ps;
  j["relative_contact_area"] = as;
  j["bracket"] = {{"open", {{"pressure", p[lo]}, {"relative_contact_area", a[lo]}}},
                  {"sealed", {{"pressure", p[hi]}, {"relative_contact_area", a[hi]}}}};
  char msg[200];
  std::snprintf(msg, sizeof msg, "the leakage stops at p = %.4g (between %.4g and %.4g), contact area %.4f",
                ps, p[lo], p[hi], as);
  j["message"] = msg;
  return j;
}

nlohmann::json run_curve(const std::string& case_path, const Config& cfg, const std::string& dir,
                         const CurveOptions& opts) {
  if (!cfg.sweep.active() ||
      (cfg.sweep.parameter != "load.pressure" && cfg.sweep.parameter != "load.approach"))
    throw InputError(case_path, "not a curve: make the configuration with curve_config");
  // Under mpirun every process solves the points (run_sweep); rank 0 alone writes and reads
  // the directory, and the tables' JSON is its (empty on the others).
  on_root([&] { fs::create_directories(dir); });
  SweepOptions so = opts.sweep;
  for (const auto& s : curve_overrides()) so.overrides.push_back(s);
  const std::string pdir = (fs::path(dir) / kPointsDir).string();
  nlohmann::json j;
  // The tables of the published points; the figure of earlier tables goes with them (the
  // front end draws it anew), so that a figure never shows other points than its table.
  const auto tables = [&] {
    std::error_code ec;
    fs::remove(fs::path(dir) / "curve.png", ec);
    fs::remove(fs::path(dir) / "curve.pdf", ec);
    j = write_curve_tables(case_path, cfg, dir, opts.sweep.overrides);
  };
  try {
    run_sweep(case_path, cfg, pdir, so);
  } catch (const SolveError&) {
    // Interrupted too: the points finished so far are tabulated where they were published (a
    // first attempt); where an earlier curve's points were kept, so are its tables.
    std::error_code ec;
    if (mpi::root() && !fs::exists(fs::path(pdir) / kStagingName, ec)) try {
        tables();
      } catch (const std::exception&) {
        // The first error is the one to report.
      }
    throw;
  }
  on_root(tables);
  return j;
}

}  // namespace gfmd
