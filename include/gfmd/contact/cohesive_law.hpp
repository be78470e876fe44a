// The adhesive interaction's cohesive law on a grid cell (interaction.model = "adhesive"),
// written once for the host and the CUDA device (GFMD_HD): the Maugis-Dugdale law integrated
// over a cell whose gap is linear across it (src/contact/adhesion.cpp, docs/solver.md).
#pragma once

#include <cmath>

#include "gfmd/core/host_device.hpp"

namespace gfmd {

// The fraction of a cell where the gap is below `range` (1 in contact), the gap having the
// value `gap` at the cell's centre and the range `spread` over it:
// clamp((range - gap)/spread + 1/2, 0, 1). The cell's adhesive traction is sigma0 times it.
GFMD_HD inline double adhesive_fraction(double gap, double spread, double range) {
  if (gap <= 0.0) return 1.0;
  if (spread > 0.0) return fmin(fmax((range - gap) / spread + 0.5, 0.0), 1.0);
  return gap < range ? 1.0 : 0.0;
}

// The cell's adhesive energy per area over sigma0: minus the integral of adhesive_fraction from
// the gap to infinity (-range in contact where spread <= 2 range; 0 beyond range + spread/2),
// so that the traction is its derivative in the gap.
GFMD_HD inline double adhesive_potential(double gap, double spread, double range) {
  const double g = fmax(gap, 0.0);
  if (!(spread > 0.0)) return g < range ? g - range : 0.0;
  // The fraction is 1 up to a0 = max(range - spread/2, 0), falls linearly to 0 at
  // hi = range + spread/2 and is 0 beyond.
  const double hi = range + 0.5 * spread, a0 = fmax(range - 0.5 * spread, 0.0);
  if (g >= hi) return 0.0;
  // The linear part from max(g, a0) to hi: the area of a triangle of height f there.
  const double from = fmax(g, a0);
  const double f_from = fmin(fmax((range - from) / spread + 0.5, 0.0), 1.0);
  return -(0.5 * f_from * (hi - from) + fmax(a0 - g, 0.0));
}

}  // namespace gfmd
