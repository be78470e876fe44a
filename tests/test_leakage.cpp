// Leakage of solved contacts: percolation threshold of the egg-crate, CLI flow outputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gfmd/case/config.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/studies/percolation.hpp"
#include "test_util.hpp"

using namespace gfmd;
namespace fs = std::filesystem;

namespace {
const char* kEggcrate = R"(
[grid]
nx = 128
lx = 1.0
[elastic]
poisson = 0.25
[indenter]
type = "eggcrate"
wavelength = 1.0
amplitude = 0.025330295910584444
[load]
pressure = 0.01
)";
}  // namespace

TEST(Leakage, EggcratePercolationThreshold) {
  // Egg-crate h0 [cos(2 pi x/l) + cos(2 pi y/l)], h0 = l/(2 pi)^2, frictionless, half-space:
  // a_c* = 0.405 (Dapp & Mueser, EPL 109, 44001 (2015), quoted in the paper), at 128^2.
  PercolationOptions po;
  po.axis = 0;
  po.area_tolerance = 0.002;
  const auto j = find_percolation(parse_config(kEggcrate, "egg.toml"), po);
  const double ac = j["critical_relative_contact_area"];
  std::printf("egg-crate a_c* along x at 128^2: %.4f after %d solves\n", ac, j["solves"].get<int>());
  EXPECT_NEAR(ac, 0.405, 0.01);
  EXPECT_TRUE(j["converged"].get<bool>());
  // Square symmetry: the same along y.
  po.axis = 1;
  const auto jy = find_percolation(parse_config(kEggcrate, "egg.toml"), po);
  EXPECT_NEAR(jy["critical_relative_contact_area"].get<double>(), ac, 1e-9);
}

TEST(Leakage, FrictionOpensSlidingDirectionAndClosesTransverse) {
  // Paper Fig. 3(j-m): constrictions open along the sliding direction, close across it.
  PercolationOptions po;
  po.area_tolerance = 0.004;
  const Config c = parse_config(kEggcrate, "egg.toml", {"friction.coefficient=1"});
  po.axis = 0;
  const double along = find_percolation(c, po)["critical_relative_contact_area"];
  po.axis = 1;
  const double across = find_percolation(c, po)["critical_relative_contact_area"];
  std::printf("with friction: a_c* along sliding %.4f, across %.4f\n", along, across);
  EXPECT_GT(along, 0.405 + 0.004);
  EXPECT_LT(across, 0.405 - 0.004);
}

