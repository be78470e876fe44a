// Contact solve validated against closed-form solutions (SPEC §7).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

using gfmd::testing::solve;

const char* kHertz = R"(
[grid]
nx = 128
lx = 1.6
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[solver]
tolerance = 1e-10
)";

struct HertzErrors {
  double radius, p0, area_radius;
};

// Relative errors against Hertz: a = (3FR/4E*)^(1/3), p0 = 3F/(2 pi a^2).
HertzErrors hertz_errors(const CaseResult& r) {
  const double F = 0.01, a = std::cbrt(3 * F / 4), p0 = 3 * F / (2 * std::numbers::pi * a * a);
  const Grid& g = r.config.grid;
  // Pressure-weighted second moment: int p r^2 / int p = (2/5) a^2 for Hertz.
  double m0 = 0, m2 = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double p = r.fields.pressure[iy * g.nx + ix];
      const double x = (ix - g.nx / 2) * g.dx(), y = (iy - g.ny / 2) * g.dy();
      m0 += p;
      m2 += p * (x * x + y * y);
    }
  const double a_moment = std::sqrt(2.5 * m2 / m0);
  const double a_area = std::sqrt(r.observables.relative_contact_area * g.area() / std::numbers::pi);
  return {std::abs(a_moment / a - 1), std::abs(r.observables.max_pressure / p0 - 1),
          std::abs(a_area / a - 1)};
}

}  // namespace

TEST(Contact, HertzFrictionlessConvergesUnderRefinement) {
  // a / dx = 15.7 at nx = 128 and 31.3 at nx = 256 (L = 1.6 R, F = 0.01 E* R^2).
  for (const char* nu : {"0.25", "0.49"}) {
    const auto coarse = hertz_errors(solve(kHertz, {std::string("elastic.poisson=") + nu}));
    const auto fine = hertz_errors(solve(kHertz, {std::string("elastic.poisson=") + nu, "grid.nx=256"}));
    std::printf("nu=%s  nx=128: a %.4f p0 %.4f a_area %.4f | nx=256: a %.4f p0 %.4f a_area %.4f\n", nu,
                coarse.radius, coarse.p0, coarse.area_radius, fine.radius, fine.p0, fine.area_radius);
    EXPECT_LT(coarse.radius, 0.02);
    EXPECT_LT(coarse.p0, 0.02);
    EXPECT_LT(fine.radius, 0.02);
    EXPECT_LT(fine.p0, 0.02);
    EXPECT_LT(fine.area_radius, 0.03);
    EXPECT_LT(fine.p0, coarse.p0);
    EXPECT_LT(fine.area_radius, coarse.area_radius);
  }
}

TEST(Contact, FrictionlessIndependentOfPoissonAndCouplingOnHalfSpace) {
  const auto a = solve(kHertz, {"elastic.poisson=0.0"});
  const auto b = solve(kHertz, {"elastic.poisson=0.45", "elastic.coupling=false"});
  for (std::size_t i = 0; i < a.fields.pressure.size(); ++i)
    ASSERT_NEAR(a.fields.pressure[i], b.fields.pressure[i], 1e-8);
}

TEST(Contact, HardWallHertz) {
  const auto r = hertz_errors(solve(kHertz, {"interaction.model=\"hardwall\"", "grid.nx=256"}));
  EXPECT_LT(r.radius, 0.02);
  EXPECT_LT(r.p0, 0.02);
}

TEST(Contact, WestergaardSinusoid) {
  // 1D sinusoid h0 cos(2 pi x / lambda) on a half-space: p = p* sin^2(pi a / lambda),
  // a the half contact width, complete contact at p* = pi E* h0 / lambda (Westergaard 1939;
  // Johnson, Contact Mechanics §13.2).
  const Grid g{1024, 4, 1.0, 4.0 / 1024};
  const double h0 = 0.01, pstar = std::numbers::pi * h0;
  Topography topo{g, RealField(g.size()), "sinusoid"};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      topo.h[iy * g.nx + ix] = h0 * std::cos(2 * std::numbers::pi * ix / g.nx);
  ElasticBody body(g, homogeneous_body(1.0, 0.3, std::numeric_limits<double>::infinity(), true));
  ContactSolver solver(body, topo, InteractionParams{}, FrictionParams{}, SolverParams{1e-10, 20000, 10});
  for (double frac : {0.1, 0.3, 0.6, 0.9}) {
    ContactFields f;
    const auto info = solver.solve(LoadParams{LoadMode::Pressure, frac * pstar}, f);
    ASSERT_TRUE(info.converged);
    int n = 0;
    for (int ix = 0; ix < g.nx; ++ix) n += f.pressure[ix] > 0;
    const double a_num = 0.5 * n * g.dx();
    const double a_exact = std::asin(std::sqrt(frac)) / std::numbers::pi;
    EXPECT_NEAR(a_num / a_exact, 1.0, 0.02) << "p/p* = " << frac;
  }
  ContactFields f;
  solver.solve(LoadParams{LoadMode::Pressure, 1.02 * pstar}, f);
  for (int ix = 0; ix < g.nx; ++ix) EXPECT_GT(f.pressure[ix], 0.0);
  solver.solve(LoadParams{LoadMode::Pressure, 0.98 * pstar}, f);
  int open = 0;
  for (int ix = 0; ix < g.nx; ++ix) open += f.pressure[ix] == 0.0;
  EXPECT_GT(open, 0);
}

