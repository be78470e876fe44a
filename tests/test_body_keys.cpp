// The keys of the kinds of body (elastic/body.hpp's BodyKey) are read and written by the case
// files from the registry: each key of each kind, set in [elastic] and in [indenter_body], selects
// its kind, is written back and reads back to the same case (also for an elastic indenter, whose
// keys are [indenter]'s); a key that needs another is refused alone, naming both.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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
    case BodyKey::Kind::Tables: {
      // One table, each field given: 0.05 plus its position (a modulus, a ratio or a thickness
      // that any such key takes).
      std::string t;
      for (std::size_t j = 0; j < k.fields.size(); ++j)
        t +=
            (j ? ", " : "") + k.fields[j].name + " = " + std::to_string(0.05 + 0.01 * static_cast<double>(j));
      return k.name + " = [{" + t + "}]";
    }
  }
  return "";
}

// elastic_keys in [elastic] (a layer of thickness 0.1); indenter_keys in [indenter].
std::string case_text(const std::string& elastic_keys, const std::string& indenter_keys = "") {
  return "[grid]\nnx = 32\nlx = 1.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n" + indenter_keys +
         "\n[load]\nforce = 0.01\n[elastic]\nthickness = 0.1\n" + elastic_keys + "\n";
}

// The case file's error for elastic_keys (empty if it reads).
std::string error_of(const std::string& elastic_keys) {
  try {
    (void)parse_config(case_text(elastic_keys), "case.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
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

// A table-shaped key is read by the case reader from its fields alone (BodyKey::fields): its
// values land in their fields' places, an omitted optional field takes its default, and the
// reader refuses, naming the table: a field left out that is required, a key that is no field, a
// value that is no number, an entry that is no table and a value that is no array.
TEST(BodyKeys, ATableKeyIsReadFromItsFieldsAlone) {
  int checked = 0;
  for (const BodyKey* k : body_keys()) {
    if (k->kind != BodyKey::Kind::Tables) continue;
    SCOPED_TRACE(k->name);
    ++checked;
    ASSERT_FALSE(k->fields.empty());
    const Config c = parse_config(case_text(setting(*k)), "case.toml");
    const std::vector<std::vector<double>> rows = k->rows(c.elastic);
    ASSERT_EQ(rows.size(), 1u);
    for (std::size_t j = 0; j < k->fields.size(); ++j)
      EXPECT_DOUBLE_EQ(rows[0][j], 0.05 + 0.01 * static_cast<double>(j)) << k->fields[j].name;
    for (std::size_t j = 0; j < k->fields.size(); ++j) {
      // The table without field j.
      std::string t;
      for (std::size_t i = 0; i < k->fields.size(); ++i)
        if (i != j) t += (t.empty() ? "" : ", ") + k->fields[i].name + " = 0.07";
      const std::string why = error_of(k->name + " = [{" + t + "}]");
      if (k->fields[j].required) {
        EXPECT_NE(why.find("elastic." + k->name + "[0]: needs " + k->fields[j].name), std::string::npos)
            << why;
      } else {
        EXPECT_EQ(why, "");
        const Config d = parse_config(case_text(k->name + " = [{" + t + "}]"), "case.toml");
        EXPECT_EQ(k->rows(d.elastic)[0][j], k->fields[j].default_value);
      }
    }
    const std::string first = k->fields[0].name;
    const std::string unknown = error_of(k->name + " = [{" + first + " = 1.0, thicknes = 0.1}]");
    EXPECT_NE(unknown.find("elastic." + k->name + "[0].thicknes: unknown key"), std::string::npos) << unknown;
    const std::string text = error_of(k->name + " = [{" + first + " = \"a\"}]");
    EXPECT_NE(text.find("elastic." + k->name + "[0]." + first + ": must be a number"), std::string::npos)
        << text;
    const std::string number = error_of(k->name + " = [1.0]");
    EXPECT_NE(number.find("elastic." + k->name + "[0]: must be a table {" + first), std::string::npos)
        << number;
    const std::string scalar = error_of(k->name + " = 1.0");
    EXPECT_NE(scalar.find("elastic." + k->name + ": must be an array of tables {" + first), std::string::npos)
        << scalar;
  }
  EXPECT_GT(checked, 0);  // layers
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
