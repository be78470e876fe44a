// Queries of the CUDA device (core/device.hpp); the runtime is linked statically and finds
// the driver at run time, so a machine without a GPU or driver gets a reason, not a crash.
#include "gfmd/core/device.hpp"

#if GFMD_HAVE_CUDA
#include <cuda_runtime_api.h>
#endif

namespace gfmd {

#if GFMD_HAVE_CUDA
bool cuda_built() { return true; }

DeviceStatus cuda_device() {
  DeviceStatus s;
  int count = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&count); e != cudaSuccess) {
    s.reason = std::string("no usable CUDA device (") + cudaGetErrorString(e) + ")";
    cudaGetLastError();  // clear the sticky error of a failed query
    return s;
  }
  if (count == 0) {
    s.reason = "no CUDA device on this machine";
    return s;
  }
  cudaDeviceProp prop{};
  if (const cudaError_t e = cudaGetDeviceProperties(&prop, 0); e != cudaSuccess) {
    s.reason = std::string("cannot query CUDA device 0 (") + cudaGetErrorString(e) + ")";
    return s;
  }
  s.name = prop.name;
  if (const cudaError_t e = cudaMemGetInfo(&s.free_bytes, &s.total_bytes); e != cudaSuccess) {
    s.reason = std::string("cannot query the memory of CUDA device 0 (") + cudaGetErrorString(e) + ")";
    return s;
  }
  s.available = true;
  return s;
}
#else
bool cuda_built() { return false; }

DeviceStatus cuda_device() {
  DeviceStatus s;
  s.reason = "this gfmd was built without CUDA (no nvcc found when it was configured; see docs/gpu.md)";
  return s;
}
#endif

}  // namespace gfmd
