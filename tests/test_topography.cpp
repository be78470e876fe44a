// Tests of the portable RNG, the indenter topographies and their statistics (the readers:
// test_topography_files.cpp).
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
#include "topography_helpers.hpp"

namespace {

using gfmd::Grid;
using gfmd::InputError;
using gfmd::SelfAffineParams;
using gfmd::Topography;
constexpr double kPi = std::numbers::pi;
using topo_test::bit_identical;
using topo_test::expect_input_error;
using topo_test::paper_like;

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
