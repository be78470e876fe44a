// Periodic simulation cell and its discrete wave vectors.
//
// Real fields are stored row-major with x fastest: value(ix, iy) = f[iy * nx + ix].
// The r2c half-spectrum has ny rows of (nx/2 + 1) complex modes, kx fastest.
//
// A Grid may describe a slab of the cell (a distributed run, core/mpi.hpp): this process
// then holds rows [y0, y0 + rows()) of every real field and the same rows (ky) of every
// half spectrum, stored from index 0 (value(ix, y0 + r) = f[r * nx + ix]). nx, ny, lx and
// ly always describe the whole cell; size() counts the whole cell, local_size() the rows
// held here. A whole grid is its own slab (y0 = 0, rows() = ny).
// Fourier convention (SPEC §1): f(r) = sum_q f~(q) exp(+i q.r); FFTW's forward
// transform analyses, its backward transform synthesises, and we divide by nx*ny once.
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>

namespace gfmd {

struct Grid {
  int nx = 0, ny = 0;
  double lx = 0.0, ly = 0.0;
  int y0 = 0;          // first row held here (a slab of a distributed run)
  int slab_rows = -1;  // rows held here; -1: all ny

  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(nx) * ny; }
  [[nodiscard]] int nxh() const { return nx / 2 + 1; }  // complex modes along x
  [[nodiscard]] std::size_t spectral_size() const { return static_cast<std::size_t>(nxh()) * rows(); }
  // Rows held here, and the points and half-spectrum modes they hold (the storage size of a
  // field; the whole cell's for a whole grid).
  [[nodiscard]] int rows() const { return slab_rows < 0 ? ny : slab_rows; }
  [[nodiscard]] std::size_t local_size() const { return static_cast<std::size_t>(nx) * rows(); }
  // True when this grid is part of a cell distributed over processes.
  [[nodiscard]] bool is_slab() const { return rows() != ny; }
  // The whole cell this grid is part of.
  [[nodiscard]] Grid whole() const { return Grid{nx, ny, lx, ly}; }
  [[nodiscard]] double dx() const { return lx / nx; }
  [[nodiscard]] double dy() const { return ly / ny; }
  [[nodiscard]] double cell_area() const { return dx() * dy(); }
  [[nodiscard]] double area() const { return lx * ly; }
  [[nodiscard]] double x(int ix) const { return ix * dx(); }
  [[nodiscard]] double y(int iy) const { return iy * dy(); }

  // Signed integer wave numbers of a half-spectrum mode.
  [[nodiscard]] int kx(int ikx) const { return ikx; }
  [[nodiscard]] int ky(int iky) const { return iky <= ny / 2 ? iky : iky - ny; }
  [[nodiscard]] double qx(int ikx) const { return 2.0 * std::numbers::pi * kx(ikx) / lx; }
  [[nodiscard]] double qy(int iky) const { return 2.0 * std::numbers::pi * ky(iky) / ly; }
  // Wave vector used for first derivatives: the Nyquist component is dropped so that
  // derivatives of real fields stay real.
  [[nodiscard]] double qx_deriv(int ikx) const { return (nx % 2 == 0 && ikx == nx / 2) ? 0.0 : qx(ikx); }
  [[nodiscard]] double qy_deriv(int iky) const { return (ny % 2 == 0 && iky == ny / 2) ? 0.0 : qy(iky); }
  // Multiplicity of a half-spectrum mode in the full spectrum (1 for kx = 0 and the
  // x-Nyquist column, 2 otherwise): sums of |f~|^2 over the half spectrum use it.
  [[nodiscard]] double weight(int ikx) const {
    return (ikx == 0 || (nx % 2 == 0 && ikx == nx / 2)) ? 1.0 : 2.0;
  }
};

}  // namespace gfmd
