// Several viscoelastic parts of different models in one layered body (elastic.viscoelastic_parts):
// proportional models are the body viscoelastic throughout (another code path), a part whose
// model is elastic is no part, parts of different relaxations balance their work, and the list is
// checked key by key and written back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::config_problem;
using gfmd::testing::max_abs;
using gfmd::testing::max_abs_diff;
using gfmd::testing::solve;

namespace {

// A sphere (R = 1) sliding frictionless over a three-material stack: a coating (E0* = 1, nu = 0.3,
// h = 0.05 R), an interlayer (E0* = 3, nu = 0.2, h = 0.02 R) and a substrate (E0* = 0.5,
// nu = 0.45). The top layer is a standard linear solid (E_inf* = 10, tau = 1); F = 0.005 E0* R^2,
// v0 = 0.1 R/tau (near the loss peak of the contact's modes).
const char* kStack = R"(
[grid]
nx = 128
lx = 2.0
[elastic]
contact_modulus = 1.0
poisson = 0.3
thickness = 0.05
layers = [{contact_modulus = 3.0, poisson = 0.2, thickness = 0.02}]
substrate_contact_modulus = 0.5
substrate_poisson = 0.45
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

// A further part: elastic.viscoelastic_parts with one standard linear solid.
std::string sls_part(const std::string& part, double einf, double tau) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "{viscoelastic = \"sls\", viscoelastic_part = \"%s\", high_frequency_modulus = %.17g, "
                "relaxation_time = %.17g}",
                part.c_str(), einf, tau);
  return buf;
}

}  // namespace

// Every material a standard linear solid of the same ratio E_inf/E0 and time: each modulus is its
// own E0 times the one E(omega)/E0, which is the body viscoelastic throughout
// (elastic.viscoelastic_part = "all", whose modes are the elastic ones times the factor: another
// code path). Three parts of three models against "all": the pressure to 1e-9 of its peak, the
// hysteresis friction and the peak tensile stress to 1e-8, the planes in the coating (0.03) and in
// the substrate (0.1) to 1e-8 of their largest stress.
TEST(ViscoelasticParts, ProportionalPartsAreTheBodyViscoelasticThroughout) {
  const std::string parts = "elastic.viscoelastic_parts=[" + sls_part("layers[0]", 30.0, 1.0) + ", " +
                            sls_part("substrate", 5.0, 1.0) + "]";
  const CaseResult three = solve(kStack, {parts, "stress.depths=[0.03, 0.1]"});
  const CaseResult all = solve(kStack, {"elastic.viscoelastic_part=\"all\"", "stress.depths=[0.03, 0.1]"});
  ASSERT_GT(all.observables.hysteresis_friction, 1e-3);
  const double peak = max_abs(all.fields.pressure);
  std::printf("three parts against \"all\": pressure %.2e of its peak, mu_h %.12g against %.12g\n",
              max_abs_diff(three.fields.pressure, all.fields.pressure) / peak,
              three.observables.hysteresis_friction, all.observables.hysteresis_friction);
  EXPECT_LT(max_abs_diff(three.fields.pressure, all.fields.pressure), 1e-9 * peak);
  EXPECT_NEAR(three.observables.hysteresis_friction / all.observables.hysteresis_friction, 1.0, 1e-8);
  EXPECT_NEAR(three.stress_summary->max_tensile_stress / all.stress_summary->max_tensile_stress, 1.0, 1e-8);
  EXPECT_LT(three.observables.hysteresis_balance_error, 1e-9);
  ASSERT_EQ(three.subsurface.size(), 2u);
  ASSERT_EQ(all.subsurface.size(), 2u);
  const FFT fft(all.config.grid);
  for (const double depth : {0.03, 0.1}) {
    const StressField a =
        subsurface_stress(fft, three.config.elastic, three.fields, depth, three.config.visco);
    const StressField b = subsurface_stress(fft, all.config.elastic, all.fields, depth, all.config.visco);
    std::printf("depth %.2f: the three parts' plane against \"all\"'s %.2e\n", depth,
                gfmd::testing::stress_difference(a, b));
    EXPECT_LT(gfmd::testing::stress_difference(a, b), 1e-8) << "depth " << depth;
  }
  // Not proportional (the substrate relaxing 100 times slower), the body is another.
  const CaseResult slow = solve(kStack, {"elastic.viscoelastic_parts=[" + sls_part("layers[0]", 30.0, 1.0) +
                                         ", " + sls_part("substrate", 5.0, 100.0) + "]"});
  EXPECT_GT(std::abs(slow.observables.hysteresis_friction / all.observables.hysteresis_friction - 1.0), 1e-3);
}

