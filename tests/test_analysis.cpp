// Tests of the analysis functions: contact patches (contact/patches), histograms
// (core/histogram) and the spectral analysis of topographies (surface/spectrum).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "gfmd/contact/patches.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/histogram.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/surface/spectrum.hpp"
#include "gfmd/surface/topography.hpp"
#include "test_util.hpp"

namespace {

using gfmd::Grid;
using gfmd::PatchStats;
using gfmd::Topography;
constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------------------------
// Patches. Grid 8 x 8 on 4 x 2: dx = 0.5, dy = 0.25, so that faces along x and y differ;
// a face between x-neighbours has length dy, one between y-neighbours length dx.

const Grid kG{8, 8, 4.0, 2.0};
constexpr double kDx = 0.5, kDy = 0.25, kCell = kDx * kDy;

std::vector<unsigned char> mask_of(const Grid& g, const std::vector<std::pair<int, int>>& cells) {
  std::vector<unsigned char> m(g.size(), 0);
  for (auto [ix, iy] : cells) m[static_cast<std::size_t>(iy) * g.nx + ix] = 1;
  return m;
}

// Cells of the w x h rectangle with lower-left corner (x0, y0), wrapped.
std::vector<std::pair<int, int>> rect(int x0, int y0, int w, int h) {
  std::vector<std::pair<int, int>> c;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) c.emplace_back((x0 + i) % kG.nx, (y0 + j) % kG.ny);
  return c;
}

