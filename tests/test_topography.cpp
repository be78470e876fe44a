// Tests of the portable RNG, the indenter topographies, their statistics and the readers.
#include <gtest/gtest.h>
#include <netcdf.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/surface/topography.hpp"

namespace {

using gfmd::Grid;
using gfmd::InputError;
using gfmd::SelfAffineParams;
using gfmd::Topography;
constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------------------------
// Rng

// Expected values computed once with an independent pure-Python implementation of
// SplitMix64 (seeding) + xoshiro256** (arbitrary-precision ints masked to 64 bits,
// written from the published algorithm descriptions), run with /usr/bin/python3.
TEST(Rng, GoldenValuesFromIndependentReference) {
  struct Case {
    std::uint64_t seed;
    std::uint64_t first[5];
  };
  const Case cases[] = {
      {0ull,
       {0x99ec5f36cb75f2b4ull, 0xbf6e1f784956452aull, 0x1a5f849d4933e6e0ull, 0x6aa594f1262d2d2cull,
        0xbba5ad4a1f842e59ull}},
      {12345ull,
       {0xbe6a36374160d49bull, 0x214aaa0637a688c6ull, 0xf69d16de9954d388ull, 0x0c60048c4e96e033ull,
        0x8e2076aeed51c648ull}},
      {0xFFFFFFFFFFFFFFFFull,
       {0x8f5520d52a7ead08ull, 0xc476a018caa1802dull, 0x81de31c0d260469eull, 0xbf658d7e065f3c2full,
        0x913593fda1bca32aull}},
  };
  for (const auto& c : cases) {
    gfmd::Rng rng(c.seed);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(rng.next_u64(), c.first[i]) << "seed " << c.seed << " draw " << i;
  }
  gfmd::Rng rng(42);
  for (int i = 0; i < 999; ++i) rng.next_u64();
  EXPECT_EQ(rng.next_u64(), 0x8de5848c61ab8968ull);  // the 1000th output for seed 42
}

TEST(Rng, UniformGoldenValues) {
  // (next >> 11) * 2^-53 for seed 42, same Python reference (printed with repr()).
  gfmd::Rng rng(42);
  EXPECT_EQ(rng.uniform(), 0.08386297105988216);
  EXPECT_EQ(rng.uniform(), 0.3789802506626686);
  EXPECT_EQ(rng.uniform(), 0.6800434110281394);
  EXPECT_EQ(rng.uniform(), 0.9246929453253876);
}

TEST(Rng, SplitMix64MatchesPublishedFirstOutput) {
  std::uint64_t x = 0;
  EXPECT_EQ(gfmd::Rng::splitmix64(x), 0xe220a8397b1dcdafull);  // Vigna's reference, seed 0
}

TEST(Rng, UniformInUnitIntervalWithCorrectMoments) {
  gfmd::Rng rng(7);
  const int n = 200000;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum2 += u * u;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 0.002);
}

// ------------------------------------------------------------------------------------
// Helpers

bool bit_identical(const gfmd::RealField& a, const gfmd::RealField& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Power |h~(q)|^2 of every half-spectrum mode with h~ = FFT(h)/N, and |q|.
struct ModePower {
  double q, power;
  int ikx, iky;
};
std::vector<ModePower> mode_powers(const Topography& t) {
  const Grid& g = t.grid;
  gfmd::FFT fft(g);
  gfmd::SpecField c = fft.spec_field();
  fft.forward(t.h.data(), c.data());
  const double n = static_cast<double>(g.size());
  std::vector<ModePower> out;
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < g.nxh(); ++ikx) {
      const double qx = g.qx(ikx), qy = g.qy(iky);
      out.push_back({std::sqrt(qx * qx + qy * qy),
                     std::norm(c[static_cast<std::size_t>(iky) * g.nxh() + ikx] / n), ikx, iky});
    }
  return out;
}

template <class F>
void expect_input_error(F&& f, const std::string& where, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "expected InputError mentioning '" << where << "' and '" << fragment << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(where), std::string::npos) << "message: " << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "message: " << msg;
  }
}

SelfAffineParams paper_like(double L) {
  SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = L / 2;
  p.lambda_short = L / 32;
  p.rms_height = 0.01 * L / 2;
  p.seed = 12345;
  return p;
}

// ------------------------------------------------------------------------------------
// Self-affine surfaces

TEST(TopographySelfAffine, RealisedRmsHeightEqualsRequest) {
  const Grid g{128, 96, 1.0, 0.75};
  SelfAffineParams p = paper_like(0.75);
  p.rms_height = 0.0123;
  const Topography t = gfmd::make_selfaffine(g, p);
  EXPECT_EQ(t.kind, "selfaffine");
  ASSERT_EQ(t.h.size(), g.size());
  const auto s = gfmd::statistics(t);
  EXPECT_NEAR(s.rms_height, 0.0123, 1e-12 * 0.0123);
  EXPECT_NEAR(s.mean, 0.0, 1e-14);  // q = 0 carries no power
}

