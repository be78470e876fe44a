// Plausibility (issue 41): the pressure limit under approach control, the warning on a steep
// surface (likely a unit mistake), and three-column x, y, z text maps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/io/height_map.hpp"
#include "gfmd/surface/topography.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using gfmd::testing::run_gfmd;
using gfmd::testing::write_file;

namespace {

fs::path scratch(const std::string& name) { return gfmd::testing::scratch_dir("plausibility", name); }

// The message of the InputError that f throws ("" if none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const gfmd::InputError& e) {
    return e.what();
  }
  return "";
}

// z of the test lattice at (ix, iy): distinct for every point.
double z_at(int ix, int iy) { return 0.5 * ix - 0.25 * iy + 0.01 * ix * iy; }

}  // namespace

// ---- x, y, z text maps (io) ----------------------------------------------------------------

TEST(XyzText, PointsWithAHeaderArePlacedOnTheirGrid) {
  const fs::path d = scratch("header");
  // A 4 x 3 grid (dx = 0.5, dy = 0.2), the rows in a shuffled order.
  std::ostringstream os;
  os << "x,y,z\n";
  std::vector<std::pair<int, int>> pts;
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) pts.emplace_back(ix, iy);
  std::reverse(pts.begin(), pts.end());
  std::swap(pts[1], pts[7]);
  for (const auto& [ix, iy] : pts)
    os << 1.0 + 0.5 * ix << "," << -0.4 + 0.2 * iy << "," << z_at(ix, iy) << "\n";
  write_file(d / "map.csv", os.str());
  const gfmd::HeightMap m = gfmd::read_height_file((d / "map.csv").string());
  ASSERT_EQ(m.nx, 4);
  ASSERT_EQ(m.ny, 3);
  EXPECT_NEAR(m.lx, 2.0, 1e-12);  // spacing x count
  EXPECT_NEAR(m.ly, 0.6, 1e-12);
  EXPECT_EQ(m.missing, 0u);
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) EXPECT_EQ(m.h[iy * 4 + ix], z_at(ix, iy)) << ix << ", " << iy;
}

TEST(XyzText, RepeatedColumnsWithoutHeaderArePointsAndGapsAreMissing) {
  const fs::path d = scratch("partial");
  // A 5 x 4 grid in um, blank-separated, without the pair (ix, iy) = (2, 1).
  std::ostringstream os;
  os << "# unit = um\n";
  for (int iy = 0; iy < 4; ++iy)
    for (int ix = 0; ix < 5; ++ix)
      if (ix != 2 || iy != 1) os << 0.1 * ix << " " << 0.1 * iy << " " << z_at(ix, iy) << "\n";
  write_file(d / "map.txt", os.str());
  const gfmd::HeightMap m = gfmd::read_height_file((d / "map.txt").string());
  ASSERT_EQ(m.nx, 5);
  ASSERT_EQ(m.ny, 4);
  EXPECT_EQ(m.unit, "m");
  EXPECT_NEAR(m.lx, 0.5e-6, 1e-18);
  EXPECT_NEAR(m.ly, 0.4e-6, 1e-18);
  EXPECT_EQ(m.missing, 1u);
  EXPECT_TRUE(std::isnan(m.h[1 * 5 + 2]));
  EXPECT_NE(m.first_missing.find("which no row gives"), std::string::npos) << m.first_missing;
  EXPECT_NEAR(m.h[3 * 5 + 4], z_at(4, 3) * 1e-6, 1e-18);
  // A solve needs every point: the case's missing-point policy names the gap.
  const std::string e = input_error([&] { (void)gfmd::read_height_map((d / "map.txt").string(), 0, 0); });
  EXPECT_NE(e.find("indenter.missing"), std::string::npos) << e;
}