// A further part whose glassy modulus is its relaxed one (E_inf = E0) is elastic at every
// frequency: the body is the one-part body, bit for bit.
TEST(ViscoelasticParts, AnElasticPartIsNoPart) {
  const CaseResult two =
      solve(kStack, {"elastic.viscoelastic_parts=[" + sls_part("substrate", 0.5, 3.0) + "]"});
  const CaseResult one = solve(kStack);
  EXPECT_EQ(two.fields.pressure, one.fields.pressure);
  EXPECT_EQ(two.observables.hysteresis_friction, one.observables.hysteresis_friction);
}

// An elastic film over two viscoelastic parts of different relaxations (an interlayer and the
// substrate): the hysteresis from the fields and from the spectrum agree (1e-9) sliding
// frictionless; on an egg-crate in full contact with Coulomb's law the work balances (1e-6),
// sliding and rolling with stick; the surface stress is the plane's at depth 0 (5e-3, the Nyquist
// lines apart). Either part alone has another hysteresis than both.
TEST(ViscoelasticParts, TwoRelaxationsBalanceTheirWork) {
  const std::vector<std::string> two{
      "elastic.viscoelastic_part=\"layers[0]\"", "elastic.contact_modulus=5", "elastic.thickness=0.01",
      "elastic.viscoelastic_parts=[" + sls_part("substrate", 5.0, 30.0) + "]", "stress.depths=[0.0, 0.05]"};
  const CaseResult both = solve(kStack, two);
  EXPECT_LT(both.observables.hysteresis_balance_error, 1e-9);
  EXPECT_LT(gfmd::testing::surface_stress_against_plane(both).output, 5e-3);
  std::vector<std::string> layer_only(two.begin(), two.end());
  layer_only.erase(layer_only.begin() + 3);
  const CaseResult layer = solve(kStack, layer_only);
  std::vector<std::string> substrate_only{"elastic.viscoelastic_part=\"substrate\"",
                                          "elastic.contact_modulus=5", "elastic.thickness=0.01",
                                          "elastic.high_frequency_modulus=5", "elastic.relaxation_time=30"};
  const CaseResult substrate = solve(kStack, substrate_only);
  std::printf("mu_h: both %.6g, the interlayer alone %.6g, the substrate alone %.6g\n",
              both.observables.hysteresis_friction, layer.observables.hysteresis_friction,
              substrate.observables.hysteresis_friction);
  EXPECT_GT(layer.observables.hysteresis_friction, 1e-4);
  EXPECT_GT(substrate.observables.hysteresis_friction, 1e-4);
  // Each part's relaxation matters (the other's stiffening at speed may raise or lower the
  // hysteresis: no sign is asserted).
  EXPECT_GT(std::abs(both.observables.hysteresis_friction / layer.observables.hysteresis_friction - 1.0),
            1e-2);
  EXPECT_GT(std::abs(both.observables.hysteresis_friction / substrate.observables.hysteresis_friction - 1.0),
            1e-2);
  gfmd::testing::expect_work_balances(gfmd::testing::eggcrate_in_full_contact(
      "contact_modulus = 5.0\npoisson = 0.3\nthickness = 0.01\nsubstrate_contact_modulus = 0.5\n"
      "substrate_poisson = 0.45\nlayers = [{contact_modulus = 1.0, poisson = 0.3, thickness = 0.05}]\n"
      "viscoelastic = \"sls\"\nviscoelastic_part = \"layers[0]\"\nhigh_frequency_modulus = 10.0\n"
      "relaxation_time = 1.0\nviscoelastic_parts = [" +
          sls_part("substrate", 5.0, 30.0) + "]\n",
      "", "velocity = 0.16\n"));
}

