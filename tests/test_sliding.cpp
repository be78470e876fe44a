// Steady frictional sliding: energy balance, uncoupled limits, paper Fig. 2 trends.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gfmd/config.hpp"
#include "gfmd/run.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

using gfmd::testing::solve;

// Hertz R = 1, F = 0.01 E* R^2 (a = 0.196), cell 1.6 R, 256^2 (a/dx = 31).
const char* kHertz = R"(
[grid]
nx = 256
lx = 1.6
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 1.0
[solver]
tolerance = 1e-9
)";

// Self-affine indenter against a nu = 0.49 layer h = 0.1 lambda_l (paper Fig. 2e), at a
// reduced resolution: lambda_s = lambda_l/16, dx = lambda_s/4.
const char* kRoughLayer = R"(
[grid]
nx = 128
lx = 2.0
[elastic]
poisson = 0.49
thickness = 0.1
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 1.0
lambda_short = 0.0625
rms_height = 0.01
seed = 0
[load]
pressure = 0.03
[friction]
coefficient = 1.0
)";

double mirror_asymmetry(const CaseResult& r) {
  const Grid& g = r.config.grid;
  double pmax = 0, d = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double p = r.fields.pressure[iy * g.nx + ix];
      const double q = r.fields.pressure[iy * g.nx + (g.nx - ix) % g.nx];
      pmax = std::max(pmax, p);
      d = std::max(d, std::abs(p - q));
    }
  return d / pmax;
}

}  // namespace

TEST(Sliding, UncoupledGivesMicroscopicFrictionAndSymmetricPressure) {
  // SPEC §7: nu = 0.5 on a half-space, and any nu without coupling: mu = mu_c, p symmetric.
  for (const std::vector<std::string>& sets :
       {std::vector<std::string>{"elastic.poisson=0.5"}, std::vector<std::string>{"elastic.coupling=false"},
        std::vector<std::string>{"elastic.coupling=false", "elastic.poisson=0.49",
                                 "elastic.thickness=0.2"}}) {
    const auto r = solve(kHertz, sets);
    EXPECT_NEAR(r.observables.friction_coefficient, 1.0, 1e-3) << sets.back();
    EXPECT_NEAR(r.observables.friction_coefficient_downhill, 1.0, 1e-6) << sets.back();
    EXPECT_LT(mirror_asymmetry(r), 1e-6) << sets.back();
    EXPECT_NEAR(r.observables.relative_contact_area, r.reference.relative_contact_area, 1e-12);
  }
}

TEST(Sliding, EnergyBalanceHertzAndRough) {
  // Dissipation P/v0 against mu_c F + downhill force (SM Eqs. 7-8): equal up to second
  // order in the strains; against the exact work of the driving force: equal.
  struct Case {
    const char* toml;
    std::vector<std::string> sets;
  };
  const std::vector<Case> cases = {{kHertz, {}},
                                   {kHertz, {"elastic.coupling=false"}},
                                   {kHertz, {"elastic.poisson=0.49", "elastic.thickness=0.2"}},
                                   {kRoughLayer, {}},
                                   {kRoughLayer, {"elastic.coupling=false"}},
                                   {kRoughLayer, {"elastic.poisson=0.25", "elastic.thickness=\"inf\""}}};
  for (const auto& c : cases) {
    const auto r = solve(c.toml, c.sets);
    EXPECT_LT(r.observables.energy_balance_error, 1e-3) << r.config.to_toml();
    EXPECT_LT(r.observables.energy_balance_error_exact, 1e-4) << r.config.to_toml();
  }
}

