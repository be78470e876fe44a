// The CUDA backend (solver.backend = "cuda"): the same solutions as the host to 1e-10
// relative on the example cases, where a CUDA device is usable (skipped with the reason
// elsewhere: CI has no GPU); and, everywhere, what "cuda" and "auto" do without one.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#if GFMD_HAVE_CUDA
#include <cuda_runtime_api.h>
#endif

#include "device_helpers.hpp"
#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/device.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "test_util.hpp"

using namespace gfmd;
using namespace gfmd::testing;

namespace {

// A case run with its stresses kept, both post-analyses and the profiles, on one backend.
CaseResult run_with_stresses(const std::string& toml, std::vector<std::string> sets,
                             const std::string& backend) {
  sets.emplace_back("output.fields=false");
  sets.emplace_back("solver.backend=\"" + backend + "\"");
  Config c = parse_config(toml, "test.toml", sets);
  c.stress.post_analysis = {"paper", "consistent"};
  c.stress.profiles = true;
  c.stress.depths = {0.01 * c.grid.lx};  // on the host in both runs
  RunOptions o;
  o.keep_stress_fields = true;
  CaseResult r = run_case(c, o);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return r;
}

// Two stress summaries (a: device, b: host): values to `bound`; the cells of the maxima the
// same, or -- where the field has near-equal maxima (a symmetric contact), which round-off
// picks -- a cell where the host's field (when given) is within `bound` of its maximum; the
// high-tension fractions to a cell or two (a value at the threshold may fall either way).
void expect_same_summary(const StressSummary& a, const StressSummary& b, double bound, const char* what,
                         int nx, std::size_t cells, const RealField* s1 = nullptr,
                         const RealField* vm = nullptr) {
  SCOPED_TRACE(what);
  EXPECT_LE(relative(a.max_tensile_stress, b.max_tensile_stress), bound);
  EXPECT_LE(relative(a.max_von_mises, b.max_von_mises), bound);
  const auto same_cell = [&](int ax, int ay, int bx, int by, double max, const RealField* f) {
    if (ax == bx && ay == by) return;
    ASSERT_NE(f, nullptr) << "maxima at different cells: (" << ax << ", " << ay << ") vs (" << bx << ", "
                          << by << ")";
    const double v = (*f)[static_cast<std::size_t>(ay) * nx + ax];
    EXPECT_LE(relative(v, max), bound) << "the device's maximum cell (" << ax << ", " << ay << ")";
  };
  same_cell(a.max_tensile_ix, a.max_tensile_iy, b.max_tensile_ix, b.max_tensile_iy, b.max_tensile_stress, s1);
  same_cell(a.max_von_mises_ix, a.max_von_mises_iy, b.max_von_mises_ix, b.max_von_mises_iy, b.max_von_mises,
            vm);
  EXPECT_NEAR(a.high_tension_area_fraction, b.high_tension_area_fraction, 2.5 / static_cast<double>(cells));
}

// The surface stresses of a solution evaluated on the device and on the host: every field
// (tensor, principal values, the eigenvector) and every summary to `bound`.
void compare_stresses_with_host(const std::string& toml, const std::vector<std::string>& sets,
                                double bound = 1e-10) {
  const CaseResult h = run_with_stresses(toml, sets, "threads");
  const CaseResult d = run_with_stresses(toml, sets, "cuda");
  EXPECT_FALSE(h.stress_on_device);
  EXPECT_TRUE(d.stress_on_device);
  ASSERT_TRUE(h.stress_summary && d.stress_summary);
  // The solutions differ by the solve's round-off (compare_with_host): the stresses inherit it.
  const int nx = h.config.grid.nx;
  const std::size_t cells = h.config.grid.size();
  expect_same_summary(*d.stress_summary, *h.stress_summary, bound, "solution", nx, cells, &h.principal.s1,
                      &h.principal.von_mises);
  const std::pair<const RealField*, const RealField*> fields[] = {
      {&d.stress.xx, &h.stress.xx},       {&d.stress.yy, &h.stress.yy},
      {&d.stress.zz, &h.stress.zz},       {&d.stress.xy, &h.stress.xy},
      {&d.stress.xz, &h.stress.xz},       {&d.stress.yz, &h.stress.yz},
      {&d.principal.s1, &h.principal.s1}, {&d.principal.s2, &h.principal.s2},
      {&d.principal.s3, &h.principal.s3}, {&d.principal.von_mises, &h.principal.von_mises}};
  double worst = 0.0;
  for (const auto& [a, b] : fields) worst = std::max(worst, field_difference(*a, *b));
  // The eigenvector of s1, where s1 is well separated from s2 (elsewhere it is not defined).
  double de = 0.0;
  for (std::size_t k = 0; k < h.principal.s1.size(); ++k)
    if (h.principal.s1[k] - h.principal.s2[k] > 1e-3 * std::abs(h.stress_summary->max_von_mises))
      de = std::max({de, std::abs(d.principal.e1x[k] - h.principal.e1x[k]),
                     std::abs(d.principal.e1y[k] - h.principal.e1y[k]),
                     std::abs(d.principal.e1z[k] - h.principal.e1z[k])});
  std::printf("    stresses device vs host: fields %.2e, e1 %.2e, s1 max %.6g / %.6g\n", worst, de,
              d.stress_summary->max_tensile_stress, h.stress_summary->max_tensile_stress);
  EXPECT_LE(worst, bound);
  EXPECT_LE(de, 1e-8);
  EXPECT_NEAR(d.area_above_half_max, h.area_above_half_max, 2.5 / static_cast<double>(cells));
  EXPECT_EQ(d.profiles.has_value(), h.profiles.has_value());
  ASSERT_EQ(d.subsurface.size(), 1U);
  ASSERT_EQ(h.subsurface.size(), 1U);
  EXPECT_LE(relative(d.subsurface[0].summary.max_von_mises, h.subsurface[0].summary.max_von_mises), bound);
  EXPECT_LE(field_difference(d.subsurface[0].s1, h.subsurface[0].s1), bound);
  EXPECT_LE(field_difference(d.subsurface[0].von_mises, h.subsurface[0].von_mises), bound);
  std::printf("    subsurface (depth %.3g) device vs host: s1 %.2e, von Mises %.2e\n", d.subsurface[0].depth,
              field_difference(d.subsurface[0].s1, h.subsurface[0].s1),
              field_difference(d.subsurface[0].von_mises, h.subsurface[0].von_mises));
  ASSERT_EQ(d.post_analyses.size(), 2U);
  ASSERT_EQ(h.post_analyses.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(d.post_analyses[k].kind, h.post_analyses[k].kind);
    // Their von Mises fields are not kept: its maximum's value is compared, not its cell.
    StressSummary dk = d.post_analyses[k].summary;
    dk.max_von_mises_ix = h.post_analyses[k].summary.max_von_mises_ix;
    dk.max_von_mises_iy = h.post_analyses[k].summary.max_von_mises_iy;
    expect_same_summary(dk, h.post_analyses[k].summary, bound, h.post_analyses[k].kind.c_str(), nx, cells,
                        &h.post_analyses[k].s1);
    EXPECT_LE(field_difference(d.post_analyses[k].s1, h.post_analyses[k].s1), bound);
    EXPECT_NEAR(d.post_analyses[k].area_above_half_max, h.post_analyses[k].area_above_half_max,
                2.5 / static_cast<double>(cells));
  }
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
  // Refused before the directory is made (it was left holding a failed status.json).
  EXPECT_FALSE(std::filesystem::exists(dir / "out")) << o.output;
  // A finished result of the case is still reused by --resume (nothing to solve, no device).
  write_file(dir / "threads.toml", kSmallHertz);
  ASSERT_EQ(run_gfmd("run " + (dir / "threads.toml").string() + " -q -o " + (dir / "done").string()).code, 0);
  const std::filesystem::path summary = dir / "done" / "summary.json";
  nlohmann::json j = nlohmann::json::parse(read_file(summary));
  j["input"]["solver"]["backend"] = "cuda";  // as if solved on a device
  write_file(summary, j.dump(2));
  const Outcome again =
      run_gfmd("run " + (dir / "case.toml").string() + " -o " + (dir / "done").string() + " --resume");
  EXPECT_EQ(again.code, 0) << again.output;
}

// The physics the device lacks (device_lacks): "auto" solves it on the cores, on any machine;
// "cuda" is refused naming the key where a device is usable (without one it stops at
// solver.backend, above).
TEST(Device, AutoKeepsHostOnlyPhysicsOnTheCoresAndCudaNamesIt) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"elastic.viscoelastic=\"sls\"", "elastic.high_frequency_modulus=10", "elastic.relaxation_time=1",
        "friction.velocity=0.02"},
       "elastic.viscoelastic"},
      {{"interaction.model=\"adhesive\"", "interaction.work_of_adhesion=1e-3", "interaction.range=0.02",
        "interaction.hardness=0.5"},
       "interaction.hardness"}};
  const DeviceStatus dev = cuda_device();
  for (const auto& [sets, key] : cases) {
    std::vector<std::string> with = sets;
    with.emplace_back("solver.backend=\"auto\"");
    const CaseResult a = solve(kSmallHertz, with);
    EXPECT_EQ(a.config.backend, "threads") << key;
    if (!dev.available) continue;
    with.back() = "solver.backend=\"cuda\"";
    try {
      (void)run_case(parse_config(kSmallHertz, "test.toml", with));
      ADD_FAILURE() << key << ": accepted on the cuda backend";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

TEST(Device, BackendNamesListCudaAndAuto) {
  const auto names = backend_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "cuda"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "auto"), names.end());
  EXPECT_NE(find_backend("auto"), nullptr);
  EXPECT_EQ(find_backend("cuda")->name(), "cuda");
}

