// NumPy .npy height maps (format versions 1.0, 2.0 and 3.0): a 2-D array of floats or
// integers, indexed [iy, ix]. The format carries neither a physical size nor units.
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>

#include "gfmd/core/files.hpp"
#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

// The value of key 'name' in the header's Python dict literal, as text (up to the next
// top-level comma or closing brace).
std::string_view dict_value(const ByteReader& r, std::string_view dict, std::string_view name) {
  for (const char q : {'\'', '"'}) {
    const std::string quote(1, q);
    const std::string key = cat(quote, name, quote);
    const std::size_t k = dict.find(key);
    if (k == std::string_view::npos) continue;
    std::size_t p = dict.find(':', k + key.size());
    if (p == std::string_view::npos) break;
    ++p;
    while (p < dict.size() && dict[p] == ' ') ++p;
    std::size_t e = p;
    int depth = 0;
    while (e < dict.size() && !(depth == 0 && (dict[e] == ',' || dict[e] == '}'))) {
      if (dict[e] == '(') ++depth;
      if (dict[e] == ')') --depth;
      ++e;
    }
    return dict.substr(p, e - p);
  }
  r.fail_at(10, "the .npy header has no '" + std::string(name) + "' entry ('" + excerpt(dict) + "')");
}

long long parse_int(const ByteReader& r, std::string_view s) {
  long long v = 0;
  bool any = false;
  for (const char c : s) {
    if (c == ' ' || c == 'L') continue;
    if (c < '0' || c > '9') r.fail_at(10, "the .npy shape holds '" + excerpt(s) + "', not a dimension");
    if (v > (1LL << 40)) r.fail_at(10, "the .npy shape holds a dimension too large to read");
    v = v * 10 + (c - '0');
    any = true;
  }
  if (!any) r.fail_at(10, "the .npy shape holds an empty dimension");
  return v;
}

}  // namespace

HeightMap read_npy(const std::string& path) {
  // The data size is checked against the header below; 2^28 doubles plus a header.
  const std::string bytes = read_regular_file(path, (std::size_t{1} << 31) + (1 << 20), "topography file");
  ByteReader r(path, bytes);
  if (r.bytes(6) != "\x93NUMPY") r.fail_at(0, "not a .npy file (no \\x93NUMPY signature)");
  const int major = r.u8();
  r.u8();  // minor
  if (major < 1 || major > 3)
    r.fail_at(6, ".npy format version " + std::to_string(major) + " is not known (1, 2 or 3)");
  const std::size_t hlen = major == 1 ? r.u16le() : r.u32le();
  const std::string_view dict = r.bytes(hlen);
  const std::string_view descr_q = dict_value(r, dict, "descr");
  if (descr_q.size() < 5 || (descr_q.front() != '\'' && descr_q.front() != '"'))
    r.fail_at(10,
              "the .npy dtype '" + excerpt(descr_q) + "' is not a plain numeric type (a structured array?)");
  const std::string_view descr = descr_q.substr(1, descr_q.size() - 2);
  const char order = descr[0];
  const char kind = descr.size() >= 3 ? descr[1] : '?';
  const std::string_view width_text = descr.size() >= 3 ? descr.substr(2) : std::string_view();
  const int width = width_text == "1"   ? 1
                    : width_text == "2" ? 2
                    : width_text == "4" ? 4
                    : width_text == "8" ? 8
                                        : 0;
  const bool ok_kind =
      (kind == 'f' && (width == 4 || width == 8)) || ((kind == 'i' || kind == 'u') && width > 0);
  if (!ok_kind || (order != '<' && order != '>' && order != '|' && order != '='))
    r.fail_at(10, "the .npy dtype '" + excerpt(descr) +
                      "' is not supported (float32/64 or integers of 1 to 8 bytes, either byte order)");
  const bool big = order == '>' || (order == '=' && std::endian::native == std::endian::big);
  const std::string_view fortran = dict_value(r, dict, "fortran_order");
  const bool col_major = fortran.starts_with("True");
  if (!col_major && !fortran.starts_with("False"))
    r.fail_at(10, "the .npy fortran_order is '" + excerpt(fortran) + "', not True or False");
  std::string_view shape = dict_value(r, dict, "shape");
  if (shape.size() < 2 || shape.front() != '(' || shape.back() != ')')
    r.fail_at(10, "the .npy shape '" + excerpt(shape) + "' is not a tuple");
  shape = shape.substr(1, shape.size() - 2);
  while (!shape.empty() && (shape.back() == ' ' || shape.back() == ',')) shape.remove_suffix(1);
  const std::size_t comma = shape.find(',');
  if (comma == std::string_view::npos || shape.find(',', comma + 1) != std::string_view::npos)
    r.fail_at(10, "the array has shape (" + excerpt(shape) + "): a height map needs 2 dimensions (ny, nx)");
  const long long ny = parse_int(r, shape.substr(0, comma));
  const long long nx = parse_int(r, shape.substr(comma + 1));
  check_map_dims(path, nx, ny);
  const std::size_t n = static_cast<std::size_t>(nx * ny);
  if (n * static_cast<std::size_t>(width) != r.remaining())
    r.fail("the header describes " + std::to_string(ny) + " x " + std::to_string(nx) + " values of " +
           std::to_string(width) + " bytes (" + std::to_string(n * static_cast<std::size_t>(width)) +
           " bytes) but " + std::to_string(r.remaining()) + " bytes of data follow");

  HeightMap t;
  t.format = "npy";
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  t.h.resize(n);
  const std::string_view data = r.bytes(n * static_cast<std::size_t>(width));
  for (std::size_t k = 0; k < n; ++k) {
    unsigned char raw[8];
    std::memcpy(raw, data.data() + k * static_cast<std::size_t>(width), static_cast<std::size_t>(width));
    if (big != (std::endian::native == std::endian::big))
      for (int a = 0, b = width - 1; a < b; ++a, --b) std::swap(raw[a], raw[b]);
    double v = 0.0;
    if (kind == 'f') {
      if (width == 8) {
        double d;
        std::memcpy(&d, raw, 8);
        v = d;
      } else {
        float f;
        std::memcpy(&f, raw, 4);
        v = f;
      }
    } else {
      std::uint64_t u = 0;
      std::memcpy(&u, raw, static_cast<std::size_t>(width));  // little-endian host
      if (kind == 'i' && width < 8 && (u >> (8 * width - 1)) & 1) u |= ~std::uint64_t{0} << (8 * width);
      v = kind == 'i' ? static_cast<double>(static_cast<std::int64_t>(u)) : static_cast<double>(u);
    }
    // C order: k = iy * nx + ix; Fortran order: k = ix * ny + iy.
    const std::size_t idx = col_major ? (k % static_cast<std::size_t>(ny)) * static_cast<std::size_t>(nx) +
                                            k / static_cast<std::size_t>(ny)
                                      : k;
    t.h[idx] = v;
    if (std::isnan(v) && t.first_missing.empty())
      t.first_missing = "(iy, ix) = (" + std::to_string(idx / static_cast<std::size_t>(nx)) + ", " +
                        std::to_string(idx % static_cast<std::size_t>(nx)) + ")";
  }
  return t;
}

}  // namespace gfmd::io_detail
