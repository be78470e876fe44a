// Hostile and careless use of the gfmd program: shell metacharacters in paths, two writers
// on one directory, stale outputs, a full disk, signals to every subcommand, bad
// command-line values. Each case is a defect once seen (issue 22) kept as a regression test.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return gfmd::testing::scratch_dir("abuse", name); }
using gfmd::testing::read_file;
using gfmd::testing::write_file;

std::string status_of(const fs::path& dir) {
  std::ifstream in(dir / "status.json");
  if (!in) return "";
  return nlohmann::json::parse(in).value("status", "");
}

// What a child process may be given before it runs gfmd.
struct ChildSetup {
  fs::path cwd;                   // working directory ("" = unchanged)
  long file_size_limit = -1;      // RLIMIT_FSIZE in bytes (SIGXFSZ ignored: writes fail with EFBIG)
  long address_space_limit = -1;  // RLIMIT_AS in bytes (ulimit -v)
  fs::path tmpfs;                 // mount a private tmpfs of tmpfs_kb here first (namespace)
  int tmpfs_kb = 0;
};

// gfmd started with an argument vector (no shell); output to a file.
class Gfmd {
 public:
  Gfmd(const std::vector<std::string>& args, const fs::path& log, const ChildSetup& s = {}) : log_(log) {
    pid_ = fork();
    if (pid_ == 0) {
      if (!s.tmpfs.empty()) {
        // A private mount namespace (root, or user namespaces): skip (77) where not allowed.
        if (unshare(CLONE_NEWNS) != 0 || mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
          _exit(77);
        const std::string opt = "size=" + std::to_string(s.tmpfs_kb) + "k";
        if (mount("tmpfs", s.tmpfs.c_str(), "tmpfs", 0, opt.c_str()) != 0) _exit(77);
      }
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
      }
      if (!s.cwd.empty() && chdir(s.cwd.c_str()) != 0) _exit(126);
      if (s.file_size_limit >= 0) {
        ::signal(SIGXFSZ, SIG_IGN);
        rlimit rl{static_cast<rlim_t>(s.file_size_limit), static_cast<rlim_t>(s.file_size_limit)};
        setrlimit(RLIMIT_FSIZE, &rl);
      }
      if (s.address_space_limit >= 0) {
        rlimit rl{static_cast<rlim_t>(s.address_space_limit), static_cast<rlim_t>(s.address_space_limit)};
        setrlimit(RLIMIT_AS, &rl);
      }
      std::vector<char*> argv;
      std::string exe = GFMD_EXE;
      argv.push_back(exe.data());
      std::vector<std::string> copy = args;
      for (auto& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      if (!s.tmpfs.empty()) {
        // Run gfmd as a grandchild, then leave what the tmpfs holds in a listing outside it
        // (the mount vanishes with this process).
        const pid_t g = fork();
        if (g == 0) {
          execv(GFMD_EXE, argv.data());
          _exit(127);
        }
        int st = 0;
        waitpid(g, &st, 0);
        std::ofstream listing(log.string() + ".listing");
        std::error_code ec;
        for (const auto& e : fs::recursive_directory_iterator(s.tmpfs, ec))
          listing << e.path().lexically_relative(s.tmpfs).string() << "\n";
        std::ifstream status(s.tmpfs / "out" / "status.json");
        listing << "STATUS " << std::string(std::istreambuf_iterator<char>(status), {}) << "\n";
        listing.close();
        _exit(WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0));
      }
      execv(GFMD_EXE, argv.data());
      _exit(127);
    }
  }
  void signal(int sig) const { kill(pid_, sig); }
  // Exit status (128 + signal number when killed).
  int wait() {
    if (done_) return code_;
    int st = 0;
    waitpid(pid_, &st, 0);
    done_ = true;
    code_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
    return code_;
  }
  // Whether it has exited within `seconds`.
  bool exits_within(double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      int st = 0;
      const pid_t r = waitpid(pid_, &st, WNOHANG);
      if (r == pid_) {
        done_ = true;
        code_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  [[nodiscard]] std::string output() const { return read_file(log_); }
  ~Gfmd() {
    if (!done_) {
      kill(pid_, SIGKILL);
      wait();
    }
  }

 private:
  pid_t pid_ = -1;
  fs::path log_;
  bool done_ = false;
  int code_ = -1;
};

ChildSetup in_dir(const fs::path& d) {
  ChildSetup s;
  s.cwd = d;
  return s;
}

int run(const std::vector<std::string>& args, const fs::path& log, const ChildSetup& s = {}) {
  Gfmd g(args, log, s);
  return g.wait();
}

const std::string& kHertz = gfmd::testing::kSmallHertz;

// Rough thin-layer sliding (the paper's Fig. 2e case) on 512^2: seconds per solve, so a
// signal after a fraction of a second always arrives during a solve.
const std::string kSlow = R"([grid]
nx = 512
lx = 2.0
[elastic]
poisson = 0.49
thickness = 0.05
[indenter]
type = "selfaffine"
lambda_long = 1.0
lambda_short = 0.03125
rms_gradient = 0.1
[load]
pressure = 0.1
[friction]
coefficient = 1.0
[output]
png = false
)";

}  // namespace

