// A viscoelastic coating (the top layer a standard linear solid) on an elastic substrate or over
// elastic layers: the complex transfer matrices against the closed form of a layer, the limit of
// a rigid substrate against the homogeneous viscoelastic layer, the state at rest, the energy
// balance, and the planes below the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/layered.hpp"
#include "gfmd/elastic/stress.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::max_abs;
using gfmd::testing::max_abs_diff;
using gfmd::testing::solve;

namespace {

// A sphere (R = 1) sliding frictionless over a coating (SLS: E0* = 1, E_inf* = 10, tau = 1,
// nu = 0.3, h = 0.05 R) bonded to an elastic substrate (E2* = 2, nu = 0.25), F = 0.005 E0* R^2.
const char* kCoated = R"(
[grid]
nx = 128
lx = 2.0
[elastic]
contact_modulus = 1.0
poisson = 0.3
thickness = 0.05
substrate_contact_modulus = 2.0
substrate_poisson = 0.25
viscoelastic = "sls"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.005
[interaction]
model = "hardwall"
[friction]
velocity = 0.1
[solver]
tolerance = 1e-10
[output]
analysis = false
)";

}  // namespace

// The transfer matrices with a complex modulus: for a single layer on a rigid base they are the
// closed form (SPEC section 2) times E0/E by the correspondence principle, to 1e-12, at qh from
// 1e-3 to 60 and loss angles up to 80 degrees.
TEST(ViscoelasticCoating, ComplexTransferMatricesAreTheClosedFormTimesTheFactor) {
  for (const double nu : {0.0, 0.3, 0.49}) {
    const ElasticParams layer = homogeneous_body(1.0, nu, 0.5);
    for (const double q : {2e-3, 0.3, 4.0, 120.0})
      for (const std::complex<double> e :
           {std::complex<double>(1.0, 0.0), std::polar(3.0, 0.5), std::polar(7.0, 1.4)}) {
        const RotatedCompliance r = layered_compliance(q, layer);
        const ComplexRotatedCompliance c = layered_compliance(q, layer, {e, 1.0});
        const std::complex<double> f = 1.0 / e;
        const double scale = std::abs(f) * std::max({std::abs(r.c11), std::abs(r.c22), std::abs(r.c33)});
        EXPECT_LT(std::abs(c.c11 - f * r.c11), 1e-12 * scale) << nu << " " << q << " " << e;
        EXPECT_LT(std::abs(c.c22 - f * r.c22), 1e-12 * scale) << nu << " " << q << " " << e;
        EXPECT_LT(std::abs(c.c33 - f * r.c33), 1e-12 * scale) << nu << " " << q << " " << e;
        EXPECT_LT(std::abs(c.c13 - f * r.c13), 1e-12 * scale) << nu << " " << q << " " << e;
      }
  }
}

// At rest the coating is the elastic coated body, bit for bit.
TEST(ViscoelasticCoating, AtRestItIsTheElasticCoating) {
  const CaseResult ve = solve(kCoated, {"friction.velocity=0"});
  std::string plain = gfmd::testing::without_keys(
      kCoated, {"viscoelastic", "high_frequency_modulus", "relaxation_time", "velocity"});
  const CaseResult el = solve(plain);
  EXPECT_EQ(ve.fields.pressure, el.fields.pressure);
  EXPECT_EQ(ve.observables.hysteresis_dissipation, 0.0);
}

// A nearly rigid substrate (E2* = 1e7 E0*) is the rigid base: the coating then is the homogeneous
// viscoelastic layer, whose modes are the closed form times E0/E(omega) (another code path). The
// pressure to 1e-6 of its peak, the hysteresis friction and the peak tensile stress to 1e-5 (the
// substrate's compliance is 1e-7 of the coating's), at the loss peak; the friction balances (1e-9).
TEST(ViscoelasticCoating, ARigidSubstrateIsTheViscoelasticLayer) {
  const CaseResult coated = solve(kCoated, {"elastic.substrate_contact_modulus=1e7"});
  const std::string plain =
      gfmd::testing::without_keys(kCoated, {"substrate_contact_modulus", "substrate_poisson"});
  const CaseResult layer = solve(plain);
  ASSERT_GT(layer.observables.hysteresis_friction, 1e-3);
  const double peak = max_abs(layer.fields.pressure);
  std::printf(
      "rigid substrate: pressure %.2e of its peak, mu_h %.8g against %.8g, tension %.8g against %.8g\n",
      max_abs_diff(coated.fields.pressure, layer.fields.pressure) / peak,
      coated.observables.hysteresis_friction, layer.observables.hysteresis_friction,
      coated.stress_summary->max_tensile_stress, layer.stress_summary->max_tensile_stress);
  EXPECT_LT(max_abs_diff(coated.fields.pressure, layer.fields.pressure), 1e-6 * peak);
  EXPECT_NEAR(coated.observables.hysteresis_friction / layer.observables.hysteresis_friction, 1.0, 1e-5);
  EXPECT_NEAR(coated.stress_summary->max_tensile_stress / layer.stress_summary->max_tensile_stress, 1.0,
              1e-5);
  EXPECT_LT(coated.observables.hysteresis_balance_error, 1e-9);
}