std::vector<std::pair<int, int>> join(std::vector<std::pair<int, int>> a,
                                      const std::vector<std::pair<int, int>>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Expected perimeters: a w x h rectangle has 2 h faces between x-neighbours and 2 w between
// y-neighbours. All the expected values are sums of powers of two: exact in doubles.
double rect_perimeter(int w, int h) { return 2 * h * kDy + 2 * w * kDx; }

struct Expected {
  std::vector<double> areas, perimeters;  // largest first
  bool px = false, py = false;
};

PatchStats check(const std::vector<std::pair<int, int>>& cells, const Expected& e) {
  const PatchStats s = gfmd::contact_patches(kG, mask_of(kG, cells));
  EXPECT_EQ(s.count, e.areas.size());
  EXPECT_EQ(s.areas, e.areas);
  EXPECT_EQ(s.perimeters, e.perimeters);
  double total = 0.0;
  for (double a : e.areas) total += a;
  EXPECT_EQ(s.contact_area, total);
  EXPECT_EQ(s.largest_area, e.areas.empty() ? 0.0 : e.areas.front());
  EXPECT_EQ(s.percolates_x, e.px);
  EXPECT_EQ(s.percolates_y, e.py);
  EXPECT_EQ(s.percolating, (e.px || e.py) ? 1u : 0u);  // at most one wrapping patch here
  return s;
}

TEST(Patches, TwoSeparateSquaresSortedByArea) {
  // The 2 x 2 square comes first in row-major order but is the smaller one.
  const auto cells = join(rect(1, 1, 2, 2), rect(4, 4, 3, 3));
  const PatchStats s = check(cells, {{9 * kCell, 4 * kCell}, {rect_perimeter(3, 3), rect_perimeter(2, 2)}});
  EXPECT_EQ(s.cells, (std::vector<std::size_t>{9, 4}));
  std::vector<std::int32_t> labels;
  gfmd::contact_patches(kG, mask_of(kG, cells), labels);
  EXPECT_EQ(labels[1 * 8 + 1], 1);
  EXPECT_EQ(labels[5 * 8 + 5], 0);
  EXPECT_EQ(labels[0], -1);
}

TEST(Patches, StripesPercolateAlongTheirDirectionOnly) {
  check(rect(0, 3, 8, 1), {{8 * kCell}, {16 * kDx}, true, false});  // faces above and below only
  check(rect(2, 0, 2, 8), {{16 * kCell}, {16 * kDy}, false, true});
}

TEST(Patches, PatchAcrossThePeriodicBoundaryIsOneAndDoesNotPercolate) {
  // A 2 x 2 square on the four corners of the cell, and a 3 x 1 bar across x = 0.
  check(join(rect(7, 7, 2, 2), rect(7, 3, 3, 1)),
        {{4 * kCell, 3 * kCell}, {rect_perimeter(2, 2), rect_perimeter(3, 1)}});
}

TEST(Patches, LShapePerimeter) {
  // Column x = 2, y = 2..4 and row y = 2, x = 2..4: per row 2 + 2 + 2 x-faces, per column
  // 2 + 2 + 2 y-faces (the 3 x 3 bounding box's 12 unit faces, 6 of each kind).
  check({{2, 2}, {2, 3}, {2, 4}, {3, 2}, {4, 2}}, {{5 * kCell}, {6 * kDy + 6 * kDx}});
}

TEST(Patches, DiagonalStaircasePercolatesInBothDirections) {
  // Cells (i, i) and (i + 1, i): a staircase closing on itself after 8 cells in x and in y,
  // two x-faces per row and two y-faces per column.
  std::vector<std::pair<int, int>> cells;
  for (int i = 0; i < 8; ++i) cells.insert(cells.end(), {{i, i}, {(i + 1) % 8, i}});
  check(cells, {{16 * kCell}, {16 * kDy + 16 * kDx}, true, true});
}

TEST(Patches, EmptyAndFullMasks) {
  check({}, {});
  check(rect(0, 0, 8, 8), {{kG.lx * kG.ly}, {0.0}, true, true});
  EXPECT_EQ(gfmd::contact_patches(kG, std::vector<unsigned char>(kG.size(), 7)).count, 1u);  // any nonzero
  EXPECT_THROW(gfmd::contact_patches(kG, std::vector<unsigned char>(5, 1)), gfmd::ParameterError);
}

// Random masks against independent counts: the patch sizes from a plain (non-wrapping)
// union-find with periodic neighbours, the faces counted over the whole mask, and the
// percolation from the flow part's winding union-find (gfmd::percolates on the mask as gap).
TEST(Patches, RandomMasksAgreeWithIndependentCounts) {
  const Grid g{96, 64, 3.0, 1.0};
  for (double density : {0.35, 0.5, 0.6, 0.75}) {
    gfmd::Rng rng(17);
    std::vector<unsigned char> m(g.size());
    std::vector<double> gap(g.size());
    for (std::size_t i = 0; i < m.size(); ++i) {
      m[i] = rng.uniform() < density;
      gap[i] = m[i];
    }
    std::vector<std::size_t> parent(g.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
    std::function<std::size_t(std::size_t)> find = [&](std::size_t i) {
      return parent[i] == i ? i : parent[i] = find(parent[i]);
    };
    std::size_t xf = 0, yf = 0;
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        const std::size_t i = static_cast<std::size_t>(iy) * g.nx + ix;
        const std::size_t r = static_cast<std::size_t>(iy) * g.nx + (ix + 1) % g.nx;
        const std::size_t u = static_cast<std::size_t>((iy + 1) % g.ny) * g.nx + ix;
        if (m[i] != m[r]) xf += 1;
        if (m[i] != m[u]) yf += 1;
        if (m[i] && m[r]) parent[find(i)] = find(r);
        if (m[i] && m[u]) parent[find(i)] = find(u);
      }
    std::vector<std::size_t> size(g.size(), 0);
    for (std::size_t i = 0; i < m.size(); ++i)
      if (m[i]) ++size[find(i)];
    std::vector<std::size_t> sizes;
    for (std::size_t s : size)
      if (s > 0) sizes.push_back(s);
    std::sort(sizes.rbegin(), sizes.rend());

    const PatchStats s = gfmd::contact_patches(g, m);
    EXPECT_EQ(s.cells, sizes) << "density " << density;
    double perimeter = 0.0;
    for (double p : s.perimeters) perimeter += p;
    EXPECT_NEAR(perimeter, xf * g.dy() + yf * g.dx(), 1e-9) << "density " << density;
    EXPECT_EQ(s.percolates_x, gfmd::percolates(g, gap.data(), 0)) << "density " << density;
    EXPECT_EQ(s.percolates_y, gfmd::percolates(g, gap.data(), 1)) << "density " << density;
  }
}

TEST(Patches, ContactMaskIsPressureAboveZero) {
  gfmd::ContactFields f;
  f.pressure = gfmd::RealField{0.0, 1e-300, -1.0, 2.0, std::numeric_limits<double>::quiet_NaN(), -0.0};
  EXPECT_EQ(gfmd::contact_mask(f), (std::vector<unsigned char>{0, 1, 0, 1, 0, 0}));
}

// Solves a case (integration label): the mask reproduces the observable's contact area and
// the Hertz contact is one patch.
TEST(PatchesCase, MaskMatchesTheContactAreaOfAHertzCase) {
  const gfmd::CaseResult r = gfmd::testing::solve(gfmd::testing::kSmallHertz);
  const Grid& g = r.topography.grid;
  const auto m = gfmd::contact_mask(r.fields);
  const PatchStats s = gfmd::contact_patches(g, m);
  EXPECT_EQ(s.count, 1u);
  EXPECT_DOUBLE_EQ(s.contact_area / g.area(), r.observables.relative_contact_area);
  EXPECT_EQ(s.percolating, 0u);
}

// ------------------------------------------------------------------------------------
// Histogram

TEST(Histogram, KnownDataCountsMeanAndPdf) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<double> v{4.0, 0.0, 1.0, nan, 2.0, 3.0, inf, 4.0};
  // Range [0, 4] in 4 bins of width 1; 4 (the top) falls into the last bin.
  const gfmd::Histogram h = gfmd::histogram(v.data(), v.size(), 4);
  EXPECT_EQ(h.samples, 6u);
  EXPECT_EQ(h.edges, (std::vector<double>{0.0, 1.0, 2.0, 3.0, 4.0}));
  EXPECT_EQ(h.counts, (std::vector<double>{1.0, 1.0, 1.0, 3.0}));
  EXPECT_DOUBLE_EQ(h.mean, 14.0 / 6.0);
  EXPECT_EQ(h.min, 0.0);
  EXPECT_EQ(h.max, 4.0);
  EXPECT_DOUBLE_EQ(h.pdf[3], 3.0 / 6.0);
}

