// Text height maps: whitespace, CSV or TSV matrices with optional size and unit headers, or
// three columns of x, y, z points on a regular grid.
// See include/gfmd/io/height_map.hpp.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gfmd/core/files.hpp"
#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

enum class ParseStatus { Ok, NotNumber, OutOfRange, Missing };

// Parses the whole token as a double (an optional leading '+' is accepted); "nan" in any
// case, with an optional sign, is a missing point.
ParseStatus parse_double(std::string_view tok, double& v) {
  std::string_view t = tok;
  if (!t.empty() && (t.front() == '+' || t.front() == '-')) t.remove_prefix(1);
  if (lower(t) == "nan") return ParseStatus::Missing;
  if (tok.size() > 1 && tok.front() == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
  const char* first = tok.data();
  const char* last = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range && ptr == last) return ParseStatus::OutOfRange;
  if (ec != std::errc() || ptr != last || tok.empty()) return ParseStatus::NotNumber;
  return ParseStatus::Ok;
}

// A header line after its '#': "lx = v [unit]", "ly: v [unit]" or "unit = u". Returns the
// key ("lx", "ly", "unit") and its value text, or "" for a plain comment.
std::string header_key(std::string_view rest, std::string_view& value) {
  rest = trim(rest);
  for (const char* key : {"lx", "ly", "unit"}) {
    const std::size_t n = std::char_traits<char>::length(key);
    if (rest.size() <= n || lower(rest.substr(0, n)) != key) continue;
    const std::string_view after = trim(rest.substr(n));
    if (after.empty() || (after.front() != '=' && after.front() != ':')) continue;
    value = trim(after.substr(1));
    return key;
  }
  return "";
}

struct Header {
  std::optional<double> value;  // lx, ly
  std::string unit;             // as written ("" = none)
  long line = 0;
};

// A row of column names x, y, z: separated as a data row (commas, semicolons or blanks), any
// case, quoted or not, each optionally followed by its unit in brackets ("x (um)", with commas
// or semicolons between the names); z may also be h, height or heights.
bool is_xyz_header(std::string_view s) {
  const char sep = s.find(',') != std::string_view::npos   ? ','
                   : s.find(';') != std::string_view::npos ? ';'
                                                           : ' ';
  std::vector<std::string> names;
  std::size_t pos = 0;
  while (pos < s.size() && names.size() <= 3) {
    std::size_t end = pos;
    if (sep == ' ') {
      while (pos < s.size() && is_blank(s[pos])) ++pos;
      end = pos;
      while (end < s.size() && !is_blank(s[end])) ++end;
    } else {
      end = std::min(s.find(sep, pos), s.size());
    }
    std::string_view tok = trim(s.substr(pos, end - pos));
    pos = end + 1;
    if (tok.empty()) continue;
    if (tok.size() >= 2 && (tok.front() == '"' || tok.front() == '\'') && tok.back() == tok.front())
      tok = trim(tok.substr(1, tok.size() - 2));
    std::size_t n = 0;
    while (n < tok.size() && std::isalpha(static_cast<unsigned char>(tok[n])) != 0) ++n;
    const std::string_view unit = trim(tok.substr(n));
    if (n == 0 || (!unit.empty() && unit.front() != '(' && unit.front() != '[')) return false;
    names.push_back(lower(tok.substr(0, n)));
  }
  return names.size() == 3 && names[0] == "x" && names[1] == "y" &&
         (names[2] == "z" || names[2] == "h" || names[2] == "height" || names[2] == "heights");
}

// Sorted distinct values of column c (0: x, 1: y) of three-column rows; NaN left out.
std::vector<double> distinct_column(const std::vector<double>& d, int c) {
  std::vector<double> u;
  u.reserve(d.size() / 3);
  for (std::size_t i = static_cast<std::size_t>(c); i < d.size(); i += 3)
    if (!std::isnan(d[i])) u.push_back(d[i]);
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  return u;
}

// Three columns read as x, y, z points without a header: the first two columns have no missing
// value and two values or more each, and one of them repeats a value (a matrix of measured
// heights almost never does).
bool looks_like_points(const std::vector<double>& d, long long rows) {
  for (std::size_t i = 0; i < d.size(); i += 3)
    if (std::isnan(d[i]) || std::isnan(d[i + 1])) return false;
  const std::size_t nxu = distinct_column(d, 0).size(), nyu = distinct_column(d, 1).size();
  const auto n = static_cast<std::size_t>(rows);
  return nxu >= 2 && nyu >= 2 && (nxu < n || nyu < n);
}

