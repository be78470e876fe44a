// Output directories: which may be written, staging and publication, failed and interrupted
// attempts that leave the previous result untouched (RunDirectory), through the library and
// the command line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/studies/sweep.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using gfmd::testing::read_file;
using gfmd::testing::run_gfmd;
using gfmd::testing::write_file;

namespace {

fs::path scratch(const std::string& name) { return gfmd::testing::scratch_dir("rundir_test", name); }

std::string status_of(const fs::path& dir) {
  return nlohmann::json::parse(read_file(dir / "status.json")).value("status", "");
}

// Runs f with the working directory set to dir.
template <class F>
void in_directory(const fs::path& dir, F&& f) {
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  try {
    f();
  } catch (...) {
    fs::current_path(before);
    throw;
  }
  fs::current_path(before);
}

}  // namespace

TEST(RunDirectory, RefusesRootHomeWorkingAndForeignDirectories) {
  const fs::path d = scratch("refuse");
  EXPECT_THROW(gfmd::check_output_directory("/", true), gfmd::InputError);
  EXPECT_THROW(gfmd::check_output_directory("", false), gfmd::InputError);
  in_directory(d, [] {
    EXPECT_THROW(gfmd::check_output_directory(".", true), gfmd::InputError);
    EXPECT_THROW(gfmd::check_output_directory("./", true), gfmd::InputError);
  });
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    EXPECT_THROW(gfmd::check_output_directory(home, true), gfmd::InputError);
  }
  // A user's directory with files: refused without force, naming the option.
  fs::create_directories(d / "mine");
  write_file(d / "mine" / "spectrum.csv", "mine\n");
  try {
    gfmd::check_output_directory((d / "mine").string(), false);
    ADD_FAILURE() << "a foreign non-empty directory was accepted";
  } catch (const gfmd::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
    EXPECT_EQ(e.where(), (d / "mine").string());
  }
  EXPECT_NO_THROW(gfmd::check_output_directory((d / "mine").string(), true));
  // New, empty and gfmd's own directories are fine; a file is not a directory.
  EXPECT_NO_THROW(gfmd::check_output_directory((d / "new" / "deeper").string(), false));
  fs::create_directories(d / "empty");
  EXPECT_NO_THROW(gfmd::check_output_directory((d / "empty").string(), false));
  fs::create_directories(d / "ours");
  write_file(d / "ours" / gfmd::kDirectoryMarker, "");
  write_file(d / "ours" / "summary.json", "{}");
  EXPECT_NO_THROW(gfmd::check_output_directory((d / "ours").string(), false));
  EXPECT_THROW(gfmd::check_output_directory((d / "mine" / "spectrum.csv").string(), true), gfmd::InputError);
}

TEST(RunDirectory, PublishReplacesTheOutputsTogetherAndFailureKeepsThem) {
  const fs::path d = scratch("publish");
  {
    gfmd::RunDirectory rd(d.string());
    rd.begin();
    write_file(fs::path(rd.staging()) / "summary.json", "old");
    write_file(fs::path(rd.staging()) / "flow.json", "old flow");
    rd.publish();
  }
  write_file(d / "notes.txt", "the user's");
  EXPECT_EQ(status_of(d), "converged");
  {
    // A failed attempt: nothing it staged arrives, the previous set stays and status.json says so.
    gfmd::RunDirectory rd(d.string());
    EXPECT_TRUE(rd.had_result());
    rd.begin();
    EXPECT_EQ(status_of(d), "running");
    write_file(fs::path(rd.staging()) / "summary.json", "new but failed");
    const std::string note = rd.fail("solve did not converge");
    EXPECT_NE(note.find("kept unchanged"), std::string::npos) << note;
  }
  EXPECT_EQ(read_file(d / "summary.json"), "old");
  EXPECT_EQ(read_file(d / "flow.json"), "old flow");
  EXPECT_FALSE(fs::exists(d / gfmd::kStagingName));
  const auto st = nlohmann::json::parse(read_file(d / "status.json"));
  EXPECT_EQ(st["status"], "failed");
  EXPECT_NE(st.value("result", "").find("kept"), std::string::npos);
  {
    // An attempt that is destroyed without an ending (an exception): its staging goes too.
    gfmd::RunDirectory rd(d.string());
    rd.begin();
    write_file(fs::path(rd.staging()) / "summary.json", "abandoned");
  }
  EXPECT_FALSE(fs::exists(d / gfmd::kStagingName));
  EXPECT_EQ(read_file(d / "summary.json"), "old");
  {
    // A new complete set replaces the old one; outputs it lacks (flow.json) go, the user's stay.
    gfmd::RunDirectory rd(d.string());
    rd.begin();
    write_file(fs::path(rd.staging()) / "summary.json", "new");
    rd.publish();
  }
  EXPECT_EQ(read_file(d / "summary.json"), "new");
  EXPECT_FALSE(fs::exists(d / "flow.json"));
  EXPECT_EQ(read_file(d / "notes.txt"), "the user's");
  EXPECT_EQ(status_of(d), "converged");
}

