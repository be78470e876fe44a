// Steady frictional sliding: energy balance, uncoupled limits, paper Fig. 2 trends.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
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
    EXPECT_NEAR(r.observables.relative_contact_area, r.reference->observables.relative_contact_area, 1e-12);
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
  EXPECT_GT(r.observables.relative_contact_area, r.reference->observables.relative_contact_area);  // dA/A > 0
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

TEST(Sliding, ThinLayerSticksAndBalancesEnergy) {
  // A thinner layer (h = 0.05 lambda_l) at p = 0.1 E*: in-plane strains (e_s.grad) u_s reach
  // -1 and some contact points move with the indenter. The full-slip law tau = mu_c p v/|v|
  // has no fixed point there; the set-valued law (stick where v = 0, |tau| <= mu_c p)
  // converges, and the dissipation of the slipping points equals the work of the driving
  // force (xi sum tau.e_s + dF) to 1e-6.
  const std::vector<std::string> thin = {"elastic.thickness=0.05", "load.pressure=0.1"};
  const auto exact = solve(kRoughLayer, thin);
  ASSERT_TRUE(exact.info.converged) << exact.info.status;
  EXPECT_GT(exact.observables.stick_fraction, 0.0);
  EXPECT_LT(exact.observables.stick_fraction, 0.05);
  EXPECT_GT(exact.info.stick_points, 0u);
  // 2e-5 at this coarse grid (128^2); 2.6e-7 at 512^2 (lambda_s = lambda_l/32).
  EXPECT_LT(exact.observables.energy_balance_error_exact, 1e-4);
  // Stuck points: zero slip velocity, traction inside the friction disc; slipping points:
  // |tau| = mu_c p.
  const auto& f = exact.fields;
  ASSERT_EQ(f.stick.size(), f.pressure.size());
  double inside = 0.0, on = 0.0;
  for (std::size_t i = 0; i < f.pressure.size(); ++i) {
    if (!(f.pressure[i] > 0)) {
      EXPECT_EQ(f.stick[i], 0);
      continue;
    }
    const double t = std::hypot(f.tx[i], f.ty[i]) / f.pressure[i];
    if (f.stick[i])
      inside = std::max(inside, t);
    else
      on = std::max(on, std::abs(t - 1.0));
  }
  EXPECT_LE(inside, 1.0 + 1e-12);
  EXPECT_LT(on, 1e-9);
  // The regularised law stays available and converges too, with the old observables.
  auto sets = thin;
  sets.emplace_back("friction.regularization=0.1");
  const auto reg = solve(kRoughLayer, sets);
  EXPECT_GT(reg.observables.near_stick_fraction, 0.0);
  EXPECT_LT(reg.observables.energy_balance_error_exact, 1e-4);
  EXPECT_TRUE(reg.fields.stick.empty());
  // Where every contact point slips the law is the full-slip one: the same numbers with and
  // without a regularisation that never acts, to the last bit, and no stick.
  const auto a = solve(kRoughLayer);
  const auto b = solve(kRoughLayer, {"friction.regularization=0.1"});
  EXPECT_GT(a.observables.min_slip_velocity, 0.1);
  EXPECT_EQ(a.observables.friction_coefficient, b.observables.friction_coefficient);
  EXPECT_EQ(a.observables.relative_contact_area, b.observables.relative_contact_area);
  EXPECT_EQ(a.observables.stick_fraction, 0.0);
  EXPECT_EQ(b.observables.near_stick_fraction, 0.0);
}