// On a softer substrate the coating sliding frictionless dissipates what its pressure's asymmetry
// drives (the spectral and the field sums agree to 1e-9) and less than on a rigid base at this
// speed; with Coulomb's law an egg-crate in full contact balances its work to 1e-6, with stick in
// rolling too.
TEST(ViscoelasticCoating, ItBalancesItsWork) {
  const CaseResult soft = solve(kCoated);
  EXPECT_GT(soft.observables.hysteresis_friction, 1e-3);
  EXPECT_LT(soft.observables.hysteresis_balance_error, 1e-9);
  const CaseResult stiff = solve(kCoated, {"elastic.substrate_contact_modulus=1e7"});
  EXPECT_NE(soft.observables.hysteresis_friction, stiff.observables.hysteresis_friction);
  gfmd::testing::expect_work_balances(gfmd::testing::eggcrate_in_full_contact(
      "contact_modulus = 1.0\npoisson = 0.3\nthickness = 0.1\nsubstrate_contact_modulus = 0.5\n"
      "substrate_poisson = 0.45\nlayers = [{contact_modulus = 3.0, poisson = 0.2, thickness = 0.05}]\n"
      "viscoelastic = \"sls\"\nhigh_frequency_modulus = 10.0\nrelaxation_time = 1.0\n",
      "", "velocity = 0.16\n"));
}

// The planes below a moving coating: their stresses come from the transfer matrices at each
// mode's E(omega). On a nearly rigid substrate they are the homogeneous viscoelastic layer's
// (whose stresses from tractions do not depend on E) to 1e-5 of the largest component, in the
// coating and at its bottom; at depth 0 the plane is the surface stress (Hooke's law of the top
// layer at E(omega)) to 5e-3, the Nyquist lines apart.
TEST(ViscoelasticCoating, ItsSubsurfacePlanesFollowEachModesModulus) {
  const CaseResult coated = solve(kCoated, {"elastic.substrate_contact_modulus=1e7"});
  const std::string plain =
      gfmd::testing::without_keys(kCoated, {"substrate_contact_modulus", "substrate_poisson"});
  const CaseResult layer = solve(plain);
  const FFT fft(coated.config.grid);
  for (const double depth : {0.02, 0.05}) {
    const StressField a =
        subsurface_stress(fft, coated.config.elastic, coated.fields, depth, coated.config.visco);
    const StressField b =
        subsurface_stress(fft, layer.config.elastic, layer.fields, depth, layer.config.visco);
    const double d = gfmd::testing::stress_difference(a, b);
    std::printf("depth %.2f: the coating's plane against the layer's %.2e\n", depth, d);
    EXPECT_LT(d, 1e-5) << "depth " << depth;
  }
  const CaseResult soft = solve(kCoated, {"stress.depths=[0.0, 0.03]"});
  ASSERT_EQ(soft.subsurface.size(), 2u);
  EXPECT_LT(gfmd::testing::surface_stress_against_plane(soft).output, 5e-3);
  // The elastic planes (E0 everywhere) are not these: the coating's modulus matters.
  const StressField elastic = subsurface_stress(fft, soft.config.elastic, soft.fields, 0.03);
  const StressField visco = subsurface_stress(fft, soft.config.elastic, soft.fields, 0.03, soft.config.visco);
  EXPECT_GT(max_abs_diff(elastic.xx, visco.xx), 0.01 * max_abs(visco.xx));
}

