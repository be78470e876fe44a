// gfmd curve: the load curves of one case (contact area, mean gap, friction, leakage against
// the pressure) and the percolation threshold, from the library and the command line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/studies/curve.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using gfmd::testing::Outcome;
using gfmd::testing::read_file;
using gfmd::testing::run_gfmd;
using gfmd::testing::write_file;

namespace {

// The paper's egg-crate on a half-space at 64^2: the flow through the saddles stops between
// p = 0.02 (a ~ 0.25) and p = 0.06 (a ~ 0.6).
const std::string kEgg = R"([grid]
nx = 64
lx = 1.0
[elastic]
poisson = 0.25
[indenter]
type = "eggcrate"
wavelength = 1.0
amplitude = 0.025330295910584444
[load]
pressure = 0.01
[output]
fields = false
)";
const std::vector<double> kPressures = {0.002, 0.006, 0.02, 0.06, 0.2};

fs::path scratch(const std::string& name) { return gfmd::testing::scratch_dir("curve_test", name); }

struct Table {
  std::vector<std::string> head;
  std::vector<std::map<std::string, std::string>> rows;
  [[nodiscard]] double num(std::size_t i, const std::string& c) const { return std::stod(rows.at(i).at(c)); }
};

Table read_csv(const fs::path& p) {
  Table t;
  std::istringstream in(read_file(p));
  std::string line;
  const auto split = [](const std::string& s) {
    std::vector<std::string> cells;
    std::stringstream ss(s);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (!s.empty() && s.back() == ',') cells.emplace_back();
    return cells;
  };
  if (!std::getline(in, line)) return t;
  t.head = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < t.head.size() && k < cells.size(); ++k) row[t.head[k]] = cells[k];
    t.rows.push_back(row);
  }
  return t;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_file(p)); }

}  // namespace

TEST(Curve, ParsesListsAndLogSpacedRanges) {
  EXPECT_EQ(gfmd::parse_pressures("0.1"), std::vector<double>({0.1}));
  EXPECT_EQ(gfmd::parse_pressures("0.3, 0.1,0.2"), std::vector<double>({0.3, 0.1, 0.2}));
  const auto r = gfmd::parse_pressures("0.001:1:4");
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r.front(), 0.001);  // the ends exactly
  EXPECT_EQ(r.back(), 1.0);
  EXPECT_NEAR(r[1], 0.01, 1e-15);
  EXPECT_NEAR(r[2], 0.1, 1e-15);
  EXPECT_EQ(gfmd::parse_pressures("0.001:1:10").size(), 10u);
  const auto mixed = gfmd::parse_pressures("0.001:0.01:2,0.05");
  EXPECT_EQ(mixed, std::vector<double>({0.001, 0.01, 0.05}));
  for (const char* bad : {"", " ", "0.1,,0.2", "0.1,", "abc", "0.1x", "0.1:1", "0.1:1:1", "0:1:3", "-1:1:3",
                          "0.1:1:2.5", "0.1:1:3:4", "0.1:1:", "1:inf:3", "0.1:1:1e9"}) {
    try {
      (void)gfmd::parse_pressures(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const gfmd::InputError& e) {
      EXPECT_EQ(e.where(), "pressures") << bad;
    }
  }
}

// Decided: a list out of order is sorted (a curve is warm-started from the smallest load up,
// and the threshold needs ascending loads); a value given twice, a non-positive or
// non-finite one, or no value at all is refused.
TEST(Curve, SortsPressuresAndRefusesBadOnes) {
  EXPECT_EQ(gfmd::curve_pressures({0.2, 0.01, 0.05}), std::vector<double>({0.01, 0.05, 0.2}));
  for (const std::vector<double>& bad : std::vector<std::vector<double>>{
           {}, {0.1, 0.0}, {-0.1}, {0.1, std::nan("")}, {INFINITY}, {0.1, 0.2, 0.1}}) {
    EXPECT_THROW((void)gfmd::curve_pressures(bad), gfmd::InputError) << bad.size();
  }
  try {
    (void)gfmd::curve_pressures({0.1, 0.2, 0.1});
  } catch (const gfmd::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0.1 is given twice"), std::string::npos) << e.what();
  }
}

