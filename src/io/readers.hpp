// The height-map readers, one per file format, and what they share: bounded binary
// reading with offsets in the errors, units, size limits. Private to io; the public entry
// is read_height_file in include/gfmd/io/height_map.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "gfmd/core/error.hpp"
#include "gfmd/io/height_map.hpp"

namespace gfmd::io_detail {

// ---- one reader per format; each returns a HeightMap as documented in height_map.hpp ----
HeightMap read_text_map(const std::string& path);    // whitespace / CSV / TSV matrix
HeightMap read_netcdf_map(const std::string& path);  // NetCDF (classic or 4)
HeightMap read_x3p(const std::string& path);         // ISO 25178-72 (zip + XML)
HeightMap read_npy(const std::string& path);         // NumPy .npy (format 1.0/2.0/3.0)
HeightMap read_gwy(const std::string& path);         // Gwyddion native .gwy
HeightMap read_sur(const std::string& path);         // Digital Surf .sur

// ---- limits, checked before any allocation that a file's header asks for ----
// A map has 1 .. kMaxMapSide points per side and at most kMaxMapPoints in all (2 GiB of
// doubles); the solver's grid has the same per-side limit.
inline constexpr long long kMaxMapSide = 65536;
inline constexpr long long kMaxMapPoints = 1LL << 28;
// Throws InputError(path, "... NX x NY ...") when the dimensions are out of range.
void check_map_dims(const std::string& path, long long nx, long long ny);

// ---- units ----
// Metres per unit for a length unit as files write it: m, cm, mm, um (also µm in either
// Unicode spelling, "micron", "micrometer"), nm, pm, A / Å / Angstrom, case-insensitive for
// the spelled-out names. Returns 0 for anything else (the caller names the unit in its error).
double metres_per_unit(std::string_view unit);

// ---- bounded little/big-endian reading of a byte buffer ----
// Every read checks the bytes left and fails with InputError(path, "offset N: <reason>").
class ByteReader {
 public:
  ByteReader(std::string path, std::string_view bytes) : path_(std::move(path)), b_(bytes) {}

  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return b_.size() - pos_; }
  [[nodiscard]] std::size_t size() const { return b_.size(); }
  [[nodiscard]] const std::string& path() const { return path_; }
  void seek(std::size_t pos);
  void skip(std::size_t n);
  // n raw bytes (a view into the buffer).
  std::string_view bytes(std::size_t n);
  std::uint8_t u8();
  std::uint16_t u16le();
  std::int16_t i16le();
  std::uint32_t u32le();
  std::int32_t i32le();
  std::uint64_t u64le();
  float f32le();
  double f64le();
  // A NUL-terminated string of at most max_len bytes (the NUL not counted).
  std::string cstring(std::size_t max_len);
  // Fails at the current offset (or at `at`) with the reason.
  [[noreturn]] void fail(const std::string& why) const { fail_at(pos_, why); }
  [[noreturn]] void fail_at(std::size_t at, const std::string& why) const;

 private:
  void need(std::size_t n, const char* what);
  std::string path_;
  std::string_view b_;
  std::size_t pos_ = 0;
};

// A short, printable excerpt of bytes or text for an error message (at most 40 characters,
// non-printable bytes as \xNN).
std::string excerpt(std::string_view s);

// "%.10g"
std::string num(double v);

// Concatenation of strings and string views (written out so that GCC 12's -Wrestrict false
// positive on `"literal" + std::string&&` (GCC bug 105329) does not fire).
template <typename... A>
std::string cat(const A&... parts) {
  std::string s;
  (s.append(std::string_view(parts)), ...);
  return s;
}

}  // namespace gfmd::io_detail
