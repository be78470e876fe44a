// NetCDF height maps (classic and NetCDF-4). See include/gfmd/io/height_map.hpp.
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "nc_file.hpp"
#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

bool positive_finite(double v) { return v > 0.0 && std::isfinite(v); }

// netcdf-c (4.9) reads the data of a truncated classic-format file (CDF-1/2/5) as zeros
// without reporting an error. We therefore parse the classic header (big-endian; see the
// NetCDF classic format specification) to find where every variable's data ends and
// compare with the file size. Returns the number of bytes the header implies (0 when it
// cannot be determined, e.g. a streamed record count), or throws on a malformed header.
class ClassicHeader {
 public:
  struct NeedMore {};  // thrown when the bytes given end inside the header

  ClassicHeader(const std::string& path, std::vector<unsigned char> bytes, bool complete)
      : path_(path), b_(std::move(bytes)), complete_(complete) {}

  std::uint64_t required_size() {
    if (b_.size() < 4) fail();
    const int version = b_[3];
    wide_ = version == 5;                         // CDF-5: 64-bit counts
    wide_offset_ = version == 2 || version == 5;  // CDF-2/5: 64-bit begin
    const std::uint64_t numrecs = count();
    const bool streaming = !wide_ && numrecs == 0xFFFFFFFFull;
    // Dimensions.
    std::vector<std::uint64_t> dim_len;
    const std::uint64_t ndims = list_header(0x0A);
    for (std::uint64_t i = 0; i < ndims; ++i) {
      skip_name();
      dim_len.push_back(count());
    }
    skip_atts();
    struct Var {
      std::uint64_t size, vsize, begin;
      bool record;
    };
    std::vector<Var> vars;
    const std::uint64_t nvars = list_header(0x0B);
    for (std::uint64_t v = 0; v < nvars; ++v) {
      skip_name();
      const std::uint64_t nd = count();
      bool record = false;
      std::uint64_t elems = 1;
      for (std::uint64_t d = 0; d < nd; ++d) {
        const std::uint64_t id = count();
        if (id >= dim_len.size()) fail();
        if (d == 0 && dim_len[id] == 0)
          record = true;
        else
          elems = mul(elems, dim_len[id]);
      }
      skip_atts();
      const std::uint64_t tsize = type_size(static_cast<int>(u32()));
      const std::uint64_t vsize = count();
      const std::uint64_t begin = wide_offset_ ? u64() : u32();
      vars.push_back({mul(elems, tsize), vsize, begin, record});
    }
    std::uint64_t need = pos_;
    std::uint64_t recsize = 0;
    int nrec = 0;
    for (const auto& v : vars)
      if (v.record) {
        recsize += v.vsize;
        ++nrec;
      }
    for (const auto& v : vars) {
      if (!v.record) {
        need = std::max(need, add(v.begin, v.size));
      } else if (!streaming && numrecs > 0) {
        const std::uint64_t rs = nrec == 1 ? v.size : recsize;
        need = std::max(need, add(add(v.begin, mul(numrecs - 1, rs)), v.size));
      }
    }
    return need;
  }

 private:
  [[noreturn]] void fail() const {
    if (!complete_) throw NeedMore{};
    throw InputError(path_, std::string("corrupt NetCDF header: ") + nc_strerror(NC_ETRUNC));
  }
  std::uint64_t u32() {
    if (pos_ + 4 > b_.size()) fail();
    std::uint64_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | b_[pos_++];
    return v;
  }
  std::uint64_t u64() { return (u32() << 32) | u32(); }
  std::uint64_t count() { return wide_ ? u64() : u32(); }
  static std::uint64_t pad4(std::uint64_t n) { return (n + 3) / 4 * 4; }
  std::uint64_t add(std::uint64_t a, std::uint64_t b) const {
    if (a > std::numeric_limits<std::uint64_t>::max() - b) fail();
    return a + b;
  }
  std::uint64_t mul(std::uint64_t a, std::uint64_t b) const {
    if (b != 0 && a > std::numeric_limits<std::uint64_t>::max() / b) fail();
    return a * b;
  }
  void skip(std::uint64_t n) {
    if (n > b_.size() - pos_) fail();
    pos_ += n;
  }
  // A list: tag (or ZERO for absent) and element count.
  std::uint64_t list_header(std::uint64_t tag) {
    const std::uint64_t t = u32();
    const std::uint64_t n = count();
    if (t == 0 && n == 0) return 0;
    if (t != tag) fail();
    return n;
  }
  void skip_name() { skip(pad4(count())); }
  static std::uint64_t type_size(int type) {
    switch (type) {
      case NC_BYTE:
      case NC_CHAR:
      case NC_UBYTE:
        return 1;
      case NC_SHORT:
      case NC_USHORT:
        return 2;
      case NC_INT:
      case NC_UINT:
      case NC_FLOAT:
        return 4;
      case NC_DOUBLE:
      case NC_INT64:
      case NC_UINT64:
        return 8;
      default:
        return 0;
    }
  }
  void skip_atts() {
    const std::uint64_t n = list_header(0x0C);
    for (std::uint64_t i = 0; i < n; ++i) {
      skip_name();
      const std::uint64_t ts = type_size(static_cast<int>(u32()));
      if (ts == 0) fail();
      skip(pad4(mul(count(), ts)));
    }
  }

