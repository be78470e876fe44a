// Where grid passes, reductions and FFTs run: the one seam between the physics and the
// machine. The parts above core write their loops as passes (parallel_for, for_rows,
// grid_sums, ...) and their transforms as FFT objects; which workers run them is the
// current Backend's business. Built in: "threads" (OpenMP over the cores, the default),
// "serial" (one thread, plain loops: the reference every other backend must reproduce bit
// for bit) and "cuda" (passes as "threads"; the contact solve itself runs on the GPU with its
// fields resident there: contact/device_solve.cu, docs/gpu.md). "auto" names "cuda" where a
// CUDA device is usable and "threads" elsewhere. docs/architecture.md says how MPI slabs plug in.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gfmd {

// The OpenMP spin count the front ends set where the user chose no wait policy (app/gfmd.cpp,
// python/gfmd/__init__.py): threads at a barrier spin this many times, then sleep.
inline constexpr const char* kSpinCount = "10000";
// How this process's OpenMP threads wait, as its environment said at the first call (libgomp
// reads it once, at start-up; the Python package makes that call as it loads, before it takes
// its GOMP_SPINCOUNT out of the environment again): "GOMP_SPINCOUNT=10000",
// "OMP_WAIT_POLICY=passive", ...; "default": libgomp's own. summary.json "omp_wait".
std::string omp_wait_setting();

struct Grid;
class FftEngine;
enum class Planner;

// A non-owning reference to a callable void(std::ptrdiff_t lo, std::ptrdiff_t hi): what a
// pass hands to its backend (one indirect call per range, the loop inside stays inlined).
class RangeBody {
 public:
  template <class F>
  explicit RangeBody(F& f)
      : obj_(&f),
        call_([](void* o, std::ptrdiff_t lo, std::ptrdiff_t hi) { (*static_cast<F*>(o))(lo, hi); }) {}
  void operator()(std::ptrdiff_t lo, std::ptrdiff_t hi) const { call_(obj_, lo, hi); }

 private:
  void* obj_;
  void (*call_)(void*, std::ptrdiff_t, std::ptrdiff_t);
};

class Backend {
 public:
  Backend() = default;
  Backend(const Backend&) = delete;
  Backend& operator=(const Backend&) = delete;
  virtual ~Backend() = default;

  [[nodiscard]] virtual std::string_view name() const = 0;
  // Splits [0, n) into disjoint contiguous ranges and calls body(lo, hi) once for each, in
  // any order and possibly concurrently; returns when all have run. The bodies of one pass
  // write disjoint data, so the result never depends on the split.
  virtual void for_ranges(std::ptrdiff_t n, RangeBody body) const = 0;
  // Workers a pass may use (1: everything runs on the calling thread).
  [[nodiscard]] virtual int workers() const = 0;
  // Threads of the FFT plans made while this backend is current.
  [[nodiscard]] virtual int fft_threads() const = 0;
  // The engine behind every FFT object made while this backend is current: by default
  // FFTW's plans with fft_threads() threads (core/fft.cpp).
  [[nodiscard]] virtual std::unique_ptr<FftEngine> make_fft_engine(const Grid& grid, Planner planner) const;
};

// The backend passes run on now: threads_backend() unless a BackendScope says otherwise.
const Backend& backend();
const Backend& threads_backend();
const Backend& serial_backend();
// The backend of that name (built in or registered; "auto" resolved now), or nullptr.
const Backend* find_backend(std::string_view name);
// Names of the built-in backends, "auto", then the registered ones.
std::vector<std::string> backend_names();
// Makes b selectable by name (solver.backend, find_backend): how a backend built outside
// core (MPI slabs, a device) joins. b must outlive every use; a name taken already is
// refused with std::invalid_argument.
void register_backend(const Backend& b);

// Makes b the current backend for its lifetime (process-wide, like set_threads) and puts
// the previous one back on exit. Nested scopes are fine. Under a one-worker backend the
// OpenMP loops that remain inside parts (the flow's own AMG kernels) run on one thread too.
class BackendScope {
 public:
  explicit BackendScope(const Backend& b);
  ~BackendScope();
  BackendScope(const BackendScope&) = delete;
  BackendScope& operator=(const BackendScope&) = delete;

 private:
  const Backend* previous_;
  int previous_omp_threads_;
};

// Calls f(i) for every i in [0, n): one elementwise pass over a field.
template <class F>
void parallel_for(std::ptrdiff_t n, F&& f) {
  auto body = [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (std::ptrdiff_t i = lo; i < hi; ++i) f(i);
  };
  backend().for_ranges(n, RangeBody(body));
}

// Calls f(row) for every row in [0, rows): a pass over the rows of a grid or a spectrum
// (f loops over the row's points itself).
template <class F>
void for_rows(int rows, F&& f) {
  auto body = [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (std::ptrdiff_t r = lo; r < hi; ++r) f(static_cast<int>(r));
  };
  backend().for_ranges(rows, RangeBody(body));
}

}  // namespace gfmd
