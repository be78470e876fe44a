// What a contact solve on the CUDA device (solver.backend = "cuda") needs of it: asked before
// anything is made, so that a grid that does not fit is refused with a clear error.
#pragma once

#include <cstddef>

#include "gfmd/core/grid.hpp"

namespace gfmd {

// Device memory of a solve on this grid: fields, spectra, per-mode tables and cuFFT's work
// area (docs/gpu.md gives it per point); the friction iteration's mixing history comes on
// top and grows with the traction's support. With adhesion its fields, tables and the mixing
// history of its traction (`anderson` steps deep) count too. 0 in a build without CUDA.
std::size_t device_solve_bytes(const Grid& grid, bool friction, bool adhesion = false, int anderson = 0);
// Throws InputError naming "grid" when that does not fit the device's free memory with a
// sixteenth of the card to spare, or naming "solver.backend" when no device is usable.
void require_device_fits(const Grid& grid, bool friction, bool adhesion = false, int anderson = 0);

}  // namespace gfmd
