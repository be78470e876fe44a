// The backend seam (core/backend.hpp): passes, reductions and FFTs give the same numbers on
// every backend, and the solver, stresses and flow run on whichever backend is current
// without knowing which (shown with the serial reference and a third backend defined here).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <complex>
#include <cstring>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/core/rng.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

// A backend unlike both built-in ones: ranges of at most 5 indices, run last first on
// short-lived std::threads, with a count of the ranges it ran. If any pass depended on the
// order or the split of its ranges, or bypassed the backend, the tests below would see it.
class ScrambledBackend final : public Backend {
 public:
  [[nodiscard]] std::string_view name() const override { return "scrambled-test"; }
  void for_ranges(std::ptrdiff_t n, RangeBody body) const override {
    if (n <= 0) return;
    std::vector<std::pair<std::ptrdiff_t, std::ptrdiff_t>> ranges;
    for (std::ptrdiff_t lo = 0; lo < n; lo += 5) ranges.emplace_back(lo, std::min(n, lo + 5));
    std::atomic<std::size_t> next{0};
    auto work = [&] {
      for (std::size_t k; (k = next.fetch_add(1)) < ranges.size();) {
        const auto& r = ranges[ranges.size() - 1 - k];
        body(r.first, r.second);
      }
    };
    std::thread other(work);
    work();
    other.join();
    ranges_run_ += ranges.size();
  }
  [[nodiscard]] int workers() const override { return 2; }
  [[nodiscard]] int fft_threads() const override { return 1; }
  // FFTW's plans, single-threaded, counted.
  [[nodiscard]] std::unique_ptr<FftEngine> make_fft_engine(const Grid& grid, Planner planner) const override {
    ++engines_made_;
    return make_fftw_engine(grid, planner, 1);
  }
  [[nodiscard]] std::size_t ranges_run() const { return ranges_run_.load(); }
  [[nodiscard]] std::size_t engines_made() const { return engines_made_.load(); }

 private:
  mutable std::atomic<std::size_t> ranges_run_{0}, engines_made_{0};
};

const ScrambledBackend& scrambled() {
  static ScrambledBackend b;
  static std::once_flag once;
  std::call_once(once, [] { register_backend(b); });
  return b;
}

// Drops what may differ between runs of the same numbers: timings and the backend's name.
nlohmann::json without_timings(nlohmann::json j) {
  for (auto it = j.begin(); it != j.end();) {
    const std::string& k = it.key();
    if (k == "backend" || k == "threads" || k.find("time") != std::string::npos ||
        k.find("seconds") != std::string::npos) {
      it = j.erase(it);
    } else {
      if (it->is_object()) *it = without_timings(*it);
      ++it;
    }
  }
  return j;
}

std::vector<const Backend*> all_backends() { return {&threads_backend(), &serial_backend(), &scrambled()}; }

}  // namespace

TEST(Backend, EveryIndexIsVisitedOnceOnEveryBackend) {
  for (const Backend* b : all_backends()) {
    const BackendScope scope(*b);
    EXPECT_EQ(&backend(), b);
    for (std::ptrdiff_t n : {0, 1, 2, 7, 1000, 4099}) {
      std::vector<int> seen(static_cast<std::size_t>(n), 0);
      parallel_for(n, [&](std::ptrdiff_t i) { ++seen[static_cast<std::size_t>(i)]; });
      for (std::ptrdiff_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], 1) << b->name() << " n=" << n << " i=" << i;
      std::vector<int> rows(static_cast<std::size_t>(n), 0);
      for_rows(static_cast<int>(n), [&](int r) { ++rows[static_cast<std::size_t>(r)]; });
      for (std::ptrdiff_t i = 0; i < n; ++i) ASSERT_EQ(rows[i], 1) << b->name() << " n=" << n << " row=" << i;
    }
  }
}

TEST(Backend, ScopesNestAndRestore) {
  const Backend& outer = backend();
  {
    const BackendScope s1(serial_backend());
    EXPECT_EQ(backend().name(), "serial");
    {
      const BackendScope s2(threads_backend());
      EXPECT_EQ(backend().name(), "threads");
    }
    EXPECT_EQ(backend().name(), "serial");
  }
  EXPECT_EQ(&backend(), &outer);
}