TEST(Contact, ApproachControlReproducesLoadControl) {
  const auto lc = solve(kHertz);
  char buf[64];
  std::snprintf(buf, sizeof buf, "load.approach=%.17g", lc.info.approach);
  const auto dc = solve(kHertz, {buf});
  EXPECT_NEAR(dc.observables.normal_force / lc.observables.normal_force, 1.0, 1e-6);
  EXPECT_NEAR(dc.observables.relative_contact_area, lc.observables.relative_contact_area, 1e-12);
}

TEST(Contact, LayerApproachIncludesUniformCompression) {
  // On a bonded layer the mean surface moves down by p h (1-2nu)/((1-nu)^2 E*) (SPEC §7).
  const std::string t = kHertz;
  const auto r = solve(t, {"elastic.thickness=0.5", "elastic.poisson=0.3"});
  double mean = 0;
  for (double v : r.fields.uz) mean += v;
  mean /= static_cast<double>(r.fields.uz.size());
  const double pbar = 0.01 / (1.6 * 1.6);
  EXPECT_NEAR(mean, -pbar * 0.5 * 0.4 / (0.7 * 0.7), 1e-12);
}

TEST(Contact, RoughContactAreaLinearInPressure) {
  // Small loads: a_c = kappa p / (E* g_rms) with kappa constant (Persson 2001; Hyun et
  // al. 2004; Prodanov, Dapp & Mueser 2014 give kappa ~ 2 in the continuum limit; the
  // harmonic repulsion and 8 points per lambda_s raise it). 16 lambda_s per lambda_l.
  const char* rough = R"(
[grid]
nx = 512
lx = 1.0
[elastic]
poisson = 0.25
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 0.25
lambda_short = 0.015625
rms_gradient = 0.1
seed = 1
[load]
pressure = 1e-4
[solver]
tolerance = 1e-9
)";
  std::vector<double> kappa;
  for (double p : {0.0005, 0.00158, 0.005}) {
    const auto r = solve(rough, {"load.pressure=" + std::to_string(p * 0.1)});
    kappa.push_back(r.observables.relative_contact_area * r.topography_stats.rms_gradient / (p * 0.1));
    std::printf("p/(E* g) = %.5f  a_c = %.5f  kappa = %.4f  iterations %d\n", p,
                r.observables.relative_contact_area, kappa.back(), r.info.iterations);
  }
  const double mean = (kappa[0] + kappa[1] + kappa[2]) / 3;
  for (double k : kappa) EXPECT_NEAR(k / mean, 1.0, 0.05);
  // Exponent of a_c ~ p^b over the decade.
  EXPECT_NEAR(1.0 + std::log10(kappa[2] / kappa[0]), 1.0, 0.05);
  EXPECT_GT(kappa[1], 1.8);
  EXPECT_LT(kappa[1], 3.5);
}

// Cost accounting used by the benchmarks: a conjugate-gradient step of the normal problem
// applies the compliance twice (2 forward + 2 inverse transforms); the final displacement
// update adds a few more. The count covers this solve only.
TEST(Contact, SolveCountsItsTransforms) {
  const CaseResult r = solve(kHertz, {"grid.nx=64", "solver.tolerance=1e-8"});
  ASSERT_TRUE(r.info.converged);
  ASSERT_GT(r.info.iterations, 5);
  const auto its = static_cast<std::uint64_t>(r.info.iterations);
  EXPECT_GE(r.info.transforms, 4 * its);
  EXPECT_LE(r.info.transforms, 4 * its + 12);
  // The time inside the transforms is counted too, and is part of the solve's time.
  EXPECT_GT(r.info.fft_seconds, 0.0);
  EXPECT_LT(r.info.fft_seconds, r.info.wall_time_s);
}
