// The keys of the kinds of body (elastic/body.hpp's BodyKey) are read and written by the case
// files from the registry: each key of each kind, set in [elastic] and in [indenter_body], selects
// its kind, is written back and reads back to the same case (also for an elastic indenter, whose
// keys are [indenter]'s); a key that needs another is refused alone, naming both.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/body.hpp"

namespace {

using namespace gfmd;

// A value of the key other than its default, as TOML text (with what it needs).
std::string setting(const BodyKey& k) {
  switch (k.kind) {
    case BodyKey::Kind::Number:
    case BodyKey::Kind::NumberOrInf: {
      std::string line =
          k.name + " = " + std::to_string(std::isfinite(k.default_value) ? k.default_value + 0.125 : 7.5);
      if (!k.needs.empty()) line += "\n" + k.needs + " = 5.0";
      return line;
    }
    case BodyKey::Kind::Layers:
      return k.name + " = [{contact_modulus = 3.0, poisson = 0.2, thickness = 0.05}]";
  }
  return "";
}

// elastic_keys in [elastic] (a layer of thickness 0.1); indenter_keys in [indenter].
std::string case_text(const std::string& elastic_keys, const std::string& indenter_keys = "") {
  return "[grid]\nnx = 32\nlx = 1.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n" + indenter_keys +
         "\n[load]\nforce = 0.01\n[elastic]\nthickness = 0.1\n" + elastic_keys + "\n";
}

const BodyType& owner(const BodyKey& key) {
  for (const BodyType* t : body_types())
    for (const BodyKey& k : t->keys)
      if (k.name == key.name) return *t;
  throw std::logic_error("no kind owns " + key.name);
}

TEST(BodyKeys, EachKeyOfEachKindIsReadWrittenAndReadBack) {
  ASSERT_FALSE(body_keys().empty());
  for (const BodyKey* k : body_keys()) {
    SCOPED_TRACE(k->name);
    const Config c = parse_config(case_text(setting(*k)), "case.toml");
    EXPECT_EQ(body_type_of(c.elastic).name, owner(*k).name);
    const nlohmann::json j = c.to_json();
    ASSERT_TRUE(j["elastic"].contains(k->name)) << j["elastic"].dump();
    if (k->member != nullptr) {
      EXPECT_NE(c.elastic.*(k->member), k->default_value);
      EXPECT_EQ(j["elastic"][k->name].get<double>(), c.elastic.*(k->member));
    }
    // Written as TOML and read again: the same case.
    EXPECT_EQ(parse_config(c.to_toml(), "again.toml").to_json(), j);
    // The defaults are not written where the kind says so (a rigid base has no substrate keys).
    const Config plain = parse_config(case_text(""), "plain.toml");
    if (k->written != nullptr && !k->written(plain.elastic)) {
      EXPECT_FALSE(plain.to_json()["elastic"].contains(k->name));
    }
  }
}

TEST(BodyKeys, AnElasticIndenterTakesTheSameKeys) {
  for (const BodyKey* k : body_keys()) {
    SCOPED_TRACE(k->name);
    const Config c =
        parse_config(case_text("", "contact_modulus = 2.0\nthickness = 0.2\n" + setting(*k)), "case.toml");
    ASSERT_TRUE(c.indenter.body.has_value());
    EXPECT_EQ(body_type_of(*c.indenter.body).name, owner(*k).name);
    EXPECT_TRUE(c.to_json()["indenter"].contains(k->name)) << c.to_json()["indenter"].dump();
    EXPECT_EQ(parse_config(c.to_toml(), "again.toml").to_json(), c.to_json());
    // On a rigid indenter (no contact_modulus) the key is refused, naming it.
    try {
      (void)parse_config(case_text("", setting(*k)), "case.toml");
      ADD_FAILURE() << "accepted on a rigid indenter";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("indenter." + k->name), std::string::npos) << e.what();
    }
  }
}

TEST(BodyKeys, AKeyThatNeedsAnotherIsRefusedAloneNamingBoth) {
  int checked = 0;
  for (const BodyKey* k : body_keys()) {
    if (k->needs.empty()) continue;
    ++checked;
    try {
      (void)parse_config(case_text(k->name + " = 0.3"), "case.toml");
      ADD_FAILURE() << k->name << " alone was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("elastic." + k->name), std::string::npos) << what;
      EXPECT_NE(what.find(k->needs), std::string::npos) << what;
    }
  }
  EXPECT_GT(checked, 0);  // substrate_poisson needs substrate_contact_modulus
}

}  // namespace

namespace {

// Config::to_toml (fields.nc's input_toml, Python's Result.toml) is TOML that reads back to the
// same case for every example: arrays of tables (layers, viscoelastic parts) inline, strings
// escaped. (Until 2026-11-28 a layer was written as a JSON object, which no TOML reader takes.)
TEST(ConfigOut, TheTomlOfEveryExampleReadsBackToTheSameCase) {
  namespace fs = std::filesystem;
  int read = 0, with_tables = 0;
  for (const auto& e : fs::directory_iterator(fs::path(GFMD_SOURCE_DIR) / "examples")) {
    if (e.path().extension() != ".toml") continue;
    SCOPED_TRACE(e.path().filename().string());
    const Config c = load_config(e.path().string(), {});
    const std::string text = c.to_toml();
    // Read from the example's folder, where its relative paths (height files, master curves) lie.
    const Config again = parse_config(text, e.path().string());
    EXPECT_EQ(again.to_json(), c.to_json());
    ++read;
    with_tables += text.find("= [{") != std::string::npos ? 1 : 0;
  }
  EXPECT_GT(read, 20);
  EXPECT_GT(with_tables, 0);  // some example has layers or viscoelastic parts
}

TEST(ConfigOut, StringsAreEscaped) {
  Config c = parse_config(case_text(""), "case.toml");
  c.length_unit = "a \"quoted\" \\ unit\nwith a line";
  const std::string text = c.to_toml();
  EXPECT_NE(text.find(R"(unit = "a \"quoted\" \\ unit\nwith a line")"), std::string::npos) << text;
}

}  // namespace
