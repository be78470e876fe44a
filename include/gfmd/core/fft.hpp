// Real-to-complex 2D FFTs on a Grid: plans made once, executed many times (FFTW).
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "gfmd/core/grid.hpp"

namespace gfmd {

using cplx = std::complex<double>;

// Allocator returning SIMD-aligned memory (64 bytes) so that every field can be passed to
// the new-array execute functions of a plan. Blocks of 4 MiB and more are aligned to 2 MiB
// and advised for transparent huge pages: the column passes of a 2048^2 transform touch a
// new 4 KiB page at nearly every element otherwise (bare 3+3 FFTs 76 -> 56 ms there).
template <class T>
struct FftwAllocator {
  using value_type = T;
  FftwAllocator() = default;
  template <class U>
  FftwAllocator(const FftwAllocator<U>&) {}  // NOLINT
  T* allocate(std::size_t n);
  void deallocate(T* p, std::size_t) noexcept;
  template <class U>
  bool operator==(const FftwAllocator<U>&) const {
    return true;
  }
};

using RealField = std::vector<double, FftwAllocator<double>>;
using SpecField = std::vector<cplx, FftwAllocator<cplx>>;

void* fftw_aligned_alloc(std::size_t bytes);
void fftw_aligned_free(void* p) noexcept;

// While alive, every allocation comes from the heap, which is not trimmed; on exit the
// library's policy (large blocks mapped, heap trimmed) is back and the free heap pages are
// returned to the system. For libraries that make many short-lived large allocations
// (HYPRE's AMG set-up): mapping and unmapping each of them costs page faults (2048^2 flow
// set-up 8 s instead of 3 s). Nested scopes are fine; the policy is process-wide.
class HeapAllocationScope {
 public:
  explicit HeapAllocationScope(std::size_t expected_bytes = 0);
  ~HeapAllocationScope();
  HeapAllocationScope(const HeapAllocationScope&) = delete;
  HeapAllocationScope& operator=(const HeapAllocationScope&) = delete;
};

template <class T>
T* FftwAllocator<T>::allocate(std::size_t n) {
  return static_cast<T*>(fftw_aligned_alloc(n * sizeof(T)));
}
template <class T>
void FftwAllocator<T>::deallocate(T* p, std::size_t) noexcept {
  fftw_aligned_free(p);
}

// Sets the number of threads used by FFTW plans created afterwards and by the
// OpenMP loops of the library. 0 means "all cores".
void set_threads(int threads);
int threads();

// Estimate: plans from FFTW's heuristics, made instantly, for one line: the rows are
// transformed, then the columns of the half spectrum, each line by the same plan, so the bits
// are the same on every run, for every thread count and on the slabs of any number of
// processes (src/core/fft_lines.hpp). Measure: FFTW times candidate plans
// (seconds at 2048^2 the first time) and is up to ~1.9x faster at 2048^2 on our machine;
// plans are kept as FFTW wisdom in $GFMD_FFTW_WISDOM, else $XDG_CACHE_HOME/gfmd/fftw-wisdom,
// else ~/.cache/gfmd/fftw-wisdom, and reused by later runs (same plan -> same bits once
// the wisdom exists; results differ from Estimate's at round-off level).
enum class Planner { Estimate, Measure };

// What executes the transforms of an FFT object: FFTW's plans unless the current backend
// supplies its own (Backend::make_fft_engine: line transforms with FFTW-MPI's transposes on
// slabs, cuFFT on a device). The
// conventions are those of FFT::forward and FFT::backward_unscaled_destroying.
class FftEngine {
 public:
  FftEngine() = default;
  FftEngine(const FftEngine&) = delete;
  FftEngine& operator=(const FftEngine&) = delete;
  virtual ~FftEngine() = default;
  // r2c analysis; in is not modified.
  virtual void forward(const double* in, cplx* out) = 0;
  // c2r synthesis without 1/(nx*ny); in is overwritten.
  virtual void backward_unscaled(cplx* in, double* out) = 0;
};

// FFTW's plans on the grid with `threads` threads (the default engine of every backend).
std::unique_ptr<FftEngine> make_fftw_engine(const Grid& grid, Planner planner, int threads);

class FFT {
 public:
  // Plans made by the current backend (backend().make_fft_engine).
  FFT(const Grid& grid, Planner planner = Planner::Estimate);
  ~FFT();
  FFT(const FFT&) = delete;
  FFT& operator=(const FFT&) = delete;

  // Analysis: out[q] = sum_r in[r] exp(-i q.r) (no normalisation). in is not modified.
  void forward(const double* in, cplx* out) const;
  // Synthesis including the 1/(nx*ny): out[r] = (1/N) sum_q in[q] exp(+i q.r).
  // in is not modified (it is copied into a buffer this object allocates on first use).
  void backward(const cplx* in, double* out) const;
  // Synthesis without the 1/(nx*ny) (fold it into the spectrum), overwriting `in`, which
  // must come from an FFTW-aligned allocation (SpecField): one pass less than backward().
  void backward_unscaled_destroying(cplx* in, double* out) const;

  [[nodiscard]] const Grid& grid() const { return grid_; }
  // Number of transforms (forward + backward) executed so far by this object.
  [[nodiscard]] std::uint64_t transforms() const { return transforms_; }
  // Wall time spent inside FFTW's executes so far (the transforms alone, no scaling passes).
  [[nodiscard]] double seconds() const { return seconds_; }
  // A field for the rows this transform works on (the whole cell, or its slab).
  [[nodiscard]] RealField real_field(double value = 0.0) const {
    return RealField(grid_.local_size(), value);
  }
  [[nodiscard]] SpecField spec_field() const { return SpecField(grid_.spectral_size()); }

 private:
  Grid grid_;
  std::unique_ptr<FftEngine> engine_;
  mutable SpecField cbuf_;  // backward()'s copy of its input, allocated on first use
  mutable std::uint64_t transforms_ = 0;
  mutable double seconds_ = 0.0;
};

}  // namespace gfmd