// `-o '/tmp/x$(touch PWNED)"q'` once ran the command in a shell and lost profiles.png.
TEST(Abuse, ShellMetacharactersInPathsAreData) {
  const fs::path d = scratch("shell");
  write_file(d / "case.toml", kHertz + "[friction]\ncoefficient = 1.0\n");
  const std::string out = (d / "x$(touch PWNED)\"q;`touch PWNED2`").string();
  ASSERT_EQ(run({"run", (d / "case.toml").string(), "-o", out, "-q"}, d / "log", in_dir(d)), 0)
      << read_file(d / "log");
  EXPECT_FALSE(fs::exists(d / "PWNED"));
  EXPECT_FALSE(fs::exists(d / "PWNED2"));
  EXPECT_TRUE(fs::exists(fs::path(out) / "summary.json"));
  EXPECT_TRUE(fs::exists(fs::path(out) / "profiles.png")) << "the plotting helper did not get the path";
  // A sweep plot with a quote in the --plot key and the directory: the key is data (a column
  // the summaries do not have: exit 2 naming it), the directory too.
  const std::string sout = (d / "s\"$(touch PWNED3)").string();
  EXPECT_EQ(run({"sweep", (d / "case.toml").string(), "-o", sout, "-q", "--set", "load.force=0.005,0.01",
                 "--plot", "relative_contact_area\"$(touch PWNED4)"},
                d / "log2", in_dir(d)),
            2)
      << read_file(d / "log2");
  EXPECT_NE(read_file(d / "log2").find("no column 'relative_contact_area\"$(touch PWNED4)'"),
            std::string::npos)
      << read_file(d / "log2");
  EXPECT_EQ(run({"sweep", (d / "case.toml").string(), "-o", sout, "-q", "--set", "load.force=0.005,0.01",
                 "--plot", "relative_contact_area"},
                d / "log3", in_dir(d)),
            0)
      << read_file(d / "log3");
  EXPECT_TRUE(fs::exists(fs::path(sout) / "sweep_relative_contact_area.png"));
  for (const char* f : {"PWNED3", "PWNED4"}) EXPECT_FALSE(fs::exists(d / f)) << f;
}

// Two runs into one directory once both exited 0 with summary.json from one and fields.nc
// from the other. Now the directory has one writer.
TEST(Abuse, SecondWriterIsRefusedAndWaitWaits) {
  const fs::path d = scratch("lock");
  write_file(d / "case.toml", kHertz);
  const fs::path out = d / "out";
  auto lock = std::make_unique<gfmd::DirectoryLock>(out.string());  // another writer holds it
  const std::string no_maps = "output.png=false";  // no maps needed here (matplotlib: ~1 s a run)
  ASSERT_EQ(run({"run", (d / "case.toml").string(), "-o", out.string(), "-q", "--set", no_maps}, d / "log"),
            2);
  EXPECT_NE(read_file(d / "log").find("in use by another gfmd run (process " + std::to_string(getpid())),
            std::string::npos)
      << read_file(d / "log");
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "status.json"));
  // With --wait it waits for the holder, then runs.
  Gfmd waiting({"run", (d / "case.toml").string(), "-o", out.string(), "-q", "--wait", "--set", no_maps},
               d / "log2");
  EXPECT_FALSE(waiting.exits_within(1.0)) << waiting.output();
  lock.reset();
  ASSERT_TRUE(waiting.exits_within(60.0));
  EXPECT_EQ(waiting.wait(), 0) << waiting.output();
  EXPECT_EQ(status_of(out), "converged");
  // Sweeps and flow runs take the same lock.
  lock = std::make_unique<gfmd::DirectoryLock>(out.string());
  EXPECT_EQ(run({"flow", out.string()}, d / "log3"), 2) << read_file(d / "log3");
  EXPECT_NE(read_file(d / "log3").find("in use by another gfmd run"), std::string::npos);
  EXPECT_EQ(run({"sweep", (d / "case.toml").string(), "-o", out.string(), "-q", "--set",
                 "load.force=0.005,0.01", "--set", no_maps},
                d / "log4"),
            2);
}