TEST(XyzText, PointsOffARegularGridAreRefusedNamingTheLine) {
  const fs::path d = scratch("irregular");
  const auto lattice = [](std::ostringstream& os) {
    for (int iy = 0; iy < 3; ++iy)
      for (int ix = 0; ix < 3; ++ix) os << ix << "," << iy << "," << z_at(ix, iy) << "\n";
  };
  std::ostringstream off;
  off << "x, y, z\n";
  lattice(off);
  off << "0.45,1," << 7.5 << "\n";  // line 11: between x = 0 and x = 1
  write_file(d / "off.csv", off.str());
  std::string e = input_error([&] { (void)gfmd::read_height_file((d / "off.csv").string()); });
  EXPECT_NE(e.find("off.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("line 11"), std::string::npos) << e;
  EXPECT_NE(e.find("not a regular grid"), std::string::npos) << e;
  std::ostringstream twice;
  lattice(twice);
  twice << "1,2,9.5\n";  // line 10: (1, 2) again
  write_file(d / "twice.csv", twice.str());
  e = input_error([&] { (void)gfmd::read_height_file((d / "twice.csv").string()); });
  EXPECT_NE(e.find("line 10"), std::string::npos) << e;
  EXPECT_NE(e.find("given twice (first on line 8)"), std::string::npos) << e;
}

TEST(XyzText, ManyPointsAndThreeColumnMatrices) {
  const fs::path d = scratch("many");
  // 300 x 240 points: more rows than a matrix may have (65536).
  std::string text;
  for (int iy = 0; iy < 240; ++iy)
    for (int ix = 0; ix < 300; ++ix)
      text += std::to_string(ix) + "\t" + std::to_string(iy) + "\t" + std::to_string(ix % 7) + "\n";
  write_file(d / "big.tsv", text);
  const gfmd::HeightMap m = gfmd::read_height_file((d / "big.tsv").string());
  EXPECT_EQ(m.nx, 300);
  EXPECT_EQ(m.ny, 240);
  EXPECT_EQ(m.h[5 * 300 + 12], 5.0);
  // Heights three points wide whose first two columns do not repeat: still a 3 x n matrix.
  write_file(d / "matrix.csv", "0.1,0.7,0.3\n0.2,0.9,0.4\n0.3,0.8,0.1\n0.4,0.6,0.2\n");
  const gfmd::HeightMap w = gfmd::read_height_file((d / "matrix.csv").string());
  EXPECT_EQ(w.nx, 3);
  EXPECT_EQ(w.ny, 4);
  EXPECT_EQ(w.h[4], 0.9);
  // A missing value in the first two columns is no coordinate: a matrix with missing points.
  write_file(d / "holes.csv", "0.1,0.7,0.3\nnan,0.9,0.4\n0.3,nan,0.1\n0.4,0.6,0.2\n");
  const gfmd::HeightMap m2 = gfmd::read_height_file((d / "holes.csv").string());
  EXPECT_EQ(m2.nx, 3);
  EXPECT_EQ(m2.ny, 4);
  EXPECT_EQ(m2.missing, 2u);
}

// ---- steep surfaces warn; approach control obeys the pressure limit (case) -------------------

TEST(Plausibility, NanometreMapDeclaredAsMicrometresWarnsNamingTheUnit) {
  const fs::path d = scratch("units");
  // A smooth 32 x 32 map of amplitude 200 (nm) over a 10 um cell, declared as um: gradient 88.9.
  std::ostringstream os;
  for (int iy = 0; iy < 32; ++iy) {
    for (int ix = 0; ix < 32; ++ix)
      os << (ix ? " " : "")
         << 200.0 * std::cos(2 * std::numbers::pi * ix / 32) * std::cos(2 * std::numbers::pi * iy / 32);
    os << "\n";
  }
  write_file(d / "map.txt", os.str());
  const std::string toml =
      "[grid]\nlx = 10.0\nunit = \"um\"\n[indenter]\ntype = \"file\"\npath = \"map.txt\"\n"
      "unit = \"um\"\n[load]\npressure = 0.01\n";
  write_file(d / "case.toml", toml);
  gfmd::Config cfg = gfmd::load_config((d / "case.toml").string());
  gfmd::MapReport rep;
  const gfmd::Topography t = gfmd::make_topography(cfg, &rep);
  const auto w = gfmd::plausibility_warnings(cfg, gfmd::statistics(t), &rep);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("rms gradient is 88.9"), std::string::npos) << w[0];  // 200 (2 pi / 10) / sqrt 2
  EXPECT_NE(w[0].find("indenter.unit"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("\"um\" given"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("grid.lx = 10"), std::string::npos) << w[0];
  // In nm, as it is: no warning.
  cfg = gfmd::load_config((d / "case.toml").string(), {"indenter.unit=\"nm\""});
  EXPECT_TRUE(
      gfmd::plausibility_warnings(cfg, gfmd::statistics(gfmd::make_topography(cfg)), nullptr).empty());
}

namespace {
// The warnings of a case given as TOML text on its own surface.
std::vector<std::string> case_warnings(const std::string& toml) {
  const gfmd::Config cfg = gfmd::parse_config(toml, "t.toml");
  return gfmd::plausibility_warnings(cfg, gfmd::statistics(gfmd::make_topography(cfg)), nullptr);
}
}  // namespace

// A viscoelastic body without a speed is at rest (relaxed, no hysteresis): valid, but usually a
// forgotten friction.velocity; the case warns, naming the key. Given (0 too) it does not.
TEST(Plausibility, AViscoelasticBodyWithoutASpeedWarns) {
  const std::string toml =
      "[grid]\nnx = 32\nlx = 1.5\n[elastic]\nviscoelastic = \"sls\"\nhigh_frequency_modulus = 10.0\n"
      "relaxation_time = 1.0\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n[load]\nforce = 0.01\n";
  const auto w = case_warnings(toml);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("friction.velocity is not"), std::string::npos) << w[0];
  for (const char* v : {"0.02", "0.0"})  // given, even as 0 (at rest on purpose): no warning
    EXPECT_TRUE(case_warnings(toml + "[friction]\nvelocity = " + v + "\n").empty()) << v;
}

// A friction law chosen with friction.coefficient = 0 is frictionless (tresca's min(mu_c p, tau0)
// is zero): it ran silently, without even friction_law in the summary. It warns, naming the key.
TEST(Plausibility, AFrictionLawWithoutACoefficientWarns) {
  const std::string toml =
      "[grid]\nnx = 32\nlx = 1.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n[load]\nforce = 0.01\n"
      "[friction]\nlaw = \"tresca\"\nshear_strength = 0.05\n";
  const auto w = case_warnings(toml);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("friction.law = \"tresca\" with friction.coefficient = 0 is frictionless"),
            std::string::npos)
      << w[0];
  EXPECT_TRUE(case_warnings(toml + "coefficient = 3.0\n").empty());
}

TEST(Plausibility, SteepHertzWarnsOnStderrAndInTheSummary) {
  const fs::path d = scratch("hertz");
  // R = 0.05 on a cell of 4: rms gradient about L / (R sqrt 6) = 32.7 (33.1 spectrally, with the
  // kink at the cell's edge). Contact radius 0.155, above 2 dx.
  write_file(d / "steep.toml", gfmd::testing::kSmallHertz);
  const std::string sets = " --set indenter.radius=0.05 --set load.force=0.1 --set output.png=false";
  const auto r = run_gfmd("run " + (d / "steep.toml").string() + " -o " + (d / "steep").string() + sets);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("gfmd: warning: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rms gradient is 33.1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("indenter.radius = 0.05"), std::string::npos) << r.output;
  std::ifstream in(d / "steep" / "summary.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_TRUE(j["warnings"].is_array());
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("indenter.radius"), std::string::npos);
  // The same case as shipped (R = 1): rms gradient 1.6, no warning, an empty list.
  const auto ok = run_gfmd("run " + (d / "steep.toml").string() + " -o " + (d / "ok").string() +
                           " --set output.png=false");
  ASSERT_EQ(ok.code, 0) << ok.output;
  EXPECT_EQ(ok.output.find("warning"), std::string::npos) << ok.output;
  std::ifstream in2(d / "ok" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(in2)["warnings"], nlohmann::json::array());
}

TEST(Plausibility, ApproachBeyondThePressureLimitFailsLikeANonConvergedSolve) {
  const std::string toml = gfmd::testing::kSmallHertz + "[output]\npng = false\n";
  gfmd::Config cfg = gfmd::parse_config(toml, "test.toml", {"grid.nx=32", "load.force=0.1"});
  cfg.load = {gfmd::LoadMode::Approach, 1e6};
  const gfmd::CaseResult r = gfmd::run_case(cfg);
  EXPECT_FALSE(r.info.converged);
  EXPECT_NE(r.info.status.find("load.approach = 1e+06"), std::string::npos) << r.info.status;
  EXPECT_NE(r.info.status.find("above the limit of 1000 E*"), std::string::npos) << r.info.status;
  EXPECT_NE(r.info.status.find("mean pressure of "), std::string::npos) << r.info.status;
  EXPECT_FALSE(r.stress_summary.has_value());  // stopped before the post-processing
  // A moderate approach is a contact problem.
  cfg.load = {gfmd::LoadMode::Approach, 0.01};
  EXPECT_TRUE(gfmd::run_case(cfg).info.converged);
  // The command line: exit 3, the reason, nothing written.
  const fs::path d = scratch("approach");
  write_file(d / "case.toml",
             "[grid]\nnx = 32\nlx = 4.0\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
             "[load]\napproach = 1e6\n[output]\npng = false\n");
  const auto out = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "out").string() + " -q");
  EXPECT_EQ(out.code, 3) << out.output;
  EXPECT_NE(out.output.find("load.approach = 1e+06 reached a mean pressure of"), std::string::npos)
      << out.output;
  EXPECT_NE(out.output.find("no results written"), std::string::npos) << out.output;
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "out" / "fields.nc"));
}

