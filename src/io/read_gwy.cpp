// Gwyddion native .gwy height maps. The file is "GWYP" and one serialized object, a
// GwyContainer. A serialized object is its type name (NUL-terminated), a u32 byte size of
// its components, then the components; a component is its name (NUL-terminated), a type
// character and the value: b (bool, 1 byte), c (char), i (i32), q (i64), d (double),
// s (NUL-terminated string), o (an object), or an array of them, C I Q D S O, which is a
// u32 count and the items. All little-endian. An image channel is the container's
// component "/N/data", a GwyDataField (xres, yres, xreal, yreal, si_unit_xy, si_unit_z as
// GwySIUnit objects with "unitstr", and data, a 'D' array of xres * yres values, row by
// row); "/N/mask", a GwyDataField of 0/1 of the same size, marks points (1) to leave out.
// Everything else is skipped by its type. Source: the Gwyddion user guide, "Format of
// Gwyddion Files" (gwyddion.net/documentation/user-guide-en/gwyfile-format.html).
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "gfmd/core/files.hpp"
#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

constexpr std::size_t kMaxName = 4096;  // longest name or string value accepted

// Fails unless n more bytes of the current object remain before `end`.
void within(const ByteReader& r, std::size_t end, std::size_t n, const std::string& what) {
  if (r.offset() > end || n > end - r.offset())
    r.fail(what + " (" + std::to_string(n) +
           " bytes) runs past the end of the object that holds it (offset " + std::to_string(end) +
           "): corrupt file?");
}

std::string name_at(ByteReader& r, std::size_t end, const char* what) {
  const std::size_t at = r.offset();
  std::string s = r.cstring(kMaxName);
  if (r.offset() > end)
    r.fail_at(at, std::string(what) + " '" + excerpt(s) + "' runs past the end of its object");
  return s;
}

struct Span {
  std::string type;
  std::size_t at, end;  // where the object starts; where its components end
};

// An object's header; its components then lie in [r.offset(), span.end).
Span object_header(ByteReader& r, std::size_t end) {
  const std::size_t at = r.offset();
  std::string type = name_at(r, end, "an object type name");
  within(r, end, 4, "the size of object '" + excerpt(type) + "'");
  const std::uint32_t size = r.u32le();
  if (size > end - r.offset())
    r.fail_at(r.offset() - 4, "object '" + excerpt(type) + "' declares " + std::to_string(size) +
                                  " bytes of components but only " + std::to_string(end - r.offset()) +
                                  (end == r.size() ? " are left in the file: truncated file?"
                                                   : " are left in the object that holds it: corrupt file?"));
  return {std::move(type), at, r.offset() + size};
}

struct Component {
  std::string name;
  char type;
  std::size_t at;
};

Component component_header(ByteReader& r, std::size_t end) {
  const std::size_t at = r.offset();
  std::string name = name_at(r, end, "a component name");
  within(r, end, 1, "the type of component '" + excerpt(name) + "'");
  return {std::move(name), static_cast<char>(r.u8()), at};
}

std::uint32_t array_count(ByteReader& r, std::size_t end, const Component& c, std::uint64_t min_item) {
  within(r, end, 4, "the item count of array '" + excerpt(c.name) + "'");
  const std::uint32_t n = r.u32le();
  if (n * min_item > end - r.offset())
    r.fail_at(r.offset() - 4, "array '" + excerpt(c.name) + "' declares " + std::to_string(n) +
                                  " items (at least " + std::to_string(n * min_item) + " bytes) but only " +
                                  std::to_string(end - r.offset()) + " bytes are left in its object");
  return n;
}

// The item size of a fixed-size type (scalars lower case, arrays upper case); 0 for others.
std::uint64_t fixed_size(char type) {
  const auto in = [type](std::string_view set) { return set.find(type) != std::string_view::npos; };
  return in("bcC") ? 1 : in("iI") ? 4 : in("qdQD") ? 8 : 0;
}

// Skips a component's value by its type.
void skip_value(ByteReader& r, std::size_t end, const Component& c) {
  if (c.type == 's') {
    name_at(r, end, "the string of component");
  } else if (c.type == 'o') {
    r.seek(object_header(r, end).end);
  } else if (c.type == 'S') {
    const std::uint32_t n = array_count(r, end, c, 1);
    for (std::uint32_t k = 0; k < n; ++k) name_at(r, end, "a string of array");
  } else if (c.type == 'O') {
    const std::uint32_t n = array_count(r, end, c, 5);
    for (std::uint32_t k = 0; k < n; ++k) r.seek(object_header(r, end).end);
  } else if (const std::uint64_t size = fixed_size(c.type); size == 0) {
    r.fail_at(c.at, "component '" + excerpt(c.name) + "' has type '" + excerpt(std::string(1, c.type)) +
                        "', not one of b c i q d s o C I Q D S O: corrupt file?");
  } else if (c.type >= 'a') {
    within(r, end, size, "component '" + excerpt(c.name) + "'");
    r.skip(size);
  } else {
    r.skip(array_count(r, end, c, size) * size);
  }
}