// Re-running into an old directory once kept its flow.json and slip maps.
TEST(Abuse, RerunRemovesStaleOutputs) {
  const fs::path d = scratch("stale");
  write_file(d / "friction.toml", kHertz + "[friction]\ncoefficient = 1.0\n[flow]\ndirection = \"both\"\n");
  write_file(d / "plain.toml", kHertz);
  const fs::path out = d / "out";
  ASSERT_EQ(run({"run", (d / "friction.toml").string(), "-o", out.string(), "-q"}, d / "log"), 0)
      << read_file(d / "log");
  for (const char* f : {"flow.json", "slip_longitudinal.png", "current_x.png", "dissipation.png"})
    ASSERT_TRUE(fs::exists(out / f)) << f;
  write_file(out / "notes.txt", "mine");
  ASSERT_EQ(run({"run", (d / "plain.toml").string(), "-o", out.string(), "-q"}, d / "log"), 0);
  for (const char* f : {"flow.json", "flow.nc", "slip_longitudinal.png", "current_x.png", "dissipation.png"})
    EXPECT_FALSE(fs::exists(out / f)) << f << " of the earlier run is still there";
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_EQ(read_file(out / "notes.txt"), "mine") << "a file gfmd did not write was touched";
  // A shorter sweep into a longer one's directory: the extra point and the old plot go.
  const fs::path sw = d / "sweep";
  ASSERT_EQ(
      run({"sweep", (d / "plain.toml").string(), "-o", sw.string(), "-q", "--set",
           "load.force=0.004,0.006,0.008", "--plot", "relative_contact_area", "--set", "output.png=false"},
          d / "log"),
      0)
      << read_file(d / "log");
  ASSERT_TRUE(fs::exists(sw / "point_002" / "summary.json"));
  ASSERT_EQ(run({"sweep", (d / "plain.toml").string(), "-o", sw.string(), "-q", "--set",
                 "load.force=0.004,0.006", "--plot", "mean_gap", "--set", "output.png=false"},
                d / "log"),
            0)
      << read_file(d / "log");
  EXPECT_FALSE(fs::exists(sw / "point_002"));
  EXPECT_FALSE(fs::exists(sw / "sweep_relative_contact_area.png"));
  EXPECT_TRUE(fs::exists(sw / "point_001" / "summary.json"));
}