// elastic.viscoelastic_part = "all": every layer's and the substrate's modulus times the one ratio
// E(omega)/E0, so the transfer matrices with all moduli scaled are the elastic ones times E0/E (to
// 1e-12), and a coating of the substrate's own material is the viscoelastic half-space (the factor
// path; the pressure to 1e-9 of its peak, the hysteresis friction to 1e-8).
TEST(ViscoelasticCoating, ViscoelasticThroughoutIsTheElasticStackTimesTheFactor) {
  ElasticParams stack = homogeneous_body(1.0, 0.3, 0.05);
  stack.layers = {{3.0, 0.2, 0.02}};
  stack.substrate_contact_modulus = 0.5;
  stack.substrate_poisson = 0.45;
  for (const double q : {0.5, 20.0, 300.0})
    for (const std::complex<double> e : {std::polar(2.0, 0.3), std::polar(9.0, 1.2)}) {
      const RotatedCompliance r = layered_compliance(q, stack);
      const ComplexRotatedCompliance c = layered_compliance(q, stack, {e, 3.0 * e, 0.5 * e});
      const std::complex<double> f = 1.0 / e;
      const double scale = std::abs(f) * std::max({std::abs(r.c11), std::abs(r.c22), std::abs(r.c33)});
      EXPECT_LT(std::abs(c.c11 - f * r.c11), 1e-12 * scale) << q << " " << e;
      EXPECT_LT(std::abs(c.c22 - f * r.c22), 1e-12 * scale) << q << " " << e;
      EXPECT_LT(std::abs(c.c33 - f * r.c33), 1e-12 * scale) << q << " " << e;
      EXPECT_LT(std::abs(c.c13 - f * r.c13), 1e-12 * scale) << q << " " << e;
    }
  const CaseResult all =
      solve(kCoated, {"elastic.substrate_contact_modulus=1", "elastic.substrate_poisson=0.3",
                      "elastic.viscoelastic_part=\"all\""});
  const std::string plain =
      gfmd::testing::without_keys(kCoated, {"substrate_contact_modulus", "substrate_poisson", "thickness"});
  const CaseResult half = solve(plain);
  EXPECT_LT(max_abs_diff(all.fields.pressure, half.fields.pressure), 1e-9 * max_abs(half.fields.pressure));
  EXPECT_NEAR(all.observables.hysteresis_friction / half.observables.hysteresis_friction, 1.0, 1e-8);
}

// elastic.viscoelastic_part = "substrate": an elastic coating (a hard film) on a viscoelastic
// substrate (its relaxed modulus substrate_contact_modulus). A film 1e7 times thinner than the
// cell is the viscoelastic half-space of the substrate's material (the hysteresis friction to
// 1e-3: the film's share is first order in q h); a film thicker than 40/q_min hides the substrate
// (no hysteresis); between, an egg-crate in full contact balances its work to 1e-6 sliding and
// rolling with stick, and the surface stress is the plane's at depth 0 (5e-3, the Nyquist lines
// apart); the substrate's planes are given.
TEST(ViscoelasticCoating, AnElasticFilmOnAViscoelasticSubstrate) {
  const std::vector<std::string> substrate{"elastic.viscoelastic_part=\"substrate\"",
                                           "elastic.substrate_contact_modulus=1",
                                           "elastic.substrate_poisson=0.3"};
  const auto with = [&](std::vector<std::string> more) {
    more.insert(more.end(), substrate.begin(), substrate.end());
    return more;
  };
  const CaseResult thin = solve(kCoated, with({"elastic.thickness=2e-7", "elastic.contact_modulus=3"}));
  const std::string plain =
      gfmd::testing::without_keys(kCoated, {"substrate_contact_modulus", "substrate_poisson", "thickness"});
  const CaseResult half = solve(plain);
  std::printf("thin film: mu_h %.6g against the half-space's %.6g\n", thin.observables.hysteresis_friction,
              half.observables.hysteresis_friction);
  EXPECT_NEAR(thin.observables.hysteresis_friction / half.observables.hysteresis_friction, 1.0, 1e-3);
  const CaseResult thick = solve(kCoated, with({"elastic.thickness=15"}));
  EXPECT_LT(std::abs(thick.observables.hysteresis_friction), 1e-12);
  const CaseResult film = solve(kCoated, with({"elastic.contact_modulus=5", "stress.depths=[0.0, 0.1]"}));
  ASSERT_GT(film.observables.hysteresis_friction, 1e-3);
  EXPECT_LT(film.observables.hysteresis_balance_error, 1e-9);
  ASSERT_EQ(film.subsurface.size(), 2u);
  const FFT fft(film.config.grid);
  EXPECT_LT(gfmd::testing::surface_stress_against_plane(film).output, 5e-3);
  gfmd::testing::expect_work_balances(gfmd::testing::eggcrate_in_full_contact(
      "contact_modulus = 5.0\npoisson = 0.3\nthickness = 0.05\nsubstrate_contact_modulus = 1.0\n"
      "substrate_poisson = 0.45\nviscoelastic = \"sls\"\nviscoelastic_part = \"substrate\"\n"
      "high_frequency_modulus = 10.0\nrelaxation_time = 1.0\n",
      "", "velocity = 0.16\n"));
}

