// The CUDA code's shared pieces (for .cu files only): error checks, device arrays counted
// in a tally, the grid pass `launch_each`, and deterministic reductions (fixed launch shape,
// block partials added in block order, so the same sums on every run). Used by the contact
// solve (src/contact/device_solve.cu) and the surface stresses (src/elastic/device_stress.cu).
#pragma once

#include <cuda_runtime.h>
#include <cufft.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include "gfmd/core/error.hpp"

namespace gfmd::cuda_kernels {

constexpr int kThreads = 256;     // threads per block of every kernel
constexpr int kMaxBlocks = 1024;  // blocks of a reduction (fixed per size: the same sums every run)
constexpr int kMaxSums = 16;      // sums one reduction kernel forms

inline void cuda_check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    const std::string msg = std::string("CUDA: ") + what + ": " + cudaGetErrorString(e);
    cudaGetLastError();
    throw SolveError(msg);
  }
}
inline void cufft_check(cufftResult r, const char* what) {
  if (r != CUFFT_SUCCESS)
    throw SolveError(std::string("cuFFT: ") + what + " failed (code " + std::to_string(r) + ")");
}

// Device memory held now and at most (the allocations of one solver).
struct Tally {
  std::size_t now = 0, peak = 0;
  void add(std::size_t b) {
    now += b;
    peak = std::max(peak, now);
  }
  void sub(std::size_t b) { now -= b; }
};

// Device memory of one array, freed with its owner; counted in a shared tally.
template <class T>
class DevArray {
 public:
  DevArray() = default;
  DevArray(const DevArray&) = delete;
  DevArray& operator=(const DevArray&) = delete;
  ~DevArray() { release(); }
  void allocate(std::size_t n, Tally* tally, const char* what) {
    release();
    if (n == 0) return;
    cuda_check(cudaMalloc(reinterpret_cast<void**>(&p_), n * sizeof(T)), what);
    n_ = n;
    tally_ = tally;
    if (tally_) tally_->add(n * sizeof(T));
  }
  // Keeps the first `keep` entries, zeroes the rest up to n.
  void grow(std::size_t n, std::size_t keep, Tally* tally, const char* what) {
    T* q = nullptr;
    cuda_check(cudaMalloc(reinterpret_cast<void**>(&q), n * sizeof(T)), what);
    cuda_check(cudaMemset(q, 0, n * sizeof(T)), what);
    if (p_ && keep > 0) cuda_check(cudaMemcpy(q, p_, keep * sizeof(T), cudaMemcpyDeviceToDevice), what);
    release();
    p_ = q;
    n_ = n;
    tally_ = tally;
    if (tally_) tally_->add(n * sizeof(T));
  }
  void release() {
    if (p_) cudaFree(p_);
    if (tally_) tally_->sub(n_ * sizeof(T));
    p_ = nullptr;
    n_ = 0;
    tally_ = nullptr;
  }
  [[nodiscard]] T* get() const { return p_; }
  [[nodiscard]] std::size_t size() const { return n_; }
  void swap(DevArray& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    std::swap(tally_, o.tally_);
  }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
  Tally* tally_ = nullptr;
};

// Complex arithmetic on cuFFT's double-precision complex type.
__device__ inline cufftDoubleComplex cmul(cufftDoubleComplex a, cufftDoubleComplex b) {
  return {a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x};
}
__device__ inline cufftDoubleComplex cscale(double s, cufftDoubleComplex a) { return {s * a.x, s * a.y}; }
__device__ inline cufftDoubleComplex cadd(cufftDoubleComplex a, cufftDoubleComplex b) {
  return {a.x + b.x, a.y + b.y};
}
// i c z for real c.
__device__ inline cufftDoubleComplex times_i(double c, cufftDoubleComplex z) { return {-c * z.y, c * z.x}; }
__device__ inline cufftDoubleComplex cdiv1(cufftDoubleComplex d) {  // 1 / d
  const double s = 1.0 / (d.x * d.x + d.y * d.y);
  return {d.x * s, -d.y * s};
}

template <class F>
__global__ void each_kernel(std::size_t n, F f) {
  for (std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x; i < n;
       i += static_cast<std::size_t>(blockDim.x) * gridDim.x)
    f(i);
}

