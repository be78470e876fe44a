// Height-map files: the format dispatch, the size rules, and what the readers share
// (bounded binary reading, units, limits). See include/gfmd/io/height_map.hpp.
#include "gfmd/io/height_map.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "readers.hpp"

namespace gfmd {

namespace io_detail {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string excerpt(std::string_view s) {
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (out.size() >= 37) {
      out += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7f) {
      out += ch;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  return out;
}

void check_map_dims(const std::string& path, long long nx, long long ny) {
  const std::string dims = std::to_string(nx) + " x " + std::to_string(ny);
  if (nx < 1 || ny < 1) throw InputError(path, "the map is " + dims + " points: it holds no data");
  if (nx > kMaxMapSide || ny > kMaxMapSide)
    throw InputError(path, "the map is " + dims + " points; at most " + std::to_string(kMaxMapSide) +
                               " per side can be read");
  if (nx * ny > kMaxMapPoints)
    throw InputError(path, "the map is " + dims + " points (" + std::to_string(nx * ny) + "); at most " +
                               std::to_string(kMaxMapPoints) + " (2 GiB of heights) can be read");
}

double metres_per_unit(std::string_view unit) {
  std::string u;
  for (const char c : unit)
    if (c != ' ') u += c;
  // Micro: 'u', U+00B5 MICRO SIGN (C2 B5) or U+03BC GREEK SMALL LETTER MU (CE BC).
  for (const std::string_view micro : {std::string_view("\xC2\xB5"), std::string_view("\xCE\xBC")})
    if (u.starts_with(micro)) u.replace(0, micro.size(), 1, 'u');
  if (u == "m") return 1.0;
  if (u == "cm") return 1e-2;
  if (u == "mm") return 1e-3;
  if (u == "um") return 1e-6;
  if (u == "nm") return 1e-9;
  if (u == "pm") return 1e-12;
  if (u == "A" || u == "\xC3\x85" || u == "\xE2\x84\xAB") return 1e-10;  // A, Å (U+00C5, U+212B)
  std::string lower = u;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "metre" || lower == "meter" || lower == "metres" || lower == "meters") return 1.0;
  if (lower == "micron" || lower == "microns" || lower == "micrometre" || lower == "micrometer" ||
      lower == "micrometres" || lower == "micrometers")
    return 1e-6;
  if (lower == "nanometre" || lower == "nanometer" || lower == "nanometres" || lower == "nanometers")
    return 1e-9;
  if (lower == "millimetre" || lower == "millimeter" || lower == "millimetres" || lower == "millimeters")
    return 1e-3;
  if (lower == "angstrom" || lower == "angstroms") return 1e-10;
  return 0.0;
}

// ---- ByteReader ----

void ByteReader::fail_at(std::size_t at, const std::string& why) const {
  throw InputError(path_, "offset " + std::to_string(at) + ": " + why);
}

void ByteReader::need(std::size_t n, const char* what) {
  if (n > remaining())
    fail("the file ends inside " + std::string(what) + " (" + std::to_string(n) + " bytes needed, " +
         std::to_string(remaining()) + " left): truncated file?");
}

void ByteReader::seek(std::size_t pos) {
  if (pos > b_.size())
    fail("a position beyond the end of the file (" + std::to_string(pos) + " of " +
         std::to_string(b_.size()) + " bytes) was asked for: truncated or corrupt file");
  pos_ = pos;
}

void ByteReader::skip(std::size_t n) {
  need(n, "a field");
  pos_ += n;
}

std::string_view ByteReader::bytes(std::size_t n) {
  need(n, "a block of data");
  const std::string_view v = b_.substr(pos_, n);
  pos_ += n;
  return v;
}

namespace {
template <typename T>
T load_le(std::string_view b) {
  std::array<unsigned char, sizeof(T)> raw{};
  std::memcpy(raw.data(), b.data(), sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(raw.begin(), raw.end());
  T v;
  std::memcpy(&v, raw.data(), sizeof(T));
  return v;
}
}  // namespace

std::uint8_t ByteReader::u8() {
  need(1, "a byte");
  return static_cast<std::uint8_t>(b_[pos_++]);
}
std::uint16_t ByteReader::u16le() {
  need(2, "a 16-bit integer");
  const auto v = load_le<std::uint16_t>(b_.substr(pos_));
  pos_ += 2;
  return v;
}
std::int16_t ByteReader::i16le() { return static_cast<std::int16_t>(u16le()); }
std::uint32_t ByteReader::u32le() {
  need(4, "a 32-bit integer");
  const auto v = load_le<std::uint32_t>(b_.substr(pos_));
  pos_ += 4;
  return v;
}
std::int32_t ByteReader::i32le() { return static_cast<std::int32_t>(u32le()); }
std::uint64_t ByteReader::u64le() {
  need(8, "a 64-bit integer");
  const auto v = load_le<std::uint64_t>(b_.substr(pos_));
  pos_ += 8;
  return v;
}
float ByteReader::f32le() { return std::bit_cast<float>(u32le()); }
double ByteReader::f64le() { return std::bit_cast<double>(u64le()); }

std::string ByteReader::cstring(std::size_t max_len) {
  const std::size_t start = pos_;
  const std::size_t limit = std::min(remaining(), max_len + 1);
  const std::size_t nul = b_.substr(pos_, limit).find('\0');
  if (nul == std::string_view::npos) {
    if (limit == remaining() && remaining() <= max_len)
      fail("the file ends inside a string: truncated file?");
    fail_at(start, "a string longer than " + std::to_string(max_len) + " bytes ('" +
                       excerpt(b_.substr(start, 40)) + "'): corrupt file?");
  }
  std::string s(b_.substr(pos_, nul));
  pos_ += nul + 1;
  return s;
}

}  // namespace io_detail

// ---------------------------------------------------------------------------------------
// Dispatch

namespace {

using namespace io_detail;

enum class Format { Text, NetCdf, X3p, Npy, Gwy, Sur };

Format detect(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 12> m{};
  in.read(m.data(), m.size());
  const std::string_view head(m.data(), static_cast<std::size_t>(in.gcount()));
  if (head.starts_with("PK\x03\x04") || head.starts_with("PK\x05\x06")) return Format::X3p;
  if (head.starts_with("GWYP")) return Format::Gwy;
  if (head.starts_with("DIGITAL SURF") || head.starts_with("DSCOMPRESSED")) return Format::Sur;
  if (head.starts_with("\x93NUMPY")) return Format::Npy;
  if (head.size() >= 4 && head.starts_with("CDF") && (head[3] == 1 || head[3] == 2 || head[3] == 5))
    return Format::NetCdf;
  if (head.starts_with("\x89HDF\r\n\x1a\n")) return Format::NetCdf;
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".nc") return Format::NetCdf;
  const auto binary_ext = [&](const char* e, const char* what) {
    if (ext == e)
      throw InputError(path, std::string("the file's name says ") + what +
                                 " but it does not start with that format's signature ('" + excerpt(head) +
                                 "'): wrong or damaged file");
  };
  binary_ext(".x3p", "x3p (a zip archive)");
  binary_ext(".npy", "NumPy .npy");
  binary_ext(".gwy", "Gwyddion .gwy");
  binary_ext(".sur", "Digital Surf .sur");
  return Format::Text;
}

void check_readable(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    throw InputError(path, "cannot open the topography file: no such file");
  require_regular_file(path, "topography file");
}

double choose_size(const std::string& path, const char* name, double arg, double from_file,
                   const std::string& how_in_file) {
  if (arg > 0.0) {
    if (!std::isfinite(arg))
      throw InputError(path, std::string(name) + " must be finite (got " + num(arg) + ")");
    return arg;  // the caller's value wins over the file
  }
  if (std::isnan(arg)) throw InputError(path, std::string(name) + " is NaN");
  if (from_file > 0.0) return from_file;
  throw InputError(path, std::string("no physical size ") + name + ": the file has no " + how_in_file +
                             " and no " + name + " > 0 was given");
}

std::string size_source(const std::string& format) {
  if (format == "text") return "'# lx = <value>' or '# ly = <value>' header line";
  if (format == "netcdf") return "attribute 'lx'/'ly' or 1-D coordinate variable";
  return "physical size (" + format + " files never carry one)";
}

}  // namespace

double metres_per_unit(std::string_view unit) { return io_detail::metres_per_unit(unit); }

HeightMap read_height_file(const std::string& path) {
  check_readable(path);
  HeightMap m;
  switch (detect(path)) {
    case Format::NetCdf:
      m = read_netcdf_map(path);
      break;
    case Format::X3p:
      m = read_x3p(path);
      break;
    case Format::Npy:
      m = read_npy(path);
      break;
    case Format::Gwy:
      m = read_gwy(path);
      break;
    case Format::Sur:
      m = read_sur(path);
      break;
    case Format::Text:
      m = read_text_map(path);
      break;
  }
  if (m.h.size() != static_cast<std::size_t>(m.nx) * static_cast<std::size_t>(m.ny))
    throw InputError(path, "internal error: the reader returned a map of the wrong size");
  std::size_t missing = 0;
  for (const double v : m.h) {
    if (std::isnan(v))
      ++missing;
    else if (!std::isfinite(v))
      throw InputError(path, "an infinite height: not a height map value");
  }
  m.missing = missing;
  return m;
}

std::string missing_points_message(std::size_t count, const std::string& first) {
  return std::to_string(count) + " point" + (count == 1 ? " has" : "s have") +
         " no value (NaN or the file's no-data marker)" +
         (first.empty() ? std::string() : ", the first at " + first) +
         "; set indenter.missing = \"interpolate\" or \"mean\" to fill them";
}

HeightMap read_height_map(const std::string& path, double lx, double ly) {
  HeightMap m = read_height_file(path);
  if (m.missing > 0) throw InputError(path, missing_points_message(m.missing, m.first_missing));
  const std::string how = size_source(m.format);
  // One side known (given or from the file) gives the other by square pixels.
  const double known_x = lx > 0 ? lx : m.lx, known_y = ly > 0 ? ly : m.ly;
  if (!(ly > 0) && !(m.ly > 0) && known_x > 0 && std::isfinite(known_x)) m.ly = known_x * m.ny / m.nx;
  if (!(lx > 0) && !(m.lx > 0) && known_y > 0 && std::isfinite(known_y)) m.lx = known_y * m.nx / m.ny;
  m.lx = choose_size(path, "lx", lx, m.lx, how);
  m.ly = choose_size(path, "ly", ly, m.ly, how);
  return m;
}

}  // namespace gfmd