TEST(Leakage, FlowCommandWritesFlowJson) {
  const fs::path d = fs::temp_directory_path() / ("gfmd_flow_cli_" + std::to_string(getpid()));
  fs::create_directories(d);
  std::ofstream(d / "case.toml") << kEggcrate << "[flow]\ndirection = \"both\"\n";
  const std::string exe = GFMD_EXE, toml = (d / "case.toml").string();
  const auto gfmd = [&](const std::string& args) {
    return std::system((exe + " " + args + " > /dev/null 2>&1").c_str());
  };
  const auto json_at = [](const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
  };
  ASSERT_EQ(gfmd("run " + toml + " -o " + (d / "out").string() + " -q"), 0);
  const auto j = json_at(d / "out" / "flow.json");
  for (const char* k :
       {"flow_factor_x", "flow_factor_y", "percolates_x", "percolates_y", "conservation_error"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_TRUE(j["percolates_x"].get<bool>());
  EXPECT_NEAR(j["flow_factor_x"].get<double>(), j["flow_factor_y"].get<double>(), 1e-9);
  EXPECT_LT(j["conservation_error"].get<double>(), 1e-8);
  EXPECT_EQ(j["linear_solver"].get<std::string>(), "amg");
  ASSERT_TRUE(j["faces_closed_by_cutoff"].is_number_unsigned());
  EXPECT_LT(j["faces_closed_by_cutoff"].get<std::size_t>(), 128u * 128u / 100u);
  EXPECT_TRUE(fs::exists(d / "out" / "flow.nc"));
  EXPECT_TRUE(fs::exists(d / "out" / "current_x.png"));
  // gfmd flow on the solved directory gives the same numbers.
  fs::remove(d / "out" / "flow.json");
  ASSERT_EQ(gfmd("flow " + (d / "out").string() + " --direction x"), 0);
  const auto j2 = json_at(d / "out" / "flow.json");
  EXPECT_NEAR(j2["flow_factor_x"].get<double>(), j["flow_factor_x"].get<double>(), 1e-9);
  EXPECT_FALSE(j2.contains("flow_factor_y"));
  // HYPRE's BoomerAMG, asked for on the command line and in the case file: the same flow.
  ASSERT_EQ(gfmd("flow " + (d / "out").string() + " --direction x --solver boomeramg"), 0);
  const auto j4 = json_at(d / "out" / "flow.json");
  EXPECT_EQ(j4["linear_solver"].get<std::string>(), "boomeramg");
  EXPECT_NEAR(j4["flow_factor_x"].get<double>(), j["flow_factor_x"].get<double>(), 1e-9);
  EXPECT_NE(gfmd("flow " + (d / "out").string() + " --solver petsc"), 0);
  ASSERT_EQ(gfmd("run " + toml + " -o " + (d / "hypre").string() + " -q --set flow.solver='\"boomeramg\"'"),
            0);
  const auto j5 = json_at(d / "hypre" / "flow.json");
  EXPECT_EQ(j5["linear_solver"].get<std::string>(), "boomeramg");
  EXPECT_NEAR(j5["flow_factor_y"].get<double>(), j["flow_factor_y"].get<double>(), 1e-9);
  // The summary records the solver asked for by its config name.
  EXPECT_EQ(json_at(d / "hypre" / "summary.json")["input"]["flow"]["solver"].get<std::string>(), "boomeramg");
  EXPECT_EQ(json_at(d / "out" / "summary.json")["input"]["flow"]["solver"].get<std::string>(), "auto");
  // Sealed contact: no flow.
  ASSERT_EQ(gfmd("run " + toml + " -o " + (d / "sealed").string() + " -q --set load.pressure=0.06"), 0);
  const auto j3 = json_at(d / "sealed" / "flow.json");
  EXPECT_FALSE(j3["percolates_x"].get<bool>());
  EXPECT_EQ(j3["flow_factor_x"].get<double>(), 0.0);
  fs::remove_all(d);
}

TEST(Leakage, APercolationSearchReadsItsHeightsOnce) {
  // The egg-crate as a height file: the search solves it at several loads; the file rewritten
  // after the first solve (twice the amplitude) changes none of them: the same threshold and
  // history, bit for bit, as the search on the file left alone.
  const fs::path dir = fs::temp_directory_path() / ("gfmd_perc_heights_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Topography egg = make_topography(parse_config(kEggcrate, "egg.toml"));
  const auto write_heights = [&](double scale) {
    std::ofstream f(dir / "heights.txt");
    f.precision(17);
    f << "# lx = 1.0\n# ly = 1.0\n";
    for (int iy = 0; iy < egg.grid.ny; ++iy) {
      for (int ix = 0; ix < egg.grid.nx; ++ix)
        f << (ix ? " " : "") << scale * egg.h[static_cast<std::size_t>(iy) * egg.grid.nx + ix];
      f << "\n";
    }
  };
  const std::string text = "[elastic]\npoisson = 0.25\n[indenter]\ntype = \"file\"\npath = \"" +
                           (dir / "heights.txt").string() + "\"\n[load]\npressure = 0.01\n";
  PercolationOptions po;
  po.area_tolerance = 0.004;
  write_heights(1.0);
  const nlohmann::json plain = find_percolation(parse_config(text, "file.toml"), po);
  int solves = 0;
  po.log = [&](const std::string&) {
    if (++solves == 1) write_heights(2.0);
  };
  const nlohmann::json rewritten = find_percolation(parse_config(text, "file.toml"), po);
  EXPECT_GT(solves, 2);
  EXPECT_EQ(rewritten["critical_relative_contact_area"], plain["critical_relative_contact_area"]);
  EXPECT_EQ(rewritten["solves"], plain["solves"]);
  fs::remove_all(dir);
}

// gfmd percolation's directory: status.json follows the search ("converged" with
// percolation.json; stopped part-way, "interrupted" with the reason and the earlier result kept).
TEST(Leakage, PercolationDirectorySaysWhereTheSearchStands) {
  const fs::path d = fs::temp_directory_path() / ("gfmd_percolation_dir" + std::to_string(getpid()));
  fs::remove_all(d);
  const std::string out = (d / "p").string();
  const Config c = parse_config(kEggcrate, "egg.toml", {"grid.nx=32"});
  PercolationOptions po;
  po.area_tolerance = 0.02;
  const auto j = run_percolation(c, po, out);
  const auto status = [&out] {
    std::ifstream in(fs::path(out) / "status.json");
    return nlohmann::json::parse(in);
  };
  EXPECT_EQ(status()["status"], "converged");
  std::ifstream in(fs::path(out) / "percolation.json");
  EXPECT_EQ(nlohmann::json::parse(in)["solves"], j["solves"]);
  // gfmd plot knows it (it said "not a gfmd run ... directory", exit 2): nothing to draw.
  const auto plot = gfmd::testing::run_gfmd("plot " + out);
  EXPECT_EQ(plot.code, 0) << plot.output;
  EXPECT_NE(plot.output.find("holds a gfmd percolation result: it has no figures"), std::string::npos)
      << plot.output;
  int solves = 0;
  po.log = [&solves](const std::string&) { ++solves; };
  po.stop_request = [&solves] { return solves >= 1; };
  EXPECT_THROW(
      run_percolation(parse_config(kEggcrate, "egg.toml", {"grid.nx=32", "load.pressure=0.02"}), po, out),
      Interrupted);
  const nlohmann::json s = status();
  EXPECT_EQ(s["status"], "interrupted") << s.dump();
  EXPECT_TRUE(fs::exists(fs::path(out) / "percolation.json"));  // the earlier result stays
  fs::remove_all(d);
}
