// Height-map files: plain text and NetCDF, read into the grid's row-major layout.
#pragma once

#include <string>

#include "gfmd/core/fft.hpp"

namespace gfmd {

// A height map as read: nx x ny values, x fastest, and the physical size of the map.
struct HeightMap {
  int nx = 0, ny = 0;
  double lx = 0.0, ly = 0.0;
  RealField h;
};

// Reads a height map (heights towards the body, see surface/topography.hpp). Files whose name ends in ".nc"
// (any case) or that start with a NetCDF/HDF5 signature are read as NetCDF, everything else as text.
//
// Text format: one data row per line, row iy (the y index, iy = 0 first) holding nx
// whitespace-separated numbers for ix = 0..nx-1; every data row must have the same count.
// Blank lines are ignored. A line whose first non-blank character is '#' is a comment,
// except header lines "# lx = <number>" and "# ly = <number>" (':' may replace '=')
// that give the physical size of the cell; they may appear anywhere, at most once each.
// Values are heights in the convention above (larger = towards the body), used as is.
//
// NetCDF: a 2-D numeric variable named "topography" (else "height", else "heights") with
// dimensions (y, x); CF packing attributes scale_factor/add_offset are applied; values
// equal to the variable's fill value are rejected. Size: attribute "lx"/"ly" of the
// variable, else global attribute, else 1-D coordinate variables (named like the
// dimension, else "x"/"y") of uniform increasing spacing: L = spacing * count.
//
// lx, ly > 0 given here win over the file (a mismatch with the file is not an error);
// lx, ly <= 0 take the size from the file, and it is an error if the file has none.
// Every problem throws InputError(path, reason): missing/unreadable file, empty file,
// ragged rows (line number and counts), non-numeric token (line number), NaN/Inf
// (line number, or index for NetCDF), missing size, NetCDF errors (netcdf's message).
HeightMap read_height_map(const std::string& path, double lx, double ly);

}  // namespace gfmd
