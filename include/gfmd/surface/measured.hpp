// Measured topographies: a height-map file (io/height_map.hpp) turned into the solver's
// periodic height field — units, cropping, missing points, tilt, periodicity, resampling —
// with a record of every step.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gfmd/surface/topography.hpp"

namespace gfmd {

// The values MapOptions::missing, detrend and periodize may take (the case file's checks use them too).
inline const std::vector<std::string> kMissingMethods{"error", "mean", "interpolate"};
inline const std::vector<std::string> kDetrendMethods{"none", "mean", "plane"};
inline const std::vector<std::string> kPeriodizeMethods{"none", "mirror", "pad"};

struct MapOptions {
  // The case's length unit ("" = none named). With a file that states its units the map is
  // converted to it (metres when none is named); with a file that states none, `file_unit`
  // says what its numbers are (they are converted to the case unit, or taken as the case
  // unit when none is named).
  std::string case_unit;
  std::string file_unit;
  double lx = 0.0, ly = 0.0;                  // the map's size in case units, > 0 wins over the file's
  std::array<long long, 4> crop{0, 0, 0, 0};  // ix0, iy0, nx, ny in the file's points; nx = 0: none
  std::string missing = "error";              // error | mean | interpolate (harmonic)
  std::string detrend = "none";               // none | mean | plane (least squares over the valid points)
  std::string periodize = "none";             // none | mirror | pad
  int nx = 0, ny = 0;                         // the solver's grid; 0 = the map's points (after periodize)
};

// What was done, for summary.json.
struct MapReport {
  std::string path, format, file_unit, case_unit;
  double unit_factor = 1.0;             // case units per file unit
  int file_nx = 0, file_ny = 0;         // as read
  double file_lx = 0.0, file_ly = 0.0;  // in case units (0: the file gives none)
  std::array<long long, 4> crop{0, 0, 0, 0};
  std::string missing;             // method
  std::size_t missing_points = 0;  // filled
  int fill_iterations = 0;         // interpolate: relaxation sweeps
  std::string detrend;
  double removed_mean = 0.0, removed_slope_x = 0.0, removed_slope_y = 0.0;  // plane: h -= mean + sx x + sy y
  std::string periodize;
  double edge_mismatch = 0.0;           // rms jump across the cell's edges / rms height, before periodize
  double map_area_fraction = 1.0;       // measured area / cell area (pad: < 1)
  int map_nx = 0, map_ny = 0;           // after crop and periodize
  int grid_nx = 0, grid_ny = 0;         // the solver's grid
  double lost_gradient_fraction = 0.0;  // of <|grad h|^2>, dropped by resampling to a coarser grid
  std::vector<std::string> warnings;
};

// Reads and prepares a height map for a grid. Steps, in order: read (any format of
// read_height_file); convert units; crop; detrend (fitted over the valid points); fill the
// missing points ("error" refuses them, naming the count and the first); make periodic:
//   mirror  the map and its mirror images (2nx x 2ny, 2lx x 2ly): continuous across every edge;
//   pad     the map in the corner of a cell twice its size, the rest filled far below the
//           map's lowest point (the height range below it), which never touches: the
//           periodic images then do not interact through contact, and with the pressure
//           zero outside the map, the periodic elastic response inside the map equals the
//           non-periodic one of a doubled domain (the DC-FFT argument). load.pressure and area
//           fractions then refer to the whole cell (map_area_fraction says how much is map);
// then resample spectrally onto nx x ny (Fourier interpolation, or truncation of the
// wavelengths the grid cannot hold, with a warning when they carry more than 1 % of the
// squared rms gradient). Warns when a map solved as periodic (periodize = none) has opposite
// edges that differ by more than half its rms height.
// Errors: InputError naming the file for file problems, ParameterError naming the option
// ("unit", "crop", "missing", "detrend", "periodize", "lx") for bad options.
Topography load_height_map(const std::string& path, const MapOptions& opts, MapReport* report = nullptr);

}  // namespace gfmd