// Planes of stress.depths below an elastic indenter's base were dropped from its stresses
// without a word (the body's own depths are checked against its thickness): the case warns.
TEST(Plausibility, DepthsBelowAnElasticIndentersBaseWarn) {
  const std::string toml =
      "[grid]\nnx = 32\nlx = 1.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\ncontact_modulus = 1.0\n"
      "thickness = 0.05\n[load]\nforce = 0.01\n[stress]\ndepths = [0.02, 0.1]\n";
  const auto w = case_warnings(toml);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("stress.depths 0.1 lie below the elastic indenter's base (indenter.thickness 0.05)"),
            std::string::npos)
      << w[0];
  std::string shallow = toml;
  shallow.replace(shallow.find("0.02, 0.1"), 9, "0.02, 0.04");
  EXPECT_TRUE(case_warnings(shallow).empty());
}

// A power law with an exponent above 2 is steep far from its contact by design: n = 4, R = 1 on a
// cell of 4 (rms gradient of the heights about 10) is a sound case and does not warn; a radius in
// another unit than the cell does, as for Hertz (the paraboloid's L/(R sqrt 6) = 32.7).
TEST(Plausibility, APowerLawIsWeighedByItsRadiusNotItsFarField) {
  const std::string toml =
      "[grid]\nnx = 64\nlx = 4.0\n[indenter]\ntype = \"powerlaw\"\nradius = 1.0\nexponent = 4.0\n[load]\n"
      "force = 0.01\n";
  const gfmd::Config cfg = gfmd::parse_config(toml, "t.toml");
  EXPECT_GT(gfmd::statistics(gfmd::make_topography(cfg)).rms_gradient, 5.0) << "the far field is steep";
  EXPECT_TRUE(case_warnings(toml).empty());
  std::string small = toml;
  small.replace(small.find("radius = 1.0"), 12, "radius = 0.05");
  const auto w = case_warnings(small);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("rms gradient is 32.7"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("indenter.radius = 0.05"), std::string::npos) << w[0];
}