TEST(Sliding, StickAccelerationReachesThePlainSplittingAnswerInFewerSteps) {
  // The thin layer at p = 0.1 E* with the upwind2 derivative: the full-slip map stalls and
  // the stick-slip splitting takes over. Anderson mixing of its variable
  // (friction.stick_acceleration) converges to the same answer, to the solve's tolerance, in
  // fewer splitting steps (128^2: 244 plain, 120 accelerated).
  const std::vector<std::string> sets = {"elastic.thickness=0.05", "load.pressure=0.1",
                                         "friction.slip_derivative=\"upwind2\""};
  auto acc_sets = sets;
  acc_sets.emplace_back("friction.stick_acceleration=5");
  const auto plain = solve(kRoughLayer, sets);
  const auto acc = solve(kRoughLayer, acc_sets);
  ASSERT_TRUE(plain.info.converged) << plain.info.status;
  ASSERT_TRUE(acc.info.converged) << acc.info.status;
  ASSERT_GT(plain.info.stick_points, 0u);
  EXPECT_EQ(acc.info.stick_points, plain.info.stick_points);
  EXPECT_LT(acc.info.tangential_iterations, plain.info.tangential_iterations);
  const auto rel = [](double a, double b) { return std::abs(a - b) / std::abs(b); };
  EXPECT_LT(rel(acc.observables.friction_coefficient, plain.observables.friction_coefficient), 1e-7);
  EXPECT_EQ(acc.observables.relative_contact_area, plain.observables.relative_contact_area);
  EXPECT_EQ(acc.observables.stick_fraction, plain.observables.stick_fraction);
  double dt = 0, tmax = 0;
  for (std::size_t i = 0; i < plain.fields.tx.size(); ++i) {
    dt = std::max({dt, std::abs(acc.fields.tx[i] - plain.fields.tx[i]),
                   std::abs(acc.fields.ty[i] - plain.fields.ty[i])});
    tmax = std::max(tmax, std::hypot(plain.fields.tx[i], plain.fields.ty[i]));
  }
  EXPECT_LT(dt, 1e-5 * tmax);
  // Where every contact point slips the option changes nothing, to the last bit.
  const auto a = solve(kRoughLayer, {"friction.slip_derivative=\"upwind2\""});
  const auto b =
      solve(kRoughLayer, {"friction.slip_derivative=\"upwind2\"", "friction.stick_acceleration=5"});
  EXPECT_EQ(a.info.tangential_iterations, 0);
  EXPECT_EQ(a.observables.friction_coefficient, b.observables.friction_coefficient);
  EXPECT_EQ(a.info.iterations, b.info.iterations);
  EXPECT_EQ(a.info.outer_iterations, b.info.outer_iterations);
}

