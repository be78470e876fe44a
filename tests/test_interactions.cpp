// Interaction models as registered parts (contact/interaction.hpp): every model is read from a
// case and written back through the registry, its keys checked by key, its backends named.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/contact/interaction.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

const char* kCase = R"(
[grid]
nx = 32
lx = 1.0
[indenter]
type = "hertz"
radius = 1.0
[load]
approach = 0.001
)";

std::string problem(const std::vector<std::string>& sets) {
  return gfmd::testing::config_problem(kCase, sets);
}

}  // namespace

TEST(Interactions, EveryModelIsReadAndWrittenBackThroughTheRegistry) {
  ASSERT_GE(interaction_types().size(), 3u);
  for (const InteractionType* t : interaction_types()) {
    std::vector<std::string> sets = {"interaction.model=\"" + t->name + "\""};
    // Its own keys at values its checks accept (1e-4, 1e-3, ...), distinct per key.
    double v = 1e-4;
    for (const InteractionType::Key& k : t->keys) {
      sets.push_back("interaction." + k.name + "=" + std::to_string(v));
      v *= 10;
    }
    const Config c = parse_config(kCase, "t.toml", sets);
    EXPECT_EQ(&interaction_type(c.interaction), t) << t->name;
    EXPECT_EQ(c.interaction.hard_wall, t->hard_wall) << t->name;
    const nlohmann::json j = c.to_json()["interaction"];
    EXPECT_EQ(j["model"], t->name);
    EXPECT_EQ(j.contains("repulsion"), t->repulsion_key) << t->name;
    v = 1e-4;
    for (const InteractionType::Key& k : t->keys) {
      EXPECT_DOUBLE_EQ(j[k.name].get<double>(), v) << t->name << "." << k.name;
      v *= 10;
    }
    // Written back, the case reads as the same parameters.
    const Config again = parse_config(c.to_toml(), "again.toml");
    EXPECT_EQ(&interaction_type(again.interaction), t) << t->name;
    for (const InteractionType::Key& k : t->keys)
      EXPECT_EQ(again.interaction.*k.member, c.interaction.*k.member) << t->name << "." << k.name;
    // A model the device lacks is refused there by name.
    const auto [key, why] = device_lacks(c.interaction, FrictionParams{}, false, false);
    EXPECT_EQ(key.empty(), t->on_device) << t->name;
    if (!t->on_device) {
      EXPECT_NE(why.find("\"" + t->name + "\""), std::string::npos) << why;
    }
    // With Coulomb friction too (the device's friction law).
    FrictionParams sliding;
    sliding.coefficient = 0.3;
    EXPECT_EQ(device_lacks(c.interaction, sliding, false, false).first.empty(), t->on_device) << t->name;
  }
}

TEST(Interactions, NamesAndKeysComeFromTheRegistry) {
  // An unknown model lists every registered one, with a guess.
  std::string list;
  for (const InteractionType* t : interaction_types()) list += (list.empty() ? "" : ", ") + t->name;
  const std::string e = problem({"interaction.model=\"adhesiv\""});
  EXPECT_NE(e.find("interaction.model: unknown model \"adhesiv\" (did you mean 'adhesive'?); one of " + list),
            std::string::npos)
      << e;
  // The old spelling of the hard wall.
  EXPECT_TRUE(parse_config(kCase, "t.toml", {"interaction.model=\"hard_wall\""}).interaction.hard_wall);
  // A model's keys belong to it; a repulsion is a model without keys of its own.
  // A key of another model names that model (not "unknown key"): the model is what is missing.
  EXPECT_NE(
      problem({"interaction.range=0.01"})
          .find(
              "interaction.range: belongs to interaction.model = \"adhesive\" (this case's is \"harmonic\")"),
      std::string::npos)
      << problem({"interaction.range=0.01"});
  EXPECT_NE(problem({"interaction.rnage=0.01"}).find("interaction.rnage: unknown key"), std::string::npos);
  // The harmonic repulsion's stiffness under a hard wall was ignored without a word; 0 (the
  // written default) stays accepted there.
  EXPECT_NE(problem({"interaction.model=\"hardwall\"", "interaction.stiffness=10"})
                .find("interaction.stiffness: belongs to the harmonic repulsion"),
            std::string::npos)
      << problem({"interaction.model=\"hardwall\"", "interaction.stiffness=10"});
  EXPECT_EQ(problem({"interaction.model=\"hardwall\"", "interaction.stiffness=0"}), "");
  EXPECT_EQ(problem({"interaction.stiffness=10"}), "");
  EXPECT_NE(problem({"interaction.model=\"adhesive\"", "interaction.work_of_adhesion=1e-3",
                     "interaction.range=0.01", "interaction.repulsion=\"adhesive\""})
                .find("interaction.repulsion: unknown repulsion \"adhesive\"; one of harmonic, hardwall"),
            std::string::npos);
  // The adhesive model on the harmonic repulsion, and without adhesion written as its repulsion.
  const Config h = parse_config(kCase, "t.toml",
                                {"interaction.model=\"adhesive\"", "interaction.work_of_adhesion=1e-3",
                                 "interaction.range=0.01", "interaction.repulsion=\"harmonic\""});
  EXPECT_FALSE(h.interaction.hard_wall);
  EXPECT_EQ(h.to_json()["interaction"]["repulsion"], "harmonic");
  const Config none = parse_config(
      kCase, "t.toml",
      {"interaction.model=\"adhesive\"", "interaction.work_of_adhesion=0", "interaction.range=0.01"});
  EXPECT_EQ(none.to_json()["interaction"]["model"], "hardwall");
}