TEST(RunDirectory, APublicationCutShortIsFinishedOnTheNextOpening) {
  const fs::path d = scratch("crash");
  {
    gfmd::RunDirectory rd(d.string());
    rd.begin();
    write_file(fs::path(rd.staging()) / "summary.json", "old");
    rd.publish();
  }
  // What a crash between the marker and the last rename leaves: a complete staged set.
  fs::create_directories(d / gfmd::kStagingName);
  write_file(d / gfmd::kStagingName / "summary.json", "new");
  write_file(d / gfmd::kStagingName / "fields.nc", "new fields");
  write_file(d / gfmd::kStagingName / ".publishing", "publishing\n");
  { const gfmd::RunDirectory rd(d.string()); }
  EXPECT_EQ(read_file(d / "summary.json"), "new");
  EXPECT_EQ(read_file(d / "fields.nc"), "new fields");
  EXPECT_FALSE(fs::exists(d / gfmd::kStagingName));
  // Without the marker the staged set was incomplete: it goes, the published one stays.
  fs::create_directories(d / gfmd::kStagingName);
  write_file(d / gfmd::kStagingName / "summary.json", "half");
  { const gfmd::RunDirectory rd(d.string()); }
  EXPECT_EQ(read_file(d / "summary.json"), "new");
  EXPECT_FALSE(fs::exists(d / gfmd::kStagingName));
}

// Every value of a sweep is read before its directory is touched: a bad one later in the list
// leaves a finished sweep as it was (status "converged", not "running") and makes no new
// directory; the message names the point and its value.
TEST(RunDirectory, ABadValueLaterInASweepWritesNothing) {
  const fs::path d = scratch("sweep_bad_value");
  write_file(d / "case.toml",
             gfmd::testing::kSmallHertz + "[output]\nfields = false\npng = false\nanalysis = false\n");
  const std::string casep = (d / "case.toml").string(), out = (d / "s").string();
  gfmd::SweepOptions so;
  gfmd::run_sweep(casep, gfmd::sweep_config(casep, {}, "load.force", {0.006, 0.014}), out, so);
  const std::string table = read_file(fs::path(out) / "sweep.csv"),
                    status = read_file(fs::path(out) / "status.json");
  for (const std::string& dir : {out, (d / "fresh").string()}) {
    try {
      gfmd::run_sweep(casep, gfmd::sweep_config(casep, {}, "elastic.poisson", {0.3, 0.4, 0.7}), dir, so);
      ADD_FAILURE() << "a Poisson ratio of 0.7 was swept";
    } catch (const gfmd::InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("point_002 (elastic.poisson = 0.7)"), std::string::npos) << m;
      EXPECT_NE(m.find("poisson"), m.rfind("poisson")) << m;  // the key's own message follows
    }
  }
  EXPECT_EQ(read_file(fs::path(out) / "sweep.csv"), table);
  EXPECT_EQ(read_file(fs::path(out) / "status.json"), status);
  EXPECT_EQ(status_of(out), "converged");
  EXPECT_FALSE(fs::exists(d / "fresh"));
}

