// The bare cuFFT cost of the transforms of one solver step, the floor the CUDA backend's
// time per step is measured against (BENCHMARKS.md): 3 D2Z + 3 Z2D in double precision on
// an n x n grid, as the solve plans them, timed with CUDA events; median of the repeats after
// a warm-up. Usage: bench_cufft N [repeats]; prints {"n": N, "seconds": s, "device": "..."}.
#include <cuda_runtime.h>
#include <cufft.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    std::fprintf(stderr, "bench_cufft: %s: %s\n", what, cudaGetErrorString(e));
    std::exit(1);
  }
}
void check(cufftResult r, const char* what) {
  if (r != CUFFT_SUCCESS) {
    std::fprintf(stderr, "bench_cufft: %s failed (cuFFT code %d)\n", what, static_cast<int>(r));
    std::exit(1);
  }
}

// Not zeros: a hash of the index in [-0.5, 0.5).
__global__ void fill(double* f, std::size_t n, unsigned salt) {
  for (std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x; i < n;
       i += static_cast<std::size_t>(blockDim.x) * gridDim.x) {
    unsigned long long h = (i + 1) * 0x9E3779B97F4A7C15ULL ^ salt;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 29;
    f[i] = static_cast<double>(h >> 11) / 9007199254740992.0 - 0.5;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_cufft N [repeats]\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 30;
  if (n < 2 || repeats < 1) {
    std::fprintf(stderr, "bench_cufft: N must be >= 2 and repeats >= 1\n");
    return 2;
  }
  const std::size_t points = static_cast<std::size_t>(n) * n;
  const std::size_t modes = static_cast<std::size_t>(n) * (n / 2 + 1);
  double* real[3];
  cufftDoubleComplex* spec[3];
  for (int k = 0; k < 3; ++k) {
    check(cudaMalloc(reinterpret_cast<void**>(&real[k]), points * sizeof(double)), "cudaMalloc");
    check(cudaMalloc(reinterpret_cast<void**>(&spec[k]), modes * sizeof(cufftDoubleComplex)), "cudaMalloc");
    fill<<<1024, 256>>>(real[k], points, 17u * static_cast<unsigned>(k + 1));
    check(cudaGetLastError(), "fill");
  }
  cufftHandle fwd, bwd;
  check(cufftPlan2d(&fwd, n, n, CUFFT_D2Z), "D2Z plan");
  check(cufftPlan2d(&bwd, n, n, CUFFT_Z2D), "Z2D plan");
  cudaEvent_t a, b;
  check(cudaEventCreate(&a), "event");
  check(cudaEventCreate(&b), "event");
  std::vector<float> ms;
  for (int r = -3; r < repeats; ++r) {
    check(cudaEventRecord(a), "event");
    for (int k = 0; k < 3; ++k) check(cufftExecD2Z(fwd, real[k], spec[k]), "D2Z");
    for (int k = 0; k < 3; ++k) check(cufftExecZ2D(bwd, spec[k], real[k]), "Z2D");
    check(cudaEventRecord(b), "event");
    check(cudaEventSynchronize(b), "sync");
    float t = 0;
    check(cudaEventElapsedTime(&t, a, b), "elapsed");
    if (r >= 0) ms.push_back(t);
    // The inverse transforms leave unnormalised fields: refill so that values stay O(1).
    for (int k = 0; k < 3; ++k) fill<<<1024, 256>>>(real[k], points, 31u * static_cast<unsigned>(r + 5) + k);
  }
  std::sort(ms.begin(), ms.end());
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, 0), "device properties");
  std::printf("{\"n\": %d, \"seconds\": %.9g, \"min_seconds\": %.9g, \"repeats\": %d, \"device\": \"%s\"}\n",
              n, ms[ms.size() / 2] * 1e-3, ms.front() * 1e-3, repeats, prop.name);
  return 0;
}
