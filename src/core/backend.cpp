#include "gfmd/core/backend.hpp"

#include <omp.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "gfmd/core/device.hpp"
#include "gfmd/core/fft.hpp"

namespace gfmd {

std::string omp_wait_setting() {
  static const std::string first = [] {
    std::string out;
    for (const char* v : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"})
      if (const char* x = std::getenv(v); x != nullptr)
        out += (out.empty() ? "" : " ") + std::string(v) + "=" + std::string(x).substr(0, 64);
    return out.empty() ? std::string("default") : out;
  }();
  return first;
}

namespace {

// OpenMP over the cores set by set_threads: each thread one contiguous range, as
// schedule(static) gives (the same thread touches the same pages in every pass).
// Named "cuda" it is also the host side of the CUDA backend: the contact solve runs on the
// device (contact/device_solve.cu), every other pass on the cores.
class ThreadsBackend final : public Backend {
 public:
  explicit ThreadsBackend(std::string_view name) : name_(name) {}
  [[nodiscard]] std::string_view name() const override { return name_; }
  void for_ranges(std::ptrdiff_t n, RangeBody body) const override {
    if (n <= 0) return;
    const int t = threads();
    if (t <= 1 || n == 1) {
      body(0, n);
      return;
    }
#pragma omp parallel num_threads(t)
    {
      const std::ptrdiff_t nt = omp_get_num_threads(), id = omp_get_thread_num();
      const std::ptrdiff_t chunk = n / nt, extra = n % nt;
      const std::ptrdiff_t lo = id * chunk + (id < extra ? id : extra);
      const std::ptrdiff_t hi = lo + chunk + (id < extra ? 1 : 0);
      if (hi > lo) body(lo, hi);
    }
  }
  [[nodiscard]] int workers() const override { return threads(); }
  [[nodiscard]] int fft_threads() const override { return threads(); }

 private:
  std::string_view name_;
};

// Everything on the calling thread, in index order.
class SerialBackend final : public Backend {
 public:
  [[nodiscard]] std::string_view name() const override { return "serial"; }
  void for_ranges(std::ptrdiff_t n, RangeBody body) const override {
    if (n > 0) body(0, n);
  }
  [[nodiscard]] int workers() const override { return 1; }
  [[nodiscard]] int fft_threads() const override { return 1; }
};

const ThreadsBackend g_threads_backend("threads");
const SerialBackend g_serial_backend;
const ThreadsBackend g_cuda_backend("cuda");
std::atomic<const Backend*> g_current{&g_threads_backend};

}  // namespace

const Backend& backend() { return *g_current.load(std::memory_order_acquire); }
const Backend& threads_backend() { return g_threads_backend; }
const Backend& serial_backend() { return g_serial_backend; }

namespace {
std::mutex g_registry_mutex;
std::vector<const Backend*>& registry() {
  static std::vector<const Backend*> r{&g_threads_backend, &g_serial_backend, &g_cuda_backend};
  return r;
}
}  // namespace

const Backend* find_backend(std::string_view name) {
  if (name == "auto") return cuda_device().available ? &g_cuda_backend : &g_threads_backend;
  const std::lock_guard lock(g_registry_mutex);
  for (const Backend* b : registry())
    if (b->name() == name) return b;
  return nullptr;
}

std::vector<std::string> backend_names() {
  const std::lock_guard lock(g_registry_mutex);
  std::vector<std::string> names;
  for (const Backend* b : registry()) names.emplace_back(b->name());
  names.insert(names.begin() + 3, "auto");
  return names;
}

void register_backend(const Backend& b) {
  const std::lock_guard lock(g_registry_mutex);
  for (const Backend* e : registry())
    if (e->name() == b.name())
      throw std::invalid_argument("backend \"" + std::string(b.name()) + "\" exists already");
  registry().push_back(&b);
}

BackendScope::BackendScope(const Backend& b)
    : previous_(g_current.exchange(&b, std::memory_order_acq_rel)),
      previous_omp_threads_(omp_get_max_threads()) {
  omp_set_num_threads(b.workers());
}

BackendScope::~BackendScope() {
  g_current.store(previous_, std::memory_order_release);
  omp_set_num_threads(previous_omp_threads_);
}

}  // namespace gfmd