TEST(Backend, RegistryFindsByNameAndRefusesDuplicates) {
  EXPECT_EQ(find_backend("threads"), &threads_backend());
  EXPECT_EQ(find_backend("serial"), &serial_backend());
  EXPECT_EQ(find_backend("no-such-backend"), nullptr);
  const Backend& s = scrambled();
  EXPECT_EQ(find_backend("scrambled-test"), &s);
  EXPECT_THROW(register_backend(s), std::invalid_argument);
  const auto names = backend_names();
  ASSERT_GE(names.size(), 3U);
  EXPECT_EQ(names[0], "threads");
  EXPECT_EQ(names[1], "serial");
}

TEST(Backend, ReductionsAndTransformsGiveTheSameBitsOnEveryBackend) {
  // Sums of a random field (rows summed in order) and a forward + backward FFT: the same
  // bits under each backend, so no result depends on where it ran.
  const Grid g{96, 80, 1.0, 1.0};
  RealField f(g.size());
  Rng rng(7);
  for (auto& v : f) v = rng.uniform() - 0.5;
  std::vector<std::array<double, 2>> sums;
  std::vector<RealField> back;
  for (const Backend* b : all_backends()) {
    const BackendScope scope(*b);
    sums.push_back(grid_sums<2>(g, [&](std::size_t i, std::array<double, 2>& a) {
      a[0] += f[i];
      a[1] += f[i] * f[i];
    }));
    const FFT fft(g);
    SpecField s = fft.spec_field();
    RealField r = fft.real_field();
    fft.forward(f.data(), s.data());
    fft.backward(s.data(), r.data());
    back.push_back(r);
  }
  for (std::size_t k = 1; k < sums.size(); ++k) {
    EXPECT_EQ(sums[k][0], sums[0][0]) << all_backends()[k]->name();
    EXPECT_EQ(sums[k][1], sums[0][1]) << all_backends()[k]->name();
    EXPECT_EQ(std::memcmp(back[k].data(), back[0].data(), g.size() * sizeof(double)), 0)
        << all_backends()[k]->name();
  }
  // and the round trip is the identity to round-off
  double err = 0;
  for (std::size_t i = 0; i < g.size(); ++i) err = std::max(err, std::abs(back[0][i] - f[i]));
  EXPECT_LT(err, 1e-14);
}