// The part's key is checked: a substrate part needs a substrate, the names are three, and the key
// belongs to a viscoelastic body.
TEST(ViscoelasticCoating, ThePartIsChecked) {
  using gfmd::testing::config_problem;
  const std::string homogeneous =
      gfmd::testing::without_keys(kCoated, {"substrate_contact_modulus", "substrate_poisson"});
  EXPECT_NE(config_problem(homogeneous, {"elastic.viscoelastic_part=\"substrate\""})
                .find("elastic.viscoelastic_part"),
            std::string::npos);
  EXPECT_NE(
      config_problem(kCoated, {"elastic.viscoelastic_part=\"middle\""}).find("elastic.viscoelastic_part"),
      std::string::npos);
  EXPECT_NE(config_problem(kCoated, {"elastic.viscoelastic=\"none\"", "elastic.viscoelastic_part=\"all\""})
                .find("elastic.viscoelastic_part"),
            std::string::npos);
  // The substrate's relaxed modulus bounds the glassy one.
  EXPECT_NE(config_problem(
                kCoated, {"elastic.viscoelastic_part=\"substrate\"", "elastic.substrate_contact_modulus=20"})
                .find("high_frequency_modulus"),
            std::string::npos);
  const Config c = parse_config(kCoated, "t.toml", {"elastic.viscoelastic_part=\"substrate\""});
  EXPECT_EQ(c.to_json()["elastic"]["viscoelastic_part"], "substrate");
  EXPECT_FALSE(parse_config(kCoated, "t.toml").to_json()["elastic"].contains("viscoelastic_part"));
}

// elastic.viscoelastic_part = "layers[0]": a viscoelastic interlayer (E0* = 1, E_inf* = 10,
// h = 0.05 R) between an elastic film and an elastic substrate (E2* = 2). Under a film 2e-7 R
// thin it is the viscoelastic coating on that substrate (the "top" part, another path): the
// hysteresis friction to 1e-4; under a film of E* = 5, h = 0.01 R it balances its work on an
// egg-crate sliding and rolling, its surface stress is the plane's at depth 0 (the film's Hooke's
// law, 5e-3, the Nyquist lines apart), and its planes are given; the layer's index is checked.
TEST(ViscoelasticCoating, AViscoelasticInterlayer) {
  const auto interlayer = [](const std::string& film_modulus, const std::string& film_thickness) {
    return std::vector<std::string>{
        "elastic.contact_modulus=" + film_modulus, "elastic.thickness=" + film_thickness,
        "elastic.layers=[{contact_modulus = 1.0, poisson = 0.3, thickness = 0.05}]",
        "elastic.viscoelastic_part=\"layers[0]\""};
  };
  const CaseResult thin = solve(kCoated, interlayer("5", "2e-7"));
  const CaseResult top = solve(kCoated);
  std::printf("under a 2e-7 R film: mu_h %.7g against the coating's %.7g\n",
              thin.observables.hysteresis_friction, top.observables.hysteresis_friction);
  EXPECT_NEAR(thin.observables.hysteresis_friction / top.observables.hysteresis_friction, 1.0, 1e-4);
  std::vector<std::string> planes = interlayer("5", "0.01");
  planes.push_back("stress.depths=[0.0, 0.03]");
  const CaseResult film = solve(kCoated, planes);
  EXPECT_GT(film.observables.hysteresis_friction, 1e-3);
  EXPECT_LT(film.observables.hysteresis_balance_error, 1e-9);
  EXPECT_EQ(film.subsurface.size(), 2u);
  EXPECT_LT(gfmd::testing::surface_stress_against_plane(film).output, 5e-3);
  gfmd::testing::expect_work_balances(gfmd::testing::eggcrate_in_full_contact(
      "contact_modulus = 5.0\npoisson = 0.3\nthickness = 0.01\nsubstrate_contact_modulus = 2.0\n"
      "substrate_poisson = 0.45\nlayers = [{contact_modulus = 1.0, poisson = 0.3, thickness = 0.05}]\n"
      "viscoelastic = \"sls\"\nviscoelastic_part = \"layers[0]\"\nhigh_frequency_modulus = 10.0\n"
      "relaxation_time = 1.0\n",
      "", "velocity = 0.16\n"));
  using gfmd::testing::config_problem;
  std::vector<std::string> beyond = interlayer("5", "0.01");
  beyond.back() = "elastic.viscoelastic_part=\"layers[1]\"";
  EXPECT_NE(config_problem(kCoated, beyond).find("elastic.viscoelastic_part"), std::string::npos);
  std::vector<std::string> bad = interlayer("5", "0.01");
  bad.back() = "elastic.viscoelastic_part=\"layers[x]\"";
  EXPECT_NE(config_problem(kCoated, bad).find("elastic.viscoelastic_part"), std::string::npos);
  const Config c = parse_config(kCoated, "t.toml", interlayer("5", "0.01"));
  EXPECT_EQ(c.to_json()["elastic"]["viscoelastic_part"], "layers[0]");
  // The layer's modulus is the relaxed one the glassy modulus must exceed.
  std::vector<std::string> soft = interlayer("5", "0.01");
  soft[2] = "elastic.layers=[{contact_modulus = 20.0, poisson = 0.3, thickness = 0.05}]";
  EXPECT_NE(config_problem(kCoated, soft).find("high_frequency_modulus"), std::string::npos);
}
