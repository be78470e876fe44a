// One case into its run directory (case/run_in_directory), as gfmd run -o DIR [--resume] and
// Python's gfmd.run(resume=True) use it: solved and published, reused when finished, a failure
// to converge reported whole (its status, then the counts) with nothing published, and a stop
// that keeps the solve's state for the next call.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_in_directory.hpp"
#include "test_util.hpp"

namespace {

using namespace gfmd;
namespace fs = std::filesystem;
using Outcome = DirectoryRun::Outcome;

const char* kHertz = R"(
[grid]
nx = 64
lx = 4.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 0.5
[output]
png = false
analysis = false
)";

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(std::ifstream(p)); }

TEST(RunInDirectory, SolvesOnceThenReusesTheFinishedResult) {
  const fs::path dir = gfmd::testing::scratch_dir("run_in_directory", "reuse");
  const Config cfg = parse_config(kHertz, "case.toml");
  DirectoryRunOptions o;
  o.resume = true;
  int ready_calls = 0;
  o.on_ready = [&](bool nothing_to_do) {
    ++ready_calls;
    EXPECT_FALSE(nothing_to_do);
  };
  const DirectoryRun first = run_in_directory(cfg, (dir / "run").string(), o);
  ASSERT_EQ(first.outcome, Outcome::Solved) << first.why;
  EXPECT_EQ(ready_calls, 1);
  EXPECT_TRUE(fs::exists(dir / "run" / "summary.json"));
  EXPECT_FALSE(fs::exists(first.checkpoint));  // removed once published
  const auto stamp = fs::last_write_time(dir / "run" / "summary.json");
  DirectoryRunOptions again;
  again.resume = true;
  bool reused = false;
  again.on_ready = [&](bool nothing_to_do) { reused = nothing_to_do; };
  const DirectoryRun second = run_in_directory(cfg, (dir / "run").string(), again);
  EXPECT_EQ(second.outcome, Outcome::AlreadySolved);
  EXPECT_TRUE(reused);
  EXPECT_EQ(fs::last_write_time(dir / "run" / "summary.json"), stamp);
  EXPECT_EQ(second.finished["friction_coefficient"],
            read_json(dir / "run" / "summary.json")["friction_coefficient"]);
  // Without resume the same case is solved again.
  EXPECT_EQ(run_in_directory(cfg, (dir / "run").string(), {}).outcome, Outcome::Solved);
}

TEST(RunInDirectory, AFailureToConvergeIsReportedWholeAndPublishesNothing) {
  // A tresca cap switched at the contact's edge (128², mu_c = 300): its status names the cure and
  // the docs' section, over 500 characters; gfmd run's message had cut it at 512 with the counts.
  const fs::path dir = gfmd::testing::scratch_dir("run_in_directory", "not_converged");
  const Config cfg = load_config(std::string(GFMD_SOURCE_DIR) + "/examples/adhesive_sliding_sphere.toml",
                                 {"grid.nx=128", "friction.shear_strength=0.05", "load.approach=0.01",
                                  "friction.coefficient=300", "output.png=false"});
  const DirectoryRun r = run_in_directory(cfg, (dir / "run").string(), {});
  ASSERT_EQ(r.outcome, Outcome::NotConverged);
  EXPECT_GT(r.why.size(), 512u);
  EXPECT_NE(r.why.find("(docs/solver.md, \"Adhesion with friction\") after "), std::string::npos) << r.why;
  EXPECT_NE(r.why.find(", tolerance 1.0e-08)"), std::string::npos) << r.why;
  EXPECT_FALSE(fs::exists(dir / "run" / "summary.json"));
  const nlohmann::json status = read_json(dir / "run" / "status.json");
  EXPECT_EQ(status["status"], "failed");
  EXPECT_EQ(status["reason"], r.why);
}

TEST(RunInDirectory, AStopKeepsTheSolvesStateForTheNextCall) {
  const fs::path dir = gfmd::testing::scratch_dir("run_in_directory", "stop");
  const Config cfg = parse_config(kHertz, "case.toml");
  DirectoryRunOptions o;
  o.resume = true;
  int polls = 0;
  o.directory.stop_request = [&] { return ++polls > 20; };  // after a few iterations
  const DirectoryRun r = run_in_directory(cfg, (dir / "run").string(), o);
  ASSERT_EQ(r.outcome, Outcome::Interrupted);
  EXPECT_TRUE(r.saved_state);
  EXPECT_TRUE(fs::exists(r.checkpoint)) << r.checkpoint;
  EXPECT_FALSE(fs::exists(dir / "run" / "summary.json"));
  EXPECT_EQ(read_status((dir / "run").string()), "interrupted");
  // The next call continues from the checkpoint and finishes.
  std::string said;
  DirectoryRunOptions next;
  next.resume = true;
  next.log = [&](const std::string& m) { said += m + "\n"; };
  const DirectoryRun done = run_in_directory(cfg, (dir / "run").string(), next);
  EXPECT_EQ(done.outcome, Outcome::Solved) << done.why;
  EXPECT_NE(said.find("resuming from the checkpoint"), std::string::npos) << said;
  EXPECT_TRUE(fs::exists(dir / "run" / "summary.json"));
}

}  // namespace