TEST(TopographySelfAffine, RmsGradientNormalisation) {
  const Grid g{128, 128, 2.0, 2.0};
  SelfAffineParams p = paper_like(2.0);
  p.rms_height = 0.0;
  p.rms_gradient = 0.25;
  const auto s = gfmd::statistics(gfmd::make_selfaffine(g, p));
  EXPECT_NEAR(s.rms_gradient, 0.25, 1e-12 * 0.25);
  // Cross-check against a finite-difference gradient: with lambda_short = 4 dx the
  // central difference underestimates the slope of each mode by sin(q dx)/(q dx) >= 0.9.
  const Topography t = gfmd::make_selfaffine(g, p);
  double sum = 0.0;
  const double dx = g.dx();
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      auto at = [&](int x, int y) {
        return t.h[static_cast<std::size_t>((y + g.ny) % g.ny) * g.nx + (x + g.nx) % g.nx];
      };
      const double gx = (at(ix + 1, iy) - at(ix - 1, iy)) / (2 * dx);
      const double gy = (at(ix, iy + 1) - at(ix, iy - 1)) / (2 * dx);
      sum += gx * gx + gy * gy;
    }
  const double fd = std::sqrt(sum / static_cast<double>(g.size()));
  EXPECT_GT(fd, 0.25 * 0.85);
  EXPECT_LT(fd, 0.25);
}