  std::string path_;
  std::vector<unsigned char> b_;
  bool complete_ = true;
  std::size_t pos_ = 4;
  bool wide_ = false, wide_offset_ = false;
};

void check_classic_not_truncated(const std::string& path) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot determine the file size: " + ec.message());
  // The header has no length field: parse the first 64 KiB, and the whole file if the
  // header is longer than that.
  // A header is at most 16 MiB here: longer ones (names of megabytes) are refused, not read whole.
  constexpr std::uint64_t kMaxHeader = std::uint64_t{16} << 20;
  for (std::uint64_t chunk : {std::uint64_t{1} << 16, kMaxHeader}) {
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes(static_cast<std::size_t>(std::min(chunk, size)));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (static_cast<std::uint64_t>(in.gcount()) != bytes.size()) throw InputError(path, "read error");
    const bool complete = bytes.size() == size;
    try {
      const std::uint64_t need = ClassicHeader(path, std::move(bytes), complete).required_size();
      if (need > size)
        throw InputError(path, "the file has " + std::to_string(size) + " bytes but its header describes " +
                                   std::to_string(need) + " (" + nc_strerror(NC_ETRUNC) + ")");
      return;
    } catch (const ClassicHeader::NeedMore&) {
      if (chunk == kMaxHeader)
        throw InputError(
            path, "corrupt NetCDF header: longer than 16 MiB (" + std::string(nc_strerror(NC_ENOTNC)) + ")");
    }
  }
}

bool numeric_type(nc_type t) {
  switch (t) {
    case NC_BYTE:
    case NC_SHORT:
    case NC_INT:
    case NC_FLOAT:
    case NC_DOUBLE:
    case NC_UBYTE:
    case NC_USHORT:
    case NC_UINT:
    case NC_INT64:
    case NC_UINT64:
      return true;
    default:
      return false;
  }
}

// Scalar numeric attribute of a variable (or NC_GLOBAL); nullopt if absent.
std::optional<double> nc_scalar_att(const NcFile& f, int varid, const char* name) {
  nc_type type{};
  std::size_t len = 0;
  if (nc_inq_att(f.id(), varid, name, &type, &len) != NC_NOERR) return std::nullopt;
  if (!numeric_type(type) || len != 1)
    throw InputError(f.path(), std::string("attribute '") + name + "' must be a single number");
  double v = 0.0;
  f.check(nc_get_att_double(f.id(), varid, name, &v),
          std::string("NetCDF error while reading attribute ") + name);
  return v;
}

