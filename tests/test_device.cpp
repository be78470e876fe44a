// The CUDA backend (solver.backend = "cuda"): the same solutions as the host to 1e-10
// relative on the example cases, where a CUDA device is usable (skipped with the reason
// elsewhere: CI has no GPU); and, everywhere, what "cuda" and "auto" do without one.
#include <algorithm>
#include <cmath>

#if GFMD_HAVE_CUDA
#include <cuda_runtime_api.h>
#endif

#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/device.hpp"
#include "test_util.hpp"

using namespace gfmd;
using namespace gfmd::testing;

namespace {

#define REQUIRE_CUDA_DEVICE()                                                    \
  do {                                                                           \
    const DeviceStatus dev_ = cuda_device();                                     \
    if (!dev_.available) GTEST_SKIP() << "no CUDA device here: " << dev_.reason; \
  } while (0)

std::string example(const std::string& name) {
  return read_file(std::filesystem::path(GFMD_SOURCE_DIR) / "examples" / (name + ".toml"));
}

// max |a - b| / max |b|: the difference of two fields relative to the field's size.
double field_difference(const RealField& a, const RealField& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0, m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    m = std::max(m, std::abs(b[i]));
  }
  return m > 0 ? d / m : d;
}

double relative(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// Solves the case on the host ("threads") and on the device with the same settings and
// checks that fields and observables agree to `bound` (relative).
void compare_with_host(const std::string& toml, std::vector<std::string> sets, double bound = 1e-10) {
  sets.emplace_back("output.fields=false");
  std::vector<std::string> host_sets = sets, dev_sets = sets;
  host_sets.emplace_back("solver.backend=\"threads\"");
  dev_sets.emplace_back("solver.backend=\"cuda\"");
  const CaseResult h = solve(toml, host_sets);
  const CaseResult d = solve(toml, dev_sets);
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

}  // namespace

TEST(Device, FrictionlessHertzMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("hertz_nu025"), {"grid.nx=256", "solver.tolerance=1e-12"});
}

TEST(Device, HardWallUnderApproachControlMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("eggcrate"), {"grid.nx=128", "interaction.model=\"hardwall\"",
                                          "load.approach=0.01", "solver.tolerance=1e-12"});
}

TEST(Device, SlidingHertzMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("hertz_sliding"), {"grid.nx=256", "solver.tolerance=1e-12"});
}

TEST(Device, SlidingOnAThinIncompressibleLayerMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("hertz_nu049_layer"),
                    {"grid.nx=256", "friction.coefficient=0.5", "solver.tolerance=1e-12"});
}

TEST(Device, RoughSlidingMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("selfaffine"),
                    {"grid.nx=256", "indenter.lambda_short=0.0625", "friction.coefficient=1",
                     "load.pressure=0.01", "solver.tolerance=1e-12"});
}

TEST(Device, RollingWithStickMatchesTheHost) {
  // The Douglas-Rachford stick-slip solve with the upwind derivative (Kalker's limit).
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("rolling_sphere"), {"grid.nx=64", "solver.tolerance=1e-11"});
}

TEST(Device, ReportsItsMemoryPerPoint) {
  // Fields, spectra and tables of a frictionless and a sliding solve: the bytes held at the end
  // against the count device_solve_bytes makes (docs/gpu.md), within the transforms' work area
  // and the mixing history.
  REQUIRE_CUDA_DEVICE();
  const CaseResult d =
      solve(example("hertz_sliding"), {"grid.nx=512", "solver.backend=\"cuda\"", "output.fields=false"});
  const double per_point = static_cast<double>(d.info.device_bytes) / (512.0 * 512.0);
  std::printf("    sliding 512^2: %.1f B/point on the device\n", per_point);
  EXPECT_GT(per_point, 150.0);
  EXPECT_LT(per_point, 400.0);
}

TEST(Device, AGridThatDoesNotFitIsRefusedBeforeAnythingIsMade) {
  // With all but 1 GiB of the card taken, a 4096^2 sliding solve (about 3 GiB) is refused
  // with an error naming grid and the sizes, before the surface or any field is made.
  REQUIRE_CUDA_DEVICE();
#if GFMD_HAVE_CUDA
  const DeviceStatus dev = cuda_device();
  void* hog = nullptr;
  const std::size_t leave = std::size_t{1} << 30;
  ASSERT_GT(dev.free_bytes, leave);
  ASSERT_EQ(cudaMalloc(&hog, dev.free_bytes - leave), cudaSuccess);
  const Config c = parse_config(example("selfaffine"), "selfaffine.toml",
                                {"grid.nx=4096", "friction.coefficient=1", "solver.backend=\"cuda\""});
  std::string what;
  try {
    (void)run_case(c);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "grid");
    what = e.what();
  }
  cudaFree(hog);
  std::printf("    %s\n", what.c_str());
  EXPECT_NE(what.find("GiB"), std::string::npos) << what;
  EXPECT_NE(what.find("4096 x 4096"), std::string::npos) << what;
  // The estimate the check uses is the memory a solve then holds, within the mixing history.
  const CaseResult d =
      solve(example("hertz_sliding"), {"grid.nx=512", "solver.backend=\"cuda\"", "output.fields=false"});
  const double estimate = static_cast<double>(device_solve_bytes(Grid{512, 512, 4.0, 4.0}, true));
  std::printf("    512^2 sliding: estimate %.0f B, held at most %zu B\n", estimate, d.info.device_bytes);
  EXPECT_LE(estimate, 1.01 * static_cast<double>(d.info.device_bytes));
  EXPECT_GE(estimate, 0.6 * static_cast<double>(d.info.device_bytes));
#endif
}

TEST(Device, WithoutADeviceCudaIsAClearErrorAndAutoRunsOnTheCores) {
  // Runs everywhere: where no device is usable "cuda" stops before any work with an error
  // naming solver.backend and the reason, and "auto" solves on the cores.
  const DeviceStatus dev = cuda_device();
  const CaseResult a = solve(kSmallHertz, {"solver.backend=\"auto\""});
  EXPECT_EQ(a.config.backend, dev.available ? "cuda" : "threads");
  if (dev.available) return;
  EXPECT_FALSE(dev.reason.empty());
  const Config c = parse_config(kSmallHertz, "test.toml", {"solver.backend=\"cuda\""});
  try {
    (void)run_case(c);
    ADD_FAILURE() << "no error without a device";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "solver.backend");
    EXPECT_NE(std::string(e.what()).find("cuda"), std::string::npos) << e.what();
  }
  const std::filesystem::path dir = scratch_dir("device", "no_device");
  write_file(dir / "case.toml", kSmallHertz + "[solver]\nbackend = \"cuda\"\n");
  const Outcome o = run_gfmd("run " + (dir / "case.toml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(o.code, 2) << o.output;
  EXPECT_NE(o.output.find("solver.backend"), std::string::npos) << o.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

TEST(Device, BackendNamesListCudaAndAuto) {
  const auto names = backend_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "cuda"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "auto"), names.end());
  EXPECT_NE(find_backend("auto"), nullptr);
  EXPECT_EQ(find_backend("cuda")->name(), "cuda");
}