TEST(Device, SurfaceStressesAndPostAnalysesMatchTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_stresses_with_host(example("hertz_sliding"), {"grid.nx=128", "solver.tolerance=1e-12"});
}

TEST(Device, StressesOfRoughSlidingOnALayerMatchTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_stresses_with_host(
      example("selfaffine"),
      {"grid.nx=256", "indenter.lambda_short=0.0625", "friction.coefficient=1", "load.pressure=0.01",
       "elastic.thickness=0.1", "elastic.poisson=0.49", "solver.tolerance=1e-12"});
}

TEST(Device, StressesOnTheSameFieldsAgreeToRoundOff) {
  // The same input fields on both sides: only the arithmetic's order differs.
  REQUIRE_CUDA_DEVICE();
  const CaseResult h = solve(example("hertz_sliding"), {"grid.nx=128", "output.fields=false"});
  const FFT fft(h.config.grid);
  const StressField s = surface_stress(fft, h.config.elastic, h.fields);
  const PrincipalField p = principal(s);
  const StressSummary sum = summarize(h.config.grid, p, 0.9);
  DeviceStressRequest q;
  q.tensor = true;
  q.parts = PrincipalParts::All;
  const auto d = device_surface_stress(h.config.grid, h.config.elastic, h.fields, q);
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(d->device_bytes, 0U);
  EXPECT_LE(field_difference(d->tensor.xx, s.xx), 1e-13);
  EXPECT_LE(field_difference(d->tensor.xy, s.xy), 1e-13);
  EXPECT_LE(field_difference(d->tensor.xz, s.xz), 0.0);
  EXPECT_LE(field_difference(d->principal.s1, p.s1), 1e-13);
  EXPECT_LE(field_difference(d->principal.von_mises, p.von_mises), 1e-13);
  expect_same_summary(d->summary, sum, 1e-13, "same fields", h.config.grid.nx, h.config.grid.size(), &p.s1,
                      &p.von_mises);
  const ElasticBody body(h.config.grid, h.config.elastic);
  const PrincipalField pc = principal(post_analysis_stress(fft, body, h.fields.pressure, 0.3, 20.0));
  q.tensor = false;
  q.parts = PrincipalParts::SummaryOnly;
  q.s1 = true;
  const auto dc = device_post_analysis_stress(body, h.fields.pressure, 0.3, 20.0, q);
  ASSERT_TRUE(dc.has_value());
  EXPECT_LE(field_difference(dc->principal.s1, pc.s1), 1e-12);
  EXPECT_TRUE(dc->principal.von_mises.empty());
  // A plane below the surface of a layer (both of its per-mode forms: qh below and above 1).
  ElasticParams layer = h.config.elastic;
  layer.thickness = 0.3;
  layer.poisson = 0.45;
  const PrincipalField ps = principal(subsurface_stress(fft, layer, h.fields, 0.05));
  q.von_mises = true;
  const auto dsub = device_subsurface_stress(h.config.grid, layer, h.fields, 0.05, q);
  ASSERT_TRUE(dsub.has_value());
  EXPECT_LE(field_difference(dsub->principal.s1, ps.s1), 1e-12);
  EXPECT_LE(field_difference(dsub->principal.von_mises, ps.von_mises), 1e-12);
  std::printf("    subsurface, same fields: s1 %.2e, von Mises %.2e\n",
              field_difference(dsub->principal.s1, ps.s1),
              field_difference(dsub->principal.von_mises, ps.von_mises));
}

