#include "gfmd/core/fft.hpp"

#include <fftw3.h>
#include <omp.h>
#include <sys/mman.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <mutex>
#include <new>
#include <string>
#include <system_error>

#include "fft_lines.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"

namespace gfmd {

namespace {
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}
int g_threads = 0;
bool g_fftw_threads_ready = false;
bool g_wisdom_loaded = false;

// Wisdom file of the measuring planner: $GFMD_FFTW_WISDOM, else
// $XDG_CACHE_HOME/gfmd/fftw-wisdom, else $HOME/.cache/gfmd/fftw-wisdom ("" = none).
std::string wisdom_file() {
  if (const char* p = std::getenv("GFMD_FFTW_WISDOM")) return p;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/gfmd/fftw-wisdom";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/gfmd/fftw-wisdom";
  return {};
}

// Written atomically (write_text_atomic), so that concurrent runs never read a
// half-written file. A cache that cannot be written is not an error (plans are only slower
// to make next time).
void save_wisdom(const std::string& path) {
  if (path.empty()) return;
  char* text = fftw_export_wisdom_to_string();
  if (text == nullptr) return;
  try {
    const std::filesystem::path target(path);
    std::error_code ec;
    if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path(), ec);
    write_text_atomic(path, text);
  } catch (const std::exception&) {
    // unwritable cache: ignored
  }
  fftw_free(text);
}
}  // namespace

#ifdef __GLIBC__
// Grid-sized blocks must be mapped and unmapped whole, so that a freed field goes back to
// the system. SuperLU_DIST (loaded with HYPRE) switches that off in its static
// initialiser (mallopt M_MMAP_MAX = 0, M_TRIM_THRESHOLD = -1: every block from the heap,
// never trimmed), which kept every field ever freed resident (+70-150 B per grid point
// of peak memory at 2048^2). This initialiser runs after those of the shared libraries:
// it restores mapping, with a fixed threshold (glibc would otherwise raise it to the size
// of a freed block, up to 32 MiB) and the default trimming.
namespace {
bool restore_block_mapping() {
  return mallopt(M_MMAP_MAX, 65536) == 1 && mallopt(M_MMAP_THRESHOLD, 1 << 20) == 1 &&
         mallopt(M_TRIM_THRESHOLD, 128 * 1024) == 1;
}
[[maybe_unused]] const bool g_block_mapping = restore_block_mapping();
std::mutex g_heap_scope_mutex;
int g_heap_scopes = 0;
}  // namespace

HeapAllocationScope::HeapAllocationScope(std::size_t expected_bytes) {
  std::lock_guard<std::mutex> lock(g_heap_scope_mutex);
  if (g_heap_scopes++ == 0) {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1);
    if (expected_bytes >= (std::size_t{8} << 20)) {
      // Grow the heap once by the expected size and ask for transparent huge pages there:
      // the blocks carved from it later fault in 2 MiB at a time instead of 4 KiB. Only
      // what is touched becomes resident.
      if (void* p = std::malloc(expected_bytes)) {
        const auto a = reinterpret_cast<std::uintptr_t>(p);
        const std::uintptr_t huge = std::uintptr_t{2} << 20;
        const std::uintptr_t lo = (a + huge - 1) & ~(huge - 1), hi = (a + expected_bytes) & ~(huge - 1);
        if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
        std::free(p);
      }
    }
  }
}

HeapAllocationScope::~HeapAllocationScope() {
  std::lock_guard<std::mutex> lock(g_heap_scope_mutex);
  if (--g_heap_scopes == 0) {
    restore_block_mapping();
    malloc_trim(0);
  }
}
#else
HeapAllocationScope::HeapAllocationScope(std::size_t) {}
HeapAllocationScope::~HeapAllocationScope() = default;
#endif

void* fftw_aligned_alloc(std::size_t bytes) {
  constexpr std::size_t huge = std::size_t{2} << 20;
  if (bytes >= 2 * huge) {
    const std::size_t rounded = (bytes + huge - 1) / huge * huge;
    void* p = std::aligned_alloc(huge, rounded);
    if (p == nullptr) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);
    return p;
  }
  void* p = std::aligned_alloc(64, (bytes + 63) / 64 * 64 + (bytes == 0 ? 64 : 0));
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void fftw_aligned_free(void* p) noexcept { std::free(p); }

void set_threads(int n) {
  std::lock_guard lock(planner_mutex());
  if (n <= 0) n = omp_get_num_procs();
  g_threads = n;
  if (!g_fftw_threads_ready) {
    fftw_init_threads();
    g_fftw_threads_ready = true;
  }
  omp_set_num_threads(n);  // FFTW's thread count is set per plan, from the backend (FftwEngine)
}

int threads() { return g_threads > 0 ? g_threads : omp_get_max_threads(); }

