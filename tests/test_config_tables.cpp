// A case given as tables (config_from_tables, what the Python library passes) is read by the
// same rules as the same case written as TOML text (parse_config).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"

namespace {

using nlohmann::json;

// A coated body with a layer beneath it, an adhesive interaction with a cap, friction options
// and solver options: the text and the tables say the same.
const char* kText = R"(
[grid]
nx = 32
lx = 1.5
[elastic]
contact_modulus = 2.0
poisson = 0.3
thickness = 0.1
substrate_contact_modulus = 1.0
substrate_poisson = 0.25
layers = [{contact_modulus = 3.0, poisson = 0.2, thickness = 0.05}]
[indenter]
type = "hertz"
radius = 2.0
[load]
approach = 0.01
[friction]
coefficient = 0.3
direction = 30.0
[interaction]
model = "adhesive"
work_of_adhesion = 1e-3
range = 0.02
hardness = 0.5
[solver]
tolerance = 1e-9
max_iterations = 4000
[stress]
depths = [0.01, 0.02]
)";

json tables() {
  return json{
      {"grid", {{"nx", 32}, {"lx", 1.5}}},
      {"elastic",
       {{"contact_modulus", 2.0},
        {"poisson", 0.3},
        {"thickness", 0.1},
        {"substrate_contact_modulus", 1.0},
        {"substrate_poisson", 0.25},
        {"layers", json::array({{{"contact_modulus", 3.0}, {"poisson", 0.2}, {"thickness", 0.05}}})}}},
      {"indenter", {{"type", "hertz"}, {"radius", 2.0}}},
      {"load", {{"approach", 0.01}}},
      {"friction", {{"coefficient", 0.3}, {"direction", 30.0}}},
      {"interaction",
       {{"model", "adhesive"}, {"work_of_adhesion", 1e-3}, {"range", 0.02}, {"hardness", 0.5}}},
      {"solver", {{"tolerance", 1e-9}, {"max_iterations", 4000}}},
      {"stress", {{"depths", {0.01, 0.02}}}},
  };
}

std::string error_of(const json& t) {
  try {
    (void)gfmd::config_from_tables(t, "tables");
  } catch (const gfmd::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigTables, ReadAsTheSameCaseInText) {
  json a = gfmd::parse_config(kText, "text").to_json();
  json b = gfmd::config_from_tables(tables(), "tables").to_json();
  EXPECT_EQ(a, b);
  // And the parts that the JSON record does not hold verbatim.
  const gfmd::Config c = gfmd::config_from_tables(tables(), "tables");
  EXPECT_EQ(c.grid.nx, 32);
  EXPECT_EQ(c.grid.ny, 32);
  EXPECT_DOUBLE_EQ(c.elastic.contact_modulus, 2.0);
  ASSERT_EQ(c.elastic.layers.size(), 1U);
  EXPECT_DOUBLE_EQ(c.elastic.layers[0].thickness, 0.05);
  EXPECT_DOUBLE_EQ(c.interaction.hardness, 0.5);
  // Overrides apply as to a file.
  const gfmd::Config d = gfmd::config_from_tables(tables(), "tables", {"grid.nx=64"});
  EXPECT_EQ(d.grid.nx, 64);
}

TEST(ConfigTables, ProblemsNameTheirKeysWithoutAPlaceInAFile) {
  json t = tables();
  t["solver"]["tolerance"] = -1.0;
  t["grid"]["nx"] = 32.5;  // not an integer: a float stays a float
  const std::string e = error_of(t);
  EXPECT_NE(e.find("solver.tolerance"), std::string::npos) << e;
  EXPECT_NE(e.find("grid.nx"), std::string::npos) << e;
  EXPECT_EQ(e.find(".toml:"), std::string::npos) << e;
  EXPECT_EQ(e.find("[tables:"), std::string::npos) << e;  // no line numbers: there is no text

  json u = tables();
  u["elastic"]["layers"][0]["poisson"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_of(u).find("elastic.layers[0].poisson: must not be NaN"), std::string::npos) << error_of(u);

  json v = tables();
  v["interaction"]["range"] = nullptr;
  EXPECT_NE(error_of(v).find("interaction.range"), std::string::npos) << error_of(v);

  json w = tables();
  w["solverr"] = json::object();
  EXPECT_NE(error_of(w).find("solverr: unknown section"), std::string::npos) << error_of(w);

  EXPECT_NE(error_of(json::array()).find("a table of sections"), std::string::npos);

  // inf is a value a case holds (an unbounded thickness).
  json x = tables();
  x["elastic"].erase("substrate_contact_modulus");
  x["elastic"].erase("substrate_poisson");
  x["elastic"].erase("layers");
  x["elastic"]["thickness"] = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isinf(gfmd::config_from_tables(x, "tables").elastic.thickness));
}

}  // namespace