TEST(TopographySelfAffine, SpectrumSlopeMatchesHurst) {
  const double L = 1.0;
  const Grid g{512, 512, L, L};
  SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = L / 2;
  p.lambda_short = L / 64;
  p.rms_height = 0.01;
  p.seed = 99;
  const Topography t = gfmd::make_selfaffine(g, p);
  const double ql = 2 * kPi / p.lambda_long, qs = 2 * kPi / p.lambda_short;
  // Radial average in logarithmic bins, then least-squares fit of log P vs log q.
  const int nbins = 16;
  std::vector<double> psum(nbins, 0.0), lqsum(nbins, 0.0);
  std::vector<int> cnt(nbins, 0);
  for (const auto& m : mode_powers(t)) {
    if (m.q < ql * (1 - 1e-9) || m.q > qs * (1 + 1e-9)) continue;
    int b = static_cast<int>(std::floor(std::log(m.q / ql) / std::log(qs / ql) * nbins));
    b = std::min(std::max(b, 0), nbins - 1);
    psum[b] += m.power;
    lqsum[b] += std::log(m.q);
    ++cnt[b];
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (int b = 0; b < nbins; ++b) {
    if (cnt[b] == 0) continue;
    const double x = lqsum[b] / cnt[b], y = std::log(psum[b] / cnt[b]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
  }
  ASSERT_GE(n, 10);
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  EXPECT_NEAR(slope, -2.0 - 2.0 * 0.8, 0.05);
}

TEST(TopographySelfAffine, ModePowerIsExactPowerLawInBandAndZeroOutside) {
  // Each mode has amplitude exactly C q^(-1-H); this also fails if the kx = 0 / Nyquist
  // columns were not made Hermitian (c2r would then mix q and -q). Even and odd grids.
  for (const Grid& g : {Grid{64, 48, 1.0, 0.75}, Grid{45, 33, 1.0, 0.75}}) {
    SCOPED_TRACE("nx = " + std::to_string(g.nx) + ", ny = " + std::to_string(g.ny));
    SelfAffineParams p;
    p.hurst = 0.6;
    p.lambda_long = 0.5;
    p.lambda_short = 0.05;
    p.rms_height = 1.0;
    p.seed = 5;
    const Topography t = gfmd::make_selfaffine(g, p);
    const double ql = 2 * kPi / p.lambda_long, qs = 2 * kPi / p.lambda_short;
    double cmin = std::numeric_limits<double>::infinity(), cmax = 0.0, pmax = 0.0;
    int inband = 0, kx0_inband = 0;
    const auto modes = mode_powers(t);
    for (const auto& m : modes) pmax = std::max(pmax, m.power);
    for (const auto& m : modes) {
      if (m.q >= ql * (1 - 1e-12) && m.q <= qs * (1 + 1e-12)) {
        const double c = m.power * std::pow(m.q, 2 + 2 * p.hurst);
        cmin = std::min(cmin, c);
        cmax = std::max(cmax, c);
        ++inband;
        kx0_inband += (m.ikx == 0);
      } else {
        EXPECT_LT(m.power, 1e-24 * pmax) << "mode (" << m.ikx << ", " << m.iky << ") q = " << m.q;
      }
    }
    EXPECT_GT(inband, 100);
    EXPECT_GT(kx0_inband, 5);
    EXPECT_LT((cmax - cmin) / cmax, 1e-9);
  }
}

TEST(TopographySelfAffine, RolloffGivesPlateauBelowLambdaLong) {
  const Grid g{64, 64, 1.0, 1.0};
  SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = 0.25;
  p.lambda_short = 0.05;
  p.lambda_rolloff = 1.0;
  p.rms_height = 1.0;
  p.seed = 11;
  const Topography t = gfmd::make_selfaffine(g, p);
  const double ql = 2 * kPi / p.lambda_long, qs = 2 * kPi / p.lambda_short, qr = 2 * kPi / p.lambda_rolloff;
  // Reference constant C from the in-band modes.
  double c = 0.0;
  for (const auto& m : mode_powers(t))
    if (m.q >= ql && m.q <= qs) c = m.power * std::pow(m.q, 2 + 2 * p.hurst);
  ASSERT_GT(c, 0.0);
  const double plateau = c * std::pow(ql, -2 - 2 * p.hurst);
  int nplateau = 0;
  for (const auto& m : mode_powers(t)) {
    if (m.q >= qr * (1 - 1e-12) && m.q < ql * (1 - 1e-12)) {
      EXPECT_NEAR(m.power, plateau, 1e-9 * plateau) << "q = " << m.q;
      ++nplateau;
    }
    if (m.q == 0.0) {
      EXPECT_LT(m.power, 1e-28);
    }
  }
  EXPECT_GT(nplateau, 20);  // 1 <= |k| < 4
}

TEST(TopographySelfAffine, NyquistModesWhenLambdaShortIsTwoGridSpacings) {
  // lambda_short = 2 dx puts the self-conjugate modes (0, ny/2) and (nx/2, 0) in the band.
  const Grid g{32, 32, 1.0, 1.0};
  SelfAffineParams p;
  p.hurst = 0.5;
  p.lambda_long = 1.0;
  p.lambda_short = 2.0 / 32;
  p.rms_height = 1.0;
  p.seed = 3;
  const Topography t = gfmd::make_selfaffine(g, p);
  double c_ref = 0.0, c_nyq_x = 0.0, c_nyq_y = 0.0;
  for (const auto& m : mode_powers(t)) {
    const double c = m.power * std::pow(m.q, 3.0);
    if (m.ikx == 1 && m.iky == 0) c_ref = c;
    if (m.ikx == 16 && m.iky == 0) c_nyq_x = c;
    if (m.ikx == 0 && m.iky == 16) c_nyq_y = c;
  }
  EXPECT_NEAR(c_nyq_x, c_ref, 1e-9 * c_ref);
  EXPECT_NEAR(c_nyq_y, c_ref, 1e-9 * c_ref);
}

TEST(TopographySelfAffine, MatchesIndependentPythonReference) {
  // Reference: a numpy implementation of the documented algorithm (phase draw order
  // iky outer / ikx inner, Hermitian kx = 0 and Nyquist columns, roll-off, irfft2,
  // rescale to rms), with the Python SplitMix64 + xoshiro256** above, run once with
  // /usr/bin/python3 (numpy 1.24). nx = 16, ny = 12, lx = 2, ly = 1.5, H = 0.7,
  // lambda_long = 1.5, lambda_short = 0.25 (= 2 dx), lambda_rolloff = 2, rms 0.3, seed 2024.
  const Grid g{16, 12, 2.0, 1.5};
  SelfAffineParams p;
  p.hurst = 0.7;
  p.lambda_long = 1.5;
  p.lambda_short = 0.25;
  p.lambda_rolloff = 2.0;
  p.rms_height = 0.3;
  p.seed = 2024;
  const Topography t = gfmd::make_selfaffine(g, p);
  const double tol = 1e-12;
  EXPECT_NEAR(t.h[0], 0.3773858142436395, tol);
  EXPECT_NEAR(t.h[5], 0.7613118191384503, tol);
  EXPECT_NEAR(t.h[17], 0.5051239723555843, tol);
  EXPECT_NEAR(t.h[100], -0.18503783965137743, tol);
  EXPECT_NEAR(t.h[191], 0.2816222906506264, tol);
  const auto s = gfmd::statistics(t);
  EXPECT_NEAR(s.max, 0.7613118191384503, tol);
  EXPECT_NEAR(s.min, -0.761026708096014, tol);
}

TEST(TopographySelfAffine, SameSeedBitIdenticalDifferentSeedDifferent) {
  const Grid g{128, 128, 1.0, 1.0};
  SelfAffineParams p = paper_like(1.0);
  const Topography a = gfmd::make_selfaffine(g, p);
  const Topography b = gfmd::make_selfaffine(g, p);
  EXPECT_TRUE(bit_identical(a.h, b.h));
  p.seed += 1;
  const Topography c = gfmd::make_selfaffine(g, p);
  EXPECT_FALSE(bit_identical(a.h, c.h));
  double diff = 0.0;
  for (std::size_t i = 0; i < a.h.size(); ++i) diff = std::max(diff, std::abs(a.h[i] - c.h[i]));
  EXPECT_GT(diff, 0.5 * p.rms_height);
}

TEST(TopographySelfAffine, IndependentOfThreadCount) {
  const int saved = gfmd::threads();
  const Grid g{256, 256, 1.0, 1.0};
  SelfAffineParams p = paper_like(1.0);
  gfmd::set_threads(1);
  const Topography a = gfmd::make_selfaffine(g, p);
  const auto sa = gfmd::statistics(a);
  p.rms_height = 0.0;
  p.rms_gradient = 0.1;
  const Topography ga = gfmd::make_selfaffine(g, p);
  gfmd::set_threads(2);
  const Topography gb = gfmd::make_selfaffine(g, p);
  p.rms_height = paper_like(1.0).rms_height;
  p.rms_gradient = 0.0;
  const Topography b = gfmd::make_selfaffine(g, p);
  const auto sb = gfmd::statistics(b);
  gfmd::set_threads(saved);
  EXPECT_TRUE(bit_identical(a.h, b.h));
  EXPECT_TRUE(bit_identical(ga.h, gb.h));
  EXPECT_EQ(sa.rms_height, sb.rms_height);
  EXPECT_EQ(sa.rms_gradient, sb.rms_gradient);
  EXPECT_EQ(sa.rms_curvature, sb.rms_curvature);
}

TEST(TopographySelfAffine, RejectsBadParameters) {
  const Grid g{64, 64, 1.0, 1.0};
  auto with = [&](auto edit) {
    SelfAffineParams p = paper_like(1.0);
    edit(p);
    return [g, p] { (void)gfmd::make_selfaffine(g, p); };
  };
  expect_input_error(with([](SelfAffineParams& p) { p.hurst = 1.0; }), "hurst", "0 < H < 1");
  expect_input_error(with([](SelfAffineParams& p) { p.hurst = 0.0; }), "hurst", "0 < H < 1");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_long = 2.0; }), "lambda_long", "cell size");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_long = 0.0; }), "lambda_long", "> 0");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_short = 0.6; }), "lambda_short", "smaller than");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_short = 1.5 / 64; }), "lambda_short",
                     "grid spacing is too coarse");
  expect_input_error(with([](SelfAffineParams& p) { p.rms_gradient = 0.1; }), "rms_height", "exactly one");
  expect_input_error(with([](SelfAffineParams& p) { p.rms_height = 0.0; }), "rms_height", "exactly one");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_rolloff = 0.4; }), "lambda_rolloff",
                     "larger than lambda_long");
  expect_input_error(with([](SelfAffineParams& p) { p.lambda_rolloff = 3.0; }), "lambda_rolloff",
                     "cell size");
  expect_input_error(with([](SelfAffineParams& p) {
                       p.lambda_long = 0.9;
                       p.lambda_short = 0.8;
                     }),
                     "lambda_short", "no Fourier mode");
  // lambda_short = 2 dx exactly is accepted.
  EXPECT_NO_THROW(with([](SelfAffineParams& p) { p.lambda_short = 2.0 / 64; })());
}

