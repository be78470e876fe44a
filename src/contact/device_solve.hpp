// The contact solve on a CUDA device (private to the contact part): the same algorithm as
// ContactSolver (Polonsky-Keer for the normal problem, the friction fixed point with
// Anderson mixing on the traction's support, Douglas-Rachford for stick), its fields
// resident in device memory from set-up to the end, cuFFT for the transforms. Only the
// solution comes back. Built when CMake finds nvcc (GFMD_CUDA); otherwise making one throws
// an InputError that says so. docs/gpu.md.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include "gfmd/contact/device.hpp"
#include "gfmd/contact/solver.hpp"

namespace gfmd {

// What the device solve needs from its ContactSolver: the problem as the host set it up.
struct DeviceProblem {
  const ElasticBody* body = nullptr;
  const RealField* g0 = nullptr;  // separation at first touch
  double g0_rms = 0.0;
  double stiffness = 0.0;  // k_if (inf: hard wall)
  double inv_stiffness = 0.0;
  bool hard_wall = false;
  FrictionParams friction;
  SolverParams solver;
  double stick_step = 0.0;  // gamma of the Douglas-Rachford iteration (exact law with friction)
  // gamma once an automatic slip derivative turns to upwind2 (the solve met stick).
  double stick_step_upwind2 = 0.0;
  // Adhesion (interaction.model = "adhesive"): sigma0 = work_of_adhesion / range and the range;
  // the host's field that receives the last step's gap spread (the residual check reads it).
  bool adhesive = false;
  double adhesive_stress = 0.0, range = 0.0;
  RealField* adhesive_spread = nullptr;
};

// The host's hooks, polled at the same points as on the host.
struct DeviceHooks {
  const std::function<void(const Progress&)>* progress = nullptr;
  const std::function<bool()>* stop = nullptr;
  const std::function<void(const ContactFields&)>* checkpoint = nullptr;
  double checkpoint_interval_s = 0.0;
};

class DeviceSolve {
 public:
  DeviceSolve() = default;
  DeviceSolve(const DeviceSolve&) = delete;
  DeviceSolve& operator=(const DeviceSolve&) = delete;
  virtual ~DeviceSolve() = default;
  // Solves as ContactSolver::solve does, from the warm start in f (pressure, tx, ty); fills
  // every field of f (gap included) and every entry of the returned info except the
  // residual check, which the host does on the returned fields. `total_iterations` counts the
  // inner iterations as they happen (ContactSolver::iterations_done).
  virtual SolveInfo solve(const LoadParams& load, ContactFields& f, const DeviceHooks& hooks,
                          int& total_iterations) = 0;
  // Device memory the solve holds now (fields, spectra, plans' work areas, mixing history).
  [[nodiscard]] virtual std::size_t device_bytes() const = 0;
};

// Allocates on the device (after checking that it fits) and uploads the problem.
std::unique_ptr<DeviceSolve> make_device_solve(const DeviceProblem& problem);

}  // namespace gfmd
