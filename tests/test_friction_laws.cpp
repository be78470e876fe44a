// Friction laws as registered parts (contact/friction_law.hpp): Coulomb's, the speed-dependent
// law mu(|v|) = mu_k + (mu_s - mu_k) exp(-|v|/v_c) (regularised and with stick), Tresca's and
// the rate-strengthening law.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::solve;

namespace {

// A Hertz sphere sliding over a compressible half-space (coupled), regularised law.
const char* kSliding = R"(
[grid]
nx = 64
lx = 1.6
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 0.4
regularization = 0.01
[solver]
tolerance = 1e-10
[output]
analysis = false
)";

std::vector<std::string> velocity(double mu_s, double v_c) {
  return {"friction.law=\"velocity\"", "friction.static_coefficient=" + std::to_string(mu_s),
          "friction.velocity_scale=" + std::to_string(v_c)};
}

std::string problem(const std::vector<std::string>& sets) {
  try {
    (void)parse_config(kSliding, "t.toml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FrictionLaws, AConstantSpeedLawIsCoulombBitForBit) {
  // mu_s = mu_k: mu(|v|) = mu_k + 0 * exp(...) = mu_k exactly, so every bit is Coulomb's.
  const CaseResult c = solve(kSliding);
  const CaseResult v = solve(kSliding, velocity(0.4, 0.1));
  ASSERT_EQ(c.fields.pressure.size(), v.fields.pressure.size());
  for (std::size_t i = 0; i < c.fields.pressure.size(); ++i) {
    ASSERT_EQ(c.fields.pressure[i], v.fields.pressure[i]) << i;
    ASSERT_EQ(c.fields.tx[i], v.fields.tx[i]) << i;
    ASSERT_EQ(c.fields.ty[i], v.fields.ty[i]) << i;
  }
  EXPECT_EQ(c.observables.friction_coefficient, v.observables.friction_coefficient);
  EXPECT_EQ(c.info.iterations, v.info.iterations);
}

TEST(FrictionLaws, SpeedLawTendsToTheConstantLawsAtItsLimits) {
  // v_c -> 0: mu_k wherever the body slips faster than ~20 v_c; v_c -> inf: mu_s everywhere.
  const double mu_k = 0.4, mu_s = 0.7;
  const CaseResult fast = solve(kSliding, velocity(mu_s, 1e-6));
  const CaseResult kinetic = solve(kSliding);
  EXPECT_NEAR(fast.observables.friction_coefficient / kinetic.observables.friction_coefficient, 1.0, 1e-8);
  const CaseResult slow = solve(kSliding, velocity(mu_s, 1e7));
  const CaseResult stat = solve(kSliding, {"friction.coefficient=0.7"});
  EXPECT_NEAR(slow.observables.friction_coefficient / stat.observables.friction_coefficient, 1.0, 1e-6);
  (void)mu_k;
}

TEST(FrictionLaws, SpeedLawHoldsAtEveryContactPoint) {
  // At the solution each contact point's traction is mu(|v|) p v/|v| with the slip velocity the
  // solution's displacements give (CaseResult::derived): |tau| / p against the law.
  const double mu_k = 0.4, mu_s = 0.8, v_c = 0.5;
  const CaseResult r = solve(kSliding, velocity(mu_s, v_c));
  std::size_t checked = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < r.fields.pressure.size(); ++i) {
    const double p = r.fields.pressure[i];
    if (!(p > 1e-3 * r.observables.max_pressure)) continue;
    const double vx = 1.0 + r.derived.slip_longitudinal[i], vy = r.derived.slip_transverse[i];
    const double speed = std::hypot(vx, vy);
    ASSERT_GT(speed, 0.01) << "a point nearly at rest: the regularised branch, not tested here";
    const double expected = mu_k + (mu_s - mu_k) * std::exp(-speed / v_c);
    worst = std::max(worst, std::abs(std::hypot(r.fields.tx[i], r.fields.ty[i]) / p - expected) / expected);
    ++checked;
  }
  EXPECT_GT(checked, 50u);
  EXPECT_LT(worst, 1e-6) << "the law's traction at the converged slip";
  // The coefficient lies between the kinetic and the static one, nearer mu_k the faster the
  // body slips against v_c (|v| ~ 1 here: mu ~ mu_k + 0.14 (mu_s - mu_k) for v_c = 0.5).
  const double mu = r.observables.friction_coefficient;
  EXPECT_GT(mu, mu_k);
  EXPECT_LT(mu, mu_s);
  const CaseResult slower = solve(kSliding, velocity(mu_s, 2.0));
  EXPECT_GT(slower.observables.friction_coefficient, mu) << "a larger v_c keeps more of the static peak";
}

TEST(FrictionLaws, TheSpeedLawIsDescribedAndRoundTrips) {
  const CaseResult r = solve(kSliding, velocity(0.8, 0.5));
  const nlohmann::json s = summary_json(r);
  EXPECT_EQ(s["friction_law"], "velocity");
  EXPECT_NE(s["friction_law_traction"].get<std::string>().find("exp(-|v|/v_c)"), std::string::npos);
  const nlohmann::json in = r.config.to_json()["friction"];
  EXPECT_EQ(in["law"], "velocity");
  EXPECT_EQ(in["static_coefficient"], 0.8);
  EXPECT_EQ(in["velocity_scale"], 0.5);
  const Config again = parse_config(r.config.to_toml(), "again.toml");
  EXPECT_EQ(again.friction.law.kind, FrictionLawKind::Velocity);
  EXPECT_EQ(again.friction.law.static_coefficient, 0.8);
  // Coulomb's summaries keep their keys as they were (no law keys written).
  const Config c = parse_config(kSliding, "c.toml");
  EXPECT_FALSE(c.to_json()["friction"].contains("law"));
}

TEST(FrictionLaws, KeysAndCapabilitiesAreChecked) {
  EXPECT_NE(problem({"friction.law=\"velocty\""})
                .find("friction.law: unknown friction law \"velocty\" (did you mean "
                      "'velocity'?); one of coulomb, velocity"),
            std::string::npos);
  EXPECT_EQ(problem({"friction.law=\"velocty\"", "friction.velocity_scale=1"}).find("velocity_scale"),
            std::string::npos)
      << "the meant law's keys are no second error";
  EXPECT_NE(problem({"friction.static_coefficient=0.5"}).find("friction.static_coefficient: unknown key"),
            std::string::npos)
      << "Coulomb's law has no static coefficient";
  EXPECT_NE(problem({"friction.law=\"velocity\"", "friction.static_coefficient=0.5"})
                .find("friction.velocity_scale: must be a positive number"),
            std::string::npos);
  // mu_s has no default (it was 0: a law rising from zero, without a word).
  EXPECT_NE(problem({"friction.law=\"velocity\"", "friction.velocity_scale=1"})
                .find("friction.static_coefficient: is required with friction.law = \"velocity\""),
            std::string::npos)
      << problem({"friction.law=\"velocity\"", "friction.velocity_scale=1"});
  EXPECT_NE(
      problem({"friction.law=\"velocity\"", "friction.static_coefficient=-1", "friction.velocity_scale=1"})
          .find("friction.static_coefficient: must be a non-negative"),
      std::string::npos);
  std::vector<std::string> exact = velocity(0.8, 0.5);
  exact.push_back("friction.regularization=0");
  EXPECT_EQ(problem(exact), "") << "the exact law with stick is solved";
  // friction.coefficient = 0 switches the friction off: a law whose traction does not vanish
  // with it (a static peak, a rate term) is refused rather than dropped; one that vanishes
  // (mu_s = 0) only warns (test_plausibility).
  std::vector<std::string> peak = velocity(0.8, 0.5);
  peak.emplace_back("friction.coefficient=0");
  EXPECT_NE(problem(peak).find("friction.coefficient: must be positive with friction.law = \"velocity\""),
            std::string::npos)
      << problem(peak);
  const std::vector<std::string> rate = {"friction.law=\"rate\"", "friction.rate_coefficient=0.05",
                                         "friction.velocity_scale=0.01", "friction.coefficient=0"};
  EXPECT_NE(problem(rate).find("friction.coefficient: must be positive with friction.law = \"rate\""),
            std::string::npos)
      << problem(rate);
  // Another law from the command line drops the file's law's keys (an ensemble's frictionless
  // half sets coulomb and 0 over a velocity law).
  std::vector<std::string> off = peak;
  off.emplace_back("friction.law=\"coulomb\"");
  EXPECT_EQ(problem(off), "") << problem(off);
  std::vector<std::string> flat = velocity(0.0, 0.5);
  flat.emplace_back("friction.coefficient=0");
  EXPECT_EQ(problem(flat), "");
  // Capabilities come from the registry.
  EXPECT_TRUE(coulomb_friction_law().set_valued_stick);
  EXPECT_TRUE(velocity_friction_law().set_valued_stick);
  for (const FrictionLawType* t : friction_law_types())  // FrictionLaw is GFMD_HD: every law runs there
    EXPECT_TRUE(t->on_device) << t->name;
  EXPECT_EQ(find_friction_law("velocity"), &velocity_friction_law());
  EXPECT_EQ(find_friction_law("stribeck"), nullptr);
}

namespace {

// Tresca's law on an incompressible half-space at nx points per side: the friction does not
// change the pressure (no coupling), so p is Hertz's, p0 sqrt(1 - r^2/a^2), and the law gives
// |tau| = min(mu p, tau_0) at every slipping point. Integrating over the contact:
//   F_t = tau_0 pi r*^2 + (2 pi/3) mu p0 a^2 s^3,  s = tau_0/(mu p0), r*^2 = a^2 (1 - s^2).
// Returns the relative error of F_t/F against that; checks the pressure and the pointwise law.
double tresca_error(int nx) {
  const double F = 0.01, mu = 0.5, a = std::cbrt(3 * F / 4), p0 = 3 * F / (2 * std::numbers::pi * a * a);
  const double tau0 = 0.3 * mu * p0, s = tau0 / (mu * p0);  // the cap at 30 % of mu p0
  const std::vector<std::string> incompressible = {"elastic.poisson=0.5", "grid.nx=" + std::to_string(nx),
                                                   "friction.regularization=0", "friction.coefficient=0.5"};
  const CaseResult coulomb = solve(kSliding, incompressible);
  std::vector<std::string> sets = incompressible;
  sets.emplace_back("friction.law=\"tresca\"");
  sets.push_back("friction.shear_strength=" + std::to_string(tau0));
  const CaseResult r = solve(kSliding, sets);
  // The pressure is Coulomb's (the law never enters it without coupling).
  double dp = 0.0;
  for (std::size_t i = 0; i < r.fields.pressure.size(); ++i)
    dp = std::max(dp, std::abs(r.fields.pressure[i] - coulomb.fields.pressure[i]));
  EXPECT_LT(dp, 1e-8 * p0);
  // Pointwise: min(mu p, tau_0) where in contact (to the solve's tolerance).
  double worst = 0.0, sum = 0.0, load = 0.0;
  for (std::size_t i = 0; i < r.fields.pressure.size(); ++i) {
    const double p = r.fields.pressure[i];
    if (!(p > 0)) continue;
    const double t = std::hypot(r.fields.tx[i], r.fields.ty[i]);
    worst = std::max(worst, std::abs(t - std::min(mu * p, tau0)) / tau0);
    sum += std::min(mu * p, tau0);
    load += p;
  }
  EXPECT_LT(worst, 1e-4);
  // The force along the sliding direction: the slip direction tilts from e_s by the in-plane
  // strain only (1e-3 here).
  const double ratio = r.observables.tangential_force / r.observables.normal_force;
  EXPECT_NEAR(ratio, sum / load, 1e-3 * sum / load);
  EXPECT_LT(ratio, mu) << "below Coulomb's mu_c";
  const double closed = (tau0 * std::numbers::pi * a * a * (1 - s * s) +
                         2 * std::numbers::pi / 3 * mu * p0 * a * a * s * s * s) /
                        F;
  return ratio / closed - 1;
}

}  // namespace

TEST(FrictionLaws, TrescaCapsTheTractionAtTheShearStrength) {
  // Against the closed form: 2.9 % at nx = 128 (a = 16 dx), 1.4 % at 256 (the discrete Hertz
  // contact's edge; 0.6 % at 512, measured with gfmd run).
  const double coarse = tresca_error(128), fine = tresca_error(256);
  EXPECT_LT(std::abs(coarse), 0.035);
  EXPECT_LT(std::abs(fine), 0.018);
  EXPECT_LT(std::abs(fine), 0.6 * std::abs(coarse)) << "converges under refinement";
}

TEST(FrictionLaws, TrescaWithStickInRolling) {
  // Tractive rolling (creepage 0.002) solves the set-valued law: points stick where the traction
  // stays inside the disc |tau| <= min(mu p, tau_0), and stuck points hold no more than the cap.
  std::vector<std::string> sets = {"friction.regularization=0", "friction.creepage=0.002",
                                   "friction.law=\"tresca\"", "friction.shear_strength=0.01"};
  const CaseResult r = solve(kSliding, sets);
  ASSERT_GT(r.observables.stick_fraction, 0.05);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.fields.pressure.size(); ++i) {
    const double p = r.fields.pressure[i];
    if (!(p > 0)) continue;
    worst = std::max(worst, std::hypot(r.fields.tx[i], r.fields.ty[i]) - std::min(0.4 * p, 0.01));
  }
  EXPECT_LT(worst, 1e-9) << "no traction outside the disc";
}