std::optional<std::string> nc_text_att(const NcFile& f, int varid, const char* name) {
  nc_type type{};
  std::size_t len = 0;
  if (nc_inq_att(f.id(), varid, name, &type, &len) != NC_NOERR) return std::nullopt;
  if (type != NC_CHAR || len > 256)
    throw InputError(f.path(), std::string("attribute '") + name + "' must be a short text");
  std::string s(len, '\0');
  f.check(nc_get_att_text(f.id(), varid, name, s.data()),
          std::string("NetCDF error while reading attribute ") + name);
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

// Cell length along a dimension from a 1-D coordinate variable: spacing * count; *unit
// receives the variable's "units" attribute ("" when it has none).
std::optional<double> nc_coordinate_length(const NcFile& f, int dimid, const char* fallback,
                                           std::string* unit) {
  char dimname[NC_MAX_NAME + 1] = {};
  std::size_t n = 0;
  f.check(nc_inq_dim(f.id(), dimid, dimname, &n), "NetCDF error while reading a dimension");
  for (const char* name : {static_cast<const char*>(dimname), fallback}) {
    int varid = -1;
    if (nc_inq_varid(f.id(), name, &varid) != NC_NOERR) continue;
    int ndims = 0;
    int dims[NC_MAX_VAR_DIMS];
    nc_type type{};
    f.check(nc_inq_var(f.id(), varid, nullptr, &type, &ndims, dims, nullptr),
            "NetCDF error while reading a coordinate variable");
    if (ndims != 1 || !numeric_type(type)) continue;
    std::size_t len = 0;
    f.check(nc_inq_dimlen(f.id(), dims[0], &len), "NetCDF error while reading a dimension");
    if (len != n || n < 2) continue;
    std::vector<double> c(n);
    f.check(nc_get_var_double(f.id(), varid, c.data()),
            std::string("NetCDF error while reading coordinate variable ") + name);
    const double d = (c[n - 1] - c[0]) / static_cast<double>(n - 1);
    bool uniform = positive_finite(d);
    for (std::size_t i = 0; uniform && i + 1 < n; ++i) uniform = std::abs((c[i + 1] - c[i]) - d) <= 1e-6 * d;
    if (!uniform)
      throw InputError(f.path(),
                       std::string("coordinate variable '") + name +
                           "' is not uniformly increasing, so the cell size cannot be taken from it");
    *unit = nc_text_att(f, varid, "units").value_or("");
    return d * static_cast<double>(n);
  }
  return std::nullopt;
}

}  // namespace

