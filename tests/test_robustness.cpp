// Interruption and resume, checkpoints, thread-count independence.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/surface/topography.hpp"

using namespace gfmd;
namespace fs = std::filesystem;

namespace {
const char* kSliding = R"(
[grid]
nx = 256
lx = 1.6
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
coefficient = 1.0
[solver]
tolerance = 1e-9
)";

double max_rel_diff(const RealField& a, const RealField& b) {
  double m = 0, d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    m = std::max(m, std::abs(a[i]));
    d = std::max(d, std::abs(a[i] - b[i]));
  }
  return d / m;
}
}  // namespace

TEST(Robustness, CheckpointsDoNotChangeTheBits) {
  // When checkpoints fall depends on the wall clock (and so on the machine and the process
  // count); the solve must not: a checkpoint sees the load-rescaled pressure, and the solve
  // goes on from its own state. A checkpoint at every poll (interval 0) against none: the
  // same iterations, pressure, tractions and friction coefficient, bit for bit. (Before,
  // the rescaling was applied early at a checkpoint: round-off differences, 4.4e-12 in mu at
  // 4096^2 between runs whose checkpoints fell differently.)
  const Config cfg = parse_config(kSliding, "t.toml", {"grid.nx=128"});
  const CaseResult ref = run_case(cfg);
  ASSERT_TRUE(ref.info.converged);
  const fs::path dir = fs::temp_directory_path() / ("gfmd_ckbits_" + std::to_string(getpid()));
  fs::create_directories(dir);
  RunOptions o;
  o.checkpoint_path = (dir / "checkpoint.bin").string();
  o.checkpoint_interval_s = 0.0;
  const CaseResult ck = run_case(cfg, o);
  ASSERT_TRUE(ck.info.converged);
  EXPECT_TRUE(fs::exists(o.checkpoint_path));
  EXPECT_EQ(ck.info.iterations, ref.info.iterations);
  EXPECT_EQ(ck.observables.friction_coefficient, ref.observables.friction_coefficient);
  EXPECT_TRUE(ck.fields.pressure == ref.fields.pressure);
  EXPECT_TRUE(ck.fields.tx == ref.fields.tx);
  fs::remove_all(dir);
}

