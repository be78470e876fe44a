// What follows from a viscoelastic solve: the leakage through its deformed gap, and its stresses
// (from the tractions, not E0 times its strains).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/contact/observables.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/stress.hpp"
#include "gfmd/elastic/viscoelastic.hpp"
#include "gfmd/surface/topography.hpp"
#include "test_util.hpp"
#include "visco_util.hpp"

using namespace gfmd;
using namespace gfmd::testing::visco;

// Leakage through a sliding seal's viscoelastic gap: at rest it is the elastic case's (the same
// gap bit for bit); fast sliding stiffens the body, the contact shrinks and the seal leaks more
// (measured on a rough layer, 256^2: flow factor 0.808 at rest, 0.860 glassy).
TEST(Viscoelastic, LeakageFollowsTheDeformedGap) {
  const std::string rough = R"(
[grid]
nx = 64
lx = 1.0
[elastic]
poisson = 0.49
thickness = 0.1
viscoelastic = "sls"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 0.5
lambda_short = 0.0625
rms_height = 0.005
seed = 3
[load]
pressure = 0.002
[flow]
enabled = true
direction = "x"
[output]
analysis = false
)";
  const std::string elastic_text =
      gfmd::testing::without_keys(rough, {"viscoelastic", "high_frequency_modulus", "relaxation_time"});
  const CaseResult elastic = gfmd::testing::solve(elastic_text);
  const CaseResult rest = gfmd::testing::solve(rough, {"friction.velocity=0"});
  const CaseResult fast = gfmd::testing::solve(rough, {"friction.velocity=1e3"});
  ASSERT_TRUE(elastic.leakage && rest.leakage && fast.leakage);
  EXPECT_EQ(rest.fields.gap, elastic.fields.gap);
  const double k_el = elastic.leakage->flows.at(0).flow_factor,
               k_rest = rest.leakage->flows.at(0).flow_factor;
  const double k_fast = fast.leakage->flows.at(0).flow_factor;
  EXPECT_EQ(k_rest, k_el);
  EXPECT_LT(fast.observables.relative_contact_area, rest.observables.relative_contact_area);
  EXPECT_GT(k_fast, k_rest);
  EXPECT_TRUE(rest.leakage->flows.at(0).percolates);
}

namespace {
// A cylinder (R = 1, along y: every mode but the mean varies along x) on a nu = 0.3 standard
// linear solid, frictionless, at 0.005 E0* mean pressure.
const char* kCylinder = R"(
[grid]
nx = 128
ny = 8
lx = 2.0
ly = 0.125
[elastic]
poisson = 0.3
viscoelastic = "sls"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[indenter]
type = "cylinder"
radius = 1.0
[load]
pressure = 0.005
[interaction]
model = "hardwall"
[friction]
velocity = 1e9
[solver]
tolerance = 1e-10
[output]
analysis = false
)";

}  // namespace

// A viscoelastic body's stresses follow from its tractions alone (nu constant: each mode's
// E(omega) times its displacement is E0 times the elastic one), not from E0 times its
// displacement (10x too small at the glassy end before 2026-11-28). Sliding fast, the cylinder's
// surface stress is the elastic E_inf solve's (to 1e-9 of its largest component); near the loss
// peak it equals the stress of the plane at depth 0 from the tractions (subsurface_stress, another
// code path: to 5e-3 of the largest component, measured 1.7e-3, the Nyquist lines apart: that
// path keeps their even part; the old reading is off by more than 5 %).
TEST(Viscoelastic, ItsSurfaceStressIsThatOfItsTractions) {
  const CaseResult fast = gfmd::testing::solve(kCylinder);
  ASSERT_TRUE(fast.stress_summary);
  ASSERT_FALSE(fast.stress.xx.empty());
  std::string plain = gfmd::testing::without_keys(
      kCylinder, {"viscoelastic", "high_frequency_modulus", "relaxation_time", "velocity"});
  plain.replace(plain.find("poisson = 0.3"), 13, "poisson = 0.3\ncontact_modulus = 10.0");
  const CaseResult el = gfmd::testing::solve(plain);
  ASSERT_TRUE(el.stress_summary);
  const double big = gfmd::testing::max_abs(el.stress.xx);
  for (const auto& [a, b] :
       {std::pair{&fast.stress.xx, &el.stress.xx}, std::pair{&fast.stress.yy, &el.stress.yy},
        std::pair{&fast.stress.zz, &el.stress.zz}}) {
    double d = 0.0;
    for (std::size_t i = 0; i < a->size(); ++i) d = std::max(d, std::abs((*a)[i] - (*b)[i]));
    EXPECT_LT(d, 1e-9 * big);
  }
  EXPECT_NEAR(fast.stress_summary->max_tensile_stress / el.stress_summary->max_tensile_stress, 1.0, 1e-9);
  // The post-analyses (Coulomb's traction added to the frictionless solution) too, both kinds:
  // from the tractions, not from the viscoelastic displacement.
  const std::vector<std::string> post{"friction.coefficient=0.3", "friction.regularization=0.01",
                                      "stress.post_analysis=[\"consistent\", \"paper\"]"};
  const CaseResult fast_post = gfmd::testing::solve(kCylinder, post);
  const CaseResult el_post = gfmd::testing::solve(plain, post);
  ASSERT_EQ(fast_post.post_analyses.size(), 2u);
  ASSERT_EQ(el_post.post_analyses.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_NEAR(fast_post.post_analyses[k].summary.max_tensile_stress /
                    el_post.post_analyses[k].summary.max_tensile_stress,
                1.0, 1e-6)
        << fast_post.post_analyses[k].kind;
  // Near the loss peak (omega tau = 1 at the contact's half-width 0.04 R): against the plane.
  const CaseResult peak = gfmd::testing::solve(kCylinder, {"friction.velocity=0.04"});
  ASSERT_GT(peak.observables.hysteresis_friction, 1e-3);
  const gfmd::testing::AgainstPlane d = gfmd::testing::surface_stress_against_plane(peak);
  EXPECT_LT(d.output, 5e-3);
  EXPECT_GT(d.hooke_on_solved, 0.05);  // E0 times the viscoelastic strains
}
