// The io part's one NetCDF file handle (private to io): owns a NetCDF id and words its errors.
#pragma once

#include <netcdf.h>

#include <string>
#include <utility>

#include "gfmd/core/error.hpp"

namespace gfmd::io_detail {

// "<why>: <NetCDF's text for status st>", the wording of every NetCDF error in io.
inline std::string nc_message(int st, const std::string& why) { return why + ": " + nc_strerror(st); }

// A NetCDF file, open or not. The destructor closes an open file and ignores the status (a
// reader's close, or the clean-up after an error); a writer calls close() and checks it.
class NcFile {
 public:
  explicit NcFile(std::string path) : path_(std::move(path)) {}
  NcFile(const NcFile&) = delete;
  NcFile& operator=(const NcFile&) = delete;
  ~NcFile() {
    if (id_ >= 0) nc_close(id_);
  }

  // Open the file read-only, or create it with cmode (NC_NETCDF4 | NC_CLOBBER, ...), on a
  // handle that is not open. Return the NetCDF status; the file is open only on NC_NOERR.
  [[nodiscard]] int open_read() { return adopt(nc_open(path_.c_str(), NC_NOWRITE, &id_)); }
  [[nodiscard]] int create(int cmode) { return adopt(nc_create(path_.c_str(), cmode, &id_)); }

  // Closes the file and returns nc_close's status: a write that the library could not
  // finish (disk full, I/O error) may fail only here. The handle is closed either way.
  [[nodiscard]] int close() { return nc_close(std::exchange(id_, -1)); }

  [[nodiscard]] int id() const { return id_; }
  [[nodiscard]] const std::string& path() const { return path_; }

  // Throws InputError(path, nc_message(st, why)) unless st is NC_NOERR.
  void check(int st, const std::string& why) const {
    if (st != NC_NOERR) throw InputError(path_, nc_message(st, why));
  }

 private:
  int adopt(int st) {
    if (st != NC_NOERR) id_ = -1;
    return st;
  }

  std::string path_;
  int id_ = -1;
};

}  // namespace gfmd::io_detail