// The regular axis through sorted distinct values: the first value, the spacing (the smallest
// gap, refined over the whole span) and the count of its points.
struct Axis {
  double v0 = 0.0, step = 0.0;
  long long n = 0;
};

// Points x, y, z (three values per row of d; lines: each row's line) on a regular grid: rows
// of the map by y, columns by x, both ascending; pairs no row gives are missing points.
HeightMap points_on_grid(const std::string& path, const std::vector<double>& d,
                         const std::vector<long>& lines, bool header) {
  const std::size_t rows = lines.size();
  const auto refuse = [&](long line, const std::string& why) {
    throw InputError(path,
                     (line > 0 ? "line " + std::to_string(line) + ": " : std::string()) +
                         (header ? "the columns x, y, z" : "three columns whose first two repeat values") +
                         " are read as points (x, y, height) on a regular grid (README, \"Bring your own "
                         "surface\"), but " +
                         why + (header ? "" : "; a height map three points wide: save it as .npy"));
  };
  const auto line_of = [&](int c, double v) {
    for (std::size_t r = 0; r < rows; ++r)
      if (d[3 * r + static_cast<std::size_t>(c)] == v) return lines[r];
    return 0L;
  };
  for (std::size_t r = 0; r < rows; ++r)
    if (std::isnan(d[3 * r]) || std::isnan(d[3 * r + 1]))
      refuse(lines[r], "x or y is missing (nan): only a height may be (a missing point)");
  Axis axis[2];
  for (int c = 0; c < 2; ++c) {
    const char* name = c == 0 ? "x" : "y";
    const std::vector<double> u = distinct_column(d, c);
    if (u.size() < 2)
      refuse(0, std::string("every point has the same ") + name + " (" + num(u.front()) +
                    "): a map needs two points or more along x and y");
    double gap = u[1] - u[0];
    std::size_t at = 0;
    for (std::size_t k = 1; k + 1 < u.size(); ++k)
      if (u[k + 1] - u[k] < gap) gap = u[k + 1] - u[k], at = k;
    const double steps = std::round((u.back() - u.front()) / gap);
    if (!(steps < static_cast<double>(kMaxMapSide)))
      refuse(line_of(c, u[at + 1]),
             std::string(name) + " = " + num(u[at]) + " and " + num(u[at + 1]) + " are " + num(gap) +
                 " apart: on that spacing the grid would have more than " + std::to_string(kMaxMapSide) +
                 " points along " + name + " (not a regular grid)");
    Axis& a = axis[c];
    a.v0 = u.front();
    a.step = (u.back() - u.front()) / steps;
    a.n = static_cast<long long>(steps) + 1;
    // Off the spacing: more than 1 % of it away, beyond the rounding of values printed with
    // six significant digits.
    for (const double v : u) {
      const double k = std::round((v - a.v0) / a.step);
      if (std::abs(v - (a.v0 + k * a.step)) > 0.01 * a.step + 1e-5 * std::abs(v))
        refuse(line_of(c, v), std::string(name) + " = " + num(v) + " is off the regular spacing " +
                                  num(a.step) + " from " + name + " = " + num(a.v0) +
                                  " (not a regular grid)");
    }
  }
  const long long nx = axis[0].n, ny = axis[1].n;
  check_map_dims(path, nx, ny);
  if (nx * ny > 2 * static_cast<long long>(rows))
    refuse(0, "the " + std::to_string(rows) + " points fill less than half of the " + std::to_string(nx) +
                  " x " + std::to_string(ny) + " grid their spacings (" + num(axis[0].step) + ", " +
                  num(axis[1].step) + ") make (not a regular grid)");
  HeightMap t;
  t.format = "text";
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  t.h.assign(static_cast<std::size_t>(nx * ny), std::nan(""));
  std::vector<std::uint32_t> row_of(static_cast<std::size_t>(nx * ny), 0);  // 1 + the row given there
  for (std::size_t r = 0; r < rows; ++r) {
    const double x = d[3 * r], y = d[3 * r + 1];
    const auto ix = std::llround((x - axis[0].v0) / axis[0].step);
    const auto iy = std::llround((y - axis[1].v0) / axis[1].step);
    const auto slot = static_cast<std::size_t>(iy * nx + ix);
    if (row_of[slot] != 0)
      refuse(lines[r], "(x, y) = (" + num(x) + ", " + num(y) + ") is given twice (first on line " +
                           std::to_string(lines[row_of[slot] - 1]) + ")");
    row_of[slot] = static_cast<std::uint32_t>(r + 1);
    t.h[slot] = d[3 * r + 2];
  }
  for (std::size_t slot = 0; slot < t.h.size(); ++slot) {
    if (!std::isnan(t.h[slot])) continue;
    const double x = axis[0].v0 + static_cast<double>(static_cast<long long>(slot) % nx) * axis[0].step;
    const double y = axis[1].v0 + static_cast<double>(static_cast<long long>(slot) / nx) * axis[1].step;
    t.first_missing = row_of[slot] != 0 ? "line " + std::to_string(lines[row_of[slot] - 1]) + " (z = nan)"
                                        : "(x, y) = (" + num(x) + ", " + num(y) + "), which no row gives";
    break;
  }
  t.lx = axis[0].step * static_cast<double>(nx);
  t.ly = axis[1].step * static_cast<double>(ny);
  return t;
}

}  // namespace

