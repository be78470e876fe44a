// One [section] of a case file as the config part reads it (private to src/case/): typed
// getters that record problems instead of throwing, the check that every key was understood,
// and the "did you mean" and "[file:line]" parts of the messages.
#pragma once

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <string>
#include <toml.hpp>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd::config_detail {

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
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

// Names joined for a "one of ..." message: "a, b, c".
inline std::string comma_list(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

inline std::string did_you_mean(const std::string& key, const std::vector<std::string>& allowed) {
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

inline std::string where(const toml::value& v) {
  const auto loc = v.location();
  if (loc.file_name() == "unknown file" || loc.line() == 0) return "";
  // A command-line override is named by itself (apply_override parses it under that name).
  if (loc.file_name().rfind("--set ", 0) == 0) return " [" + loc.file_name() + "]";
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
  // A table inside this one (an array's element, say) read as a section of its own, its problems
  // reported as "<this section>.<name>.<key>" with this section's.
  [[nodiscard]] Section child(const toml::value& table, const std::string& name) const {
    return Section(name_ + "." + name, table, errors_);
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
  // A finite number (an integer is converted); nan and inf are refused.
  double number(const std::string& key, double def) { return number_impl(key, def, false); }
  // A number that may also be "inf"/"infinity" (string or TOML inf).
  double number_or_inf(const std::string& key, double def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_string()) {
      std::string s = v->as_string();
      std::transform(s.begin(), s.end(), s.begin(), ::tolower);
      if (s == "inf" || s == "infinity" || s == "infinite") return std::numeric_limits<double>::infinity();
      error(key, "must be a number or \"inf\", got \"" + std::string(v->as_string()) + "\"");
      return def;
    }
    return number_impl(key, def, true);
  }
  // An integer in [lo, hi]: out of range is an error (never a silent truncation).
  long long integer(const std::string& key, long long def, long long lo, long long hi) {
    const toml::value* v = raw(key);
    if (!v) return def;
    long long x = def;
    if (v->is_integer()) {
      x = v->as_integer();
    } else if (v->is_floating() && std::floor(v->as_floating()) == v->as_floating() &&
               std::abs(v->as_floating()) < 1e15) {
      x = static_cast<long long>(v->as_floating());
    } else {
      error(key, "must be an integer, got " + type_name(*v));
      return def;
    }
    if (x < lo || x > hi) {
      error(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                     std::to_string(x));
      return def;
    }
    return x;
  }
  bool boolean(const std::string& key, bool def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_boolean()) return v->as_boolean();
    error(key, "must be true or false, got " + type_name(*v));
    return def;
  }
  std::string string(const std::string& key, const std::string& def) {
    const toml::value* v = raw(key);
    if (!v) return def;
    if (v->is_string()) return v->as_string();
    error(key, "must be a string, got " + type_name(*v));
    return def;
  }
  // The value of a key of this section, or of a path into its arrays of tables
  // ("layers[0].thickness", as a part's check names an element's key); null if absent.
  [[nodiscard]] const toml::value* find(const std::string& key) const {
    if (!tbl_) return nullptr;
    if (tbl_->as_table().count(key)) return &tbl_->as_table().at(key);
    const toml::value* v = tbl_;
    std::size_t pos = 0;
    while (true) {
      const std::size_t dot = key.find('.', pos);
      std::string part = key.substr(pos, dot == std::string::npos ? std::string::npos : dot - pos);
      std::size_t index = 0;
      bool indexed = false;
      if (const std::size_t lb = part.find('[');
          lb != std::string::npos && part.size() > lb + 2 && part.back() == ']') {
        const std::string digits = part.substr(lb + 1, part.size() - lb - 2);
        if (digits.size() > 6 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
          return nullptr;
        index = std::stoul(digits);
        indexed = true;
        part.resize(lb);
      }
      if (!v->is_table() || !v->as_table().count(part)) return nullptr;
      v = &v->as_table().at(part);
      if (indexed) {
        if (!v->is_array() || index >= v->as_array().size()) return nullptr;
        v = &v->as_array().at(index);
      }
      if (dot == std::string::npos) return v;
      pos = dot + 1;
    }
  }
  int line(const std::string& key) const {
    const toml::value* v = find(key);
    return v ? static_cast<int>(v->location().line()) : 0;
  }
  std::string at(const std::string& key) const {
    const toml::value* v = find(key);
    return v ? where(*v) : "";
  }
  // A problem with key; the key's place in the file ("[case.toml:12]", "[--set grid.nx=abc]") is added
  // unless the reason already names a place in that file (an array element's, say).
  // One problem per key: a value of the wrong type is not also reported out of range.
  void error(const std::string& key, const std::string& why) {
    if (std::find(reported_.begin(), reported_.end(), key) != reported_.end()) return;
    reported_.push_back(key);
    const std::string loc = at(key);
    // The file's part of the place ("[case.toml:"), or an override's whole name.
    const std::size_t colon = loc.rfind(':');
    const std::string file = colon == std::string::npos ? loc : loc.substr(0, colon + 1);
    const bool placed = loc.empty() || why.find(file) != std::string::npos;
    errors_.push_back(name_ + "." + key + ": " + why + (placed ? "" : loc));
  }
  // Runs a part's own check, which throws ParameterError naming its key, and reports what it
  // throws as this section's problem with that key (so that the message names the line); false
  // when it reported one.
  template <class Check>
  bool check(Check&& part_check) {
    try {
      part_check();
    } catch (const ParameterError& e) {
      error(e.where(), e.why());
      return false;
    }
    return true;
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
  // The problems found so far in the whole case (this section's and every other's).
  [[nodiscard]] std::size_t problems() const { return errors_.size(); }

 private:
  Section(std::string name, const toml::value& table, std::vector<std::string>& errors)
      : name_(std::move(name)), errors_(errors), tbl_(&table) {}
  double number_impl(const std::string& key, double def, bool allow_inf) {
    const toml::value* v = raw(key);
    if (!v) return def;
    double x = def;
    if (v->is_floating()) {
      x = v->as_floating();
    } else if (v->is_integer()) {
      x = static_cast<double>(v->as_integer());
    } else {
      error(key, "must be a number, got " + type_name(*v));
      return def;
    }
    if (std::isnan(x) || (std::isinf(x) && !(allow_inf && x > 0))) {
      error(key, "must be a finite number, got " + std::string(std::isnan(x) ? "nan" : "inf"));
      return def;
    }
    return x;
  }

 public:
  static std::string type_name(const toml::value& v) {
    std::ostringstream os;
    os << v.type();
    return os.str();
  }

 private:
  std::string name_;
  std::vector<std::string>& errors_;
  const toml::value* tbl_ = nullptr;
  std::vector<std::string> allowed_;
  std::vector<std::string> reported_;  // keys with a problem recorded
};

// Reads the [indenter] section (its type and that type's keys) into c.indenter; a file indenter
// fills the grid keys not given (grid_given: nx, ny, lx, ly) from its height map.
// src/case/config_indenter.cpp.
struct GridKeysGiven {
  bool nx, ny, lx, ly;
};
void read_indenter(Section& ind, Config& c, std::vector<std::string>& errors, const GridKeysGiven& given,
                   const std::string& base_dir);

// The sections after [indenter] and [load], each read into c and checked key by key (Section::
// error), the section finished (its unknown keys reported). Physics (src/case/config_physics.cpp):
// [elastic] with a viscoelastic body's keys; [friction] (also friction.velocity, which needs the
// body read first); [interaction] (its combinations with friction and the body). The run
// (src/case/config_run.cpp): [solver], [sweep], [stress] (depths need the body), [flow], [output].
void read_elastic(Section& el, Config& c, const std::string& base_dir);  // master curve files: base_dir
// What lies beneath a body's top layer, in [elastic] and [indenter] alike: substrate_contact_modulus
// ("inf" or absent: a rigid base), substrate_poisson and layers = [{contact_modulus, poisson,
// thickness}, ...] (bonded beneath the top layer, top to bottom); and their JSON (absent keys for a
// single layer on a rigid base, as before the keys).
void read_body_stack(Section& s, ElasticParams& e);
void write_body_stack(const ElasticParams& e, nlohmann::json& out);
void read_friction(Section& fr, Config& c);
void read_interaction(Section& ia, Config& c);
void read_solver(Section& so, Config& c);
void read_sweep(Section& sw, Config& c);
void read_stress(Section& st, Config& c);
void read_flow(Section& fl, Config& c);
void read_output(Section& out, Config& c);

// One value given as JSON (a case held as tables, config_from_tables; an indenter's keys from
// Python, make_indenter) as the TOML parser would have made it, without a place in a file: objects
// become tables; `key` names it in errors ("elastic.layers[0].poisson: must not be NaN"); null
// and nesting deeper than kMaxTomlNesting are refused.
toml::value toml_from_json(const nlohmann::json& j, const std::string& key, int depth = 0);

}  // namespace gfmd::config_detail