TEST(Device, ASubsurfaceDepthTheBodyDoesNotHaveIsRefusedFirst) {
  // Everywhere: the depth is checked before a device is asked for.
  const Grid g{16, 16, 1.0, 1.0};
  ContactFields f;
  f.pressure.assign(g.size(), 1.0);
  ElasticParams layer;
  layer.thickness = 0.1;
  EXPECT_THROW(device_subsurface_stress(g, layer, f, 0.2, DeviceStressRequest{}), ParameterError);
  EXPECT_THROW(device_subsurface_stress(g, layer, f, -0.01, DeviceStressRequest{}), ParameterError);
}

TEST(Device, WithoutADeviceTheStressesStayOnTheHost) {
  const DeviceStatus dev = cuda_device();
  if (dev.available) GTEST_SKIP() << "a CUDA device is usable here";
  const Grid g{16, 16, 1.0, 1.0};
  ContactFields f;
  f.pressure.assign(g.size(), 1.0);
  f.ux.assign(g.size(), 0.0);
  f.uy.assign(g.size(), 0.0);
  EXPECT_FALSE(device_surface_stress(g, ElasticParams{}, f, DeviceStressRequest{}).has_value());
  EXPECT_FALSE(device_subsurface_stress(g, ElasticParams{}, f, 0.1, DeviceStressRequest{}).has_value());
}
