// Digital Surf .sur height maps (MountainsMap): a 512-byte little-endian header, a comment
// zone and a private zone of the sizes the header gives, then nx * ny points of 16 or 32
// bits, line by line (x fastest). Header fields used (byte offset: type):
//    0: char[12] signature "DIGITAL SURF" ("DSCOMPRESSED": zlib-compressed data, refused)
//   12: i16 format (0 = PC byte order)      14: i16 number of objects
//   18: i16 studiable type (2 = surface)     20, 50: char[30] object and operator names
//   86: i16 non-measured points flag (1: points equal to zmin - 2 carry no value)
//   98: i16 bits per point (16, 32)          100, 104: i32 zmin, zmax
//  108: i32 points per line (nx)             112: i32 lines (ny)    116: i32 nx * ny
//  120, 124, 128: f32 x, y, z spacing        180, 196, 212: char[16] their units
//  228, 244, 260: char[16] axis length units (used when a spacing unit is blank)
//  334, 336: i16 comment and private zone sizes                     474: f32 z offset
// Height = (value * z spacing + z offset) in the z spacing unit; size = n * spacing.
// Sources: Gwyddion's modules/file/surffile.c (header layout, value * dz + z offset),
// MountainsMap-based readers in SurfaceTopography (IO/SUR.py), surfalize (file/sur.py) and
// RosettaSciIO (digitalsurf), which give the zones and the zmin - 2 no-data value.
// Unit strings are Latin-1 (micro = 0xB5) or UTF-8.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "gfmd/core/files.hpp"
#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

constexpr std::size_t kHeader = 512;

// A fixed-size text field: up to the first NUL, blanks trimmed.
std::string text_at(ByteReader& r, std::size_t at, std::size_t len) {
  r.seek(at);
  std::string_view s = r.bytes(len);
  s = s.substr(0, s.find('\0'));
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return std::string(s);
}

// A unit field with a Latin-1 micro sign (0xB5) rewritten as 'u'.
std::string unit_at(ByteReader& r, std::size_t at, std::size_t fallback_at) {
  std::string u = text_at(r, at, 16);
  if (u.empty()) u = text_at(r, fallback_at, 16);
  std::string out;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const auto c = static_cast<unsigned char>(u[i]);
    const bool utf8_micro = c == 0xB5 && i > 0 && static_cast<unsigned char>(u[i - 1]) == 0xC2;
    out += c == 0xB5 && !utf8_micro ? 'u' : u[i];
  }
  return out;
}

std::int16_t i16_at(ByteReader& r, std::size_t at) {
  r.seek(at);
  return r.i16le();
}
std::int32_t i32_at(ByteReader& r, std::size_t at) {
  r.seek(at);
  return r.i32le();
}
float f32_at(ByteReader& r, std::size_t at) {
  r.seek(at);
  return r.f32le();
}

const char* studiable_name(int type) {
  switch (type) {
    case 1:
      return "a profile";
    case 3:
      return "a binary image";
    case 4:
      return "a series of profiles";
    case 5:
      return "a series of surfaces";
    case 6:
      return "a meridian disc";
    case 7:
      return "a multilayer profile";
    case 8:
      return "a multilayer surface";
    case 10:
      return "an intensity image";
    case 11:
      return "an intensity surface";
    case 12:
      return "an RGB image";
    case 16:
      return "an RGB intensity surface";
    default:
      return "an object of unknown type";
  }
}

}  // namespace