namespace {

std::vector<std::string> rate(double a, double v_c, std::vector<std::string> more = {}) {
  more.push_back("friction.law=\"rate\"");
  more.push_back("friction.rate_coefficient=" + std::to_string(a));
  more.push_back("friction.velocity_scale=" + std::to_string(v_c));
  return more;
}

const std::vector<std::string> kRolling = {"friction.regularization=0", "friction.creepage=0.002"};

// A rolling solution (creepage xi) against a speed-dependent law mu(|v|): the largest |tau|/p
// over the stuck contact points, and over the slipping ones (slip speed from CaseResult::derived,
// above 1 % of xi: the stick zone's edge slips too slowly to resolve) the largest relative
// error of |tau| against mu(|v|) p, with their count.
struct RollingFit {
  double stuck_ratio = 0.0, slip_error = 0.0;
  std::size_t slipping = 0;
};
RollingFit fit_rolling(const CaseResult& r, double xi, const std::function<double(double)>& mu) {
  RollingFit fit;
  for (std::size_t i = 0; i < r.fields.pressure.size(); ++i) {
    const double p = r.fields.pressure[i];
    if (!(p > 0)) continue;
    const double t = std::hypot(r.fields.tx[i], r.fields.ty[i]);
    if (r.fields.stick[i]) {
      fit.stuck_ratio = std::max(fit.stuck_ratio, t / p);
      continue;
    }
    const double speed = std::hypot(xi + r.derived.slip_longitudinal[i], r.derived.slip_transverse[i]);
    if (speed < 1e-2 * xi) continue;
    const double expected = mu(speed) * p;
    fit.slip_error = std::max(fit.slip_error, std::abs(t - expected) / expected);
    ++fit.slipping;
  }
  return fit;
}

}  // namespace