// A write that fails (here: beyond RLIMIT_FSIZE, EFBIG) once segfaulted in HDF5's exit
// handler with status.json left "running".
TEST(Abuse, WriteFailureExitsCleanly) {
  const fs::path d = scratch("fsize");
  write_file(d / "case.toml", kHertz + "[friction]\ncoefficient = 1.0\n");
  const fs::path out = d / "out";
  ChildSetup s;
  s.file_size_limit = 64 * 1024;
  const int code = run({"run", (d / "case.toml").string(), "-o", out.string(), "-q"}, d / "log", s);
  const std::string log = read_file(d / "log");
  EXPECT_EQ(code, 1) << log;
  EXPECT_NE(log.find("fields.nc"), std::string::npos) << log;
  EXPECT_NE(log.find("File too large"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(status_of(out), "failed");
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

// The same with a real full disk: a 300 kB tmpfs in a private mount namespace.
TEST(Abuse, FullDiskExitsCleanly) {
  const fs::path d = scratch("fulldisk");
  write_file(d / "case.toml", kHertz + "[friction]\ncoefficient = 1.0\n");
  fs::create_directories(d / "tfs");
  ChildSetup s;
  s.tmpfs = d / "tfs";
  s.tmpfs_kb = 300;
  const int code =
      run({"run", (d / "case.toml").string(), "-o", (d / "tfs" / "out").string(), "-q"}, d / "log", s);
  if (code == 77) GTEST_SKIP() << "no private mount namespace here (needs root or user namespaces)";
  const std::string log = read_file(d / "log"), listing = read_file(d.string() + "/log.listing");
  EXPECT_EQ(code, 1) << log;
  EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;
  EXPECT_EQ(listing.find("summary.json"), std::string::npos) << listing;
  EXPECT_EQ(listing.find(".tmp."), std::string::npos) << listing;
  EXPECT_NE(listing.find("\"failed\""), std::string::npos) << listing;
}

// nx = 8192 under `ulimit -v 8000000` once died with a bare "std::bad_alloc": the memory
// check now reads RLIMIT_AS (and cgroup limits, MemAvailable) before allocating.
TEST(Abuse, MemoryLimitIsCheckedBeforeAllocating) {
  const fs::path d = scratch("rlimit_as");
  write_file(d / "case.toml", kHertz);
  ChildSetup s;
  s.address_space_limit = 1L << 30;
  const int code =
      run({"run", (d / "case.toml").string(), "-o", (d / "out").string(), "-q", "--set", "grid.nx=4096"},
          d / "log", s);
  const std::string log = read_file(d / "log");
  EXPECT_EQ(code, 2) << log;
  EXPECT_NE(log.find("RLIMIT_AS"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(d / "out"));
}

// percolation, ensemble and sweep once ran on for minutes after SIGINT and exited 0.
TEST(Abuse, SigintStopsEverySubcommand) {
  const fs::path d = scratch("sigint");
  write_file(d / "slow.toml", kSlow);
  const std::string c = (d / "slow.toml").string();
  const std::vector<std::vector<std::string>> commands = {
      {"run", c, "-o", (d / "run").string(), "-q"},
      {"sweep", c, "-o", (d / "sweep").string(), "-q", "--set", "load.pressure=0.1,0.2"},
      {"percolation", c, "--direction", "x", "-o", (d / "perc").string(), "-q"},
      {"ensemble", c, "--seeds", "0..3", "-o", (d / "ens").string(), "-q"}};
  for (int sig : {SIGINT, SIGTERM})
    for (const auto& args : commands) {
      Gfmd g(args, d / "log");
      std::this_thread::sleep_for(std::chrono::milliseconds(600));
      g.signal(sig);
      ASSERT_TRUE(g.exits_within(5.0)) << args[0] << " ran on after signal " << sig;
      EXPECT_EQ(g.wait(), 4) << args[0] << ": " << g.output();
      EXPECT_NE(g.output().find("interrupted"), std::string::npos) << args[0] << ": " << g.output();
    }
  EXPECT_EQ(status_of(d / "run"), "interrupted");
}

// The flow solve polls the stop request too (gfmd flow, and [flow] after a solve).
TEST(Abuse, FlowSolveHonoursStopRequest) {
  const gfmd::Grid g{64, 64, 1.0, 1.0};
  std::vector<double> gap(g.size());
  for (std::size_t i = 0; i < gap.size(); ++i)
    gap[i] = 1e-3 * (1.5 + std::sin(0.37 * static_cast<double>(i)));
  EXPECT_THROW(
      (void)gfmd::compute_leakage(g, gap.data(), {0.0}, 1e-10, gfmd::FlowSolver::Amg, [] { return true; }),
      gfmd::Interrupted);
  const auto ok =
      gfmd::compute_leakage(g, gap.data(), {0.0}, 1e-10, gfmd::FlowSolver::Amg, [] { return false; });
  EXPECT_GT(ok.flows.at(0).conductivity, 0.0);
}

// An interrupted run resumed: the summary counts the iterations and time of both sessions.
TEST(Abuse, ResumeReportsCumulativeWork) {
  const fs::path d = scratch("resume");
  std::string slow = kSlow;
  slow.replace(slow.find("nx = 512"), 8, "nx = 1024");  // a few seconds: stopped after one
  write_file(d / "slow.toml", slow);
  const fs::path out = d / "out";
  {
    Gfmd g({"run", (d / "slow.toml").string(), "-o", out.string(), "-q", "--checkpoint-interval", "0.2"},
           d / "log");
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    g.signal(SIGINT);
    ASSERT_EQ(g.wait(), 4) << g.output();
  }
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin"));
  gfmd::ContactFields f;
  gfmd::CheckpointProgress before;
  ASSERT_TRUE(gfmd::read_checkpoint((out / "checkpoint.bin").string(),
                                    gfmd::load_config((d / "slow.toml").string()), f, &before));
  EXPECT_GT(before.iterations, 0);
  EXPECT_GT(before.wall_time_s, 0.2);
  // The message and status.json count what the checkpoint counts (they once left out the
  // frictionless reference's iterations).
  const std::string said = "interrupted after " + std::to_string(before.iterations) + " iterations";
  EXPECT_NE(read_file(d / "log").find(said), std::string::npos) << read_file(d / "log");
  EXPECT_NE(read_file(out / "status.json").find(said), std::string::npos) << read_file(out / "status.json");
  ASSERT_EQ(run({"run", (d / "slow.toml").string(), "-o", out.string(), "-q", "--resume"}, d / "log2"), 0)
      << read_file(d / "log2");
  std::ifstream in(out / "summary.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_TRUE(j.contains("resumed"));
  EXPECT_EQ(j["resumed"]["iterations_before"].get<std::int64_t>(), before.iterations);
  EXPECT_GT(j["iterations"].get<std::int64_t>(), before.iterations);
  EXPECT_GT(j["wall_time_s"].get<double>(), before.wall_time_s);
}

// Command-line values out of range are refused before anything runs.
TEST(Abuse, BadCommandLineValuesAreRefused) {
  const fs::path d = scratch("cli");
  write_file(d / "case.toml", kHertz);
  write_file(d / "ens.toml", kSlow);
  const std::string c = (d / "case.toml").string();
  for (const char* v : {"-1", "0", "nan", "inf", "abc", "1e99"}) {
    EXPECT_EQ(run({"run", c, "-o", (d / "o").string(), "--checkpoint-interval", v}, d / "log"), 2) << v;
    EXPECT_NE(read_file(d / "log").find("--checkpoint-interval"), std::string::npos) << v;
  }
  for (const char* v : {"0..7x", "5..2", "-1..3", "0..100000", "a..b"})
    EXPECT_EQ(run({"ensemble", (d / "ens.toml").string(), "--seeds", v, "-o", (d / "e").string()}, d / "log"),
              2)
        << v << ": " << read_file(d / "log");
  EXPECT_FALSE(fs::exists(d / "o"));
  EXPECT_FALSE(fs::exists(d / "e"));
}

// --set values: passed on exactly (a sweep once turned 1e-7 into 0) and named in errors.
TEST(Abuse, SetValuesKeepTheirDigitsAndAppearInErrors) {
  const fs::path d = scratch("set");
  write_file(d / "egg.toml", R"([grid]
nx = 32
lx = 1.0
[indenter]
type = "eggcrate"
wavelength = 1.0
[load]
pressure = 0.01
[output]
png = false
)");
  ASSERT_EQ(run({"sweep", (d / "egg.toml").string(), "-o", (d / "s").string(), "-q", "--set",
                 "load.pressure=1e-7,2.5e-7"},
                d / "log"),
            0)
      << read_file(d / "log");
  std::ifstream in(d / "s" / "point_000" / "summary.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["input"]["load"]["pressure"].get<double>(), 1e-7);
  EXPECT_NEAR(j["mean_pressure"].get<double>(), 1e-7, 1e-20);
  std::ifstream in1(d / "s" / "point_001" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(in1)["input"]["load"]["pressure"].get<double>(), 2.5e-7);
  // A failing point: the error names the --set values, no empty point directory is left.
  EXPECT_EQ(run({"sweep", (d / "egg.toml").string(), "-o", (d / "f").string(), "-q", "--set",
                 "load.pressure=0.001,0.1", "--set", "solver.max_iterations=20"},
                d / "log"),
            3);
  const std::string log = read_file(d / "log");
  EXPECT_NE(log.find("[with --set load.pressure=0.001,0.1 solver.max_iterations=20]"), std::string::npos)
      << log;
  EXPECT_NE(log.find("point_001 (load.pressure = 0.1)"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(d / "f" / "point_000" / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "f" / "point_001"));
  EXPECT_EQ(run({"run", (d / "egg.toml").string(), "-o", (d / "r").string(), "-q", "--set",
                 "solver.max_iterations=2"},
                d / "log"),
            3);
  EXPECT_NE(read_file(d / "log").find("[with --set solver.max_iterations=2]"), std::string::npos)
      << read_file(d / "log");
}

// An ensemble run again reuses its finished seeds (as a sweep reuses its points).
TEST(Abuse, EnsembleReusesFinishedSeeds) {
  const fs::path d = scratch("ensemble");
  write_file(d / "ens.toml", R"([grid]
nx = 64
lx = 2.0
[indenter]
type = "selfaffine"
lambda_long = 1.0
lambda_short = 0.0625
rms_height = 0.01
[load]
pressure = 0.01
[friction]
coefficient = 0.5
[output]
png = false
)");
  const std::vector<std::string> args = {"ensemble", (d / "ens.toml").string(), "--seeds", "0..1",
                                         "-o",       (d / "e").string()};
  ASSERT_EQ(run(args, d / "log"), 0) << read_file(d / "log");
  const auto stamp = fs::last_write_time(d / "e" / "seed_1" / "summary.json");
  const std::string first = read_file(d / "e" / "ensemble.json");
  ASSERT_EQ(run(args, d / "log"), 0) << read_file(d / "log");
  EXPECT_NE(read_file(d / "log").find("(finished earlier)"), std::string::npos) << read_file(d / "log");
  EXPECT_EQ(fs::last_write_time(d / "e" / "seed_1" / "summary.json"), stamp);
  const auto a = nlohmann::json::parse(first),
             b = nlohmann::json::parse(read_file(d / "e" / "ensemble.json"));
  EXPECT_EQ(a["conductivity_x"], b["conductivity_x"]);
  // Each seed reports the solved mu of its summary.json (and mu_c apart), fresh or reused.
  for (const auto* j : {&a, &b}) {
    ASSERT_EQ((*j)["seeds"].size(), 4U);
    for (const auto& e : (*j)["seeds"]) {
      const bool frictionless = e["mu_c"].get<double>() == 0.0;
      const auto s = nlohmann::json::parse(read_file(
          d / "e" / ((frictionless ? "frictionless_seed_" : "seed_") + std::to_string(e["seed"].get<int>())) /
          "summary.json"));
      EXPECT_EQ(e["friction_coefficient"].get<double>(), s.value("friction_coefficient", 0.0));
      if (!frictionless) {
        EXPECT_GT(std::abs(e["friction_coefficient"].get<double>() - 0.5), 1e-6);
      }
    }
  }
  EXPECT_EQ(a["friction_coefficient"], b["friction_coefficient"]);
}

// An ensemble over a case with a friction law of its own: its frictionless half sets Coulomb's
// law at mu_c = 0 (setting only mu_c = 0 is refused with a law whose traction does not vanish
// there, which stopped the ensemble after its first seed).
TEST(Abuse, EnsembleOverAFrictionLawSolvesItsFrictionlessHalf) {
  const fs::path d = scratch("ensemble_law");
  write_file(d / "ens.toml", R"([grid]
nx = 32
lx = 2.0
[indenter]
type = "selfaffine"
lambda_long = 1.0
lambda_short = 0.125
rms_height = 0.01
[load]
pressure = 0.01
[friction]
coefficient = 0.3
law = "velocity"
static_coefficient = 0.5
velocity_scale = 0.1
regularization = 0.01
[output]
png = false
)");
  ASSERT_EQ(
      run({"ensemble", (d / "ens.toml").string(), "--seeds", "0..0", "-o", (d / "e").string()}, d / "log"), 0)
      << read_file(d / "log");
  const auto s = nlohmann::json::parse(read_file(d / "e" / "frictionless_seed_0" / "summary.json"));
  EXPECT_EQ(s["input"]["friction"]["coefficient"], 0.0);
  EXPECT_FALSE(s.contains("friction_coefficient"));
}
