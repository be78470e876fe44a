// PNG maps of fields on the grid (colormaps, outlines, colour bar) and reading PNGs back.
// Written atomically like every output (see io/netcdf.hpp).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gfmd/core/grid.hpp"

namespace gfmd {

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