// examples/visco_two_parts_sphere.toml: a coating (tau = 1) on a substrate relaxing a thousand
// times slower (tau = 1000). Its hysteresis friction over speed has two peaks: near v0 = 1e-5 the
// substrate's (70 times the coating's own there, examples/visco_coated_sphere.toml), then a
// valley near 1e-4, then the coating's near 1e-2.
TEST(ViscoelasticParts, TheTwoPartsExampleHasTwoPeaks) {
  const std::string dir = std::string(GFMD_SOURCE_DIR) + "/examples/";
  const auto mu_h = [&](const char* name, const char* v) {
    const Config c = load_config(dir + name, {std::string("friction.velocity=") + v, "output.fields=false",
                                              "output.png=false", "stress.depths=[]"});
    const CaseResult r = run_case(c);
    EXPECT_TRUE(r.info.converged) << name << " " << v << ": " << r.info.status;
    return r.observables.hysteresis_friction;
  };
  const double slow = mu_h("visco_two_parts_sphere.toml", "1e-5");
  const double valley = mu_h("visco_two_parts_sphere.toml", "1e-4");
  const double fast = mu_h("visco_two_parts_sphere.toml", "1e-2");
  std::printf("mu_h at v0 = 1e-5, 1e-4, 1e-2: %.4g, %.4g, %.4g\n", slow, valley, fast);
  EXPECT_GT(slow, 2.0 * valley);
  EXPECT_GT(fast, 2.0 * valley);
  EXPECT_GT(slow, 10.0 * mu_h("visco_coated_sphere.toml", "1e-5"));
}