// An attempt that an unsettled error ends (its owner neither published, failed nor interrupted
// it) does not leave status.json "running".
TEST(RunDirectory, AnAttemptEndedByAnErrorIsMarkedFailed) {
  const fs::path d = scratch("unsettled") / "out";
  try {
    gfmd::RunDirectory rd(d.string());
    rd.begin();
    EXPECT_EQ(status_of(d), "running");
    throw std::runtime_error("disk full");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(status_of(d), "failed");
  EXPECT_FALSE(fs::exists(d / gfmd::kStagingName));
}

// A result of one kind is not replaced by another without force: a run into a sweep's directory
// deleted the sweep's table and points, a sweep into a run's its summary and fields.
TEST(Cli, AnotherKindOfResultIsNotReplacedWithoutForce) {
  const fs::path d = scratch("cli_kinds");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz + "[output]\npng = false\nfields = false\n");
  const std::string c = (d / "case.toml").string();
  ASSERT_EQ(run_gfmd("sweep " + c + " -q -o " + (d / "s").string() + " --set load.force=0.006,0.014").code,
            0);
  ASSERT_EQ(run_gfmd("run " + c + " -q -o " + (d / "r").string()).code, 0);
  EXPECT_EQ(gfmd::result_kind((d / "s").string()), "sweep");
  EXPECT_EQ(gfmd::result_kind((d / "r").string()), "run");
  const std::string table = read_file(d / "s" / "sweep.csv");
  const auto run = run_gfmd("run " + c + " -q -o " + (d / "s").string());
  EXPECT_EQ(run.code, 2) << run.output;
  EXPECT_NE(run.output.find("holds a gfmd sweep result, which this run would replace"), std::string::npos)
      << run.output;
  EXPECT_EQ(read_file(d / "s" / "sweep.csv"), table);
  EXPECT_TRUE(fs::exists(d / "s" / "point_001" / "summary.json"));
  const auto sweep =
      run_gfmd("sweep " + c + " -q -o " + (d / "r").string() + " --set load.force=0.006,0.014");
  EXPECT_EQ(sweep.code, 2) << sweep.output;
  EXPECT_TRUE(fs::exists(d / "r" / "summary.json"));
  const auto curve = run_gfmd("curve " + c + " -q --pressures 0.001,0.002 -o " + (d / "r").string());
  EXPECT_EQ(curve.code, 2) << curve.output;
  EXPECT_FALSE(fs::exists(d / "r" / "curve.json"));
  // Results without their table yet count too: a curve's points/, an ensemble's staged seeds,
  // a study's series of seeds (a sweep each).
  for (const auto& [dirs, kind] :
       {std::pair{std::vector<std::string>{"c/points"}, "curve"},
        std::pair{std::vector<std::string>{"e/" + std::string(gfmd::kStagingName) + "/seed_0"},
                  "ensemble"}}) {
    for (const auto& sub : dirs) fs::create_directories(d / sub);
    EXPECT_EQ(gfmd::result_kind((d / dirs.front().substr(0, 1)).string()), kind);
  }
  fs::create_directories(d / "series");
  fs::rename(d / "s", d / "series" / "seed_0");
  EXPECT_EQ(gfmd::result_kind((d / "series").string()), "study series");
  fs::rename(d / "series" / "seed_0", d / "s");
  // The same kind again is a re-run; --force replaces another kind.
  EXPECT_EQ(run_gfmd("run " + c + " -q -o " + (d / "r").string()).code, 0);
  EXPECT_EQ(run_gfmd("run " + c + " -q --force -o " + (d / "s").string()).code, 0);
  EXPECT_EQ(gfmd::result_kind((d / "s").string()), "run");
  EXPECT_FALSE(fs::exists(d / "s" / "sweep.csv"));
}