HeightMap read_text_map(const std::string& path) {
  // A text map is at most ~25 bytes per value; 1 GiB holds 2^25 values at ~30 B.
  const std::string text = read_regular_file(path, std::size_t{1} << 30, "topography file");
  std::vector<double> data;
  long long nx = 0, ny = 0;
  long first_row_line = 0;
  Header size[2];
  Header unit;
  std::string first_missing;
  long lineno = 0;
  // Three columns may be x, y, z points (points_on_grid): each row's line, kept while the rows
  // have three values; a first row naming the columns x, y, z says so.
  std::vector<long> row_lines;
  long xyz_header = 0;
  std::size_t next = 0;
  const auto at_line = [&] { return "line " + std::to_string(lineno) + ": "; };
  while (next < text.size()) {
    const std::size_t eol = std::min(text.find('\n', next), text.size());
    const std::string_view line(text.data() + next, eol - next);
    next = eol + 1;
    ++lineno;
    const std::string_view s = trim(line);
    if (s.empty()) continue;
    if (s.front() == '#') {
      std::string_view value;
      const std::string key = header_key(s.substr(1), value);
      if (key.empty()) continue;
      Header& h = key == "lx" ? size[0] : key == "ly" ? size[1] : unit;
      if (h.line != 0)
        throw InputError(path,
                         at_line() + key + " given twice (first on line " + std::to_string(h.line) + ")");
      h.line = lineno;
      if (key == "unit") {
        if (value.empty() || metres_per_unit(value) == 0.0)
          throw InputError(
              path, at_line() + "unknown length unit '" + excerpt(value) + "' (m, mm, um, nm, pm or A)");
        h.unit = value;
        continue;
      }
      // "<number> [unit]"
      const std::size_t sp = value.find_first_of(" \t");
      const std::string_view number = value.substr(0, sp);
      const std::string_view u = sp == std::string_view::npos ? std::string_view() : trim(value.substr(sp));
      double v = 0.0;
      if (parse_double(number, v) != ParseStatus::Ok || !(v > 0.0) || !std::isfinite(v))
        throw InputError(path, at_line() + "invalid " + key + " header value '" + excerpt(value) +
                                   "' (expected a positive number, optionally followed by its unit)");
      if (!u.empty() && metres_per_unit(u) == 0.0)
        throw InputError(path, at_line() + "unknown length unit '" + excerpt(u) + "' of " + key +
                                   " (m, mm, um, nm, pm or A)");
      h.value = v;
      h.unit = u;
      continue;
    }
    if (ny == 0 && xyz_header == 0 && is_xyz_header(s)) {
      xyz_header = lineno;
      continue;
    }
    // Data row: values separated by blanks (tabs included), or by commas or semicolons (CSV;
    // blanks around them allowed). A row uses one separator.
    const char sep = s.find(',') != std::string_view::npos   ? ','
                     : s.find(';') != std::string_view::npos ? ';'
                                                             : ' ';
    long long count = 0;
    std::size_t pos = 0;
    while (pos <= s.size()) {
      std::string_view tok;
      if (sep == ' ') {
        while (pos < s.size() && is_blank(s[pos])) ++pos;
        if (pos >= s.size()) break;
        std::size_t end = pos;
        while (end < s.size() && !is_blank(s[end])) ++end;
        tok = s.substr(pos, end - pos);
        pos = end;
      } else {
        const std::size_t end = std::min(s.find(sep, pos), s.size());
        tok = trim(s.substr(pos, end - pos));
        pos = end + 1;
        if (tok.empty() && end == s.size() && count > 0) break;  // one trailing separator
        if (tok.empty())
          throw InputError(path, at_line() + "empty value " + std::to_string(count + 1) + " between '" +
                                     std::string(1, sep) + "' separators");
      }
      if (++count > kMaxMapSide)
        throw InputError(path, at_line() + "more than " + std::to_string(kMaxMapSide) +
                                   " values in a row: at most that many points per side can be read");
      double v = 0.0;
      const ParseStatus st = parse_double(tok, v);
      if (st == ParseStatus::NotNumber)
        throw InputError(path, at_line() + "non-numeric value '" + excerpt(tok) + "' (value " +
                                   std::to_string(count) + ")");
      if (st == ParseStatus::OutOfRange || (st == ParseStatus::Ok && !std::isfinite(v)))
        throw InputError(path, at_line() + "non-finite value '" + excerpt(tok) + "' (value " +
                                   std::to_string(count) +
                                   "); Inf is not a height (write nan for a missing point)");
      if (st == ParseStatus::Missing) {
        v = std::nan("");
        if (first_missing.empty())
          first_missing = "line " + std::to_string(lineno) + ", value " + std::to_string(count);
      }
      if (static_cast<long long>(data.size()) >= kMaxMapPoints)
        throw InputError(path, at_line() + "more than " + std::to_string(kMaxMapPoints) +
                                   " values (2 GiB of heights): too large to read");
      data.push_back(v);
    }
    // Three values per row: x, y, z points perhaps, as many rows as points (checked below).
    if (ny + 1 > kMaxMapSide && nx != 3)
      throw InputError(path, at_line() + "more than " + std::to_string(kMaxMapSide) +
                                 " data rows: at most that many points per side can be read");
    if (xyz_header != 0 && count != 3)
      throw InputError(path, at_line() + std::to_string(count) + " values, but line " +
                                 std::to_string(xyz_header) + " names three columns x, y, z");
    if (count == 3) row_lines.push_back(lineno);
    if (ny == 0) {
      nx = count;
      first_row_line = lineno;
    } else if (count != nx) {
      throw InputError(path, "ragged rows: line " + std::to_string(lineno) + " has " + std::to_string(count) +
                                 " values but the first data row (line " + std::to_string(first_row_line) +
                                 ") has " + std::to_string(nx));
    }
    ++ny;
  }
  if (ny == 0)
    throw InputError(path, lineno == 0 ? "the file is empty (no data)"
                                       : "no data rows in the file (only comments or blank lines)");
  HeightMap t;
  if (nx == 3 && (xyz_header != 0 || looks_like_points(data, ny))) {
    t = points_on_grid(path, data, row_lines, xyz_header != 0);
  } else {
    if (ny > kMaxMapSide)
      throw InputError(path, "line " + std::to_string(row_lines[static_cast<std::size_t>(kMaxMapSide)]) +
                                 ": more than " + std::to_string(kMaxMapSide) +
                                 " data rows: at most that many points per side can be read");
    check_map_dims(path, nx, ny);
    t.format = "text";
    t.nx = static_cast<int>(nx);
    t.ny = static_cast<int>(ny);
    t.h.assign(data.begin(), data.end());
    t.first_missing = first_missing;
  }
  // Units: "# unit" is the heights' unit and the default of lx/ly. A size with a unit but
  // heights without one would mix a known and an unknown scale.
  const bool any_unit = !unit.unit.empty() || !size[0].unit.empty() || !size[1].unit.empty();
  if (any_unit && unit.unit.empty())
    throw InputError(path, "line " + std::to_string(size[0].unit.empty() ? size[1].line : size[0].line) +
                               ": the size has a unit but the heights have none: add a header line "
                               "'# unit = <unit of the heights>' (a case's indenter.unit is for files that "
                               "state no unit at all, and this one states the size's)");
  const double zf = any_unit ? metres_per_unit(unit.unit) : 1.0;
  t.lx *= zf;  // x, y, z points: the size their spacing makes, in the heights' unit
  t.ly *= zf;
  for (int k = 0; k < 2; ++k) {
    if (!size[k].value) continue;
    const double f = !size[k].unit.empty() ? metres_per_unit(size[k].unit) : zf;
    (k == 0 ? t.lx : t.ly) = *size[k].value * f;
  }
  if (any_unit) {
    t.unit = std::string(1, 'm');
    for (double& v : t.h) v *= zf;
  }
  return t;
}

}  // namespace gfmd::io_detail