TEST(Curve, ThresholdLiesBetweenTheLastOpenAndTheFirstSealedPoint) {
  const std::vector<double> p = {0.01, 0.02, 0.04, 0.08}, a = {0.1, 0.2, 0.3, 0.5};
  const auto j = gfmd::curve_threshold(p, a, {true, true, false, false});
  EXPECT_EQ(j["status"], "bracketed");
  EXPECT_TRUE(j["reached"].get<bool>());
  EXPECT_NEAR(j["pressure"].get<double>(), std::sqrt(0.02 * 0.04), 1e-15);  // the log-axis midpoint
  EXPECT_NEAR(j["relative_contact_area"].get<double>(), 0.25, 1e-12);
  EXPECT_EQ(j["bracket"]["open"]["pressure"].get<double>(), 0.02);
  EXPECT_EQ(j["bracket"]["sealed"]["pressure"].get<double>(), 0.04);
  EXPECT_TRUE(j["monotonic"].get<bool>());

  const auto open = gfmd::curve_threshold(p, a, {true, true, true, true});
  EXPECT_EQ(open["status"], "not_reached");
  EXPECT_FALSE(open["reached"].get<bool>());
  EXPECT_TRUE(open["pressure"].is_null());
  EXPECT_NE(open["message"].get<std::string>().find("not reached in the range"), std::string::npos);
  const auto sealed = gfmd::curve_threshold(p, a, {false, false, false, false});
  EXPECT_EQ(sealed["status"], "sealed_throughout");
  EXPECT_NE(sealed["message"].get<std::string>().find("not reached in the range"), std::string::npos);
  EXPECT_EQ(gfmd::curve_threshold({}, {}, {})["status"], "no_points");
  // Sealed, then open again: the threshold follows the last open point; flagged.
  const auto odd = gfmd::curve_threshold(p, a, {true, false, true, false});
  EXPECT_FALSE(odd["monotonic"].get<bool>());
  EXPECT_EQ(odd["bracket"]["open"]["pressure"].get<double>(), 0.04);
}

