#include "fft_lines.hpp"

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <stdexcept>

namespace gfmd::detail {

namespace {
// Columns gathered per block: 8 complex values (two cache lines) of every row at a time.
constexpr int kBlock = 8;
// Plans made on 64-byte aligned lines run on any line that FFTW calls equally aligned
// (fftw_alignment_of == 0): every complex line of our arrays; real rows when nx is even.
// Other real rows go through an aligned copy, so every line meets the same code.
constexpr unsigned kFlags = FFTW_ESTIMATE;

fftw_complex* as_fftw(cplx* p) { return reinterpret_cast<fftw_complex*>(p); }

// Complex lines are aligned as the plans' when their array is (16-byte elements): an array
// that is not (never one of the library's) would meet other code, so it is refused.
void require_aligned(cplx* p) {
  if (fftw_alignment_of(reinterpret_cast<double*>(p)) != 0)
    throw std::invalid_argument("FFT: a complex array that is not 16-byte aligned");
}
}  // namespace

// One buffer of `size` elements per thread, made on first use.
template <class Field>
void LinePlans::per_thread(std::vector<Field>& buffers, int size) const {
  if (!buffers.empty()) return;
  buffers.resize(static_cast<std::size_t>(threads_));
  for (auto& b : buffers) b.resize(static_cast<std::size_t>(size));
}

LinePlans::LinePlans(int nx, int ny, int threads)
    : nx_(nx), ny_(ny), nxh_(nx / 2 + 1), threads_(std::max(threads, 1)) {
  // Planning arrays only; the plans run on the callers' lines (new-array execute).
  RealField r(static_cast<std::size_t>(nx));
  SpecField c(static_cast<std::size_t>(std::max(nxh_, ny)));
  fftw_plan_with_nthreads(1);  // one line per thread: the lines are the parallel work
  r2c_ = fftw_plan_dft_r2c_1d(nx, r.data(), as_fftw(c.data()), kFlags);
  c2r_ = fftw_plan_dft_c2r_1d(nx, as_fftw(c.data()), r.data(), kFlags);
  fwd_ = fftw_plan_dft_1d(ny, as_fftw(c.data()), as_fftw(c.data()), FFTW_FORWARD, kFlags);
  bwd_ = fftw_plan_dft_1d(ny, as_fftw(c.data()), as_fftw(c.data()), FFTW_BACKWARD, kFlags);
  if (!r2c_ || !c2r_ || !fwd_ || !bwd_) {
    destroy();
    throw std::runtime_error("FFTW could not make a plan");
  }
}

LinePlans::~LinePlans() { destroy(); }

void LinePlans::destroy() {
  for (fftw_plan* p : {&r2c_, &c2r_, &fwd_, &bwd_})
    if (*p) {
      fftw_destroy_plan(*p);
      *p = nullptr;
    }
}

void LinePlans::rows_forward(const double* in, cplx* out, int rows) const {
  require_aligned(out);
  const bool copy = nx_ % 2 != 0 || fftw_alignment_of(const_cast<double*>(in)) != 0;
  if (copy) per_thread(row_scratch_, nx_);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (int r = 0; r < rows; ++r) {
    const double* row = in + static_cast<std::ptrdiff_t>(r) * nx_;
    if (copy) {
      double* line = row_scratch_[static_cast<std::size_t>(omp_get_thread_num())].data();
      std::copy(row, row + nx_, line);
      row = line;
    }
    fftw_execute_dft_r2c(r2c_, const_cast<double*>(row),
                         as_fftw(out + static_cast<std::ptrdiff_t>(r) * nxh_));
  }
}

void LinePlans::rows_backward(cplx* in, double* out, int rows) const {
  require_aligned(in);
  const bool copy = nx_ % 2 != 0 || fftw_alignment_of(out) != 0;
  if (copy) per_thread(row_scratch_, nx_);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (int r = 0; r < rows; ++r) {
    double* row = out + static_cast<std::ptrdiff_t>(r) * nx_;
    double* line = copy ? row_scratch_[static_cast<std::size_t>(omp_get_thread_num())].data() : row;
    fftw_execute_dft_c2r(c2r_, as_fftw(in + static_cast<std::ptrdiff_t>(r) * nxh_), line);
    if (copy) std::copy(line, line + nx_, row);
  }
}

void LinePlans::lines(cplx* data, int count, int sign) const {
  require_aligned(data);
  const fftw_plan p = sign == FFTW_FORWARD ? fwd_ : bwd_;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (int k = 0; k < count; ++k) {
    cplx* line = data + static_cast<std::ptrdiff_t>(k) * ny_;
    fftw_execute_dft(p, as_fftw(line), as_fftw(line));
  }
}

void LinePlans::columns(cplx* spec, int sign) const {
  require_aligned(spec);
  const fftw_plan p = sign == FFTW_FORWARD ? fwd_ : bwd_;
  per_thread(scratch_, kBlock * ny_);
  const int blocks = (nxh_ + kBlock - 1) / kBlock;
  const std::ptrdiff_t nxh = nxh_;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (int b = 0; b < blocks; ++b) {
    cplx* buf = scratch_[static_cast<std::size_t>(omp_get_thread_num())].data();
    const int k0 = b * kBlock, width = std::min(kBlock, nxh_ - k0);
    for (int iy = 0; iy < ny_; ++iy) {
      const cplx* row = spec + iy * nxh + k0;
      for (int j = 0; j < width; ++j) buf[static_cast<std::ptrdiff_t>(j) * ny_ + iy] = row[j];
    }
    for (int j = 0; j < width; ++j) {
      cplx* line = buf + static_cast<std::ptrdiff_t>(j) * ny_;
      fftw_execute_dft(p, as_fftw(line), as_fftw(line));
    }
    for (int iy = 0; iy < ny_; ++iy) {
      cplx* row = spec + iy * nxh + k0;
      for (int j = 0; j < width; ++j) row[j] = buf[static_cast<std::ptrdiff_t>(j) * ny_ + iy];
    }
  }
}

}  // namespace gfmd::detail