// ------------------------------------------------------------------------------------
// Analytic profiles and statistics

TEST(TopographyHertz, SymmetricWithMaximumAtCentre) {
  const Grid g{64, 48, 4.0, 3.0};
  const double rx = 1.0, ry = 1.5;
  const Topography t = gfmd::make_hertz(g, rx, ry);
  EXPECT_EQ(t.kind, "hertz");
  const int cx = 32, cy = 24;
  const auto at = [&](int ix, int iy) { return t.h[static_cast<std::size_t>(iy) * g.nx + ix]; };
  EXPECT_EQ(at(cx, cy), 0.0);
  const auto s = gfmd::statistics(t);
  EXPECT_EQ(s.max, 0.0);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      if (ix != cx || iy != cy) {
        ASSERT_LT(at(ix, iy), 0.0);
      }
      // Mirror symmetry about the centre node: ix -> nx - ix, iy -> ny - iy (exact).
      ASSERT_EQ(at(ix, iy), at((g.nx - ix) % g.nx, iy)) << ix << " " << iy;
      ASSERT_EQ(at(ix, iy), at(ix, (g.ny - iy) % g.ny)) << ix << " " << iy;
    }
  // Values: h = -(x-xc)^2/(2 rx) - (y-yc)^2/(2 ry).
  const double x = (40 - cx) * g.dx(), y = (10 - cy) * g.dy();
  EXPECT_DOUBLE_EQ(at(40, 10), -x * x / (2 * rx) - y * y / (2 * ry));
  expect_input_error([&] { (void)gfmd::make_hertz(g, 0.0, 1.0); }, "radius_x", "> 0");
  expect_input_error([&] { (void)gfmd::make_hertz(Grid{0, 4, 1.0, 1.0}, 1.0, 1.0); }, "grid", "nx");
}