// The list is checked key by key (the message names elastic.viscoelastic_parts[i].<key>) and
// written back into the case's record, which reads as the same case.
TEST(ViscoelasticParts, TheListIsCheckedAndRecorded) {
  const auto problem = [](const std::vector<std::string>& sets) { return config_problem(kStack, sets); };
  const auto names = [](const std::string& message, const std::string& key) {
    return message.find(key) != std::string::npos;
  };
  // Two models for one part; "all" with company; no first part; a part without its name.
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[" + sls_part("top", 10.0, 2.0) + "]"}),
                    "elastic.viscoelastic_parts[0].viscoelastic_part"));
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[" + sls_part("substrate", 5.0, 2.0) + ", " +
                             sls_part("substrate", 6.0, 2.0) + "]"}),
                    "elastic.viscoelastic_parts[1].viscoelastic_part"));
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_part=\"all\"",
                             "elastic.viscoelastic_parts=[" + sls_part("substrate", 5.0, 2.0) + "]"}),
                    "elastic.viscoelastic_part"));
  const std::string elastic = gfmd::testing::without_keys(
      kStack, {"viscoelastic", "high_frequency_modulus", "relaxation_time", "velocity"});
  EXPECT_TRUE(
      names(config_problem(elastic, {"elastic.viscoelastic_parts=[" + sls_part("substrate", 5.0, 2.0) + "]"}),
            "elastic.viscoelastic_parts: further viscoelastic parts need a first one"));
  EXPECT_TRUE(
      names(problem({"elastic.viscoelastic_parts=[{viscoelastic = \"sls\", high_frequency_modulus = 5.0, "
                     "relaxation_time = 1.0}]"}),
            "elastic.viscoelastic_parts[0].viscoelastic_part: is needed"));
  // Its model's keys: a glassy modulus below the part's relaxed one, a missing time, an unknown
  // key, a model's key for another model, a layer the body lacks, not an array of tables.
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[" + sls_part("substrate", 0.4, 2.0) + "]"}),
                    "elastic.viscoelastic_parts[0].high_frequency_modulus"));
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[{viscoelastic = \"sls\", viscoelastic_part = "
                             "\"substrate\", high_frequency_modulus = 5.0}]"}),
                    "elastic.viscoelastic_parts[0].relaxation_time"));
  EXPECT_TRUE(
      names(problem({"elastic.viscoelastic_parts=[{viscoelastic = \"sls\", viscoelastic_part = "
                     "\"substrate\", high_frequency_modulus = 5.0, relaxation_time = 1.0, tau = 2}]"}),
            "elastic.viscoelastic_parts[0].tau: unknown key"));
  EXPECT_TRUE(
      names(problem({"elastic.viscoelastic_parts=[{viscoelastic = \"sls\", viscoelastic_part = "
                     "\"substrate\", high_frequency_modulus = 5.0, relaxation_time = 1.0, prony_times = "
                     "[1.0]}]"}),
            "elastic.viscoelastic_parts[0].prony_times"));
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[" + sls_part("layers[1]", 30.0, 2.0) + "]"}),
                    "elastic.viscoelastic_parts[0].viscoelastic_part"));
  // A misspelt part is one problem: its default (the top) is not also reported as taken.
  const std::string misspelt =
      problem({"elastic.viscoelastic_parts=[" + sls_part("Substrate", 5.0, 2.0) + "]"});
  EXPECT_TRUE(names(misspelt, "1 problem in the case")) << misspelt;
  EXPECT_FALSE(names(misspelt, "already names")) << misspelt;
  // A part's problem found by the body's check names where it was given (the override here).
  const std::string negative =
      problem({"elastic.viscoelastic_parts=[" + sls_part("substrate", 5.0, -2.0) + "]"});
  EXPECT_TRUE(names(negative, "elastic.viscoelastic_parts[0].relaxation_time")) << negative;
  EXPECT_TRUE(names(negative, "[--set elastic.viscoelastic_parts=[")) << negative;
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=3"}), "elastic.viscoelastic_parts"));
  EXPECT_TRUE(names(problem({"elastic.viscoelastic_parts=[3]"}), "elastic.viscoelastic_parts[0]"));
  // A Prony series beside the standard linear solid, recorded and read back as the same case.
  const std::string prony =
      "elastic.viscoelastic_parts=[{viscoelastic = \"prony\", viscoelastic_part = \"substrate\", "
      "prony_moduli = "
      "[1.0, 2.0], prony_times = [0.5, 5.0]}, " +
      sls_part("layers[0]", 30.0, 2.0) + "]";
  const Config c = parse_config(kStack, "t.toml", {prony});
  ASSERT_EQ(c.visco.further.size(), 2u);
  EXPECT_EQ(c.visco.parts().size(), 3u);
  EXPECT_EQ(c.visco.parts()[1].velocity, c.visco.velocity);
  const nlohmann::json j = c.to_json();
  ASSERT_EQ(j["elastic"]["viscoelastic_parts"].size(), 2u);
  EXPECT_EQ(j["elastic"]["viscoelastic_parts"][0]["viscoelastic_part"], "substrate");
  EXPECT_EQ(j["elastic"]["viscoelastic_parts"][0]["viscoelastic"], "prony");
  EXPECT_EQ(j["elastic"]["viscoelastic_parts"][1]["viscoelastic_part"], "layers[0]");
  EXPECT_EQ(j["elastic"]["viscoelastic_parts"][1]["relaxation_time"], 2.0);
  EXPECT_EQ(config_from_tables(j, "again").to_json(), j);
  // A part given in the body itself: ElasticBody checks it too, naming the list's key.
  ViscoelasticParams v = c.visco;
  v.further[0].prony_times = {0.5, -1.0};
  try {
    const ElasticBody body(c.grid, c.elastic, v);
    ADD_FAILURE() << "a negative relaxation time was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.where(), "viscoelastic_parts[0].prony_times");
  }
}
