// The 2D real transforms as one-dimensional transforms along lines: the rows (r2c / c2r along
// x), then the columns of the half spectrum (c2c along y), each line by one plan made for a
// single line. Every line goes through the same plan wherever it is stored and whichever
// thread runs it, so a transform has the same bits on a whole grid, on the slabs of any
// process count (the columns gathered by FFTW-MPI's transposes) and for any thread count.
// Internal to core (fft.cpp, mpi.cpp).
#pragma once

#include <fftw3.h>

#include <vector>

#include "gfmd/core/fft.hpp"

namespace gfmd::detail {

class LinePlans {
 public:
  // nx: the real rows' length; ny: the columns' length. The caller holds FFTW's planner lock.
  // `threads` OpenMP threads run the lines.
  LinePlans(int nx, int ny, int threads);
  ~LinePlans();
  LinePlans(const LinePlans&) = delete;
  LinePlans& operator=(const LinePlans&) = delete;

  // r2c of `rows` rows: in is rows x nx, out rows x (nx/2 + 1). in is not modified.
  void rows_forward(const double* in, cplx* out, int rows) const;
  // c2r of `rows` rows without normalisation; in is overwritten.
  void rows_backward(cplx* in, double* out, int rows) const;
  // c2c in place on `count` contiguous lines of ny elements (sign FFTW_FORWARD/BACKWARD).
  void lines(cplx* data, int count, int sign) const;
  // c2c in place along the columns of a whole ny x (nx/2 + 1) half spectrum: blocks of
  // columns are gathered into contiguous lines, transformed as lines() does, put back.
  void columns(cplx* spec, int sign) const;

 private:
  void destroy();
  template <class Field>
  void per_thread(std::vector<Field>& buffers, int size) const;
  int nx_, ny_, nxh_, threads_;
  fftw_plan r2c_ = nullptr, c2r_ = nullptr, fwd_ = nullptr, bwd_ = nullptr;
  mutable std::vector<SpecField> scratch_;      // columns(): one block of lines per thread
  mutable std::vector<RealField> row_scratch_;  // rows of odd length: one aligned row per thread
};

}  // namespace gfmd::detail