TEST(FrictionLaws, ARateLawWithoutStrengtheningIsCoulombBitForBit) {
  // a = 0: bound = mu p, and the resolvent is the projection: Coulomb's bits, with stick.
  const CaseResult c = solve(kSliding, kRolling);
  const CaseResult r = solve(kSliding, rate(0.0, 0.01, kRolling));
  ASSERT_GT(c.observables.stick_fraction, 0.05);
  for (std::size_t i = 0; i < c.fields.pressure.size(); ++i) {
    ASSERT_EQ(c.fields.pressure[i], r.fields.pressure[i]) << i;
    ASSERT_EQ(c.fields.tx[i], r.fields.tx[i]) << i;
  }
  EXPECT_EQ(c.observables.friction_coefficient, r.observables.friction_coefficient);
}

TEST(FrictionLaws, RateLawHoldsWhereItSlipsAndTheDiscWhereItSticks) {
  // Tractive rolling: the stick zone holds |tau| <= mu_c p with zero slip, the slip zone
  // |tau| = (mu_c + a ln(1 + |v|/v_c)) p at the solution's slip speed (CaseResult::derived).
  const double mu = 0.4, a = 0.05, v_c = 1e-3, xi = 0.002;
  const CaseResult r = solve(kSliding, rate(a, v_c, kRolling));
  ASSERT_GT(r.observables.stick_fraction, 0.02);
  ASSERT_LT(r.observables.stick_fraction, 0.98);
  const RollingFit fit = fit_rolling(r, xi, [&](double speed) { return mu + a * std::log1p(speed / v_c); });
  EXPECT_GT(fit.slipping, 20u);
  EXPECT_LT(fit.stuck_ratio / mu - 1, 1e-12) << "inside the disc where stuck";
  EXPECT_LT(fit.slip_error, 1e-8) << "the law where it slips (measured 1.7e-11)";
}