// Block sums (or maxima) of NS values per point: partial[s * gridDim.x + block].
template <int NS, bool Max, class F>
__global__ void sums_kernel(std::size_t n, F f, double* partial) {
  double acc[NS];
  for (int s = 0; s < NS; ++s) acc[s] = Max ? -INFINITY : 0.0;
  for (std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x; i < n;
       i += static_cast<std::size_t>(blockDim.x) * gridDim.x)
    f(i, acc);
  __shared__ double sh[NS][kThreads];
  for (int s = 0; s < NS; ++s) sh[s][threadIdx.x] = acc[s];
  __syncthreads();
  for (int stride = kThreads / 2; stride > 0; stride >>= 1) {
    if (static_cast<int>(threadIdx.x) < stride)
      for (int s = 0; s < NS; ++s)
        sh[s][threadIdx.x] = Max ? fmax(sh[s][threadIdx.x], sh[s][threadIdx.x + stride])
                                 : sh[s][threadIdx.x] + sh[s][threadIdx.x + stride];
    __syncthreads();
  }
  if (threadIdx.x == 0)
    for (int s = 0; s < NS; ++s) partial[s * gridDim.x + blockIdx.x] = sh[s][0];
}

// Adds (or takes the maximum of) the block partials of each sum, one block per sum.
template <bool Max>
__global__ void finish_kernel(const double* partial, int blocks, double* out) {
  const double* row = partial + static_cast<std::size_t>(blockIdx.x) * blocks;
  double acc = Max ? -INFINITY : 0.0;
  for (int b = threadIdx.x; b < blocks; b += blockDim.x) acc = Max ? fmax(acc, row[b]) : acc + row[b];
  __shared__ double sh[kThreads];
  sh[threadIdx.x] = acc;
  __syncthreads();
  for (int stride = kThreads / 2; stride > 0; stride >>= 1) {
    if (static_cast<int>(threadIdx.x) < stride)
      sh[threadIdx.x] =
          Max ? fmax(sh[threadIdx.x], sh[threadIdx.x + stride]) : sh[threadIdx.x] + sh[threadIdx.x + stride];
    __syncthreads();
  }
  if (threadIdx.x == 0) out[blockIdx.x] = sh[0];
}

inline int blocks_for(std::size_t n) {
  return static_cast<int>(
      std::max<std::size_t>(1, std::min<std::size_t>((n + kThreads - 1) / kThreads, kMaxBlocks)));
}

template <class F>
void launch_each(std::size_t n, F f) {
  if (n == 0) return;
  const std::size_t blocks = std::min<std::size_t>((n + kThreads - 1) / kThreads, 65535u * 8u);
  each_kernel<<<static_cast<unsigned>(blocks), kThreads>>>(n, f);
  cuda_check(cudaGetLastError(), "a pass over the grid");
}

// Shared buffers of the reductions.
// The reductions: each writes its sums to a slot of `out` without waiting; fetch() reads
// the slots back in one copy (so that independent sums cost one synchronisation).
struct Reducer {
  static constexpr int kSlots = 2;
  DevArray<double> partial, out;
  double* host = nullptr;  // pinned
  Reducer() = default;
  Reducer(const Reducer&) = delete;
  Reducer& operator=(const Reducer&) = delete;
  ~Reducer() {
    if (host) cudaFreeHost(host);
  }
  void init(Tally* tally) {
    partial.allocate(static_cast<std::size_t>(kMaxSums) * kMaxBlocks, tally, "reduction buffers");
    out.allocate(static_cast<std::size_t>(kMaxSums) * kSlots, tally, "reduction buffers");
    cuda_check(cudaMallocHost(reinterpret_cast<void**>(&host), sizeof(double) * kMaxSums * kSlots),
               "reduction buffers");
  }
  template <int NS, bool Max = false, class F>
  void launch(int slot, std::size_t n, F f) {
    static_assert(NS <= kMaxSums);
    // No points: the finishing kernel alone writes the identity (0, or -inf for a maximum).
    const int blocks = n == 0 ? 0 : blocks_for(n);
    if (blocks > 0) {
      sums_kernel<NS, Max><<<blocks, kThreads>>>(n, f, partial.get());
      cuda_check(cudaGetLastError(), "a reduction over the grid");
    }
    finish_kernel<Max><<<NS, kThreads>>>(partial.get(), blocks, out.get() + slot * kMaxSums);
    cuda_check(cudaGetLastError(), "a reduction over the grid");
  }
  // The sums of slots 0 .. slots-1 (slot s at host[s * kMaxSums]), valid until the next fetch.
  const double* fetch(int slots) {
    cuda_check(cudaMemcpyAsync(host, out.get(), sizeof(double) * kMaxSums * slots, cudaMemcpyDeviceToHost),
               "reading a sum");
    cuda_check(cudaStreamSynchronize(nullptr), "reading a sum");
    return host;
  }
  template <int NS, bool Max = false, class F>
  std::array<double, NS> run(std::size_t n, F f) {
    launch<NS, Max>(0, n, f);
    const double* h = fetch(1);
    std::array<double, NS> r{};
    std::copy(h, h + NS, r.begin());
    return r;
  }
};

}  // namespace gfmd::cuda_kernels