void expect_type(const ByteReader& r, const Component& c, char type, const std::string& owner) {
  if (c.type != type)
    r.fail_at(c.at, "component '" + c.name + "' of " + owner + " has type '" +
                        excerpt(std::string(1, c.type)) + "', not '" + std::string(1, type) + "'");
}

// A GwySIUnit's "unitstr" ("" when it has none).
std::string read_unit(ByteReader& r, std::size_t end, const std::string& owner) {
  const Span s = object_header(r, end);
  if (s.type != "GwySIUnit")
    r.fail_at(s.at, owner + " is a '" + excerpt(s.type) + "' object, not a GwySIUnit");
  std::string unit;
  while (r.offset() < s.end) {
    const Component c = component_header(r, s.end);
    if (c.name == "unitstr") {
      expect_type(r, c, 's', owner);
      unit = name_at(r, s.end, "the unit string");
    } else {
      skip_value(r, s.end, c);
    }
  }
  return unit;
}

struct Field {
  std::string key;  // "/0/data"
  std::size_t at = 0;
  long long xres = 0, yres = 0;
  bool has_xres = false, has_yres = false;
  double xreal = 0.0, yreal = 0.0;
  bool has_xreal = false, has_yreal = false;
  std::string unit_xy, unit_z;
  std::size_t data_at = 0;  // offset of the first value
  long long count = -1;     // number of values; -1: no data component
};

Field read_field(ByteReader& r, std::size_t end, const std::string& key) {
  const Span s = object_header(r, end);
  Field f;
  f.key = key;
  f.at = s.at;
  if (s.type != "GwyDataField")
    r.fail_at(s.at, "'" + key + "' is a '" + excerpt(s.type) + "' object, not a GwyDataField");
  const std::string owner = "the GwyDataField '" + key + "'";
  while (r.offset() < s.end) {
    const Component c = component_header(r, s.end);
    if (c.name == "xres" || c.name == "yres") {
      expect_type(r, c, 'i', owner);
      within(r, s.end, 4, c.name);
      (c.name == "xres" ? f.xres : f.yres) = r.i32le();
      (c.name == "xres" ? f.has_xres : f.has_yres) = true;
    } else if (c.name == "xreal" || c.name == "yreal") {
      expect_type(r, c, 'd', owner);
      within(r, s.end, 8, c.name);
      (c.name == "xreal" ? f.xreal : f.yreal) = r.f64le();
      (c.name == "xreal" ? f.has_xreal : f.has_yreal) = true;
    } else if (c.name == "si_unit_xy" || c.name == "si_unit_z") {
      expect_type(r, c, 'o', owner);
      (c.name == "si_unit_xy" ? f.unit_xy : f.unit_z) = read_unit(r, s.end, owner + " " + c.name);
    } else if (c.name == "data") {
      expect_type(r, c, 'D', owner);
      f.count = array_count(r, s.end, c, 8);
      f.data_at = r.offset();
      r.skip(static_cast<std::size_t>(f.count) * 8);
    } else {
      skip_value(r, s.end, c);
    }
  }
  const auto require = [&](bool ok, const char* what) {
    if (!ok) r.fail_at(f.at, owner + " has no '" + std::string(what) + "' component");
  };
  require(f.has_xres, "xres");
  require(f.has_yres, "yres");
  require(f.count >= 0, "data");
  check_map_dims(r.path(), f.xres, f.yres);
  if (f.count != f.xres * f.yres)
    r.fail_at(f.data_at, owner + " holds " + std::to_string(f.count) +
                             " values but xres x yres = " + std::to_string(f.xres) + " x " +
                             std::to_string(f.yres) + " = " + std::to_string(f.xres * f.yres));
  return f;
}

// N for a key "/N/<what>", else -1.
long long channel_of(const std::string& key, std::string_view what) {
  const std::string_view k(key);
  if (k.size() < 3 || k[0] != '/') return -1;
  std::size_t p = 1;
  long long n = 0;
  while (p < k.size() && p < 10 && k[p] >= '0' && k[p] <= '9') n = n * 10 + (k[p++] - '0');
  if (p == 1 || k.substr(p) != "/" + std::string(what)) return -1;
  return n;
}

}  // namespace

