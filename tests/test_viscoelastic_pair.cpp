// A viscoelastic body under an elastic indenter (two deformable bodies, one of them lossy): at
// rest the elastic pair; sliding frictionless, the series combination of a standard linear solid
// and a spring, which is again a standard linear solid; with friction, the energy balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::max_abs_diff;
using gfmd::testing::solve;
using gfmd::testing::without_keys;

namespace {

// A sphere (R = 1) sliding frictionless over a nu = 0.3 standard linear solid (E0* = 1,
// E_inf* = 10, tau = 1), F = 0.01 E0* R^2.
const char* kSphere = R"(
[grid]
nx = 128
lx = 2.0
[elastic]
contact_modulus = 1.0
poisson = 0.3
viscoelastic = "sls"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[interaction]
model = "hardwall"
[friction]
velocity = 0.1
[solver]
tolerance = 1e-10
[output]
analysis = false
)";

std::string exact(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace

// The pair's response per mode: the body's own compliance times E0/E(omega) plus the
// indenter's elastic one (normal parts add; the indenter's coupling subtracts), here against
// the two bodies' compliances made separately; at rest the elastic pair's table.
TEST(ViscoelasticPair, ThePairsResponseIsTheBodysTimesItsFactorPlusTheIndenters) {
  const Grid g{16, 16, 1.0, 1.0};
  ViscoelasticParams ve;
  ve.model = ViscoelasticParams::Model::StandardLinearSolid;
  ve.high_frequency_modulus = 10.0;
  ve.relaxation_time = 1.0;
  ve.velocity = 0.2;
  const ElasticParams body = homogeneous_body(1.0, 0.3), ind = homogeneous_body(2.0, 0.45, 0.3);
  const ElasticBody pair(g, body, ve, &ind), own(g, body, ve), elastic_pair(g, body, {}, &ind);
  const ElasticBody ind_alone(g, ind);
  for (int ikx : {0, 1, 3, 8})
    for (int iky : {0, 2, 9}) {
      const std::size_t k = static_cast<std::size_t>(iky) * g.nxh() + ikx;
      const auto r = pair.response_compliance(ikx, iky);
      const auto o = own.response_compliance(ikx, iky);
      const auto i = ind_alone.compliance(ikx, iky);
      for (int a = 0; a < 9; ++a) {
        // The indenter's surface faces the other way: its coupling (entries xz, yz, zx, zy) subtracts.
        const double sign = (a == 2 || a == 5 || a == 6 || a == 7) ? -1.0 : 1.0;
        const std::complex<double> want = o[a] + sign * i[a];
        EXPECT_LT(std::abs(r[a] - want), 1e-13 * (std::abs(want) + std::abs(i[8])))
            << ikx << "," << iky << "," << a;
      }
      EXPECT_EQ(pair.normal_response(k), r[8]);
      if (ikx != 0) {
        EXPECT_GT(std::abs(pair.response(k) - 1.0), 1e-3) << "the mode is excited";
      }
    }
  ViscoelasticParams rest = ve;
  rest.velocity = 0.0;
  const ElasticBody at_rest(g, body, rest, &ind);
  for (std::size_t k = 0; k < at_rest.modes().size(); ++k)
    EXPECT_EQ(at_rest.normal_response(k), std::complex<double>(elastic_pair.mode(k).czz));
}

// At rest every mode of the body is relaxed: the elastic pair's solve with E0, bit for bit.
TEST(ViscoelasticPair, AtRestItIsTheElasticPair) {
  const std::vector<std::string> ind{"indenter.contact_modulus=2", "indenter.poisson=0.45"};
  std::vector<std::string> rest = ind;
  rest.push_back("friction.velocity=0");
  const CaseResult ve = solve(kSphere, rest);
  const CaseResult e = solve(
      without_keys(kSphere, {"viscoelastic", "high_frequency_modulus", "relaxation_time", "velocity"}), ind);
  EXPECT_EQ(ve.fields.pressure, e.fields.pressure);
  EXPECT_EQ(ve.observables.hysteresis_dissipation, 0.0);
}

// Frictionless, only C_zz matters: an elastic half-space indenter E_i* on a standard-linear-solid
// half-space (E0, E_inf, tau; the same nu) is the series combination 1/E(omega) + 1/E_i, again a
// standard linear solid, with E0' = E0 E_i/(E0 + E_i), E_inf' = E_inf E_i/(E_inf + E_i) and
// tau' = tau (E_inf + E_i)/(E0 + E_i) (the algebra of 1/E = (1 + i w tau)/(E0 + E_inf i w tau)):
// the rigid sphere on that solid. Pressure to 1e-7 of its peak, the hysteresis friction to 1e-6,
// below, near and above the loss peak; the hysteresis from the fields and the spectrum agree
// (1e-9): the indenter stores energy and dissipates none.
TEST(ViscoelasticPair, AnElasticIndenterActsAsASpringInSeries) {
  const double e0 = 1.0, einf = 10.0, tau = 1.0, ei = 2.0;
  const double e0p = e0 * ei / (e0 + ei), einfp = einf * ei / (einf + ei),
               taup = tau * (einf + ei) / (e0 + ei);
  for (const char* v : {"0.01", "0.1", "1"}) {
    const std::string speed = std::string("friction.velocity=") + v;
    const CaseResult pair = solve(kSphere, {"indenter.contact_modulus=2", "indenter.poisson=0.3", speed});
    const CaseResult one = solve(kSphere, {"elastic.contact_modulus=" + exact(e0p), speed,
                                           "elastic.high_frequency_modulus=" + exact(einfp),
                                           "elastic.relaxation_time=" + exact(taup)});
    const double peak = *std::max_element(one.fields.pressure.begin(), one.fields.pressure.end());
    std::printf("v0 = %s: pressure %.2e of its peak, mu_h %.6g against %.6g, balance %.1e\n", v,
                max_abs_diff(pair.fields.pressure, one.fields.pressure) / peak,
                pair.observables.hysteresis_friction, one.observables.hysteresis_friction,
                pair.observables.hysteresis_balance_error);
    EXPECT_LT(max_abs_diff(pair.fields.pressure, one.fields.pressure) / peak, 1e-7) << "v0 = " << v;
    EXPECT_GT(one.observables.hysteresis_friction, 1e-3) << "v0 = " << v;
    EXPECT_NEAR(pair.observables.hysteresis_friction / one.observables.hysteresis_friction, 1.0, 1e-6)
        << "v0 = " << v;
    EXPECT_LT(pair.observables.hysteresis_balance_error, 1e-9) << "v0 = " << v;
  }
}

// Coulomb friction with stick (the set-valued law) between an elastic indenter (E_i* = 2,
// nu = 0.45: Dundurs' beta is not zero) and a viscoelastic layer, an egg-crate in full contact
// near the loss peak: the driving work per speed goes into the interface's slip and the body's
// hysteresis to 1e-6 (the surface is periodic, so the slopes are exact); the hysteresis from the
// fields and from the spectrum agree (1e-9); the total friction is the interface's plus the
// body's; the regularised law (eps = 1e-4) is close to the exact one.
TEST(ViscoelasticPair, FrictionBetweenAnElasticIndenterAndAViscoelasticLayerBalancesItsWork) {
  const std::string crate = gfmd::testing::eggcrate_in_full_contact(
      "contact_modulus = 1.0\npoisson = 0.3\nthickness = 0.3\nviscoelastic = \"sls\"\n"
      "high_frequency_modulus = 10.0\nrelaxation_time = 1.0\n",
      "", "velocity = 0.16\n");
  const std::vector<std::string> pair{"indenter.contact_modulus=2", "indenter.poisson=0.45"};
  // Sliding and rolling (both bodies' material passes through the contact: the slip sees the
  // pair's complex in-plane response) with a small creepage, part of the contact sticking.
  const auto results = gfmd::testing::expect_work_balances(crate, pair);
  const Observables& o = results[0].observables;
  EXPECT_NEAR(o.total_friction_coefficient, o.friction_coefficient + o.hysteresis_friction, 1e-6);
  std::vector<std::string> regularised = pair;
  regularised.push_back("friction.regularization=1e-4");
  const CaseResult reg = solve(crate, regularised);
  EXPECT_NEAR(reg.observables.total_friction_coefficient / o.total_friction_coefficient, 1.0, 1e-3);
  // The indenter's compliance matters: the rigid indenter's friction differs.
  const CaseResult rigid = solve(crate);
  std::printf("regularised mu_total %.6g; rigid indenter mu_h %.6g\n",
              reg.observables.total_friction_coefficient, rigid.observables.hysteresis_friction);
  EXPECT_GT(std::abs(rigid.observables.hysteresis_friction / o.hysteresis_friction - 1.0), 0.01);
}

// The shipped examples run as their comments say (a viscoelastic body under an elastic ball, and a
// viscoelastic coating on a substrate): converged, the hysteresis near its peak, the two sums of
// it equal, the coating's planes computed.
TEST(ViscoelasticPair, TheExamplesRunAsTheirCommentsSay) {
  for (const char* name : {"visco_pair_sphere", "visco_coated_sphere"}) {
    std::ifstream in(std::string(GFMD_SOURCE_DIR) + "/examples/" + name + ".toml");
    ASSERT_TRUE(in) << name;
    std::stringstream text;
    text << in.rdbuf();
    const CaseResult r = solve(text.str(), {"output.png=false", "output.fields=false"});
    EXPECT_GT(r.observables.hysteresis_friction, 0.01) << name;
    EXPECT_LT(r.observables.hysteresis_balance_error, 1e-9) << name;
    EXPECT_LT(r.observables.energy_balance_error_exact, 1e-3) << name;
    const std::size_t planes = std::string(name) == "visco_coated_sphere" ? 2 : 0;
    EXPECT_EQ(r.subsurface.size(), planes) << name;
  }
}