TEST(Sliding, HertzCompressibleLowersFrictionAndFollowsCubeRootLaw) {
  // Paper Fig. 2(a,b,d): nu = 0.25, h = inf, mu_c = 1.
  const auto r = solve(kHertz);
  EXPECT_LT(r.observables.friction_coefficient, 1.0);
  EXPECT_GT(r.observables.relative_contact_area, r.reference.relative_contact_area);  // dA/A > 0
  EXPECT_LT(r.observables.pressure_max_shift, 0.0);  // trailing edge (indenter moves +x)
  EXPECT_LT(r.observables.centroid_shift, 0.0);
  // Delta mu ~ F^(1/3) over one decade of load.
  std::vector<double> dmu;
  for (const char* f : {"load.force=0.001", "load.force=0.01"}) {
    const auto s = solve(kHertz, {f});
    dmu.push_back(s.observables.friction_coefficient - 1.0);
  }
  const double exponent = std::log(dmu[1] / dmu[0]) / std::log(10.0);
  std::printf("Delta mu exponent %.4f (Delta mu = %.5f at F = 0.001, %.5f at F = 0.01)\n", exponent, dmu[0],
              dmu[1]);
  EXPECT_NEAR(exponent, 1.0 / 3.0, 0.03);
}

TEST(Sliding, HertzConfinedRaisesFrictionAndSkewsToLeadingEdge) {
  const auto r = solve(kHertz, {"elastic.poisson=0.49", "elastic.thickness=0.2"});
  EXPECT_GT(r.observables.friction_coefficient, 1.0);
  EXPECT_GT(r.observables.centroid_shift, 0.0);
  EXPECT_GE(r.observables.pressure_max_shift, 0.0);
}

TEST(Sliding, DirectionRotatesAndReversesTheSolution) {
  const auto x = solve(kHertz);
  const auto y = solve(kHertz, {"friction.direction=90"});
  const auto back = solve(kHertz, {"friction.direction=180"});
  const Grid& g = x.config.grid;
  const int cx = g.nx / 2, cy = g.ny / 2;
  double pmax = 0, drot = 0, drev = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double p = x.fields.pressure[iy * g.nx + ix];
      const int dx = ix - cx, dy = iy - cy;
      // Rotating +x by 90 degrees maps (dx, dy) to (-dy, dx).
      const int rx = ((cx - dy) % g.nx + g.nx) % g.nx, ry = ((cy + dx) % g.ny + g.ny) % g.ny;
      const int mx = ((cx - dx) % g.nx + g.nx) % g.nx;
      pmax = std::max(pmax, p);
      drot = std::max(drot, std::abs(p - y.fields.pressure[ry * g.nx + rx]));
      drev = std::max(drev, std::abs(p - back.fields.pressure[iy * g.nx + mx]));
    }
  EXPECT_LT(drot / pmax, 1e-6);
  EXPECT_LT(drev / pmax, 1e-6);
  EXPECT_NEAR(y.observables.friction_coefficient, x.observables.friction_coefficient, 1e-7);
  EXPECT_NEAR(back.observables.friction_coefficient, x.observables.friction_coefficient, 1e-7);
}

TEST(Sliding, RoughConfinedFrictionIsNonMonotonicInPressure) {
  // Paper Fig. 2(e): Delta mu/mu_c rises with load, then falls.
  std::vector<double> d;
  for (const char* p : {"load.pressure=0.003", "load.pressure=0.03", "load.pressure=0.3"}) {
    const auto r = solve(kRoughLayer, {p});
    d.push_back(r.observables.friction_coefficient - 1.0);
    std::printf("%s: a_c = %.4f, Delta mu/mu_c = %.5f, %d iterations\n", p,
                r.observables.relative_contact_area, d.back(), r.info.iterations);
  }
  EXPECT_GT(d[0], 0.0);
  EXPECT_GT(d[1], d[0]);
  EXPECT_LT(d[2], d[1]);
  EXPECT_GT(d[2], 0.0);
}

