// Bad input on a viscoelastic body names the key, and a solve that does not settle says why.
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

// Bad input names the key.
TEST(Viscoelastic, BadInputNamesTheKey) {
  const std::string& base = kSlsSphere;
  const auto problem = [&](const std::vector<std::string>& sets) {
    return gfmd::testing::config_problem(base, sets);
  };
  EXPECT_EQ(problem({}), "");
  EXPECT_NE(problem({"elastic.high_frequency_modulus=0.5"}).find("elastic.high_frequency_modulus"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.relaxation_time=0"}).find("elastic.relaxation_time"), std::string::npos);
  EXPECT_NE(problem({"friction.velocity=-1"}).find("friction.velocity"), std::string::npos);
  EXPECT_NE(problem({"elastic.viscoelastic=\"none\""}).find("belongs to elastic.viscoelastic"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.viscoelastic=\"maxwell\""}).find("elastic.viscoelastic"), std::string::npos);
  EXPECT_NE(problem({"elastic.viscoelastic=\"prony\""}).find("elastic.prony_moduli"), std::string::npos);
  EXPECT_EQ(problem({"friction.coefficient=0.3"}), "");  // the set-valued law: test_viscoelastic_stick.cpp
  EXPECT_EQ(problem({"friction.coefficient=0.3", "friction.regularization=0.01"}), "");
  EXPECT_EQ(problem({"interaction.hardness=0.5"}),
            "");  // plastic saturation: tests/python/test_viscoelastic.py
  // A Prony series whose times do not match its moduli (no speed).
  const std::string prony =
      gfmd::testing::without_keys(kSlsSphere, {"high_frequency_modulus", "relaxation_time", "velocity"});
  const std::vector<std::string> prony_sets = {
      "elastic.viscoelastic=\"prony\"", "elastic.prony_moduli=[1.0, 2.0]", "elastic.prony_times=[0.1]"};
  EXPECT_NE(gfmd::testing::config_problem(prony, prony_sets).find("elastic.prony_times"), std::string::npos);
  // A speed with an elastic body.
  const std::string elastic =
      gfmd::testing::without_keys(kSlsSphere, {"viscoelastic", "high_frequency_modulus", "relaxation_time"});
  EXPECT_NE(gfmd::testing::config_problem(elastic, {"friction.velocity=1.0"})
                .find("friction.velocity: a sliding speed needs a viscoelastic body"),
            std::string::npos);
}

// A solve on a viscoelastic body that stops says why its last viscoelastic solve did not settle,
// in the friction loop and in the adhesive steps alike (the text was dropped before 2026-11-28),
// and so does the active set (the frictionless default) on its own.
TEST(Viscoelastic, AFailureSaysWhyTheViscoelasticSolveDidNotSettle) {
  const std::vector<std::string> common = {"grid.nx=64", "elastic.poisson=0.5", "friction.velocity=0.02",
                                           "friction.reference=false", "solver.max_outer=3"};
  const std::string last = "; the last viscoelastic solve: not converged: ";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"friction.coefficient=0.3", "friction.regularization=0.01"},
       last + "the viscoelastic pressure did not settle in solver.max_outer = 3 steps"},
      {{"interaction.model=\"adhesive\"", "interaction.work_of_adhesion=1e-3", "interaction.range=0.02",
        "solver.viscoelastic_method=\"splitting\""},
       last + "the viscoelastic pressure did not settle in solver.max_outer = 3 steps"},
      {{"solver.max_outer=1"},
       "not converged: the viscoelastic contact set did not settle in solver.max_outer = 1 "
       "steps"}};
  for (const auto& [sets, what] : cases) {
    std::vector<std::string> all = common;
    all.insert(all.end(), sets.begin(), sets.end());
    const CaseResult r = run_case(parse_config(kSlsSphere, "visco.toml", all));
    EXPECT_FALSE(r.info.converged);
    EXPECT_NE(r.info.status.find(what), std::string::npos) << r.info.status;
  }
}

// A stiff glassy modulus (E_inf = 1000 E0) near the loss peak with the hard wall: the splitting
// cycles (the contact edge's cells switch between contact and gap; docs/solver.md). The failure
// says so and names what settles instead of suggesting more steps, and both do settle: the
// active set (the default without friction) and the harmonic interaction, on the same case.
TEST(Viscoelastic, AHardWallThatCyclesNamesTheHarmonicInteraction) {
  const std::vector<std::string> sets = {"grid.nx=128",
                                         "grid.lx=4.0",
                                         "elastic.poisson=0.5",
                                         "elastic.high_frequency_modulus=1000",
                                         "friction.velocity=1e-4",
                                         "load.force=0.01",
                                         "solver.max_outer=100"};
  std::vector<std::string> hard = sets;
  hard.push_back("interaction.model=\"hardwall\"");
  std::vector<std::string> split = hard;
  split.push_back("solver.viscoelastic_method=\"splitting\"");
  const CaseResult r = run_case(parse_config(kSlsSphere, "visco.toml", split));
  EXPECT_FALSE(r.info.converged);
  EXPECT_NE(r.info.status.find("the active set (solver.viscoelastic_method = \"active_set\") or the harmonic "
                               "interaction (interaction.model = \"harmonic\") settles there"),
            std::string::npos)
      << r.info.status;
  EXPECT_EQ(r.info.status.find("raise solver.max_outer"), std::string::npos) << r.info.status;
  const CaseResult a = run_case(parse_config(kSlsSphere, "visco.toml", hard));
  EXPECT_TRUE(a.info.converged) << a.info.status;
  EXPECT_GT(a.observables.hysteresis_friction, 0.01);
  std::vector<std::string> soft = sets;
  soft.push_back("interaction.model=\"harmonic\"");
  const CaseResult h = run_case(parse_config(kSlsSphere, "visco.toml", soft));
  EXPECT_TRUE(h.info.converged) << h.info.status;
  EXPECT_GT(h.observables.hysteresis_friction, 0.01);
}