HeightMap read_gwy(const std::string& path) {
  // 2^28 heights (2 GiB) plus room for a mask and other channels.
  const std::string bytes =
      read_regular_file(path, (std::size_t{1} << 31) + (std::size_t{1} << 30), "topography file");
  ByteReader r(path, bytes);
  if (r.size() < 4 || r.bytes(4) != "GWYP") r.fail_at(0, "not a Gwyddion .gwy file (no GWYP signature)");
  const Span top = object_header(r, r.size());
  if (top.type != "GwyContainer")
    r.fail_at(top.at, "the file holds a '" + excerpt(top.type) + "' object, not a GwyContainer");
  std::map<long long, Field> data, masks;
  while (r.offset() < top.end) {
    const Component c = component_header(r, top.end);
    const long long nd = c.type == 'o' ? channel_of(c.name, "data") : -1;
    const long long nm = c.type == 'o' ? channel_of(c.name, "mask") : -1;
    if (nd >= 0 && !data.count(nd))
      data.emplace(nd, read_field(r, top.end, c.name));
    else if (nm >= 0 && !masks.count(nm))
      masks.emplace(nm, read_field(r, top.end, c.name));
    else
      skip_value(r, top.end, c);
  }
  if (data.empty())
    r.fail_at(top.at, "the file has no image channel (no '/N/data' GwyDataField in its GwyContainer)");
  // Named, not a structured binding: clang 14 (the sanitizer and fuzz builds) cannot capture
  // one in the lambdas below.
  const auto& channel = data.begin()->first;
  const auto& f = data.begin()->second;
  const Field* mask = masks.count(channel) ? &masks.at(channel) : nullptr;
  if (mask && (mask->xres != f.xres || mask->yres != f.yres))
    r.fail_at(mask->at, "the mask '" + mask->key + "' is " + std::to_string(mask->xres) + " x " +
                            std::to_string(mask->yres) + " points but the channel '" + f.key + "' is " +
                            std::to_string(f.xres) + " x " + std::to_string(f.yres));

  HeightMap t;
  t.format = "gwy";
  t.nx = static_cast<int>(f.xres);
  t.ny = static_cast<int>(f.yres);
  double mxy = 1.0, mz = 1.0;
  if (!f.unit_xy.empty() || !f.unit_z.empty()) {
    mxy = metres_per_unit(f.unit_xy);
    mz = metres_per_unit(f.unit_z);
    const auto bad = [&](const std::string& u, const char* which) {
      r.fail_at(f.at, std::string(which) + " of '" + f.key + "' is '" + excerpt(u) +
                          "', which is not a length unit" +
                          (u.empty() ? " (it has none, while the other axis has one)" : ""));
    };
    if (mxy <= 0.0) bad(f.unit_xy, "si_unit_xy");
    if (mz <= 0.0) bad(f.unit_z, "si_unit_z");
    t.unit = "m";
  }
  const auto size = [&](bool has, double v, const char* name) {
    if (!has) return 0.0;
    if (!(v > 0.0) || !std::isfinite(v))
      r.fail_at(f.at, std::string(name) + " of '" + f.key + "' is " + num(v) + ", not a positive size");
    return v * mxy;
  };
  t.lx = size(f.has_xreal, f.xreal, "xreal");
  t.ly = size(f.has_yreal, f.yreal, "yreal");

  const std::size_t n = static_cast<std::size_t>(f.count);
  t.h.resize(n);
  r.seek(f.data_at);
  ByteReader mr(path, bytes);  // the mask's values, alongside
  if (mask) mr.seek(mask->data_at);
  const auto nx = static_cast<std::size_t>(f.xres);
  const auto where = [&](std::size_t k) {
    return "(iy, ix) = (" + std::to_string(k / nx) + ", " + std::to_string(k % nx) + ")";
  };
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t at = r.offset();
    const double v = r.f64le();
    bool masked = false;
    if (mask) {
      const double mv = mr.f64le();
      if (std::isnan(mv)) mr.fail_at(mr.offset() - 8, "the mask '" + mask->key + "' holds NaN");
      masked = mv > 0.0;
    }
    if (std::isinf(v) && !masked) r.fail_at(at, "an infinite height at " + where(k));
    t.h[k] = masked || std::isnan(v) ? std::nan("") : v * mz;
    if (std::isnan(t.h[k]) && t.first_missing.empty())
      t.first_missing = where(k) + (masked ? " (masked in " + mask->key + ")" : " (NaN)");
  }
  return t;
}

}  // namespace gfmd::io_detail