// The library: an egg-crate curve over five pressures, interrupted after two points and
// continued; the columns, the trends and the threshold.
TEST(Curve, EggCrateCurveHasTheColumnsTrendsAndThreshold) {
  const fs::path d = scratch("egg");
  write_file(d / "egg.toml", kEgg);
  const std::string path = (d / "egg.toml").string(), out = (d / "out").string();
  const gfmd::Config cfg = gfmd::curve_config(path, {}, {0.2, 0.06, 0.02, 0.006, 0.002});  // sorted
  EXPECT_EQ(cfg.sweep.parameter, "load.pressure");
  EXPECT_EQ(cfg.sweep.values, kPressures);
  EXPECT_TRUE(cfg.flow.enabled);
  EXPECT_FALSE(cfg.output.png);

  gfmd::CurveOptions stop;
  int done = 0;
  stop.sweep.on_point = [&done](int d_, int, const std::string&) { done = d_; };
  stop.sweep.stop_request = [&done] { return done >= 2; };
  EXPECT_THROW(gfmd::run_curve(path, cfg, out, stop), gfmd::Interrupted);
  const Table partial = read_csv(d / "out" / "curve.csv");
  EXPECT_EQ(partial.rows.size(), 2u);
  EXPECT_EQ(read_json(d / "out" / "curve.json")["completed"].get<int>(), 2);

  gfmd::CurveOptions again;
  std::vector<std::string> messages;
  again.sweep.on_point = [&messages](int, int, const std::string& m) { messages.push_back(m); };
  const nlohmann::json j = gfmd::run_curve(path, cfg, out, again);
  ASSERT_EQ(messages.size(), 5u);
  EXPECT_NE(messages[0].find("reused"), std::string::npos);
  EXPECT_NE(messages[1].find("reused"), std::string::npos);
  EXPECT_EQ(messages[2].find("reused"), std::string::npos);

  const Table t = read_csv(d / "out" / "curve.csv");
  const std::vector<std::string> head = {"pressure",
                                         "relative_contact_area",
                                         "mean_gap",
                                         "approach",
                                         "friction_coefficient",
                                         "friction_coefficient_downhill",
                                         "conductivity_x",
                                         "flow_factor_x",
                                         "percolates_x",
                                         "conductivity_y",
                                         "flow_factor_y",
                                         "percolates_y",
                                         "open",
                                         "iterations",
                                         "branch",
                                         "normal_force",
                                         "adhesive_force"};
  EXPECT_EQ(t.head, head);
  ASSERT_EQ(t.rows.size(), kPressures.size());
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    EXPECT_EQ(t.num(i, "pressure"), kPressures[i]);
    EXPECT_EQ(t.rows[i].at("friction_coefficient"), "") << "frictionless";
    if (i > 0) {
      EXPECT_GT(t.num(i, "relative_contact_area"), t.num(i - 1, "relative_contact_area")) << i;
      EXPECT_LT(t.num(i, "mean_gap"), t.num(i - 1, "mean_gap")) << i;
      EXPECT_LE(t.num(i, "conductivity_x"), t.num(i - 1, "conductivity_x")) << i;
    }
  }
  // Open at the small loads, sealed at the large ones.
  EXPECT_EQ(t.rows.front().at("open"), "1");
  EXPECT_EQ(t.rows.back().at("open"), "0");

  const nlohmann::json& perc = j["percolation"];
  ASSERT_EQ(perc["status"], "bracketed") << perc.dump(1);
  const double lo = perc["bracket"]["open"]["pressure"], hi = perc["bracket"]["sealed"]["pressure"];
  const double ps = perc["pressure"];
  EXPECT_LT(lo, ps);
  EXPECT_LT(ps, hi);
  // The bracket is where the leakage becomes zero: the last point with a flow and the next.
  std::size_t k = 0;
  while (k < t.rows.size() && t.rows[k].at("open") == "1") ++k;
  ASSERT_GT(k, 0u);
  ASSERT_LT(k, t.rows.size());
  EXPECT_EQ(t.num(k - 1, "pressure"), lo);
  EXPECT_EQ(t.num(k, "pressure"), hi);
  EXPECT_GT(t.num(k - 1, "conductivity_x") + t.num(k - 1, "conductivity_y"), 0.0);
  EXPECT_EQ(t.num(k, "conductivity_x"), 0.0);
  EXPECT_EQ(t.num(k, "conductivity_y"), 0.0);
  // The paper's a_c* = 0.405 for this indenter lies in the bracket's areas.
  EXPECT_LT(perc["bracket"]["open"]["relative_contact_area"].get<double>(), 0.405);
  EXPECT_GT(perc["bracket"]["sealed"]["relative_contact_area"].get<double>(), 0.405);
  EXPECT_EQ(perc["directions"]["x"]["status"], "bracketed");

  const nlohmann::json saved = read_json(d / "out" / "curve.json");
  for (const char* key : {"case", "overrides", "curve_overrides", "leakage_switched_on", "load_replaced",
                          "pressures", "completed", "total", "columns", "column_order", "points",
                          "percolation", "points_dir", "units", "input_first_point", "version", "git_commit"})
    EXPECT_TRUE(saved.contains(key)) << key;
  EXPECT_TRUE(saved["leakage_switched_on"].get<bool>());  // the case has no [flow]
  EXPECT_TRUE(saved["load_replaced"].is_null());          // the case gives a pressure
  EXPECT_EQ(saved["completed"].get<int>(), 5);
  EXPECT_EQ(saved["points"].size(), 5u);
  EXPECT_EQ(saved["column_order"].get<std::vector<std::string>>(), head);
  EXPECT_TRUE(fs::exists(d / "out" / "points" / "point_004" / "flow.json"));
  EXPECT_FALSE(fs::exists(d / "out" / "points" / "point_004" / "pressure.png"));  // no maps per point
}

