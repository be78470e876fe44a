// The CUDA device this build can use, if any: what `solver.backend = "cuda"` and "auto"
// ask before a solve runs on it. Built without CUDA (no nvcc at configure time) every
// query says so; nothing here needs a GPU to compile or to run.
#pragma once

#include <cstddef>
#include <string>

namespace gfmd {

struct DeviceStatus {
  bool available = false;       // a CUDA device can be used now
  std::string name;             // e.g. "NVIDIA H100 80GB HBM3"
  std::size_t total_bytes = 0;  // its memory
  std::size_t free_bytes = 0;   // free when asked
  std::string reason;           // why not, when !available
};

// True when this build has the CUDA backend (GFMD_CUDA at configure time).
bool cuda_built();
// Device 0 as the CUDA runtime sees it now (queried on every call).
DeviceStatus cuda_device();

}  // namespace gfmd