TEST(TopographyEggcrate, StatisticsMatchAnalytic) {
  const double lambda = 0.5, h0 = lambda / (4 * kPi * kPi);
  const Grid g{64, 128, 1.0, 2.0};  // 2 periods along x, 4 along y
  const Topography t = gfmd::make_eggcrate(g, lambda, h0);
  EXPECT_EQ(t.kind, "eggcrate");
  const double q0 = 2 * kPi / lambda;
  const auto s = gfmd::statistics(t);
  EXPECT_NEAR(s.mean, 0.0, 1e-15);
  EXPECT_NEAR(s.rms_height, h0, 1e-13 * h0);
  EXPECT_NEAR(s.rms_gradient, h0 * q0, 1e-13 * h0 * q0);
  EXPECT_NEAR(s.rms_curvature, h0 * q0 * q0 / 2, 1e-13 * h0 * q0 * q0);
  EXPECT_EQ(s.max, 2 * h0);  // peak at the origin, exactly
  EXPECT_EQ(t.h[0], 2 * h0);
  EXPECT_NEAR(s.min, -2 * h0, 1e-15);
  // Peak radius of curvature R = lambda for h0 = lambda/(2 pi)^2 (SPEC §3):
  // d2h/dx2 at the peak = -h0 q0^2 = -1/lambda.
  EXPECT_NEAR(h0 * q0 * q0, 1.0 / lambda, 1e-12);
  expect_input_error([&] { (void)gfmd::make_eggcrate(g, 0.3, h0); }, "wavelength", "divide");
  expect_input_error([&] { (void)gfmd::make_eggcrate(g, lambda, -1.0); }, "amplitude", "> 0");
}

