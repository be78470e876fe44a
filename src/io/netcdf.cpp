// NetCDF field files. See include/gfmd/io/netcdf.hpp.
#include "gfmd/io/netcdf.hpp"

#include <hdf5.h>
#include <netcdf.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <stdexcept>
#include <system_error>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "nc_file.hpp"

namespace gfmd {

namespace {

using io_detail::nc_message;
using io_detail::NcFile;

// When a NetCDF-4 file cannot be written (disk full, I/O error), nc_close fails and HDF5
// keeps a half-closed file that its exit handler then dereferences: the process segfaults
// at exit (seen with Debian's HDF5 1.10; the Python interpreter too). Files are always
// closed explicitly here, so HDF5's exit-time clean-up is not needed: switch it off before
// the library starts (a no-op if something else started HDF5 first).
const bool kHdf5NoAtexit = [] {
  H5dont_atexit();
  return true;
}();

void put_text_att(const AtomicFile& t, int ncid, int varid, const std::string& name,
                  const std::string& value) {
  const int st = nc_put_att_text(ncid, varid, name.c_str(), value.size(), value.data());
  if (st != NC_NOERR) t.fail(nc_message(st, "cannot write attribute '" + name + "'"));
}

}  // namespace

// ---------------------------------------------------------------------------------------------

void write_fields_netcdf(const std::string& path, const Grid& grid, const std::vector<NamedField>& fields,
                         const std::vector<std::pair<std::string, std::string>>& global_attrs,
                         const std::string& length_unit) {
  if (grid.nx <= 0 || grid.ny <= 0) throw InputError(path, "grid must have nx, ny > 0");
  {
    std::set<std::string> names{"x", "y"};
    for (const auto& f : fields) {
      if (f.data == nullptr) throw InputError(path, "field '" + f.name + "' has no data");
      if (f.name.empty()) throw InputError(path, "field with an empty name");
      if (!names.insert(f.name).second)
        throw InputError(path, "duplicate or reserved field name '" + f.name + "'");
    }
    std::set<std::string> attrs{"lx", "ly"};
    for (const auto& a : global_attrs)
      if (!attrs.insert(a.first).second)
        throw InputError(path, "duplicate or reserved global attribute '" + a.first + "'");
  }

  AtomicFile target(path);
  {
    // A NetCDF-4 write that fails half-way leaves HDF5 with a half-closed file, which it may
    // dereference later (at exit, when another library started HDF5 before us, as
    // python3-netcdf4 does). So the space the file may need -- its uncompressed size -- is
    // checked first against the free space of its file system and the file-size limit.
    std::size_t attrs = 0;
    for (const auto& a : global_attrs) attrs += a.first.size() + a.second.size();
    for (const auto& f : fields) attrs += f.name.size() + f.long_name.size() + f.units.size() + 64;
    const double need =
        8.0 * (static_cast<double>(fields.size()) * static_cast<double>(grid.size()) + grid.nx + grid.ny) +
        static_cast<double>(attrs) + 65536.0 * (1.0 + static_cast<double>(fields.size()) / 8.0);
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    struct statvfs fs {};
    if (::statvfs(parent.empty() ? "." : parent.c_str(), &fs) == 0) {
      const double avail = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
      if (avail < need)
        target.fail("not enough space for the fields: up to " + std::to_string(static_cast<long long>(need)) +
                    " bytes needed, " + std::to_string(static_cast<long long>(avail)) + " free (" +
                    errno_message(ENOSPC) + ")");
    }
    rlimit rl{};
    if (::getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        static_cast<double>(rl.rlim_cur) < need)
      target.fail("the fields need up to " + std::to_string(static_cast<long long>(need)) +
                  " bytes, more than the file-size limit of " +
                  std::to_string(static_cast<long long>(rl.rlim_cur)) + " (ulimit -f; " +
                  errno_message(EFBIG) + ")");
  }
  NcFile nc(target.tmp());
  // errno after a failed call tells "HDF error" apart: disk full, quota, I/O error, ...
  auto check = [&](int st, const std::string& what) {
    if (st == NC_NOERR) return;
    const int err = errno;
    std::string why = nc_message(st, what);
    if (err == ENOSPC || err == EDQUOT || err == EFBIG || err == EIO || err == EROFS || err == EACCES)
      why += " (" + errno_message(err) + ")";
    target.fail(why);
  };

  bool nc4 = true;
  int st = nc.create(NC_NETCDF4 | NC_CLOBBER);
  if (st == NC_ENOTBUILT) {
    nc4 = false;
    st = nc.create(NC_64BIT_OFFSET | NC_CLOBBER);
  }
  if (st != NC_NOERR) target.fail(nc_message(st, "cannot create temporary file '" + nc.path() + "'"));
  int old_fill = 0;
  check(nc_set_fill(nc.id(), NC_NOFILL, &old_fill), "cannot set fill mode");

  int dim_y = 0, dim_x = 0;
  check(nc_def_dim(nc.id(), "y", static_cast<size_t>(grid.ny), &dim_y), "cannot define dimension y");
  check(nc_def_dim(nc.id(), "x", static_cast<size_t>(grid.nx), &dim_x), "cannot define dimension x");

  int var_x = 0, var_y = 0;
  check(nc_def_var(nc.id(), "x", NC_DOUBLE, 1, &dim_x, &var_x), "cannot define variable x");
  check(nc_def_var(nc.id(), "y", NC_DOUBLE, 1, &dim_y, &var_y), "cannot define variable y");
  put_text_att(target, nc.id(), var_x, "long_name", "x coordinate");
  put_text_att(target, nc.id(), var_y, "long_name", "y coordinate");
  put_text_att(target, nc.id(), var_x, "axis", "X");
  put_text_att(target, nc.id(), var_y, "axis", "Y");
  if (!length_unit.empty()) {
    put_text_att(target, nc.id(), var_x, "units", length_unit);
    put_text_att(target, nc.id(), var_y, "units", length_unit);
  }

  // Chunks of about 1 MiB of whole rows (or part of a row for huge nx).
  const std::size_t chunk_x = std::min<std::size_t>(static_cast<std::size_t>(grid.nx), 131072);
  const std::size_t chunk_y = std::clamp<std::size_t>(131072 / chunk_x, 1, static_cast<std::size_t>(grid.ny));
  const std::size_t chunks[2] = {chunk_y, chunk_x};

  std::vector<int> var_ids;
  var_ids.reserve(fields.size());
  const int dims[2] = {dim_y, dim_x};
  for (const auto& f : fields) {
    int v = 0;
    check(nc_def_var(nc.id(), f.name.c_str(), NC_DOUBLE, 2, dims, &v),
          "cannot define variable '" + f.name + "'");
    if (nc4) {
      check(nc_def_var_chunking(nc.id(), v, NC_CHUNKED, chunks), "cannot set chunking of '" + f.name + "'");
      check(nc_def_var_deflate(nc.id(), v, 1, 1, 1), "cannot set compression of '" + f.name + "'");
      // Each variable is written whole, in order: a cache of a few chunks suffices. The
      // library's default (16 MiB per variable) keeps that much per variable resident
      // until the file is closed: ~400 MiB for a 2048^2 fields.nc of 25 variables.
      check(nc_set_var_chunk_cache(nc.id(), v, 4 * chunk_x * chunk_y * sizeof(double), 17, 1.0f),
            "cannot set the chunk cache of '" + f.name + "'");
    }
    put_text_att(target, nc.id(), v, "long_name", f.long_name.empty() ? f.name : f.long_name);
    if (!f.units.empty()) put_text_att(target, nc.id(), v, "units", f.units);
    var_ids.push_back(v);
  }

  check(nc_put_att_double(nc.id(), NC_GLOBAL, "lx", NC_DOUBLE, 1, &grid.lx), "cannot write attribute 'lx'");
  check(nc_put_att_double(nc.id(), NC_GLOBAL, "ly", NC_DOUBLE, 1, &grid.ly), "cannot write attribute 'ly'");
  for (const auto& [name, value] : global_attrs) put_text_att(target, nc.id(), NC_GLOBAL, name, value);

  check(nc_enddef(nc.id()), "cannot leave define mode");

  std::vector<double> coord(static_cast<std::size_t>(std::max(grid.nx, grid.ny)));
  for (int i = 0; i < grid.nx; ++i) coord[static_cast<std::size_t>(i)] = grid.x(i);
  check(nc_put_var_double(nc.id(), var_x, coord.data()), "cannot write variable x");
  for (int i = 0; i < grid.ny; ++i) coord[static_cast<std::size_t>(i)] = grid.y(i);
  check(nc_put_var_double(nc.id(), var_y, coord.data()), "cannot write variable y");
  for (std::size_t i = 0; i < fields.size(); ++i)
    check(nc_put_var_double(nc.id(), var_ids[i], fields[i].data),
          "cannot write variable '" + fields[i].name + "'");

  check(nc.close(), "cannot close NetCDF file");
  target.sync_tmp();
  target.commit();
}

std::vector<double> read_netcdf_field(const std::string& path, const std::string& var, int& nx, int& ny) {
  NcFile nc(path);
  nc.check(nc.open_read(), "cannot open NetCDF file");
  int varid = 0;
  nc.check(nc_inq_varid(nc.id(), var.c_str(), &varid), "no variable '" + var + "'");
  int ndims = 0;
  nc.check(nc_inq_varndims(nc.id(), varid, &ndims), "variable '" + var + "'");
  if (ndims != 2)
    throw InputError(
        path, "variable '" + var + "' has " + std::to_string(ndims) + " dimensions, expected 2 (y, x)");
  int dimids[2] = {0, 0};
  std::size_t len[2] = {0, 0};
  int st = nc_inq_vardimid(nc.id(), varid, dimids);
  for (int d = 0; d < 2 && st == NC_NOERR; ++d) st = nc_inq_dimlen(nc.id(), dimids[d], &len[d]);
  nc.check(st, "variable '" + var + "'");
  if (len[0] > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
      len[1] > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InputError(path, "variable '" + var + "' is too large");
  std::vector<double> data(len[0] * len[1]);
  nc.check(nc_get_var_double(nc.id(), varid, data.data()), "cannot read variable '" + var + "'");
  ny = static_cast<int>(len[0]);
  nx = static_cast<int>(len[1]);
  return data;
}
}  // namespace gfmd