TEST(Sliding, AutomaticDerivativeTurnsUpwindWhereTheSolveMeetsStick) {
  // friction.slip_derivative = "auto" (the default) for sliding: spectral while every contact
  // point slips, upwind2 once the solve meets stick (docs/solver.md). The thin layer at
  // p = 0.1 E* sticks: the automatic solve must reach the explicit upwind2 solve's answer (to
  // its tolerance) and its observables must use that derivative (its own dissipation);
  // kRoughLayer at p = 0.03 E* slips everywhere: bitwise the explicit spectral solve.
  const std::vector<std::string> stick = {"elastic.thickness=0.05", "load.pressure=0.1"};
  auto up_sets = stick;
  up_sets.emplace_back("friction.slip_derivative=\"upwind2\"");
  const auto a = solve(kRoughLayer, stick);
  const auto u = solve(kRoughLayer, up_sets);
  ASSERT_TRUE(a.info.converged) << a.info.status;
  ASSERT_TRUE(u.info.converged) << u.info.status;
  EXPECT_EQ(a.info.slip_derivative, SlipDerivative::Upwind2);
  EXPECT_EQ(summary_json(a)["slip_derivative"], "upwind2");
  ASSERT_GT(a.info.stick_points, 0u);
  EXPECT_EQ(a.info.stick_points, u.info.stick_points);
  const auto rel = [](double x, double y) { return std::abs(x - y) / std::abs(y); };
  EXPECT_LT(rel(a.observables.friction_coefficient, u.observables.friction_coefficient), 1e-7);
  EXPECT_NE(a.observables.numerical_dissipation, 0.0);
  EXPECT_LT(rel(a.observables.numerical_dissipation, u.observables.numerical_dissipation), 1e-4);
  EXPECT_EQ(a.observables.relative_contact_area, u.observables.relative_contact_area);
  // Every point slips: spectral, to the last bit.
  const auto s = solve(kRoughLayer, {});
  const auto sp = solve(kRoughLayer, {"friction.slip_derivative=\"spectral\""});
  ASSERT_TRUE(s.info.converged) << s.info.status;
  EXPECT_EQ(s.info.slip_derivative, SlipDerivative::Spectral);
  EXPECT_EQ(summary_json(s)["slip_derivative"], "spectral");
  EXPECT_EQ(s.info.tangential_iterations, 0);
  EXPECT_EQ(s.observables.friction_coefficient, sp.observables.friction_coefficient);
  EXPECT_EQ(s.observables.numerical_dissipation, 0.0);
  EXPECT_EQ(s.info.iterations, sp.info.iterations);
  // Handed over (slow points) but no point sticks in the end (nu = 0.25 half-space, mu_c = 2,
  // p = 1 E*): the automatic solve turns back and returns the spectral answer, to its
  // tolerance, not the upwind2 one (which differs by the discretisation).
  const std::vector<std::string> slow = {"elastic.poisson=0.25", "elastic.thickness=inf",
                                         "friction.coefficient=2", "load.pressure=1"};
  auto slow_spec = slow, slow_up = slow;
  slow_spec.emplace_back("friction.slip_derivative=\"spectral\"");
  slow_up.emplace_back("friction.slip_derivative=\"upwind2\"");
  const auto h = solve(kRoughLayer, slow);
  const auto hs = solve(kRoughLayer, slow_spec);
  const auto hu = solve(kRoughLayer, slow_up);
  ASSERT_TRUE(h.info.converged) << h.info.status;
  ASSERT_TRUE(hs.info.converged) << hs.info.status;
  ASSERT_TRUE(hu.info.converged) << hu.info.status;
  EXPECT_GT(h.info.tangential_iterations, 0);  // the stick-slip splitting took over
  EXPECT_EQ(h.info.stick_points, 0u);
  EXPECT_EQ(hu.info.stick_points, 0u);
  EXPECT_EQ(h.info.slip_derivative, SlipDerivative::Spectral);
  const double d_spec = rel(h.observables.friction_coefficient, hs.observables.friction_coefficient);
  const double d_up = rel(hu.observables.friction_coefficient, hs.observables.friction_coefficient);
  EXPECT_LT(d_spec, 1e-8);
  EXPECT_GT(d_up, 100 * d_spec);
  EXPECT_EQ(h.observables.relative_contact_area, hs.observables.relative_contact_area);
  // The turn costs a few friction steps, not a stall: the mixing restarts on the new map
  // (measured: 67 steps against 56 for the explicit spectral solve; 79 when the first mixing
  // step after the turn still combined the two maps' residuals).
  EXPECT_LE(h.info.outer_iterations, hs.info.outer_iterations + 15)
      << "spectral " << hs.info.outer_iterations << ", upwind2 " << hu.info.outer_iterations;
}

