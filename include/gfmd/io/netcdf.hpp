// NetCDF field files: the one NetCDF writer and reader of fields on the grid.
//
// Writers are atomic: the data go to "<path>.tmp.<pid>" in the same directory, which is
// fsync'ed and renamed over <path>. On failure the temporary is removed, the old file (if
// any) is left untouched and an exception whose message starts with the path is thrown.
//
// Fields are row-major with x fastest: value(ix, iy) = f[iy * nx + ix], x(ix) = ix * dx.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "gfmd/core/grid.hpp"

namespace gfmd {

// One field to store in a NetCDF file. `data` points to grid.size() doubles.
struct NamedField {
  std::string name;
  const double* data = nullptr;
  std::string long_name;  // empty: the name is used
  std::string units;      // empty: no units attribute
};

// Writes a NetCDF-4 file (classic 64-bit offset if the library lacks NetCDF-4) with
// dimensions y = ny, x = nx, coordinate variables x(x) = ix*dx, y(y) = iy*dy (attribute
// units = length_unit when non-empty), one double variable (y, x) per field with attributes
// long_name and units, global double attributes lx and ly and the given global text
// attributes (e.g. "gfmd_version", "git_commit", "input_toml", "normalisation").
// Written atomically. Field names must be distinct and different from "x" and "y"; global
// attribute names must be distinct and different from "lx" and "ly".
// Throws std::runtime_error (InputError for bad arguments) naming the path.
void write_fields_netcdf(const std::string& path, const Grid& grid, const std::vector<NamedField>& fields,
                         const std::vector<std::pair<std::string, std::string>>& global_attrs,
                         const std::string& length_unit = "");

// Reads one 2D variable (dims y, x) back as doubles: returns the data (x fastest) and sets
// nx, ny. Throws InputError(path, reason) if the file cannot be read, the variable is
// missing or is not two-dimensional.
std::vector<double> read_netcdf_field(const std::string& path, const std::string& var, int& nx, int& ny);

}  // namespace gfmd