TEST(FrictionLaws, RateLawInSlidingStrengthensWithSpeed) {
  // Sliding at v0 on an incompressible half-space (no coupling: the pressure is Hertz's): the
  // slip speed is 1 up to the in-plane strain, so mu ~ mu_c + a ln(1 + 1/v_c), and the work of
  // the drive equals the dissipation (energy_balance_error_exact) as for Coulomb's law.
  const double mu = 0.4, a = 0.02, v_c = 0.01;
  const CaseResult c = solve(kSliding, {"friction.regularization=0", "elastic.poisson=0.5"});
  const CaseResult r = solve(kSliding, rate(a, v_c, {"friction.regularization=0", "elastic.poisson=0.5"}));
  const double expected = mu + a * std::log1p(1.0 / v_c);
  EXPECT_NEAR(r.observables.friction_coefficient / expected, 1.0, 0.005);
  EXPECT_NEAR(c.observables.friction_coefficient / mu, 1.0, 0.005) << "Coulomb's, the same way";
  EXPECT_LT(r.observables.energy_balance_error_exact,
            std::max(1e-8, 10 * c.observables.energy_balance_error_exact));
  EXPECT_NE(problem({"friction.law=\"rate\"", "friction.velocity_scale=0.1", "friction.rate_coefficient=-1"})
                .find("friction.rate_coefficient: must be a non-negative"),
            std::string::npos);
}