// Carter (1926) steady rolling of a cylinder with traction, plane strain, nu = 0.5 (the
// normal and tangential problems decouple and share E*): pressure p0 sqrt(1 - x^2/a^2),
// a stick zone of half-width c at the leading edge (x in [a - 2c, a]), c/a = sqrt(1 -
// Q/(mu_c P)) = 1 - xi E* / (2 mu_c p0), and the traction mu_c p0 sqrt(1 - x^2/a^2) minus
// mu_c p0 (c/a) sqrt(1 - (x - a + c)^2/c^2) in the stick zone. A line contact is a cell of
// ny = 2 rows with a cylindrical indenter (radius_y = 1e12); a/L = 0.05 (periodic images
// change p0 by < 0.1 %). Returns {error of c/a from the stick mask against Carter's c/a of
// the measured Q/(mu_c P), the same against the creepage relation, the largest traction
// error in the stick zone / (mu_c p0), the error of Q/(mu_c P) against Carter's 1 - (c/a)^2
// of the creepage, dx/c}.
std::array<double, 6> carter_errors(int nx) {
  const double mu = 0.3, a_ref = 0.05, xi = 0.0075;  // xi E*/(2 mu p0) = 0.5 for p0 = a E*/2R
  std::ostringstream c;
  c << "[grid]\nnx = " << nx << "\nny = 2\nlx = 1.0\nly = " << 2.0 / nx << "\n"
    << "[elastic]\npoisson = 0.5\n[indenter]\ntype = \"hertz\"\nradius_x = 1.0\nradius_y = 1e12\n"
    << "[load]\npressure = " << std::numbers::pi * a_ref * a_ref / 4.0 << "\n"
    << "[friction]\ncoefficient = " << mu << "\ncreepage = " << xi << "\nreference = false\n"
    << "[interaction]\nmodel = \"hardwall\"\n[stress]\nprofiles = false\n";
  const auto r = solve(c.str());
  const Grid& g = r.config.grid;
  const auto& f = r.fields;
  const double dx = g.dx();
  double P = 0, Q = 0, xc = 0, n = 0, nstick = 0, stick_mid = 0;
  for (int ix = 0; ix < g.nx; ++ix) {
    const std::size_t i = static_cast<std::size_t>(ix);  // row 0
    if (!(f.pressure[i] > 0)) continue;
    P += f.pressure[i] * dx;
    Q += f.tx[i] * dx;
    xc += g.x(ix);
    n += 1;
    if (f.stick[i]) {
      nstick += 1;
      stick_mid += g.x(ix);
    }
  }
  xc /= n;
  const double a = std::sqrt(4.0 * P / std::numbers::pi), p0 = 2.0 * P / (std::numbers::pi * a);
  const double c_q = a * std::sqrt(1.0 - Q / (mu * P));
  const double c_xi = a * (1.0 - xi / (2.0 * mu * p0));
  const double c_mask = 0.5 * nstick * dx;
  // The stick zone lies at the leading edge (+x, where the material enters the contact).
  EXPECT_GT(stick_mid / nstick - xc, 0.25 * a_ref);  // Carter: at a - c = a/2
  double terr = 0, terr2 = 0;
  for (int ix = 0; ix < g.nx; ++ix) {
    const std::size_t i = static_cast<std::size_t>(ix);
    if (!(f.pressure[i] > 0)) continue;
    const double x = g.x(ix) - xc, s = x - (a - c_q);
    // Carter's traction with the computed pressure in its first term (the discrete Hertz
    // pressure at the contact edge is not the friction law's error).
    double t = mu * f.pressure[i];
    if (std::abs(s) < c_q) t -= mu * p0 * (c_q / a) * std::sqrt(1.0 - s * s / (c_q * c_q));
    terr = std::max(terr, std::abs(f.tx[i] - t) / (mu * p0));
    terr2 += std::pow((f.tx[i] - t) / (mu * p0), 2);
  }
  terr2 = std::sqrt(terr2 / n);
  std::printf(
      "Carter nx = %d: a = %.5f, Q/(mu P) = %.5f, c/a: mask %.5f, Carter(Q) %.5f, Carter(xi) %.5f; "
      "traction error max %.4f, rms %.4f mu p0\n",
      nx, a, Q / (mu * P), c_mask / a, c_q / a, c_xi / a, terr, terr2);
  return {std::abs(c_mask / c_q - 1.0),
          std::abs(c_mask / c_xi - 1.0),
          terr2,
          terr,
          std::abs(Q / (mu * P) - (1.0 - (c_xi / a) * (c_xi / a))),
          dx / c_xi};
}

TEST(Rolling, CarterTractionAndStickZone) {
  const auto coarse = carter_errors(1024);
  const auto fine = carter_errors(2048);
  for (const auto& e : {coarse, fine}) {
    EXPECT_LT(e[0], 0.02);
    EXPECT_LT(e[1], 0.02);
    EXPECT_LT(e[2], 0.02);  // rms over the contact
    // The largest error sits in the one or two cells at the stick-slip boundary, where the
    // exact traction has a kink (5 % of mu p0 at 1024, 4.7 % at 2048).
    EXPECT_LT(e[3], 0.06);
  }
  // Errors shrink under refinement: the traction and the force. The stick mask's half-width
  // is a count of cells: within one cell of Carter's at both resolutions (1024 and 2048 cells
  // both give c/a = 0.498 with the upwind derivative).
  EXPECT_LT(coarse[1], coarse[5]);
  EXPECT_LT(fine[1], fine[5]);
  EXPECT_LT(fine[2], coarse[2]);
  EXPECT_LT(fine[4], coarse[4]);
}