TEST(TopographyStatistics, SingleModeAndOffset) {
  // h = c + a sin(q x) with q = 2 pi * 3 / lx on a rectangular grid.
  const Grid g{48, 16, 3.0, 1.0};
  Topography t{g, gfmd::RealField(g.size()), "test"};
  const double a = 0.2, c = 5.0, q = 2 * kPi * 3 / g.lx;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      t.h[static_cast<std::size_t>(iy) * g.nx + ix] = c + a * std::sin(q * g.x(ix));
  const auto s = gfmd::statistics(t);
  EXPECT_NEAR(s.mean, c, 1e-14);
  EXPECT_NEAR(s.rms_height, a / std::sqrt(2.0), 1e-13);
  EXPECT_NEAR(s.rms_gradient, a * q / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(s.rms_curvature, a * q * q / (2 * std::sqrt(2.0)), 1e-11);
  // Nyquist column: its derivative is dropped, so an alternating pattern has zero slope.
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      t.h[static_cast<std::size_t>(iy) * g.nx + ix] = (ix % 2 == 0) ? 1.0 : -1.0;
  const auto sn = gfmd::statistics(t);
  EXPECT_NEAR(sn.rms_height, 1.0, 1e-14);
  EXPECT_NEAR(sn.rms_gradient, 0.0, 1e-12);
  EXPECT_NEAR(sn.rms_curvature, 0.0, 1e-12);
}

// ------------------------------------------------------------------------------------
// File readers

class TopographyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("gfmd_topo_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write_text(const std::string& name, const std::string& content) const {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

  // Writes a NetCDF file with variable `var` of dims (y, x) (or rank 3 if rank3), optional
  // global lx/ly attributes and optional coordinate variables.
  struct NcSpec {
    std::string var = "topography";
    int format = NC_CLOBBER;  // | NC_NETCDF4 for HDF5-based files
    nc_type type = NC_DOUBLE;
    double lx = 0.0, ly = 0.0;  // > 0: global attributes
    bool coords = false;        // write x, y coordinate variables with spacing dx, dy
    double dx = 0.0, dy = 0.0;
    bool rank3 = false;
    bool unlimited_y = false;  // y as the record dimension
  };
  std::string write_nc(const std::string& name, int nx, int ny, const std::vector<double>& h,
                       const NcSpec& s) const {
    const std::string p = path(name);
    int id = 0, dx_id = 0, dy_id = 0, dz_id = 0, var = 0;
    EXPECT_EQ(nc_create(p.c_str(), s.format, &id), NC_NOERR);
    EXPECT_EQ(nc_def_dim(id, "y", s.unlimited_y ? NC_UNLIMITED : static_cast<std::size_t>(ny), &dy_id),
              NC_NOERR);
    EXPECT_EQ(nc_def_dim(id, "x", static_cast<std::size_t>(nx), &dx_id), NC_NOERR);
    if (s.rank3) {
      EXPECT_EQ(nc_def_dim(id, "t", 1, &dz_id), NC_NOERR);
      const int dims[3] = {dz_id, dy_id, dx_id};
      EXPECT_EQ(nc_def_var(id, s.var.c_str(), s.type, 3, dims, &var), NC_NOERR);
    } else {
      const int dims[2] = {dy_id, dx_id};
      EXPECT_EQ(nc_def_var(id, s.var.c_str(), s.type, 2, dims, &var), NC_NOERR);
    }
    if (s.lx > 0) {
      EXPECT_EQ(nc_put_att_double(id, NC_GLOBAL, "lx", NC_DOUBLE, 1, &s.lx), NC_NOERR);
    }
    if (s.ly > 0) {
      EXPECT_EQ(nc_put_att_double(id, NC_GLOBAL, "ly", NC_DOUBLE, 1, &s.ly), NC_NOERR);
    }
    int xv = 0, yv = 0;
    if (s.coords) {
      EXPECT_EQ(nc_def_var(id, "x", NC_DOUBLE, 1, &dx_id, &xv), NC_NOERR);
      EXPECT_EQ(nc_def_var(id, "y", NC_DOUBLE, 1, &dy_id, &yv), NC_NOERR);
    }
    EXPECT_EQ(nc_enddef(id), NC_NOERR);
    const std::size_t start[2] = {0, 0},
                      count[2] = {static_cast<std::size_t>(ny), static_cast<std::size_t>(nx)};
    if (s.rank3) {
      EXPECT_EQ(nc_put_var_double(id, var, h.data()), NC_NOERR);
    } else {
      EXPECT_EQ(nc_put_vara_double(id, var, start, count, h.data()), NC_NOERR);
    }
    if (s.coords) {
      std::vector<double> x(static_cast<std::size_t>(nx)), y(static_cast<std::size_t>(ny));
      for (int i = 0; i < nx; ++i) x[i] = i * s.dx;
      for (int i = 0; i < ny; ++i) y[i] = i * s.dy;
      EXPECT_EQ(nc_put_var_double(id, xv, x.data()), NC_NOERR);
      EXPECT_EQ(nc_put_var_double(id, yv, y.data()), NC_NOERR);
    }
    EXPECT_EQ(nc_close(id), NC_NOERR);
    return p;
  }

  std::filesystem::path dir_;
};

Topography sample_surface() {
  SelfAffineParams p = paper_like(1.5);
  p.lambda_short = 0.25;
  return gfmd::make_selfaffine(Grid{32, 24, 2.0, 1.5}, p);
}

TEST_F(TopographyFile, TextRoundTrip) {
  const Topography t = sample_surface();
  std::ostringstream os;
  os.precision(17);
  os << "# a comment line\n# lx = 2.0\n#ly: 1.5\n\n";
  for (int iy = 0; iy < t.grid.ny; ++iy) {
    for (int ix = 0; ix < t.grid.nx; ++ix)
      os << (ix ? "\t" : "  ") << t.h[static_cast<std::size_t>(iy) * t.grid.nx + ix];
    os << "  \r\n";  // trailing blanks and CRLF are tolerated
  }
  const std::string p = write_text("surface.txt", os.str());
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.kind, "file");
  EXPECT_EQ(r.grid.nx, 32);
  EXPECT_EQ(r.grid.ny, 24);
  EXPECT_EQ(r.grid.lx, 2.0);
  EXPECT_EQ(r.grid.ly, 1.5);
  EXPECT_TRUE(bit_identical(r.h, t.h));  // 17 significant digits round-trip exactly
  // Arguments win over the header.
  const Topography r2 = gfmd::read_topography(p, 4.0, 3.0);
  EXPECT_EQ(r2.grid.lx, 4.0);
  EXPECT_EQ(r2.grid.ly, 3.0);
}

TEST_F(TopographyFile, TextSizeFromArgumentsWithoutHeader) {
  const std::string p = write_text("plain.dat", "1 2 3\n4 5 6\n");
  const Topography r = gfmd::read_topography(p, 3.0, 2.0);
  EXPECT_EQ(r.grid.nx, 3);
  EXPECT_EQ(r.grid.ny, 2);
  EXPECT_EQ(r.h[5], 6.0);  // row iy = 1, ix = 2
  EXPECT_EQ(r.h[1], 2.0);
}

// CSV exports: comma, semicolon or tab separated, blanks around separators, CRLF line ends
// and one trailing separator; the size from the header lines.
TEST_F(TopographyFile, ReadsCsvWithAnySeparator) {
  for (const std::string& text : {std::string("# lx = 2\n# ly = 3\n1,2,3\n4, 5 ,6\n"),
                                  std::string("# lx = 2\n# ly = 3\n1;2;3\r\n4;5;6;\r\n"),
                                  std::string("# lx = 2\n# ly = 3\n1\t2\t3\n4\t5\t6\n")}) {
    const std::string p = write_text("map.csv", text);
    const gfmd::Topography t = gfmd::read_topography(p, 0.0, 0.0);
    ASSERT_EQ(t.grid.nx, 3) << text;
    ASSERT_EQ(t.grid.ny, 2) << text;
    EXPECT_EQ(t.grid.lx, 2.0);
    EXPECT_EQ(t.grid.ly, 3.0);
    EXPECT_EQ(t.h[4], 5.0) << text;
  }
}