HeightMap read_netcdf_map(const std::string& path) {
  // A classic-format header is checked by our own parser before netcdf-c sees it: netcdf-c
  // 4.9 reads some hostile headers out of bounds (a CDF-5 attribute count near 2^64 makes
  // it copy a negative length), and reads truncated data as zeros.
  {
    std::ifstream in(path, std::ios::binary);
    char m[4] = {};
    in.read(m, 4);
    if (in.gcount() == 4 && m[0] == 'C' && m[1] == 'D' && m[2] == 'F' &&
        (m[3] == 1 || m[3] == 2 || m[3] == 5))
      check_classic_not_truncated(path);
  }
  NcFile f(path);
  f.check(f.open_read(), "cannot read the NetCDF file");
  int varid = -1;
  std::string varname;
  for (const char* name : {"topography", "height", "heights"}) {
    if (nc_inq_varid(f.id(), name, &varid) == NC_NOERR) {
      varname = name;
      break;
    }
  }
  if (varname.empty()) {
    std::string present;
    int nvars = 0;
    f.check(nc_inq_nvars(f.id(), &nvars), "NetCDF error while listing variables");
    for (int v = 0; v < nvars; ++v) {
      char name[NC_MAX_NAME + 1] = {};
      f.check(nc_inq_varname(f.id(), v, name), "NetCDF error while listing variables");
      present += (present.empty() ? "" : ", ") + std::string(name);
    }
    throw InputError(path, "no variable named 'topography', 'height' or 'heights' (variables present: " +
                               (present.empty() ? std::string("none") : present) + ")");
  }
  nc_type type{};
  int ndims = 0;
  int dims[NC_MAX_VAR_DIMS];
  f.check(nc_inq_var(f.id(), varid, nullptr, &type, &ndims, dims, nullptr),
          "NetCDF error while reading variable " + varname);
  if (ndims != 2)
    throw InputError(
        path, "variable '" + varname + "' has " + std::to_string(ndims) + " dimensions; expected 2 (y, x)");
  if (!numeric_type(type)) throw InputError(path, "variable '" + varname + "' is not numeric");
  std::size_t ny = 0, nx = 0;
  f.check(nc_inq_dimlen(f.id(), dims[0], &ny), "NetCDF error while reading dimension lengths");
  f.check(nc_inq_dimlen(f.id(), dims[1], &nx), "NetCDF error while reading dimension lengths");
  if (nx == 0 || ny == 0) throw InputError(path, "variable '" + varname + "' is empty (no data)");
  check_map_dims(path, static_cast<long long>(std::min<std::size_t>(nx, 1u << 30)),
                 static_cast<long long>(std::min<std::size_t>(ny, 1u << 30)));

  HeightMap t;
  t.format = "netcdf";
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  t.h.resize(nx * ny);
  f.check(nc_get_var_double(f.id(), varid, t.h.data()), "NetCDF error while reading variable " + varname);

  // Missing data: the fill value (the _FillValue attribute or the type's default) of any
  // numeric type, and a CF "missing_value" attribute, compared before scaling.
  std::optional<double> fill;
  {
    int no_fill = 0;
    alignas(8) unsigned char fv[8] = {};
    if (nc_inq_var_fill(f.id(), varid, &no_fill, fv) == NC_NOERR && !no_fill) {
      const auto as = [&fv]<typename T>(T) {
        T v;
        std::memcpy(&v, fv, sizeof v);
        return static_cast<double>(v);
      };
      switch (type) {
        case NC_BYTE:
          fill = as(static_cast<signed char>(0));
          break;
        case NC_UBYTE:
          fill = as(static_cast<unsigned char>(0));
          break;
        case NC_SHORT:
          fill = as(static_cast<short>(0));
          break;
        case NC_USHORT:
          fill = as(static_cast<unsigned short>(0));
          break;
        case NC_INT:
          fill = as(0);
          break;
        case NC_UINT:
          fill = as(0u);
          break;
        case NC_INT64:
          fill = as(0LL);
          break;
        case NC_UINT64:
          fill = as(0ULL);
          break;
        case NC_FLOAT:
          fill = as(0.0f);
          break;
        default:
          fill = as(0.0);
          break;
      }
    }
  }
  const std::optional<double> missing_value = nc_scalar_att(f, varid, "missing_value");
  for (std::size_t i = 0; i < t.h.size(); ++i) {
    double& v = t.h[i];
    if (std::isinf(v))
      throw InputError(path, "infinite value in '" + varname + "' at (iy, ix) = (" + std::to_string(i / nx) +
                                 ", " + std::to_string(i % nx) + ")");
    if (std::isnan(v) || (fill && v == *fill) || (missing_value && v == *missing_value)) {
      v = std::nan("");
      if (t.first_missing.empty())
        t.first_missing = "(iy, ix) = (" + std::to_string(i / nx) + ", " + std::to_string(i % nx) + ")";
    }
  }
  const auto scale = nc_scalar_att(f, varid, "scale_factor");
  const auto offset = nc_scalar_att(f, varid, "add_offset");
  if (scale || offset) {
    const double a = scale.value_or(1.0), b = offset.value_or(0.0);
    for (double& v : t.h) v = v * a + b;
  }

  // Units: the variable's "units" (heights, and lx/ly attributes); a coordinate variable's
  // own "units" for a size taken from it.
  const std::string zunit = nc_text_att(f, varid, "units").value_or("");
  const double zf = zunit.empty() ? 1.0 : metres_per_unit(zunit);
  if (zf == 0.0)
    throw InputError(path, "variable '" + varname + "' has units '" + excerpt(zunit) +
                               "', not a length unit (m, mm, um, nm, pm or A)");
  auto size_from_file = [&](const char* name, int dimid, const char* coord) -> double {
    std::optional<double> v = nc_scalar_att(f, varid, name);
    if (!v) v = nc_scalar_att(f, NC_GLOBAL, name);
    if (v && !positive_finite(*v))
      throw InputError(path, std::string("attribute '") + name + "' must be positive (got " + num(*v) + ")");
    if (v) return *v * zf;
    std::string cunit;
    v = nc_coordinate_length(f, dimid, coord, &cunit);
    if (!v) return 0.0;
    if (cunit.empty()) return *v * zf;
    const double cf = metres_per_unit(cunit);
    if (cf == 0.0)
      throw InputError(path, std::string("coordinate variable of ") + coord + " has units '" +
                                 excerpt(cunit) + "', not a length unit");
    if (zunit.empty())
      throw InputError(path, std::string("the coordinates have units ('") + excerpt(cunit) +
                                 "') but variable '" + varname + "' has none: give it a units attribute");
    return *v * cf;
  };
  t.lx = size_from_file("lx", dims[1], "x");
  t.ly = size_from_file("ly", dims[0], "y");
  if (!zunit.empty()) {
    t.unit = std::string(1, 'm');
    for (double& v : t.h) v *= zf;
  }
  return t;
}

}  // namespace gfmd::io_detail