HeightMap read_sur(const std::string& path) {
  // 2^28 points of 32 bits (1 GiB) plus the header and the two zones of up to 64 KiB.
  const std::string bytes =
      read_regular_file(path, (std::size_t{1} << 30) + (std::size_t{1} << 20), "topography file");
  ByteReader r(path, bytes);
  const std::string_view sig = r.bytes(std::min<std::size_t>(12, r.size()));
  if (sig == "DSCOMPRESSED")
    r.fail_at(0, "a compressed Digital Surf file (DSCOMPRESSED) is not supported: save it uncompressed");
  if (sig != "DIGITAL SURF") r.fail_at(0, "not a Digital Surf .sur file (no 'DIGITAL SURF' signature)");
  if (r.size() < kHeader)
    r.fail_at(r.size(), "the file ends inside the 512-byte .sur header (" + std::to_string(r.size()) +
                            " bytes): truncated file?");

  const int format = i16_at(r, 12);
  if (format != 0)
    r.fail_at(12, "byte-order format " + std::to_string(format) +
                      " is not supported (only 0, PC; 257 is Macintosh byte order)");
  const int objects = i16_at(r, 14);
  if (objects > 1)
    r.fail_at(14, "multi-object .sur files are not supported (" + std::to_string(objects) +
                      " objects: a series or multilayer studiable?)");
  const int type = i16_at(r, 18);
  // Gwyddion writes surfaces as type 1 with object "SCRATCH" and operator "csm".
  const bool gwyddion_export = type == 1 && text_at(r, 20, 30) == "SCRATCH" && text_at(r, 50, 30) == "csm";
  if (type != 2 && !gwyddion_export)
    r.fail_at(18, "studiable type " + std::to_string(type) + " is " + studiable_name(type) +
                      ", not a surface (type 2): only surfaces are height maps");
  const int bits = i16_at(r, 98);
  if (bits != 16 && bits != 32)
    r.fail_at(98, std::to_string(bits) + " bits per point: only 16 and 32 are known");
  const long long nx = i32_at(r, 108), ny = i32_at(r, 112);
  check_map_dims(path, nx, ny);
  const long long total = i32_at(r, 116);
  if (total != nx * ny)
    r.fail_at(116, "the header gives " + std::to_string(total) + " points in all but " + std::to_string(nx) +
                       " points per line x " + std::to_string(ny) + " lines = " + std::to_string(nx * ny));
  const auto comment = static_cast<std::uint16_t>(i16_at(r, 334));
  const auto priv = static_cast<std::uint16_t>(i16_at(r, 336));
  const std::size_t start = kHeader + comment + priv;
  const std::size_t width = bits == 16 ? 2 : 4;
  const std::size_t n = static_cast<std::size_t>(nx * ny);
  if (start > r.size() || n * width > r.size() - start)
    r.fail_at(std::min(start, r.size()),
              "the header describes " + std::to_string(nx) + " x " + std::to_string(ny) + " points of " +
                  std::to_string(bits) + " bits (" + std::to_string(n * width) +
                  " bytes) after a comment of " + std::to_string(comment) + " and a private zone of " +
                  std::to_string(priv) + " bytes, but only " +
                  std::to_string(r.size() > start ? r.size() - start : 0) + " bytes follow: truncated file?");

  double spacing[3];
  const char* const axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    spacing[a] = f32_at(r, 120 + 4 * static_cast<std::size_t>(a));
    if (!std::isfinite(spacing[a]) || spacing[a] == 0.0)
      r.fail_at(120 + 4 * static_cast<std::size_t>(a),
                std::string("the ") + axes[a] + " spacing is " + num(spacing[a]) + ", not a usable step");
  }
  const double zoff = f32_at(r, 474);
  if (!std::isfinite(zoff)) r.fail_at(474, "the z offset is " + num(zoff));

  HeightMap t;
  t.format = "sur";
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  double scale[3] = {1.0, 1.0, 1.0};
  std::string units[3];
  for (std::size_t a = 0; a < 3; ++a) units[a] = unit_at(r, 180 + 16 * a, 228 + 16 * a);
  if (!units[0].empty() || !units[1].empty() || !units[2].empty()) {
    for (std::size_t a = 0; a < 3; ++a) {
      scale[a] = metres_per_unit(units[a]);
      if (scale[a] <= 0.0)
        r.fail_at(180 + 16 * a, std::string("the ") + axes[a] + " unit '" + excerpt(units[a]) +
                                    "' is not a length unit" + (units[a].empty() ? " (it has none)" : ""));
    }
    t.unit = "m";
  }
  t.lx = static_cast<double>(nx) * std::abs(spacing[0]) * scale[0];
  t.ly = static_cast<double>(ny) * std::abs(spacing[1]) * scale[1];

  const bool has_missing = i16_at(r, 86) == 1;
  const std::int64_t no_data = static_cast<std::int64_t>(i32_at(r, 100)) - 2;
  t.h.resize(n);
  r.seek(start);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t v = bits == 16 ? r.i16le() : r.i32le();
    if (has_missing && v == no_data) {
      t.h[k] = std::nan("");
      if (t.first_missing.empty())
        t.first_missing = "(iy, ix) = (" + std::to_string(k / static_cast<std::size_t>(nx)) + ", " +
                          std::to_string(k % static_cast<std::size_t>(nx)) + ")";
    } else {
      t.h[k] = (static_cast<double>(v) * spacing[2] + zoff) * scale[2];
    }
  }
  return t;
}

}  // namespace gfmd::io_detail