TEST(Sliding, RegularisedCoulombSettlesNearStickAndLeavesFullSlipAlone) {
  // A thinner layer (h = 0.05 lambda_l) at p = 0.1 E*: in-plane strains (e_s.grad) u_s near
  // -1 make some contact points slip at < 1 % of v0, where the direction of the exact
  // Coulomb traction is ill-conditioned. Its fixed point does not settle and the solver
  // says why; the regularised law (traction mu_c p v / eps below |v| = eps) converges, and
  // its observables still balance the energy exactly (work of the driving force =
  // dissipation, both from the regularised traction).
  const std::vector<std::string> thin = {"elastic.thickness=0.05", "load.pressure=0.1"};
  const CaseResult exact = run_case(parse_config(kRoughLayer, "test.toml", thin));
  EXPECT_FALSE(exact.info.converged);
  EXPECT_NE(exact.info.status.find("set friction.regularization"), std::string::npos) << exact.info.status;
  auto sets = thin;
  sets.emplace_back("friction.regularization=0.1");
  const auto reg = solve(kRoughLayer, sets);
  EXPECT_GT(reg.observables.near_stick_fraction, 0.0);
  EXPECT_LT(reg.observables.near_stick_fraction, 0.01);
  EXPECT_LT(reg.observables.min_slip_velocity, 0.1);
  EXPECT_LT(reg.observables.energy_balance_error_exact, 1e-4);
  // Where every contact point slips faster than eps the law is exact Coulomb: the same
  // numbers to the last bit.
  const auto a = solve(kRoughLayer);
  const auto b = solve(kRoughLayer, {"friction.regularization=0.1"});
  EXPECT_GT(a.observables.min_slip_velocity, 0.1);
  EXPECT_EQ(a.observables.friction_coefficient, b.observables.friction_coefficient);
  EXPECT_EQ(a.observables.relative_contact_area, b.observables.relative_contact_area);
  EXPECT_EQ(b.observables.near_stick_fraction, 0.0);
}

// Largest tangential traction component where the pressure is zero (must be exactly 0).
static double traction_outside_contact(const ContactFields& f) {
  double stray = 0.0;
  for (std::size_t i = 0; i < f.tx.size(); ++i)
    if (f.pressure[i] == 0.0) stray = std::max({stray, std::abs(f.tx[i]), std::abs(f.ty[i])});
  return stray;
}

// A warm start may carry traction where the new solve has no contact (a sweep's previous
// load, a checkpoint): the solve must drop it and reach the cold start's answer. Here the
// warm traction is a long-wave shear over the whole cell, mostly outside the contact (a
// uniform one would not deform the body).
TEST(Sliding, WarmStartTractionOutsideTheContactIsDropped) {
  const Config cfg = parse_config(kHertz, "t.toml", {"grid.nx=128", "solver.tolerance=1e-8"});
  const CaseResult cold = run_case(cfg);
  ASSERT_TRUE(cold.info.converged) << cold.info.status;
  ContactFields warm = cold.fields;
  const Grid& g = cfg.grid;
  std::size_t outside = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(iy) * g.nx + ix;
      warm.tx[i] += 0.01 * std::sin(2 * std::numbers::pi * ix / g.nx);
      warm.ty[i] -= 0.005 * std::cos(2 * std::numbers::pi * iy / g.ny);
      if (warm.pressure[i] == 0.0) ++outside;
    }
  ASSERT_GT(outside, warm.tx.size() / 2);
  RunOptions o;
  o.warm_start = &warm;
  const CaseResult r = run_case(cfg, o);
  ASSERT_TRUE(r.info.converged) << r.info.status;
  EXPECT_NEAR(r.observables.friction_coefficient, cold.observables.friction_coefficient, 1e-7);
  EXPECT_EQ(traction_outside_contact(r.fields), 0.0);
}

// Without Anderson mixing (solver.anderson = 0) the plain relaxation must reach the same
// fixed point (it updates the traction on the support only), in more friction steps.
TEST(Sliding, PlainRelaxationReachesTheAcceleratedFixedPoint) {
  const Config acc = parse_config(kHertz, "t.toml", {"grid.nx=64", "solver.tolerance=1e-8"});
  const Config plain =
      parse_config(kHertz, "t.toml", {"grid.nx=64", "solver.tolerance=1e-8", "solver.anderson=0"});
  const CaseResult a = run_case(acc);
  const CaseResult b = run_case(plain);
  ASSERT_TRUE(a.info.converged) << a.info.status;
  ASSERT_TRUE(b.info.converged) << b.info.status;
  EXPECT_GT(b.info.outer_iterations, a.info.outer_iterations);
  EXPECT_NEAR(b.observables.friction_coefficient, a.observables.friction_coefficient, 1e-6);
  EXPECT_EQ(b.observables.relative_contact_area, a.observables.relative_contact_area);
  EXPECT_EQ(traction_outside_contact(b.fields), 0.0);
}
