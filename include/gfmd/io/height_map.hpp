// Height-map files: measured or generated topographies in instrument and array formats,
// read into the grid's row-major layout (x fastest, row iy = 0 first).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "gfmd/core/fft.hpp"

namespace gfmd {

// A height map as a file gives it.
struct HeightMap {
  int nx = 0, ny = 0;
  double lx = 0.0, ly = 0.0;  // physical size from the file; 0 where the file gives none
  RealField h;                // nx * ny heights; NaN where the file has no value (a missing point)
  std::string format;         // "text", "netcdf", "x3p", "npy", "gwy" or "sur"
  // "m" when the file states its units: lx, ly and h are then converted to metres.
  // "" when it states none: the values are as written.
  std::string unit;
  std::size_t missing = 0;    // number of NaN points in h
  std::string first_missing;  // where the first one is, in the file's terms ("line 3, value 2")
};

// Reads a height map of any supported format, chosen by the file's signature (x3p: a zip
// archive; gwy: "GWYP"; sur: "DIGITAL SURF"; npy: "\x93NUMPY"; NetCDF/HDF5) or, failing
// that, by its extension (.nc; everything else is text). Heights are towards the body
// (see surface/topography.hpp): larger = protrudes further. Missing points are returned
// as NaN and counted; infinite values are an error.
//
// Formats and where their sizes and units come from:
//  text   one data row per line (row iy), values separated by blanks, commas, semicolons
//         or tabs (one separator per row); blank lines ignored; '#' starts a comment, except
//         header lines "# lx = <number> [unit]", "# ly = ...", "# unit = <unit>" (the unit of
//         the heights, and of lx/ly when they name none); ':' may replace '='. A value
//         "nan" (any case) is a missing point; an empty value between separators is an error.
//         Three columns with a first row naming them x, y, z, or whose first two columns
//         repeat values, are x, y, z points on a regular grid (columns by ascending x, rows by
//         ascending y; lx, ly = spacing x count; pairs no row gives are missing points);
//         points off a regular grid, or a pair given twice, are an error naming the line.
//  netcdf a 2-D numeric variable "topography" (else "height", else "heights"), dims (y, x);
//         scale_factor/add_offset applied; the fill value marks missing points; size from
//         attributes lx/ly (of the variable, else global) or uniform 1-D coordinates; unit
//         from the variable's "units" attribute (and the coordinates' when present).
//  x3p    ISO 25178-72: main.xml (Record1 axes: CX, CY increments in metres; Record3 data
//         link to bindata/data.bin or inline <DataList>; Z data type I, L, F or D with the
//         Z axis increment and offset); NaN (F, D) or an absent <Datum> marks missing points.
//  npy    NumPy array file, 2-D, C or Fortran order, float32/64 or int8..64 of either
//         byte order; no size, no unit.
//  gwy    Gwyddion: the first channel (/0/data GwyDataField): xres, yres, xreal, yreal, and
//         the SI units of x/y and z (si_unit_xy, si_unit_z) with their power of ten.
//  sur    Digital Surf: a single surface object; point spacings, their units and the z
//         unit and scale from the 512-byte header; the no-data value marks missing points.
// Every problem throws InputError(path, reason) with the line, offset or index and a short
// excerpt: unreadable, truncated or malformed files, dimensions out of range (checked before
// any allocation: at most 65536 points per side and 2^28 in all), NaN where a format has
// no missing points, unknown units.
HeightMap read_height_file(const std::string& path);

// Why a map with missing points cannot be solved as it is: their count, the first one
// (omitted when `first` is empty) and the indenter.missing values that fill them.
std::string missing_points_message(std::size_t count, const std::string& first);

// Metres per unit of a length unit as files and cases write it: m, cm, mm, um (also µm, in
// either Unicode spelling, and micron), nm, pm, A (also Å, angstrom); 0 for anything else.
double metres_per_unit(std::string_view unit);

// The reader as a height field for a grid: read_height_file, then the size rules:
// lx, ly > 0 given here win over the file (a mismatch is not an error); lx, ly <= 0 take the
// size from the file, and it is an error if the file has none. Missing points are an error
// here (the count and the first one named). Values are used as written or, where the file
// states units, in metres.
HeightMap read_height_map(const std::string& path, double lx, double ly);

}  // namespace gfmd