// The estimating planner's transforms run line by line (src/core/fft_lines.hpp): they are
// the discrete Fourier transforms (against a direct sum in long double, to 1e-14 of the
// largest mode, on odd and even sides), and their bits do not depend on the thread count
// (each line is one thread's; odd rows go through an aligned copy).
TEST(Backend, LineTransformsAreTheDftForAnyThreadCount) {
  for (const auto& [nx, ny] :
       std::vector<std::pair<int, int>>{{15, 12}, {16, 9}, {7, 5}, {96, 90}, {45, 33}}) {
    const Grid g{nx, ny, 1.0, 1.0};
    RealField f(g.size());
    Rng rng(static_cast<std::uint64_t>(nx * 131 + ny));
    for (auto& v : f) v = rng.uniform() - 0.5;
    std::vector<SpecField> spectra;
    std::vector<RealField> back;
    for (int threads : {1, 2, 3}) {
      auto engine = make_fftw_engine(g, Planner::Estimate, threads);
      SpecField s(g.spectral_size());
      engine->forward(f.data(), s.data());
      spectra.push_back(s);
      RealField r(g.size());
      engine->backward_unscaled(s.data(), r.data());
      back.push_back(r);
    }
    for (std::size_t k = 1; k < spectra.size(); ++k) {
      EXPECT_EQ(std::memcmp(spectra[k].data(), spectra[0].data(), g.spectral_size() * sizeof(cplx)), 0)
          << nx << "x" << ny;
      EXPECT_EQ(std::memcmp(back[k].data(), back[0].data(), g.size() * sizeof(double)), 0) << nx << "x" << ny;
    }
    if (g.size() > 2000) continue;  // the direct sums on the small grids only
    double scale = 0.0, err = 0.0;
    for (int ky = 0; ky < ny; ++ky)
      for (int kx = 0; kx < g.nxh(); ++kx) {
        std::complex<long double> sum = 0.0L;
        for (int iy = 0; iy < ny; ++iy)
          for (int ix = 0; ix < nx; ++ix) {
            const long double ph =
                -2.0L * std::numbers::pi_v<long double> *
                (static_cast<long double>(kx) * ix / nx + static_cast<long double>(ky) * iy / ny);
            sum += static_cast<long double>(f[static_cast<std::size_t>(iy) * nx + ix]) *
                   std::complex<long double>(std::cos(ph), std::sin(ph));
          }
        const cplx got = spectra[0][static_cast<std::size_t>(ky) * g.nxh() + kx];
        scale = std::max(scale, static_cast<double>(std::abs(sum)));
        err = std::max(
            err, static_cast<double>(std::abs(std::complex<long double>(got.real(), got.imag()) - sum)));
      }
    EXPECT_LT(err, 1e-14 * scale) << nx << "x" << ny;
    // the synthesis without 1/N gives N f
    double rt = 0.0;
    for (std::size_t i = 0; i < g.size(); ++i)
      rt = std::max(rt, std::abs(back[0][i] / static_cast<double>(g.size()) - f[i]));
    EXPECT_LT(rt, 1e-15) << nx << "x" << ny;
  }
}

TEST(Backend, UnknownBackendIsAConfigError) {
  try {
    (void)parse_config(gfmd::testing::kSmallHertz, "test.toml", {"solver.backend=gpu"});
    FAIL() << "accepted an unknown backend";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.backend"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"serial\""), std::string::npos) << e.what();
  }
}

TEST(BackendCase, SlidingStressesAndFlowAreIdenticalOnEveryBackend) {
  // A rough indenter sliding with friction on a thin compressible layer, with surface and
  // subsurface stresses, then leakage through the gap: the whole pipeline on each backend.
  // The summaries and flow results must agree to the last bit (SPEC: same numbers on any
  // machine, thread count, and so on any backend); the third backend must have been used.
  const std::string toml = R"([grid]
nx = 64
lx = 1.0
[elastic]
poisson = 0.4
thickness = 0.2
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 0.5
lambda_short = 0.0625
rms_height = 0.01
seed = 3
[load]
pressure = 0.02
[friction]
coefficient = 0.5
[stress]
depths = [0.02]
)";
  const std::size_t before = scrambled().ranges_run(), engines_before = scrambled().engines_made();
  std::vector<nlohmann::json> summaries, flows;
  for (const char* name : {"threads", "serial", "scrambled-test"}) {
    const CaseResult r = gfmd::testing::solve(toml, {std::string("solver.backend=") + name});
    const nlohmann::json s = summary_json(r);
    EXPECT_EQ(s["backend"], name);
    EXPECT_EQ(s["input"]["solver"]["backend"], name);
    summaries.push_back(without_timings(s));
    const Backend* b = find_backend(name);
    const BackendScope scope(*b);
    const LeakageResult lk = compute_leakage(r.config.grid, r.fields.gap.data(), {0.0, 90.0}, 1e-10);
    flows.push_back(without_timings(lk.json));
  }
  EXPECT_GT(scrambled().ranges_run(), before + 1000);
  EXPECT_GT(scrambled().engines_made(), engines_before);
  ASSERT_TRUE(summaries[0].contains("friction_coefficient")) << summaries[0].dump();
  EXPECT_GT(summaries[0]["friction_coefficient"].get<double>(), 0.0);
  for (std::size_t k = 1; k < summaries.size(); ++k) {
    EXPECT_EQ(summaries[k].dump(), summaries[0].dump()) << "backend " << k;
    EXPECT_EQ(flows[k].dump(), flows[0].dump()) << "backend " << k;
  }
}