TEST(RunDirectory, SweepStoppedBetweenPointsKeepsThePreviousSweep) {
  const fs::path d = scratch("sweep");
  write_file(d / "case.toml",
             gfmd::testing::kSmallHertz + "[output]\nfields = false\npng = false\nanalysis = false\n");
  const std::string casep = (d / "case.toml").string(), out = (d / "s").string();
  gfmd::SweepOptions so;
  const gfmd::Config first = gfmd::sweep_config(casep, {}, "load.force", {0.006, 0.014});
  gfmd::run_sweep(casep, first, out, so);
  const std::string table = read_file(fs::path(out) / "sweep.csv");
  ASSERT_NE(table.find("0.014"), std::string::npos);
  // Points that need no iterations (the same case again) still honour a stop request: a new
  // sweep over other values stops after its first point.
  const gfmd::Config second = gfmd::sweep_config(casep, {}, "load.force", {0.007, 0.009, 0.012});
  int points = 0;
  so.on_point = [&points](int, int, const std::string&) { ++points; };
  so.stop_request = [&points] { return points >= 1; };
  EXPECT_THROW(gfmd::run_sweep(casep, second, out, so), gfmd::Interrupted);
  EXPECT_EQ(points, 1);
  EXPECT_EQ(read_file(fs::path(out) / "sweep.csv"), table);
  EXPECT_EQ(status_of(out), "interrupted");
  EXPECT_TRUE(fs::exists(fs::path(out) / gfmd::kStagingName / "point_000" / "summary.json"));
  // The same command again reuses the staged point and publishes the whole new sweep; the
  // earlier sweep's extra points do not survive it.
  std::string first_message;
  so.stop_request = {};
  so.on_point = [&first_message](int done, int, const std::string& m) {
    if (done == 1) first_message = m;
  };
  gfmd::run_sweep(casep, second, out, so);
  EXPECT_NE(first_message.find("reused"), std::string::npos) << first_message;
  // The swept values are the table's first column (another column's number may contain
  // "0.014" as digits).
  const std::string table2 = read_file(fs::path(out) / "sweep.csv");
  std::vector<std::string> loads;
  for (std::size_t at = table2.find('\n'); at != std::string::npos && at + 1 < table2.size();
       at = table2.find('\n', at + 1))
    loads.push_back(table2.substr(at + 1, table2.find(',', at + 1) - at - 1));
  EXPECT_EQ(loads, (std::vector<std::string>{"0.007", "0.009", "0.012"})) << table2;
  EXPECT_TRUE(fs::exists(fs::path(out) / "point_002" / "summary.json"));
  EXPECT_FALSE(fs::exists(fs::path(out) / "point_003"));
  EXPECT_FALSE(fs::exists(fs::path(out) / gfmd::kStagingName));
  EXPECT_EQ(status_of(out), "converged");
}

TEST(Cli, AForeignDirectoryIsRefusedAndNeverLosesData) {
  const fs::path d = scratch("cli_foreign");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz);
  const std::string run = "run " + (d / "case.toml").string() + " -q";
  // The example: the user's spectrum.csv in a directory gfmd did not make.
  fs::create_directories(d / "mine");
  write_file(d / "mine" / "spectrum.csv", "mine\n");
  const auto refused = run_gfmd(run + " -o " + (d / "mine").string() + " --set solver.max_iterations=2");
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_NE(refused.output.find("--force"), std::string::npos) << refused.output;
  EXPECT_EQ(read_file(d / "mine" / "spectrum.csv"), "mine\n");
  EXPECT_FALSE(fs::exists(d / "mine" / "status.json"));
  // With --force a failing run still changes none of the user's files.
  const auto failing =
      run_gfmd(run + " -o " + (d / "mine").string() + " --force --set solver.max_iterations=2");
  EXPECT_EQ(failing.code, 3) << failing.output;
  EXPECT_EQ(read_file(d / "mine" / "spectrum.csv"), "mine\n");
  EXPECT_FALSE(fs::exists(d / "mine" / "summary.json"));
  // The root directory and the working directory are refused outright, --force or not.
  for (const std::string& o : {std::string("/"), std::string(".")}) {
    const auto r = run_gfmd("run " + (d / "case.toml").string() + " -q --force -o " + o);
    EXPECT_EQ(r.code, 2) << o << ": " << r.output;
    EXPECT_NE(r.output.find("refusing"), std::string::npos) << r.output;
  }
}

TEST(Cli, AFailedRerunKeepsTheConvergedResult) {
  const fs::path d = scratch("cli_rerun");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz);
  const std::string run = "run " + (d / "case.toml").string() + " -q -o " + (d / "out").string();
  const auto ok = run_gfmd(run + " --set output.png=false");
  ASSERT_EQ(ok.code, 0) << ok.output;
  EXPECT_TRUE(ok.output.empty()) << "-q prints nothing on success: " << ok.output;
  const std::string summary = read_file(d / "out" / "summary.json");
  const std::string fields = read_file(d / "out" / "fields.nc");
  const auto bad = run_gfmd(run + " --set solver.max_iterations=2 --set load.force=0.02");
  EXPECT_EQ(bad.code, 3) << bad.output;
  EXPECT_NE(bad.output.find("kept unchanged"), std::string::npos) << bad.output;
  EXPECT_EQ(read_file(d / "out" / "summary.json"), summary);
  EXPECT_EQ(read_file(d / "out" / "fields.nc"), fields);
  EXPECT_EQ(status_of(d / "out"), "failed");
  EXPECT_FALSE(fs::exists(d / "out" / gfmd::kStagingName));
  // The next good run replaces it, and its directory is gfmd's: no --force needed.
  const auto again = run_gfmd(run + " --set load.force=0.02 --set output.png=false");
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_NE(read_file(d / "out" / "summary.json"), summary);
  EXPECT_EQ(status_of(d / "out"), "converged");
}