namespace {

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST(FrictionLaws, TheVelocityLawsResolventHasItsOneRoot) {
  // Outside the disc |z| > mu_s p the slip speed s solves bound(s) + gamma s = |z|, returned as
  // |tau| = |z| - gamma s = bound(s): checked against the law for a falling bound whose
  // f(s) = bound(s) + gamma s - |z| first falls (gamma < (mu_s - mu_k) p / v_c), for a rising
  // one, and for mu_s = mu_k (the projection).
  FrictionLaw law;
  law.kind = FrictionLawKind::Velocity;
  law.velocity_scale = 1e-3;
  const double mu_k = 0.4, p = 0.02, gamma = 0.5;
  for (const double mu_s : {0.6, 0.2, 0.4}) {
    law.static_coefficient = mu_s;
    const double rest = mu_s * p;
    for (const double zm : {1.0001 * rest, 1.01 * rest, 1.5 * rest, 10 * rest}) {
      const double t = law.resolvent(mu_k, p, zm, gamma);
      const double s = (zm - t) / gamma;
      ASSERT_GE(s, 0.0) << mu_s << " " << zm;
      EXPECT_NEAR(t, law.bound(mu_k, p, s), 1e-14 * zm) << "mu_s " << mu_s << ", |z| " << zm / rest;
      EXPECT_LE(t, std::max(mu_s, mu_k) * p + 1e-14 * zm);
      EXPECT_GE(t, std::min(mu_s, mu_k) * p - 1e-14 * zm);
    }
    EXPECT_EQ(law.resolvent(mu_k, p, 0.9 * rest, gamma), 0.9 * rest) << "inside the disc: stick, tau = z";
  }
  law.static_coefficient = 0.6;
  EXPECT_LT(law.bound_slope(mu_k, p, 0.0) + gamma, 0.0) << "the case where f first falls is the one tested";
}

TEST(FrictionLaws, AnEqualStaticAndKineticVelocityLawIsCoulombWithStick) {
  // mu_s = mu_k with stick (rolling): the resolvent's root is the projection up to rounding.
  const CaseResult c = solve(kSliding, kRolling);
  const CaseResult v = solve(kSliding, with(velocity(0.4, 0.01), kRolling));
  ASSERT_GT(c.observables.stick_fraction, 0.05);
  EXPECT_EQ(c.observables.stick_fraction, v.observables.stick_fraction);
  EXPECT_NEAR(v.observables.friction_coefficient / c.observables.friction_coefficient, 1.0, 1e-9);
  double dt = 0.0;
  for (std::size_t i = 0; i < c.fields.pressure.size(); ++i)
    dt = std::max(dt, std::abs(c.fields.tx[i] - v.fields.tx[i]));
  EXPECT_LT(dt, 1e-9 * c.observables.max_pressure);
}

TEST(FrictionLaws, VelocityWeakeningHoldsWhereItSlipsAndTheStaticDiscWhereItSticks) {
  // Tractive rolling with a static peak (mu_s = 0.6 > mu_k = 0.4, v_c = 25 xi): stuck points hold
  // |tau| <= mu_s p, slipping points |tau| = mu(|v|) p at the solution's slip speed; the traction
  // exceeds the kinetic disc somewhere in the stick zone, which Coulomb's law with mu_k cannot.
  // The step gamma is raised to 3 x the bound's steepest fall (one below it cycles: measured);
  // v_c -> inf is Coulomb's law with mu_s, stick zone and all.
  const double mu_k = 0.4, mu_s = 0.6, v_c = 0.05, xi = 0.002;
  const CaseResult r = solve(kSliding, with(velocity(mu_s, v_c), kRolling));
  ASSERT_GT(r.observables.stick_fraction, 0.02);
  ASSERT_LT(r.observables.stick_fraction, 0.98);
  const RollingFit fit =
      fit_rolling(r, xi, [&](double speed) { return mu_k + (mu_s - mu_k) * std::exp(-speed / v_c); });
  EXPECT_GT(fit.slipping, 20u);
  EXPECT_LT(fit.stuck_ratio / mu_s - 1, 1e-12) << "inside the static disc where stuck";
  EXPECT_GT(fit.stuck_ratio / mu_k - 1, 0.2) << "stuck points carry more than mu_k p";
  EXPECT_LT(fit.slip_error, 1e-8) << "the law where it slips";
  // examples/rolling_static_peak.toml is this case.
  const std::string text =
      gfmd::testing::read_file(std::string(GFMD_SOURCE_DIR) + "/examples/rolling_static_peak.toml");
  ASSERT_FALSE(text.empty()) << "examples/rolling_static_peak.toml";
  const CaseResult ex = solve(text, {"output.analysis=false"});
  EXPECT_EQ(ex.observables.stick_fraction, r.observables.stick_fraction);
  const CaseResult slow = solve(kSliding, with(velocity(mu_s, 1e3), kRolling));
  const CaseResult stat = solve(kSliding, with({"friction.coefficient=0.6"}, kRolling));
  EXPECT_EQ(slow.observables.stick_fraction, stat.observables.stick_fraction);
  EXPECT_NEAR(slow.observables.friction_coefficient / stat.observables.friction_coefficient, 1.0, 1e-5);
}

TEST(FrictionLaws, TheExactVelocityLawInSlidingIsTheRegularisedOne) {
  // Full sliding: every point slips near v0, far above eps = 0.01, so the regularised law never
  // acts and the exact solve (stick-slip splitting) must find the same state; the drive's work
  // balances the dissipation as well as for Coulomb's law.
  const CaseResult reg = solve(kSliding, velocity(0.8, 0.5));
  const CaseResult exact = solve(kSliding, with(velocity(0.8, 0.5), {"friction.regularization=0"}));
  const CaseResult coulomb = solve(kSliding, {"friction.regularization=0"});
  EXPECT_EQ(exact.observables.stick_fraction, 0.0);
  EXPECT_NEAR(exact.observables.friction_coefficient / reg.observables.friction_coefficient, 1.0, 1e-7);
  EXPECT_LT(exact.observables.energy_balance_error_exact,
            std::max(1e-8, 10 * coulomb.observables.energy_balance_error_exact));
}