// Only regular files are read: a device or a FIFO is refused at once (no endless read, no
// hang waiting for a writer).
TEST_F(TopographyFile, RefusesDevicesAndFifos) {
  expect_input_error([] { (void)gfmd::read_topography("/dev/zero", 1, 1); }, "/dev/zero",
                     "not a regular file");
  const std::string fifo = write_text("placeholder", "");
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_input_error([&] { (void)gfmd::read_topography(fifo, 1, 1); }, fifo, "not a regular file");
}

TEST_F(TopographyFile, TextErrors) {
  std::string p = write_text("ragged.txt", "# lx = 1\n# ly = 1\n1 2 3\n4 5\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "ragged rows: line 4 has 2 values");
  p = write_text("word.txt", "# lx = 1\n# ly = 1\n1 2 3\n4 five 6\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "line 4: non-numeric value 'five'");
  p = write_text("comma.txt", "1,,2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: empty value 2");
  p = write_text("mixed.txt", "1;2\n3,x\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 2: non-numeric value 'x'");
  // A long unparseable line is quoted as a short excerpt, not whole.
  p = write_text("long.txt", "1 " + std::string(5000, 'a') + "\n");
  try {
    (void)gfmd::read_topography(p, 1, 1);
    ADD_FAILURE() << "a non-numeric line was accepted";
  } catch (const gfmd::InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 300u) << e.what();
    EXPECT_NE(std::string(e.what()).find("aaa..."), std::string::npos) << e.what();
  }
  p = write_text("nan.txt", "1 2\n\n3 nan\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p,
                     "1 point has no value (NaN or the file's no-data marker), the first at line 3, value 2");
  p = write_text("inf.txt", "1 -inf\n3 4\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: non-finite");
  p = write_text("huge.txt", "1 1e999\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: non-finite");
  p = write_text("nosize.txt", "1 2\n3 4\n5 6\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no physical size lx");
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 1.0, 0.0).grid.ly, 1.5);  // ly = lx ny/nx: square pixels
  p = write_text("onlyly.txt", "# ly = 3\n1 2\n3 4\n5 6\n");
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 0, 0).grid.lx, 2.0);  // lx = ly nx/ny from the file's ly
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 1.0, 0.0).grid.ly,
                   3.0);  // lx from the argument, ly from the file
  p = write_text("empty.txt", "");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "empty");
  p = write_text("comments.txt", "# nothing here\n\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no data");
  p = write_text("badheader.txt", "# lx = -3\n1 2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 1); }, p, "line 1: invalid lx header");
  p = write_text("twice.txt", "# lx = 1\n# LX: 2\n1 2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 1); }, p, "given twice");
  p = path("does_not_exist.txt");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no such file");
  p = path("missing.nc");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no such file");
}

TEST_F(TopographyFile, NetcdfRoundTripWithAttributes) {
  const Topography t = sample_surface();
  std::vector<double> h(t.h.begin(), t.h.end());
  NcSpec s;
  s.lx = 2.0;
  s.ly = 1.5;
  const std::string p = write_nc("surface.nc", 32, 24, h, s);
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.kind, "file");
  EXPECT_EQ(r.grid.nx, 32);
  EXPECT_EQ(r.grid.ny, 24);
  EXPECT_EQ(r.grid.lx, 2.0);
  EXPECT_EQ(r.grid.ly, 1.5);
  EXPECT_TRUE(bit_identical(r.h, t.h));
  const Topography r2 = gfmd::read_topography(p, 5.0, 0.0);  // argument wins for lx only
  EXPECT_EQ(r2.grid.lx, 5.0);
  EXPECT_EQ(r2.grid.ly, 1.5);
}

TEST_F(TopographyFile, NetcdfFloatHdf5WithCoordinatesAndNoExtension) {
  std::vector<double> h(6 * 4);
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = 0.25 * static_cast<double>(i) - 1.0;  // exact in float
  NcSpec s;
  s.var = "heights";
  s.format = NC_CLOBBER | NC_NETCDF4;
  s.type = NC_FLOAT;
  s.coords = true;
  s.dx = 0.5;
  s.dy = 0.25;
  const std::string p = write_nc("surface_hdf5", 6, 4, h, s);  // detected by its signature
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.grid.nx, 6);
  EXPECT_EQ(r.grid.ny, 4);
  EXPECT_DOUBLE_EQ(r.grid.lx, 3.0);
  EXPECT_DOUBLE_EQ(r.grid.ly, 1.0);
  for (std::size_t i = 0; i < h.size(); ++i) EXPECT_EQ(r.h[i], h[i]);
}

