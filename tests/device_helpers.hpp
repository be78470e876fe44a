// Helpers of the CUDA backend's tests (test_device*.cpp): skip where no device is usable, the
// example cases, and the comparison of a case solved on the host ("threads") and on the device.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gfmd/core/device.hpp"
#include "test_util.hpp"

namespace gfmd::testing {

#define REQUIRE_CUDA_DEVICE()                                                    \
  do {                                                                           \
    const DeviceStatus dev_ = cuda_device();                                     \
    if (!dev_.available) GTEST_SKIP() << "no CUDA device here: " << dev_.reason; \
  } while (0)

inline std::string example(const std::string& name) {
  return read_file(std::filesystem::path(GFMD_SOURCE_DIR) / "examples" / (name + ".toml"));
}

// max |a - b| / max |b|: the difference of two fields relative to the field's size.
inline double field_difference(const RealField& a, const RealField& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0, m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    m = std::max(m, std::abs(b[i]));
  }
  return m > 0 ? d / m : d;
}

inline double relative(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// The case solved on the host ("threads") and then on the device with the same settings (no
// fields.nc): {host, device}.
struct HostAndDevice {
  CaseResult host, device;
};
inline HostAndDevice solve_on_host_and_device(const std::string& toml, std::vector<std::string> sets) {
  sets.emplace_back("output.fields=false");
  std::vector<std::string> host_sets = sets, dev_sets = sets;
  host_sets.emplace_back("solver.backend=\"threads\"");
  dev_sets.emplace_back("solver.backend=\"cuda\"");
  HostAndDevice r{solve(toml, host_sets), {}};
  r.device = solve(toml, dev_sets);
  return r;
}

// Solves the case on the host ("threads") and on the device with the same settings and
// checks that fields and observables agree to `bound` (relative).
inline void compare_with_host(const std::string& toml, std::vector<std::string> sets, double bound = 1e-10) {
  const auto [h, d] = solve_on_host_and_device(toml, std::move(sets));
  EXPECT_EQ(d.config.backend, "cuda");
  EXPECT_GT(d.info.device_bytes, 0U);
  const ContactFields& a = d.fields;
  const ContactFields& b = h.fields;
  const double dp = field_difference(a.pressure, b.pressure);
  const double duz = field_difference(a.uz, b.uz);
  const double dux = field_difference(a.ux, b.ux);
  const double dtx = field_difference(a.tx, b.tx);
  const double dty = field_difference(a.ty, b.ty);
  const double dgap = field_difference(a.gap, b.gap);
  std::printf(
      "    device vs host: pressure %.2e, u_z %.2e, u_x %.2e, tau_x %.2e, tau_y %.2e, gap %.2e; "
      "iterations %d / %d, friction steps %d / %d, splitting %d / %d\n",
      dp, duz, dux, dtx, dty, dgap, d.info.iterations, h.info.iterations, d.info.outer_iterations,
      h.info.outer_iterations, d.info.tangential_iterations, h.info.tangential_iterations);
  EXPECT_LE(dp, bound);
  EXPECT_LE(duz, bound);
  EXPECT_LE(dux, bound);
  EXPECT_LE(dgap, bound);
  if (h.config.friction.coefficient > 0) {
    EXPECT_LE(dtx, bound);
    EXPECT_LE(dty, bound);
  }
  EXPECT_LE(relative(d.info.approach, h.info.approach), bound);
  EXPECT_LE(relative(d.observables.normal_force, h.observables.normal_force), bound);
  EXPECT_EQ(d.fields.stick.size(), h.fields.stick.size());
  EXPECT_EQ(d.info.stick_points, h.info.stick_points);
}

}  // namespace gfmd::testing