TEST(Histogram, PdfIntegratesToOne) {
  gfmd::Rng rng(3);
  std::vector<double> v(10000);
  for (auto& x : v) x = std::exp(3.0 * rng.uniform());
  const gfmd::Histogram h = gfmd::histogram(v.data(), v.size(), 37);
  double integral = 0.0, total = 0.0;
  for (std::size_t k = 0; k < h.pdf.size(); ++k) {
    integral += h.pdf[k] * (h.edges[k + 1] - h.edges[k]);
    total += h.counts[k];
  }
  EXPECT_NEAR(integral, 1.0, 1e-12);
  EXPECT_EQ(total, 10000.0);
  EXPECT_EQ(h.edges.front(), h.min);
  EXPECT_EQ(h.edges.back(), h.max);
}

TEST(Histogram, MaskSelectsTheSamples) {
  const std::vector<double> v{-5.0, 1.0, 2.0, 100.0, 3.0};
  const std::vector<unsigned char> mask{0, 1, 1, 0, 2};
  const gfmd::Histogram h = gfmd::histogram(v.data(), v.size(), 2, mask.data());
  EXPECT_EQ(h.samples, 3u);
  EXPECT_EQ(h.min, 1.0);
  EXPECT_EQ(h.max, 3.0);
  EXPECT_DOUBLE_EQ(h.mean, 2.0);
  EXPECT_EQ(h.counts, (std::vector<double>{1.0, 2.0}));  // [1, 2), [2, 3]
}