// Decided: a case loaded by force or approach is driven by the curve's pressures (the load is
// replaced, said on stderr and in curve.json); --set load.* and --set flow.enabled=false are
// refused. The command line sorts the pressures, draws curve.png unless --no-png.
TEST(Curve, CommandLineReplacesAForceLoadAndDrawsTheFigure) {
  const fs::path d = scratch("cli");
  std::string force = kEgg;
  force.replace(force.find("pressure = 0.01"), 15, "force = 0.01");
  write_file(d / "force.toml", force);
  const std::string c = (d / "force.toml").string();
  const auto r = run_gfmd("curve " + c + " --pressures 0.2,0.002,0.02 -o " + (d / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("load.force = 0.01 is replaced"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("leakage is switched on"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("percolation threshold: the leakage stops at"), std::string::npos) << r.output;
  const Table t = read_csv(d / "out" / "curve.csv");
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.num(0, "pressure"), 0.002);
  EXPECT_EQ(t.num(2, "pressure"), 0.2);
  const nlohmann::json j = read_json(d / "out" / "curve.json");
  EXPECT_EQ(j["load_replaced"], "load.force = 0.01");
  EXPECT_EQ(j["input_first_point"]["load"]["pressure"].get<double>(), 0.002) << j["input_first_point"].dump();
  EXPECT_TRUE(fs::exists(d / "out" / "curve.png")) << r.output;
  const std::string first_csv = read_file(d / "out" / "curve.csv");

  // --set output.png=false: no figure (and the earlier one goes).
  ASSERT_EQ(run_gfmd("curve " + c + " --pressures 0.002,0.02,0.2 -q --set output.png=false -o " +
                     (d / "out").string())
                .code,
            0);
  EXPECT_FALSE(fs::exists(d / "out" / "curve.png"));
  // --no-png likewise; the points are reused.
  const auto again =
      run_gfmd("curve " + c + " --pressures 0.002,0.02,0.2 -q --no-png -o " + (d / "out").string());
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_FALSE(fs::exists(d / "out" / "curve.png"));
  EXPECT_EQ(read_file(d / "out" / "curve.csv"), first_csv);
  // gfmd plot redraws it from curve.csv (and says so).
  const auto redraw = run_gfmd("plot " + (d / "out").string());
  ASSERT_EQ(redraw.code, 0) << redraw.output;
  EXPECT_TRUE(fs::exists(d / "out" / "curve.png")) << redraw.output;
  EXPECT_NE(redraw.output.find("a curve"), std::string::npos) << redraw.output;
  // Its points are not a sweep of the user's: no sweep counted, no note about a sweep plot.
  EXPECT_NE(redraw.output.find("0 sweeps"), std::string::npos) << redraw.output;
  EXPECT_EQ(redraw.output.find("no sweep plot"), std::string::npos) << redraw.output;
  EXPECT_EQ(read_file(d / "out" / "curve.csv"), first_csv);

  // A case under approach control, a log-spaced range and output.png = false in the case.
  std::string approach = kEgg;
  approach.replace(approach.find("pressure = 0.01"), 15, "approach = 0.01");
  approach.replace(approach.find("fields = false"), 14, "fields = false\npng = false");
  write_file(d / "approach.toml", approach);
  const auto a = run_gfmd("curve " + (d / "approach.toml").string() + " --pressures 0.001:0.1:3 -q -o " +
                          (d / "approach").string());
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_EQ(read_json(d / "approach" / "curve.json")["load_replaced"], "load.approach = 0.01");
  EXPECT_EQ(read_csv(d / "approach" / "curve.csv").rows.size(), 3u);
  EXPECT_FALSE(fs::exists(d / "approach" / "curve.png"));
}

TEST(Curve, CommandLineRefusesBadInputBeforeWritingAnything) {
  const fs::path d = scratch("bad");
  write_file(d / "egg.toml", kEgg);
  const std::string c = (d / "egg.toml").string(), out = (d / "out").string();
  struct Bad {
    std::string args, fragment;
  };
  for (const Bad& b : std::vector<Bad>{
           {"--pressures ''", "--pressures: give at least one pressure"},
           {"--pressures 0,0.1", "--pressures: every pressure must be positive and finite, got 0"},
           {"--pressures 0.1,nan", "--pressures: every pressure must be positive and finite"},
           {"--pressures 0.1,inf", "--pressures: every pressure must be positive and finite"},
           {"--pressures 0.1,0.2,0.1", "--pressures: the pressure 0.1 is given twice"},
           {"--pressures 0.1,abc", "--pressures: 'abc' is not a number"},
           {"--pressures 0.001:1", "--pressures: '0.001:1': a range is FROM:TO:N"},
           {"--pressures 0.001:1:1", "N must be an integer in [2, 10000]"},
           {"--pressures 5000", "--pressures: the pressure 5000 exceeds 1000 E*"},
           {"--pressures 0.1 --set load.force=1", "--set load.force=1: the curve sets the load itself"},
           {"--pressures 0.1 --set flow.enabled=false",
            "--set flow.enabled=false: the curve needs the leakage"},
           {"--pressures 0.1 --set grid.nx=-4", "grid.nx"},
           // It left the directory with only its lock file.
           {"--pressures 0.01,0.5 --set interaction.hardness=0.2",
            "--pressures: the pressure 0.5: the mean pressure reaches interaction.hardness"},
           {"", "--pressures is required"},
       }) {
    const auto r = run_gfmd("curve " + c + " " + b.args + " -q -o " + out);
    EXPECT_EQ(r.code, 2) << b.args << ": " << r.output;
    EXPECT_NE(r.output.find(b.fragment), std::string::npos) << b.args << ": " << r.output;
    EXPECT_FALSE(fs::exists(out)) << b.args;
  }
  // The help names the log-spaced syntax.
  const auto h = run_gfmd("curve --help");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.output.find("FROM:TO:N"), std::string::npos) << h.output;
}