TEST(Robustness, InterruptedSolveResumesToTheSameAnswer) {
  const Config cfg = parse_config(kSliding, "t.toml");
  const CaseResult ref = run_case(cfg);
  ASSERT_TRUE(ref.info.converged);
  const fs::path dir = fs::temp_directory_path() / ("gfmd_resume_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string ck = (dir / "checkpoint.bin").string();
  RunOptions o;
  int polls = 0;
  o.stop_request = [&polls] { return ++polls > 40; };
  o.checkpoint_path = ck;
  EXPECT_THROW(run_case(cfg, o), Interrupted);
  ContactFields state;
  ASSERT_TRUE(read_checkpoint(ck, cfg, state));
  // A checkpoint of another input is refused.
  ContactFields other;
  EXPECT_FALSE(read_checkpoint(ck, parse_config(kSliding, "t.toml", {"elastic.poisson=0.3"}), other));
  RunOptions r;
  r.warm_start = &state;
  const CaseResult resumed = run_case(cfg, r);
  ASSERT_TRUE(resumed.info.converged);
  std::printf("resume: uninterrupted mu = %.10f (%d it), resumed mu = %.10f (%d it after %d polls)\n",
              ref.observables.friction_coefficient, ref.info.iterations,
              resumed.observables.friction_coefficient, resumed.info.iterations, polls);
  EXPECT_NEAR(resumed.observables.friction_coefficient, ref.observables.friction_coefficient, 1e-7);
  EXPECT_NEAR(resumed.observables.relative_contact_area, ref.observables.relative_contact_area, 1e-12);
  EXPECT_LT(max_rel_diff(resumed.fields.pressure, ref.fields.pressure), 1e-6);
  fs::remove_all(dir);
}

TEST(Robustness, SigtermThenResumeFromTheCommandLine) {
  const fs::path dir = fs::temp_directory_path() / ("gfmd_sigterm_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kSliding;
  const std::string exe = GFMD_EXE;
  const std::string out = (dir / "out").string(), out2 = (dir / "out2").string();
  const pid_t pid = fork();
  if (pid == 0) {
    execl(exe.c_str(), exe.c_str(), "run", (dir / "case.toml").c_str(), "-o", out.c_str(), "-q", "--set",
          "grid.nx=512", "--checkpoint-interval", "0.1", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait for the first checkpoint, then stop the run.
  for (int i = 0; i < 600 && !fs::exists(fs::path(out) / "checkpoint.bin"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  EXPECT_EQ(WEXITSTATUS(status), 4);
  EXPECT_FALSE(fs::exists(fs::path(out) / "summary.json"));
  std::ifstream st(fs::path(out) / "status.json");
  EXPECT_EQ(nlohmann::json::parse(st)["status"], "interrupted");
  const std::string resume = exe + " run " + (dir / "case.toml").string() + " -o " + out +
                             " -q --set grid.nx=512 --resume > /dev/null 2>&1";
  ASSERT_EQ(std::system(resume.c_str()), 0);
  const std::string fresh =
      exe + " run " + (dir / "case.toml").string() + " -o " + out2 + " -q --set grid.nx=512 > /dev/null 2>&1";
  ASSERT_EQ(std::system(fresh.c_str()), 0);
  std::ifstream a(fs::path(out) / "summary.json"), b(fs::path(out2) / "summary.json");
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  EXPECT_NEAR(ja["friction_coefficient"].get<double>(), jb["friction_coefficient"].get<double>(), 1e-7);
  EXPECT_NEAR(ja["relative_contact_area"].get<double>(), jb["relative_contact_area"].get<double>(), 1e-12);
  EXPECT_FALSE(fs::exists(fs::path(out) / "checkpoint.bin"));
  fs::remove_all(dir);
}

TEST(Robustness, ResultsDoNotDependOnThreadCount) {
  const char* rough = R"(
[grid]
nx = 128
lx = 2.0
[elastic]
poisson = 0.49
thickness = 0.1
[indenter]
type = "selfaffine"
lambda_long = 1.0
lambda_short = 0.0625
rms_height = 0.01
seed = 3
[load]
pressure = 0.03
[friction]
coefficient = 1.0
)";
  const CaseResult one = run_case(parse_config(rough, "t.toml", {"solver.threads=1"}));
  const CaseResult two = run_case(parse_config(rough, "t.toml", {"solver.threads=2"}));
  ASSERT_TRUE(one.info.converged);
  ASSERT_TRUE(two.info.converged);
  const double d = max_rel_diff(one.fields.pressure, two.fields.pressure);
  std::printf("1 vs 2 threads: max relative pressure difference %.3e, iterations %d vs %d\n", d,
              one.info.iterations, two.info.iterations);
  EXPECT_LT(d, 1e-12);
  EXPECT_EQ(one.info.iterations, two.info.iterations);
  EXPECT_NEAR(one.observables.friction_coefficient, two.observables.friction_coefficient, 1e-12);
}

namespace {
// kSliding swept over three forces, without field outputs.
const std::string kSlidingSweep = std::string(kSliding) +
                                  "[output]\nfields = false\npng = false\n[sweep]\n"
                                  "parameter = \"load.force\"\nvalues = [0.002, 0.005, 0.01]\n";

// A fresh directory holding case.toml with `text`; the case file's path.
std::string write_case(const fs::path& dir, const std::string& text) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << text;
  return (dir / "case.toml").string();
}
}  // namespace

TEST(Robustness, InterruptedSweepKeepsFinishedPointsAndResumes) {
  const fs::path dir = fs::temp_directory_path() / ("gfmd_sweep_resume_" + std::to_string(getpid()));
  const std::string text = kSlidingSweep;
  const std::string path = write_case(dir, text);
  const Config cfg = load_config(path);
  SweepOptions o;
  int points_done = 0;
  o.on_point = [&](int done, int, const std::string&) { points_done = done; };
  // Stop during the third point's solve (the sweep polls once between points, the solve then
  // every few iterations).
  int polls = 0;
  o.stop_request = [&] { return points_done >= 2 && ++polls > 3; };
  EXPECT_THROW(run_sweep(path, cfg, (dir / "out").string(), o), Interrupted);
  std::ifstream t1(dir / "out" / "sweep.json");
  const auto partial = nlohmann::json::parse(t1);
  EXPECT_EQ(partial["completed"].get<int>(), 2);
  EXPECT_TRUE(fs::exists(dir / "out" / "point_002" / "checkpoint.bin"));
  // status.json says where it stopped: the sweep and its point interrupted, finished points converged.
  EXPECT_EQ(read_status((dir / "out").string()), "interrupted");
  EXPECT_EQ(read_status((dir / "out" / "point_002").string()), "interrupted");
  EXPECT_EQ(read_status((dir / "out" / "point_001").string()), "converged");
  // Resume: the finished points are reused, not recomputed.
  SweepOptions again;
  std::vector<std::string> messages;
  again.on_point = [&](int, int, const std::string& m) { messages.push_back(m); };
  run_sweep(path, cfg, (dir / "out").string(), again);
  ASSERT_EQ(messages.size(), 3u);
  EXPECT_NE(messages[0].find("reused"), std::string::npos);
  EXPECT_NE(messages[1].find("reused"), std::string::npos);
  EXPECT_EQ(messages[2].find("reused"), std::string::npos);
  std::ifstream t2(dir / "out" / "sweep.json");
  const auto full = nlohmann::json::parse(t2);
  EXPECT_EQ(full["completed"].get<int>(), 3);
  EXPECT_EQ(read_status((dir / "out").string()), "converged");
  EXPECT_EQ(read_status((dir / "out" / "point_002").string()), "converged");
  // Same answer as an uninterrupted solve of the last point.
  const CaseResult last = run_case(parse_config(kSliding, "t.toml", {"load.force=0.01"}));
  EXPECT_NEAR(full["points"][2]["friction_coefficient"].get<double>(), last.observables.friction_coefficient,
              1e-7);
  EXPECT_FALSE(fs::exists(dir / "out" / "point_002" / "checkpoint.bin"));
  fs::remove_all(dir);
}

// A sweep reads its case file once: a file edited while the sweep runs (a user preparing the
// next study) changes none of its points; every point is the text the sweep started from.
TEST(Robustness, ASweepReadsItsCaseFileOnce) {
  const fs::path dir = fs::temp_directory_path() / ("gfmd_sweep_once_" + std::to_string(getpid()));
  const std::string text = kSlidingSweep;
  const std::string path = write_case(dir, text);
  const Config cfg = load_config(path);
  SweepOptions o;
  o.on_point = [&](int done, int, const std::string&) {
    if (done == 1) {  // after the first point: another coefficient of friction in the file
      std::string edited = text;
      const std::string was = "coefficient = 1.0";
      const std::size_t at = edited.find(was);
      ASSERT_NE(at, std::string::npos);
      edited.replace(at, was.size(), "coefficient = 0.123");
      std::ofstream(dir / "case.toml") << edited;
    }
  };
  const nlohmann::json j = run_sweep(path, cfg, (dir / "out").string(), o);
  ASSERT_EQ(j["points"].get<int>(), 3);
  for (int i = 0; i < 3; ++i) {
    std::ifstream in(dir / "out" / sweep_point_name(static_cast<std::size_t>(i)) / "summary.json");
    const auto s = nlohmann::json::parse(in);
    EXPECT_EQ(s["input"]["friction"]["coefficient"], cfg.friction.coefficient) << "point " << i;
  }
  EXPECT_NE(cfg.friction.coefficient, 0.123);
  fs::remove_all(dir);
}

// A sweep over the load of a measured surface reads its heights once: a height file written
// again after the first point (a user re-exporting the map with another filter, same size) changes
// no point; every point is the surface the sweep started with.
TEST(Robustness, ASweepReadsItsHeightsOnce) {
  const fs::path dir = fs::temp_directory_path() / ("gfmd_sweep_heights_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Topography t = make_hertz(Grid{64, 64, 1.6, 1.6}, 1.0, 1.0);
  // The heights times `scale`, the first `n` rows and columns (a map of another size for n < 64).
  const auto write_heights = [&](double scale, int n = 64) {
    std::ofstream f(dir / "heights.txt");
    f.precision(17);
    f << "# lx = " << 1.6 * n / 64 << "\n# ly = " << 1.6 * n / 64 << "\n";
    for (int iy = 0; iy < n; ++iy) {
      for (int ix = 0; ix < n; ++ix)
        f << (ix ? " " : "") << scale * t.h[static_cast<std::size_t>(iy) * 64 + ix];
      f << "\n";
    }
  };
  write_heights(1.0);
  std::ofstream(dir / "case.toml") << "[elastic]\npoisson = 0.25\n[indenter]\ntype = \"file\"\n"
                                      "path = \"heights.txt\"\n[load]\nforce = 0.005\n[output]\n"
                                      "fields = false\npng = false\n[sweep]\nparameter = \"load.force\"\n"
                                      "values = [0.005, 0.01, 0.02]\n";
  const std::string path = (dir / "case.toml").string();
  const Config cfg = load_config(path);
  SweepOptions o;
  o.on_point = [&](int done, int, const std::string&) {
    if (done == 1) write_heights(2.0);
  };
  const nlohmann::json j = run_sweep(path, cfg, (dir / "out").string(), o);
  EXPECT_EQ(j["points"].get<int>(), 3);
  std::vector<double> rms;
  for (int i = 0; i < 3; ++i) {
    std::ifstream in(dir / "out" / sweep_point_name(static_cast<std::size_t>(i)) / "summary.json");
    rms.push_back(nlohmann::json::parse(in)["topography"]["rms_height"].get<double>());
  }
  EXPECT_GT(rms[0], 0.0);
  EXPECT_EQ(rms[1], rms[0]);
  EXPECT_EQ(rms[2], rms[0]);
  // Rewritten with another size, the file gives the next point another grid: the sweep stops
  // naming the reason, with the finished point published and nothing mixed.
  write_heights(1.0);
  o.on_point = [&](int done, int, const std::string&) {
    if (done == 1) write_heights(1.0, 48);
  };
  try {
    (void)run_sweep(path, load_config(path), (dir / "resized").string(), o);
    ADD_FAILURE() << "the sweep went on over a resized height file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the grid changed while the sweep ran"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(dir / "resized" / "point_000" / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "resized" / "point_001" / "summary.json"));
  fs::remove_all(dir);
}

TEST(Robustness, RangeSumsDoNotDependOnThreads) {
  // range_sums adds fixed blocks in order: the same bits with 1 and 2 threads, and the
  // exact sum of a series whose partial sums are representable.
  const std::size_t len = 100003;
  const auto run = [&](int nt) {
    const int saved = threads();
    set_threads(nt);
    const auto s = range_sums(len, 2, [](std::size_t i, double* acc) {
      acc[0] += 1.0 / (1.0 + static_cast<double>(i));
      acc[1] += static_cast<double>(i);
    });
    set_threads(saved);
    return s;
  };
  const auto one = run(1), two = run(2);
  EXPECT_EQ(one[0], two[0]);
  EXPECT_EQ(one[1], two[1]);
  EXPECT_EQ(one[1], static_cast<double>(len) * static_cast<double>(len - 1) / 2.0);
  EXPECT_NEAR(one[0], std::log(static_cast<double>(len)) + 0.5772156649, 1e-5);
}

// Resident set of this process in MiB.
static double rss_mib() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

TEST(Robustness, FreedGridFieldsGoBackToTheSystem) {
  // SuperLU_DIST, loaded with HYPRE, turns off glibc's mapping of large blocks and heap
  // trimming; src/core/fft.cpp restores both. Without that, a freed field stays resident.
  double during = 0;
  {
    RealField big(std::size_t{24} << 20, 1.0);  // 192 MiB, every page touched
    during = rss_mib();
  }
  const double after = rss_mib();
  std::printf("resident: %.0f MiB with a 192 MiB field, %.0f MiB after freeing it\n", during, after);
  EXPECT_GT(during - after, 150.0);
}

TEST(Robustness, HeapAllocationScopeKeepsBlocksUntilItEnds) {
  // Inside the scope (the flow solver's HYPRE calls) a freed block stays in the heap for
  // reuse; when the scope ends, the free heap pages go back to the system.
  const double before = rss_mib();
  double kept = 0;
  {
    const HeapAllocationScope heap_only(std::size_t{256} << 20);
    {
      std::vector<double> big(std::size_t{24} << 20, 1.0);  // 192 MiB, every page touched
      ASSERT_EQ(big[12345], 1.0);
    }
    kept = rss_mib();
  }
  const double after = rss_mib();
  std::printf("resident: %.0f MiB before, %.0f MiB in the scope after freeing 192 MiB, %.0f MiB after it\n",
              before, kept, after);
  EXPECT_GT(kept - before, 150.0);
  EXPECT_LT(after - before, 40.0);
}

TEST(Robustness, StressSummariesDoNotDependOnKeepingTheFields) {
  // Without fields.nc and PNG maps the CLI keeps only the stress summaries: the same
  // numbers and the same profiles.csv as with the fields kept.
  const std::string text =
      std::string(kSliding) + "[stress]\npost_analysis = true\ndepths = [0.02]\nprofiles = true\n";
  const Config cfg = parse_config(text, "t.toml", {"grid.nx=64", "solver.tolerance=1e-7"});
  RunOptions lean;
  lean.keep_stress_fields = false;
  const CaseResult a = run_case(cfg), b = run_case(cfg, lean);
  ASSERT_TRUE(a.info.converged) << a.info.status;
  ASSERT_TRUE(b.info.converged) << b.info.status;
  EXPECT_FALSE(a.stress.xx.empty());
  EXPECT_FALSE(a.principal.e1z.empty());
  EXPECT_TRUE(b.stress.xx.empty());
  EXPECT_TRUE(b.principal.s1.empty());
  ASSERT_TRUE(a.profiles && b.profiles);
  EXPECT_FALSE(a.profiles->columns.empty());
  EXPECT_EQ(a.profiles->columns, b.profiles->columns);
  EXPECT_EQ(a.profiles->s, b.profiles->s);
  EXPECT_EQ(a.profiles->values, b.profiles->values);
  nlohmann::json ja = summary_json(a), jb = summary_json(b);
  for (auto* j : {&ja, &jb}) j->erase("wall_time_s");
  ASSERT_TRUE(ja.contains("max_tensile_stress"));
  ASSERT_TRUE(ja.contains("post_analysis"));
  ASSERT_TRUE(ja.contains("subsurface"));
  EXPECT_EQ(ja["max_tensile_stress"], jb["max_tensile_stress"]);
  EXPECT_EQ(ja["max_von_mises"], jb["max_von_mises"]);
  EXPECT_EQ(ja["high_tension_area_fraction"], jb["high_tension_area_fraction"]);
  EXPECT_EQ(ja["post_analysis"], jb["post_analysis"]);
  EXPECT_EQ(ja["subsurface"], jb["subsurface"]);
  // The ratios are figures of the result (run_case), which the summary only writes.
  const std::optional<double>& tensile = a.post_analyses.front().ratio_max_tensile_stress;
  ASSERT_TRUE(tensile && a.comparisons.delta_mu_over_mu_c);
  EXPECT_EQ(*tensile,
            a.stress_summary->max_tensile_stress / a.post_analyses.front().summary.max_tensile_stress);
  EXPECT_EQ(ja["tensile_stress_ratio_to_post_analysis"].get<double>(), *tensile);
  EXPECT_EQ(ja["post_analysis"]["ratio_max_von_mises"].get<double>(),
            *a.post_analyses.front().ratio_max_von_mises);
  EXPECT_EQ(ja["delta_mu_over_mu_c"].get<double>(), *a.comparisons.delta_mu_over_mu_c);
  EXPECT_FALSE(
      outputs_need_stress_fields(parse_config(text, "t.toml", {"output.fields=false", "output.png=false"})));
  EXPECT_TRUE(outputs_need_stress_fields(parse_config(text, "t.toml", {"output.fields=false"})));
}