namespace {
class FftwEngine final : public FftEngine {
 public:
  FftwEngine(const Grid& grid, Planner planner, int threads) {
    if (g_threads == 0) set_threads(0);
    const bool measure = planner == Planner::Measure;
    const unsigned flags = (measure ? FFTW_MEASURE : FFTW_ESTIMATE);
    std::lock_guard lock(planner_mutex());
    fftw_plan_with_nthreads(threads);
    const std::string wisdom = measure ? wisdom_file() : std::string();
    if (measure && !g_wisdom_loaded) {
      if (!wisdom.empty()) fftw_import_wisdom_from_filename(wisdom.c_str());  // absent or stale: ignored
      g_wisdom_loaded = true;
    }
    // Planning arrays only (the plans run on the callers' aligned arrays): freed at once.
    RealField rplan(grid.size());
    SpecField cplan(grid.spectral_size());
    auto* r = rplan.data();
    auto* c = reinterpret_cast<fftw_complex*>(cplan.data());
    r2c_ = fftw_plan_dft_r2c_2d(grid.ny, grid.nx, r, c, flags);
    c2r_ = fftw_plan_dft_c2r_2d(grid.ny, grid.nx, c, r, flags);
    if (r2c_ == nullptr || c2r_ == nullptr) {
      destroy();
      throw std::runtime_error("FFTW could not make a plan");
    }
    if (measure) save_wisdom(wisdom);
  }
  ~FftwEngine() override {
    std::lock_guard lock(planner_mutex());
    destroy();
  }
  FftwEngine(const FftwEngine&) = delete;
  FftwEngine& operator=(const FftwEngine&) = delete;

  void forward(const double* in, cplx* out) override {
    // r2c leaves its input intact; the const_cast only satisfies FFTW's signature.
    fftw_execute_dft_r2c(r2c_, const_cast<double*>(in), reinterpret_cast<fftw_complex*>(out));
  }
  void backward_unscaled(cplx* in, double* out) override {
    fftw_execute_dft_c2r(c2r_, reinterpret_cast<fftw_complex*>(in), out);
  }

 private:
  void destroy() {
    if (r2c_) fftw_destroy_plan(r2c_);
    if (c2r_) fftw_destroy_plan(c2r_);
    r2c_ = c2r_ = nullptr;
  }
  fftw_plan r2c_ = nullptr;
  fftw_plan c2r_ = nullptr;
};
// FFTW_ESTIMATE's transforms as lines (fft_lines.hpp): the rows, then the half spectrum's
// columns. The same bits as the slabs of a distributed run (mpi.cpp) for any process count.
class LinesEngine final : public FftEngine {
 public:
  LinesEngine(const Grid& grid, int threads) : plans_(grid.nx, grid.ny, threads), ny_(grid.ny) {}
  void forward(const double* in, cplx* out) override {
    plans_.rows_forward(in, out, ny_);
    plans_.columns(out, FFTW_FORWARD);
  }
  void backward_unscaled(cplx* in, double* out) override {
    plans_.columns(in, FFTW_BACKWARD);
    plans_.rows_backward(in, out, ny_);
  }

 private:
  detail::LinePlans plans_;
  int ny_;
};
}  // namespace

std::unique_ptr<FftEngine> make_fftw_engine(const Grid& grid, Planner planner, int threads) {
  if (grid.is_slab()) {
    if (g_threads == 0) set_threads(0);
    std::lock_guard lock(planner_mutex());
    return mpi::make_fftw_mpi_engine(grid, threads);
  }
  if (planner == Planner::Estimate) {
    if (g_threads == 0) set_threads(0);
    std::lock_guard lock(planner_mutex());
    return std::make_unique<LinesEngine>(grid, threads);
  }
  return std::make_unique<FftwEngine>(grid, planner, threads);
}

std::unique_ptr<FftEngine> Backend::make_fft_engine(const Grid& grid, Planner planner) const {
  return make_fftw_engine(grid, planner, fft_threads());
}

FFT::FFT(const Grid& grid, Planner planner)
    : grid_(grid), engine_(backend().make_fft_engine(grid, planner)) {}

FFT::~FFT() = default;

namespace {
// Adds the wall time of its scope to a counter (the transforms' own time, for benchmarks).
class ScopeTimer {
 public:
  explicit ScopeTimer(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~ScopeTimer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};
}  // namespace

void FFT::forward(const double* in, cplx* out) const {
  ++transforms_;
  const ScopeTimer timer(seconds_);
  engine_->forward(in, out);
}

void FFT::backward_unscaled_destroying(cplx* in, double* out) const {
  ++transforms_;
  const ScopeTimer timer(seconds_);
  engine_->backward_unscaled(in, out);
}

void FFT::backward(const cplx* in, double* out) const {
  ++transforms_;
  const double scale = 1.0 / static_cast<double>(grid_.size());
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(grid_.spectral_size());
  if (cbuf_.empty()) cbuf_.resize(grid_.spectral_size());  // first use: c2r destroys its input
  cplx* buf = cbuf_.data();
  parallel_for(n, [&](std::ptrdiff_t i) { buf[i] = in[i] * scale; });
  const ScopeTimer timer(seconds_);
  engine_->backward_unscaled(buf, out);
}

}  // namespace gfmd