TEST(Rolling, CreepageAndStickStepAreChecked) {
  for (const char* bad : {"friction.creepage=0", "friction.creepage=-0.1", "friction.creepage=nan",
                          "friction.creepage=inf", "friction.stick_step=-1", "solver.max_tangential=0",
                          "friction.stick_acceleration=-1", "friction.stick_acceleration=51",
                          "friction.stick_acceleration=1.5", "friction.stick_acceleration=\"yes\"",
                          "friction.stick_acceleration=5"}) {  // the last: with the spectral derivative
    try {
      const bool accel = std::string(bad) == "friction.stick_acceleration=5";
      if (accel)
        (void)parse_config(kRoughLayer, "test.toml", {bad, "friction.slip_derivative=\"spectral\""});
      else
        (void)parse_config(kRoughLayer, "test.toml", {bad});
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::exception& e) {
      const std::string key = std::string(bad).substr(0, std::string(bad).find('='));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  try {
    (void)parse_config(kRoughLayer, "test.toml", {"friction.coefficient=0", "friction.creepage=0.5"});
    ADD_FAILURE() << "creepage without friction was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("friction.creepage"), std::string::npos) << e.what();
  }
  // With the automatic derivative the stick-slip phase is upwind2: accepted.
  EXPECT_EQ(
      parse_config(kRoughLayer, "test.toml", {"friction.stick_acceleration=5"}).friction.stick_acceleration,
      5);
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

// A failed friction iteration says what its history shows: the period and amplitude of a
// limit cycle, a slow drift, or no pattern.
TEST(Sliding, FailureMessageNamesLimitCycleOrDrift) {
  std::vector<double> change, force;
  for (int t = 0; t < 90; ++t) {  // period 3 around 0.5 with amplitude 0.01
    force.push_back(0.5 + 0.01 * std::sin(2 * std::numbers::pi * t / 3.0));
    change.push_back(2e-6 + 1e-7 * (t % 3));
  }
  std::string m = gfmd::friction_history_evidence(change, force);
  EXPECT_NE(m.find("a limit cycle"), std::string::npos) << m;
  EXPECT_NE(m.find("period 3 steps"), std::string::npos) << m;
  EXPECT_NE(m.find("+-1.7"), std::string::npos) << m;  // 0.01 sin(2 pi t/3) peaks at 0.00866: 1.73e-2 of 0.5
  force.clear();
  for (int t = 0; t < 90; ++t) force.push_back(0.5 + 1e-4 * t);
  change.insert(change.begin() + 20, 1.4e-8);  // the least change, reached at step 21
  force.insert(force.begin() + 20, 0.5);
  m = gfmd::friction_history_evidence(change, force);
  EXPECT_NE(m.find("drifts slowly"), std::string::npos) << m;
  // It gave up for want of progress (damped_mixing), not of steps: no "more steps"; the floor,
  // the least change (2e-6 in the last steps) rounded up, is the tolerance that accepts it.
  EXPECT_EQ(m.find("give it more steps"), std::string::npos) << m;
  EXPECT_NE(m.find("its least over the solve 1.40e-08 (friction step 21)"), std::string::npos) << m;
  EXPECT_NE(m.find("solver.tolerance = 2e-06 would accept it"), std::string::npos) << m;
  // Where the loop ran out of solver.max_outer instead (no damping gave up), the drift wants
  // more steps, and says so.
  m = gfmd::friction_history_evidence(change, force, /*damped_out=*/false);
  EXPECT_NE(m.find("give it more steps (solver.max_outer)"), std::string::npos) << m;
  EXPECT_EQ(m.find("has a floor"), std::string::npos) << m;
  // A floor above 1e-5 is no state to accept: no tolerance is offered.
  std::vector<double> high(change.size());
  std::transform(change.begin(), change.end(), high.begin(), [](double c) { return 100.0 * c; });
  m = gfmd::friction_history_evidence(high, force);
  EXPECT_NE(m.find("has a floor"), std::string::npos) << m;
  EXPECT_EQ(m.find("solver.tolerance"), std::string::npos) << m;
  change.erase(change.begin() + 20);
  force.erase(force.begin() + 20);
  force.clear();
  std::uint64_t x = 12345;
  for (int t = 0; t < 90; ++t) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    force.push_back(0.5 + 1e-3 * static_cast<double>(x >> 11) / 9007199254740992.0);
  }
  m = gfmd::friction_history_evidence(change, force);
  EXPECT_NE(m.find("no periodic pattern"), std::string::npos) << m;
  EXPECT_NE(gfmd::friction_history_evidence({1, 2}, {1, 2}).find("too few"), std::string::npos);
}