TEST(Cli, UnknownCommandsAndOverlongListsAreNamed) {
  const auto r = run_gfmd("rnu x.toml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("unknown command 'rnu'"), std::string::npos) << r.output;
  const fs::path d = scratch("cli_list");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz);
  std::string list = "1e-3";
  for (int i = 1; i <= 10000; ++i) list += ",1e-3";  // 10 001 values
  const auto l = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "s").string() +
                          " --set load.force=" + list);
  EXPECT_EQ(l.code, 2) << l.output.substr(0, 400);
  EXPECT_NE(l.output.find("--set load.force"), std::string::npos) << l.output.substr(0, 400);
  EXPECT_NE(l.output.find("at most 10000"), std::string::npos) << l.output.substr(0, 400);
  EXPECT_FALSE(fs::exists(d / "s"));
}

TEST(Cli, AnInterruptionWhileDrawingKeepsTheFinishedSolve) {
  // A drawing script that was interrupted exits 4: gfmd stops too (exit 4), but the solve had
  // finished: its data files are published without the figures (status.json says so; on a long
  // run the solve is hours, the figures seconds), and a resumed call finds the result. The
  // interpreter here stands in for a Python that was stopped while drawing (GFMD_PYTHON names
  // the drawing scripts' interpreter). It threw the solve away.
  const fs::path d = scratch("cli_draw_stop");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz);
  write_file(d / "stopped.sh", "#!/bin/sh\nexit 4\n");
  fs::permissions(d / "stopped.sh", fs::perms::owner_all);
  const std::string run = "run " + (d / "case.toml").string() + " -q -o " + (d / "out").string();
  ASSERT_EQ(run_gfmd(run + " --set output.png=false").code, 0);
  const std::string summary = read_file(d / "out" / "summary.json");
  const std::string stopped = "GFMD_PYTHON=" + (d / "stopped.sh").string() + " ";
  const auto r = gfmd::testing::run_gfmd_env(stopped, run + " --set load.force=0.02");
  EXPECT_EQ(r.code, 4) << r.output;
  EXPECT_NE(r.output.find("their figures may be missing: gfmd plot"), std::string::npos) << r.output;
  const std::string fresh = read_file(d / "out" / "summary.json");
  EXPECT_NE(fresh, summary);
  EXPECT_NE(fresh.find("\"force\": 0.02"), std::string::npos);
  EXPECT_TRUE(fs::exists(d / "out" / "fields.nc"));
  EXPECT_FALSE(fs::exists(d / "out" / "pressure.png"));
  EXPECT_FALSE(fs::exists(d / "out" / gfmd::kStagingName));
  EXPECT_EQ(status_of(d / "out"), "converged");
  EXPECT_NE(read_file(d / "out" / "status.json").find("their figures may be missing"), std::string::npos);
  const auto again = run_gfmd(run + " --set load.force=0.02 --resume");
  EXPECT_EQ(again.code, 0) << again.output;
  EXPECT_EQ(read_file(d / "out" / "summary.json"), fresh);  // found, not solved again
  // gfmd plot draws them, and status.json no longer says they may be missing.
  const auto drawn = run_gfmd("plot " + (d / "out").string());
  EXPECT_EQ(drawn.code, 0) << drawn.output;
  EXPECT_TRUE(fs::exists(d / "out" / "pressure.png"));
  EXPECT_EQ(read_file(d / "out" / "status.json").find("may be missing"), std::string::npos);
  EXPECT_EQ(status_of(d / "out"), "converged");
  // gfmd plot stops alike.
  const auto p = gfmd::testing::run_gfmd_env(stopped, "plot " + (d / "out").string());
  EXPECT_EQ(p.code, 4) << p.output;
}

// README's exit codes: an output directory that cannot be created is bad input (2), found before
// the solve, and the message names the path and the reason.
TEST(Cli, AnOutputDirectoryThatCannotBeCreatedIsBadInput) {
  const fs::path d = scratch("cli_uncreatable");
  write_file(d / "case.toml", gfmd::testing::kSmallHertz + "[output]\npng = false\nfields = false\n");
  write_file(d / "a_file", "not a directory\n");
  const std::string out = (d / "a_file" / "out").string();
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -q -o " + out);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot create the output directory"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(out), std::string::npos) << r.output;
  EXPECT_EQ(read_file(d / "a_file"), "not a directory\n");
}
