// Text height maps: whitespace, CSV or TSV matrices with optional size and unit headers.
// See include/gfmd/io/height_map.hpp.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
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
    if (ny + 1 > kMaxMapSide)
      throw InputError(path, at_line() + "more than " + std::to_string(kMaxMapSide) +
                                 " data rows: at most that many points per side can be read");
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
  check_map_dims(path, nx, ny);

  HeightMap t;
  t.format = "text";
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  t.h.assign(data.begin(), data.end());
  t.first_missing = first_missing;
  // Units: "# unit" is the heights' unit and the default of lx/ly. A size with a unit but
  // heights without one would mix a known and an unknown scale.
  const bool any_unit = !unit.unit.empty() || !size[0].unit.empty() || !size[1].unit.empty();
  if (any_unit && unit.unit.empty())
    throw InputError(path, "line " + std::to_string(size[0].unit.empty() ? size[1].line : size[0].line) +
                               ": the size has a unit but the heights have none: add a header line "
                               "'# unit = <unit of the heights>'");
  const double zf = any_unit ? metres_per_unit(unit.unit) : 1.0;
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