TEST(Histogram, ConstantEmptyAndBadArguments) {
  const std::vector<double> c{2.0, 2.0, 2.0};
  const gfmd::Histogram h = gfmd::histogram(c.data(), c.size(), 3);
  EXPECT_EQ(h.edges.front(), 1.0);  // widened by |lo| / 2
  EXPECT_EQ(h.edges.back(), 3.0);
  EXPECT_EQ(h.counts, (std::vector<double>{0.0, 3.0, 0.0}));
  EXPECT_DOUBLE_EQ(h.pdf[1] * (2.0 / 3.0), 1.0);

  const std::vector<unsigned char> none(3, 0);
  const gfmd::Histogram e = gfmd::histogram(c.data(), c.size(), 3, none.data());
  EXPECT_EQ(e.samples, 0u);
  EXPECT_EQ(e.counts, (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_EQ(e.mean, 0.0);
  EXPECT_THROW(gfmd::histogram(c.data(), c.size(), 0), gfmd::ParameterError);
  EXPECT_THROW(gfmd::histogram(nullptr, 3, 4), gfmd::ParameterError);
}

// ------------------------------------------------------------------------------------
// Spectrum

Topography field(const Grid& g, const std::function<double(int, int)>& f) {
  Topography t{g, gfmd::RealField(g.size()), "file"};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) t.h[static_cast<std::size_t>(iy) * g.nx + ix] = f(ix, iy);
  return t;
}

// Expected values: an independent pure-Python transcription of python/gfmd/_api.py
// Topography.psd (naive DFT with cmath, numpy's fftfreq and geomspace written out), run with
// /usr/bin/python3 on this field; the modes per bin add up to 8 * 6 - 1.
TEST(Spectrum, PsdMatchesThePythonDefinition) {
  const Grid g{8, 6, 2.0, 1.5};
  const Topography t = field(g, [](int ix, int iy) { return std::sin(0.7 * ix * ix + 1.3 * iy) + 0.1 * ix; });
  struct Bin {
    double q, c;
    std::size_t modes;
  };
  const std::vector<Bin> expected{
      {3.4259310816242068, 0.00064165388107696101, 2}, {4.0741416177768821, 0.0010414698042569893, 2},
      {4.8449981993894493, 0.0021410865422667852, 4},  {5.7617063308898819, 0.0007709670560131788, 2},
      {8.1482832355570238, 0.00080129345419233545, 6}, {9.6899963987827746, 0.0010686682394115917, 14},
      {11.523412661784374, 0.00021084205652152272, 2}, {13.703724326507794, 0.00036873899981845683, 10},
      {16.29656647112057, 0.00016489894674413198, 5}};
  const gfmd::IsotropicPsd psd = gfmd::isotropic_psd(t, 10);
  ASSERT_EQ(psd.q.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(psd.q[k], expected[k].q, 1e-12 * expected[k].q) << k;
    EXPECT_NEAR(psd.c[k], expected[k].c, 1e-12 * expected[k].c) << k;
    EXPECT_EQ(psd.modes[k], expected[k].modes) << k;
  }
  EXPECT_THROW(gfmd::isotropic_psd(t, 0), gfmd::ParameterError);
}

// Parseval: (2 pi)^2 / (lx ly) sum over modes of C = variance (statistics' real-space rms).
TEST(Spectrum, PsdSatisfiesParseval) {
  const Grid g{95, 64, 1.5, 1.0};
  gfmd::Rng rng(5);
  const Topography t = field(g, [&](int, int) { return rng.uniform(); });
  const gfmd::IsotropicPsd psd = gfmd::isotropic_psd(t);
  double sum = 0.0;
  std::size_t modes = 0;
  for (std::size_t k = 0; k < psd.c.size(); ++k) {
    sum += psd.c[k] * static_cast<double>(psd.modes[k]);
    modes += psd.modes[k];
  }
  const double rms = gfmd::statistics(t).rms_height;
  EXPECT_NEAR(sum * 4.0 * kPi * kPi / (g.lx * g.ly), rms * rms, 1e-10 * rms * rms);
  EXPECT_EQ(modes, g.size() - 1);
}

// make_selfaffine's |h~|^2 is exactly C q^(-2-2H) in the band (random phases only): the fit
// inside the band, one bin width away from the cut-offs, returns H. Two H so that a fit
// returning a constant fails.
TEST(Spectrum, HurstFitOfSelfAffineSurfaces) {
  const Grid g{512, 512, 1.0, 1.0};
  for (double hurst : {0.8, 0.3}) {
    gfmd::SelfAffineParams p;
    p.hurst = hurst;
    p.lambda_long = 0.5;
    p.lambda_short = 0.02;
    p.rms_height = 1.0;
    p.seed = 11;
    const gfmd::IsotropicPsd psd = gfmd::isotropic_psd(gfmd::make_selfaffine(g, p));
    const double q_l = 2 * kPi / p.lambda_long, q_s = 2 * kPi / p.lambda_short;
    const gfmd::HurstFit f = gfmd::fit_hurst(psd, 1.25 * q_l, q_s / 1.25);
    EXPECT_NEAR(f.hurst, hurst, 0.05);
    EXPECT_GT(f.r2, 0.99);
    EXPECT_GE(f.points, 20u);
    EXPECT_GE(f.q_min, 1.25 * q_l);
    EXPECT_LE(f.q_max, q_s / 1.25);
  }
}

TEST(Spectrum, FitHurstOfAnExactPowerLawAndBadRanges) {
  gfmd::IsotropicPsd psd;
  for (int k = 0; k < 10; ++k) {
    const double q = std::pow(1.5, k);
    psd.q.push_back(q);
    psd.c.push_back(3.0 * std::pow(q, -2.0 - 2.0 * 0.65));
    psd.modes.push_back(4);
  }
  const gfmd::HurstFit f = gfmd::fit_hurst(psd, 1.4, 1e9);
  EXPECT_NEAR(f.hurst, 0.65, 1e-12);
  EXPECT_NEAR(f.prefactor, 3.0, 1e-11);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
  EXPECT_EQ(f.points, 9u);
  EXPECT_DOUBLE_EQ(f.q_min, 1.5);
  EXPECT_THROW(gfmd::fit_hurst(psd, 2.0, 1.0), gfmd::ParameterError);
  EXPECT_THROW(gfmd::fit_hurst(psd, 1.4, 2.0), gfmd::ParameterError);  // one bin
}

// h = A cos(2 pi 8 x / lx): the modes (+-8, 0) hold all the power, |h~|^2 / N^2 = A^2 / 4 each.
TEST(Spectrum, CosineHasAllItsPowerInOneBinAndOneBand) {
  const Grid g{128, 128, 2.0, 2.0};
  const double a = 0.3, q0 = 2 * kPi * 8 / g.lx;
  const Topography t = field(g, [&](int ix, int) { return a * std::cos(2 * kPi * 8 * ix / g.nx); });
  const gfmd::IsotropicPsd psd = gfmd::isotropic_psd(t);
  const double half_bin =
      0.5 * std::log(psd.q.back() / psd.q.front()) / 63.0;  // 64 bins: none empty at the ends
  std::size_t hits = 0;
  for (std::size_t k = 0; k < psd.q.size(); ++k) {
    if (psd.c[k] * psd.modes[k] < 1e-20) continue;
    ++hits;
    EXPECT_LE(std::abs(std::log(psd.q[k] / q0)), half_bin * (1 + 1e-9));
    EXPECT_NEAR(psd.c[k] * psd.modes[k], 2 * g.lx * g.ly / (4 * kPi * kPi) * a * a / 4, 1e-14);
  }
  EXPECT_EQ(hits, 1u);

  // s = 8: band 3, wavelengths (L/16, L/8].
  const auto bands = gfmd::band_statistics(t);
  ASSERT_EQ(bands.size(), 6u);  // L / (2 dx) = 64 = 2^6
  for (std::size_t k = 0; k < bands.size(); ++k) {
    const double h2 = k == 3 ? a * a / 2 : 0.0;
    EXPECT_NEAR(bands[k].rms_height * bands[k].rms_height, h2, 1e-14) << k;
    EXPECT_NEAR(bands[k].rms_gradient * bands[k].rms_gradient, h2 * q0 * q0, 1e-12) << k;
  }
  EXPECT_DOUBLE_EQ(bands[3].lambda_max, g.lx / 8);
  EXPECT_DOUBLE_EQ(bands[3].lambda_min, g.lx / 16);
}

// Sums of squares over the bands equal statistics(); white noise has power up to the
// Nyquist and corner modes, an odd nx has no Nyquist column: both conventions are tested.
TEST(Spectrum, BandSumsOfSquaresEqualStatistics) {
  gfmd::Rng rng(9);
  gfmd::SelfAffineParams p;
  p.hurst = 0.7;
  p.lambda_long = 1.0;
  p.lambda_short = 0.05;
  p.rms_gradient = 0.1;
  const std::vector<Topography> cases{field(Grid{95, 64, 1.5, 1.0}, [&](int, int) { return rng.uniform(); }),
                                      field(Grid{64, 128, 1.0, 2.0}, [&](int, int) { return rng.uniform(); }),
                                      gfmd::make_selfaffine(Grid{256, 256, 1.0, 1.0}, p)};
  for (const Topography& t : cases) {
    const gfmd::TopographyStats st = gfmd::statistics(t);
    const auto bands = gfmd::band_statistics(t);
    double h2 = 0.0, g2 = 0.0, c2 = 0.0;
    std::size_t modes = 0;
    for (const auto& b : bands) {
      h2 += b.rms_height * b.rms_height;
      g2 += b.rms_gradient * b.rms_gradient;
      c2 += b.rms_curvature * b.rms_curvature;
      modes += b.modes;
    }
    const std::string what = std::to_string(t.grid.nx) + " x " + std::to_string(t.grid.ny);
    EXPECT_NEAR(h2, st.rms_height * st.rms_height, 1e-10 * h2) << what;
    EXPECT_NEAR(g2, st.rms_gradient * st.rms_gradient, 1e-10 * g2) << what;
    EXPECT_NEAR(c2, st.rms_curvature * st.rms_curvature, 1e-10 * c2) << what;
    EXPECT_EQ(modes, t.grid.size() - 1) << what;
    const double big = std::max(t.grid.lx, t.grid.ly);
    EXPECT_EQ(bands.front().lambda_max, big) << what;
    for (std::size_t k = 1; k < bands.size(); ++k) EXPECT_EQ(bands[k].lambda_max, bands[k - 1].lambda_min);
  }
}

}  // namespace
