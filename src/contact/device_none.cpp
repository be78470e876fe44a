// The device solve's stand-in in a build without CUDA: it says so (contact/device_solve.hpp).
#include "device_solve.hpp"

#if !GFMD_HAVE_CUDA
#include "gfmd/core/device.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

std::size_t device_solve_bytes(const Grid&, bool, bool, int) { return 0; }

void require_device_fits(const Grid&, bool, bool, int) {
  throw InputError("solver.backend", "\"cuda\": " + cuda_device().reason);
}

std::unique_ptr<DeviceSolve> make_device_solve(const DeviceProblem&) {
  throw InputError("solver.backend", "\"cuda\": " + cuda_device().reason);
}

}  // namespace gfmd
#endif