TEST_F(TopographyFile, NetcdfClassicVariantsReadAndTruncationDetected) {
  // netcdf-c reads past the end of a truncated classic file as zeros; the reader checks
  // the size implied by the header. Exercised for CDF-1, CDF-2, CDF-5, with and without
  // a record dimension, with a few bytes cut off.
  std::vector<double> h(10 * 7);
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = std::sin(static_cast<double>(i));
  const int formats[] = {NC_CLOBBER, NC_CLOBBER | NC_64BIT_OFFSET, NC_CLOBBER | NC_64BIT_DATA};
  int k = 0;
  for (int fmt : formats)
    for (bool rec : {false, true}) {
      NcSpec s;
      s.format = fmt;
      s.unlimited_y = rec;
      s.coords = true;  // a second and third variable after the height map
      s.dx = 0.1;
      s.dy = 0.2;
      const std::string p = write_nc("variant" + std::to_string(k++) + ".nc", 10, 7, h, s);
      const Topography r = gfmd::read_topography(p, 0.0, 0.0);
      ASSERT_EQ(r.grid.nx, 10);
      ASSERT_EQ(r.grid.ny, 7);
      EXPECT_DOUBLE_EQ(r.grid.lx, 1.0);
      EXPECT_DOUBLE_EQ(r.grid.ly, 1.4);
      EXPECT_TRUE(bit_identical(r.h, gfmd::RealField(h.begin(), h.end())))
          << "format " << fmt << " record " << rec;
      std::filesystem::resize_file(p, std::filesystem::file_size(p) - 4);
      expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "truncated");
    }
}

TEST_F(TopographyFile, NetcdfErrors) {
  std::vector<double> h(16 * 16, 0.5);
  NcSpec s;
  s.lx = s.ly = 1.0;
  // Truncated file (classic and HDF5-based).
  std::string p = write_nc("truncated.nc", 16, 16, h, s);
  std::filesystem::resize_file(p, std::filesystem::file_size(p) / 2);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "NetCDF");
  NcSpec s4 = s;
  s4.format = NC_CLOBBER | NC_NETCDF4;
  p = write_nc("truncated4.nc", 16, 16, h, s4);
  std::filesystem::resize_file(p, std::filesystem::file_size(p) / 2);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "NetCDF");
  // Not a NetCDF file at all.
  p = write_text("garbage.nc", "this is not netcdf\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "cannot read the NetCDF file");
  // Missing variable.
  NcSpec sv = s;
  sv.var = "elevation";
  p = write_nc("novar.nc", 16, 16, h, sv);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no variable named 'topography'");
  // Wrong rank.
  NcSpec sr = s;
  sr.rank3 = true;
  p = write_nc("rank3.nc", 16, 16, h, sr);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "has 3 dimensions");
  // NaN.
  std::vector<double> hn = h;
  hn[3 * 16 + 5] = std::numeric_limits<double>::quiet_NaN();
  p = write_nc("nan.nc", 16, 16, hn, s);
  expect_input_error(
      [&] { (void)gfmd::read_topography(p, 0, 0); }, p,
      "1 point has no value (NaN or the file's no-data marker), the first at (iy, ix) = (3, 5)");
  // No size anywhere.
  p = write_nc("nosize.nc", 16, 16, h, NcSpec{});
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no physical size lx");
  EXPECT_NO_THROW((void)gfmd::read_topography(p, 1.0, 1.0));
}

}  // namespace

TEST(TopographySelfAffine, LibraryNamesTheParameterCaseNamesTheKey) {
  // Physics knows its parameters, not the case file: make_selfaffine names "lambda_long";
  // the case layer's make_topography turns that into the key "indenter.lambda_long".
  const Grid g{64, 64, 1.0, 1.0};
  SelfAffineParams p = paper_like(1.0);
  p.lambda_long = 2.0;
  try {
    (void)gfmd::make_selfaffine(g, p);
    ADD_FAILURE() << "accepted lambda_long > cell";
  } catch (const gfmd::ParameterError& e) {
    EXPECT_EQ(e.where(), "lambda_long");
    EXPECT_EQ(std::string(e.what()).find("indenter."), std::string::npos) << e.what();
  }
  gfmd::Config cfg = gfmd::parse_config(
      "[grid]\nnx = 64\nlx = 1.0\n[indenter]\ntype = \"selfaffine\"\nhurst = 0.8\nlambda_long = 0.5\n"
      "lambda_short = 0.0625\nrms_height = 0.01\n[load]\npressure = 0.01\n",
      "t.toml");
  cfg.indenter.selfaffine.lambda_long = 2.0;
  try {
    (void)gfmd::make_topography(cfg);
    ADD_FAILURE() << "accepted lambda_long > cell";
  } catch (const gfmd::ParameterError&) {
    ADD_FAILURE() << "the case layer let a ParameterError through";
  } catch (const gfmd::InputError& e) {
    EXPECT_EQ(e.where(), "indenter.lambda_long");
  }
}
