// File output: atomic text writes, NetCDF field files and PNG maps.
//
// Every writer here is atomic: the data go to "<path>.tmp.<pid>" in the same directory,
// which is fsync'ed and renamed over <path>. On failure the temporary is removed, the old
// file (if any) is left untouched and an exception derived from std::runtime_error whose
// message starts with the path is thrown.
//
// Fields are row-major with x fastest: value(ix, iy) = f[iy * nx + ix], x(ix) = ix * dx.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/files.hpp"  // write_text_atomic, read_regular_file (also used through io.hpp)
#include "gfmd/grid.hpp"

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

struct PngOptions {
  // "viridis" (default), "inferno", "coolwarm" (diverging), "gray" (alias "grey").
  std::string colormap = "viridis";
  // Colour limits ±max(|vmin|, |vmax|) (each defaulting to the data range): 0 maps to the
  // centre of the colormap.
  bool symmetric = false;
  // Colour limits; NAN: finite data minimum / maximum. Values outside are clamped.
  double vmin = NAN, vmax = NAN;
  // Optional, grid.size() entries: the boundary of the region where mask[i] != 0 (e.g. the
  // contact area) is outlined in a colour that contrasts with the colormap.
  const unsigned char* mask = nullptr;
  // Pixels per cell. 0: chosen so the long side of the map is between ~256 and ~1024 px;
  // grids longer than 1024 cells are downsampled by block averaging (NaNs ignored).
  int scale = 0;
  // Colour bar strip on the right with max (top) and min (bottom) labels.
  bool colorbar = true;
  // Optional title in a band above the map (digits, a-z, space and . - + : = _ ( ) / ,;
  // upper case is drawn as lower case).
  std::string title;
};

// Writes an RGB PNG map of `field` (y up: cell row iy = ny-1 at the top; x to the right).
// NaN cells are grey (128,128,128). Without colour bar and title the image is exactly
// (nx*scale) x (ny*scale) pixels (for scale > 0). Written atomically.
// Throws InputError(path, reason) for bad options, std::runtime_error on I/O failure.
void write_png_map(const std::string& path, const Grid& grid, const double* field,
                   const PngOptions& opt = {});

// Colour of colormap `name` at t in [0, 1] (clamped; NaN gives the NaN grey).
// Throws InputError("colormap", ...) for an unknown name.
std::array<unsigned char, 3> colormap_rgb(const std::string& name, double t);

// Reads a PNG file as 8-bit RGB (row-major, top row first, 3 bytes per pixel) and sets its
// size. Throws InputError(path, reason).
std::vector<unsigned char> read_png_rgb(const std::string& path, int& width, int& height);

}  // namespace gfmd
