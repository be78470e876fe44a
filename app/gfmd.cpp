// gfmd command line: thin front end over the library.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <new>
#include <sstream>

#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/studies/ensemble.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/version.hpp"

extern char** environ;

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }
// SIGINT/SIGTERM set a flag that every solve polls (no SA_RESTART: a wait returns early).
void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
bool stop_requested() { return g_stop != 0; }

// This program's own path (for helper scripts next to it and for study.py to call back).
std::filesystem::path self_exe() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path("gfmd") : p;
}

// The Python interpreter for the plotting helpers: $GFMD_PYTHON, else the one chosen at build
// time (Debian's, which has numpy and matplotlib).
std::string python_interpreter() {
  const char* env = std::getenv("GFMD_PYTHON");
  return env && *env ? env : GFMD_PYTHON;
}

// A helper script installed beside the program: <prefix>/share/gfmd/scripts next to
// <prefix>/bin/gfmd, or share/gfmd/scripts in the build tree. Empty if not found.
std::string find_script(const std::string& name) {
  const auto dir = self_exe().parent_path();
  for (const auto& cand :
       {dir / ".." / "share" / "gfmd" / "scripts" / name, dir / "share" / "gfmd" / "scripts" / name}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(cand, ec)) return cand.lexically_normal().string();
  }
  return "";
}

// Runs a program with an argument vector (never through a shell) and waits for it. Its
// standard output (and error, if quiet) go to /dev/null. Returns its exit status, or -1 if
// it could not be started or was killed. GFMD in its environment names this program.
int run_child(const std::vector<std::string>& args, bool quiet) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_store;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::strncmp(*e, "GFMD=", 5) != 0) env_store.emplace_back(*e);
  env_store.push_back("GFMD=" + self_exe().string());
  std::vector<char*> envp;
  for (auto& e : env_store) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  if (quiet) posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs a plotting helper; false (with nothing else done) if it is missing or fails.
bool run_script(const std::string& script, const std::vector<std::string>& args, bool quiet) {
  const std::string path = find_script(script);
  if (path.empty()) return false;
  std::vector<std::string> argv = {python_interpreter(), path};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_child(argv, quiet) == 0;
}

namespace fs = std::filesystem;

bool has_file(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  return fs::is_regular_file(dir / name, ec);
}

// Draws the PNG maps of run directories with plot_maps.py (matplotlib) from their fields.nc,
// or from the staging file write_outputs leaves when output.fields is off (removed here,
// drawn or not). `options` go before the directories (e.g. --profiles, --only current).
// Never throws: a failure is a warning (the data files are complete); returns false then.
bool draw_maps(const std::vector<std::string>& dirs, const std::vector<std::string>& options) {
  if (dirs.empty()) return true;
  bool ok = false, staged = false;
  try {
    std::vector<std::string> args = options;
    if (dirs.size() == 1 && has_file(dirs.front(), gfmd::kMapsStagingFile)) {
      args.emplace_back("--fields");
      args.push_back((fs::path(dirs.front()) / gfmd::kMapsStagingFile).string());
    }
    args.emplace_back("--");
    args.insert(args.end(), dirs.begin(), dirs.end());
    for (const auto& d : dirs) staged = staged || has_file(d, gfmd::kMapsStagingFile);
    ok = !find_script("plot_maps.py").empty() && run_script("plot_maps.py", args, false);
  } catch (const std::exception&) {
    ok = false;
  }
  for (const auto& d : dirs) {
    std::error_code ec;
    fs::remove(fs::path(d) / gfmd::kMapsStagingFile, ec);
  }
  if (!ok) {
    const std::string where = dirs.size() == 1 ? dirs.front() : std::to_string(dirs.size()) + " directories";
    std::fprintf(stderr,
                 "gfmd: warning: the PNG maps of %s were not (all) drawn (plot_maps.py with %s and "
                 "matplotlib)%s\n",
                 where.c_str(), python_interpreter().c_str(),
                 staged ? "" : "; the data files are complete: redraw with gfmd plot DIR");
  }
  return ok;
}

// The run directories below dir (point_NNN of a sweep, seed_N of an ensemble) whose maps
// are still to be drawn: a staging file of the maps, or output.png on, fields.nc there and
// no pressure.png (points finished earlier whose maps were not drawn are caught up too).
std::vector<std::string> runs_needing_maps(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_directory(ec) || !has_file(e.path(), "summary.json")) continue;
    bool need = has_file(e.path(), gfmd::kMapsStagingFile);
    if (!need && has_file(e.path(), "fields.nc") && !has_file(e.path(), "pressure.png")) {
      try {
        const auto j = nlohmann::json::parse(
            gfmd::read_regular_file((e.path() / "summary.json").string(), 64u << 20, "summary file"));
        need = j.at("input").at("output").at("png").get<bool>();
      } catch (const std::exception&) {
        need = false;
      }
    }
    if (need) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct ProgressPrinter {
  bool tty = isatty(STDERR_FILENO) != 0;
  bool quiet = false;
  bool verbose = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last = start;
  void operator()(const gfmd::Progress& p) {
    if (quiet) return;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last).count();
    if (verbose && p.outer > 0) {
      std::fprintf(stderr, "  friction step %3d: %6d iterations, traction change %.3e\n", p.outer,
                   p.iteration, p.error);
      return;
    }
    if (since < (tty ? 0.2 : 5.0)) return;
    last = now;
    const double el = std::chrono::duration<double>(now - start).count();
    if (tty)
      std::fprintf(stderr, "\r  iteration %6d  friction step %3d  change %.2e  %.1f s   ", p.iteration,
                   p.outer, p.error, el);
    else
      std::fprintf(stderr, "  iteration %d friction step %d change %.3e elapsed %.1f s\n", p.iteration,
                   p.outer, p.error, el);
  }
  void done() const {
    if (tty && !quiet) std::fprintf(stderr, "\r%80s\r", "");
  }
};

// " [with --set a=1 b=2]": errors name the overrides, the case file alone does not say what ran.
std::string sets_note(const std::vector<std::string>& sets) {
  if (sets.empty()) return "";
  std::string t = " [with --set";
  for (const auto& v : sets) t += " " + v;
  return t + "]";
}

int cmd_run(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
            bool quiet, bool verbose, bool resume, double checkpoint_s, bool wait) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / std::filesystem::path(case_path).stem()).string();
  namespace fs = std::filesystem;
  // Validates the topography before anything is written.
  (void)gfmd::make_topography(cfg);
  const gfmd::DirectoryLock lock(out_dir, wait, stop_requested);
  const std::string ckpt = (fs::path(out_dir) / "checkpoint.bin").string();
  gfmd::ContactFields warm;
  gfmd::CheckpointProgress done;
  bool have_warm = false;
  if (resume) {
    if (gfmd::finished_summary(out_dir, cfg)) {
      std::printf("%s: already solved in %s/ (summary.json); nothing to do\n", case_path.c_str(),
                  out_dir.c_str());
      return 0;
    }
    const std::string before = gfmd::read_status(out_dir);
    have_warm = gfmd::read_checkpoint(ckpt, cfg, warm, &done);
    if (!quiet) {
      // We hold the lock, so a "running" status was left by a process that died.
      if (before == "running")
        std::fprintf(stderr, "the previous run in %s/ did not finish (it crashed or was killed)\n",
                     out_dir.c_str());
      std::fprintf(stderr, "%s\n",
                   have_warm ? "resuming from the checkpoint" : "no usable checkpoint: starting afresh");
    }
  }
  // The run owns its directory: what an earlier run wrote there goes first.
  gfmd::clear_run_outputs(out_dir, have_warm);
  gfmd::write_status(out_dir, "running");
  ProgressPrinter pp;
  pp.quiet = quiet;
  pp.verbose = verbose;
  gfmd::RunOptions opts;
  opts.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  opts.stop_request = stop_requested;
  opts.checkpoint_path = ckpt;
  opts.checkpoint_interval_s = checkpoint_s;
  opts.keep_stress_fields = gfmd::outputs_need_stress_fields(cfg);
  if (have_warm) {
    opts.warm_start = &warm;
    opts.resumed = done;
  }
  // Every error from here on leaves status.json "failed" with the reason.
  const auto failed = [&](const std::string& why) {
    pp.done();
    try {
      gfmd::write_status(out_dir, "failed", why);
    } catch (const std::exception&) {
      // The status cannot be written either (disk full): the message on stderr remains.
    }
  };
  gfmd::CaseResult r;
  try {
    r = gfmd::run_case(cfg, opts);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    gfmd::write_status(out_dir, "interrupted", e.what());
    std::fprintf(stderr, "gfmd: %s: %s; state saved in %s, continue with --resume\n", case_path.c_str(),
                 e.what(), ckpt.c_str());
    return 4;
  } catch (const std::bad_alloc&) {
    failed("out of memory during the solve");
    throw;
  } catch (const std::exception& e) {
    failed(e.what());
    std::error_code ec;
    fs::remove(ckpt, ec);
    throw;
  }
  pp.done();
  if (!r.info.converged) {
    char why[512];
    std::snprintf(why, sizeof why,
                  "%s after %d iterations (pressure change %.3e, friction change %.3e, tolerance %.1e)",
                  r.info.status.c_str(), r.info.iterations, r.info.pk_error, r.info.friction_error,
                  cfg.solver.tolerance);
    failed(why);
    std::error_code ec;
    fs::remove(ckpt, ec);
    std::fprintf(stderr, "gfmd: error: %s: %s%s; no results written\n", case_path.c_str(), why,
                 sets_note(sets).c_str());
    return 3;
  }
  // The maps and profiles.png (output.png) are drawn from the data files just written.
  gfmd::publish_outputs(r, out_dir, [&] {
    if (cfg.output.png) (void)draw_maps({out_dir}, {"--profiles"});
  });
  std::error_code ec;
  fs::remove(ckpt, ec);
  const auto& o = r.observables;
  std::printf("%s: %s in %d iterations (%.2f s, residual %.2e)\n", case_path.c_str(), r.info.status.c_str(),
              r.info.iterations, r.info.wall_time_s, r.info.residual);
  std::printf("  relative contact area  %.6g\n", o.relative_contact_area);
  std::printf("  normal force           %.6g\n", o.normal_force);
  std::printf("  mean / max pressure    %.6g / %.6g\n", o.mean_pressure, o.max_pressure);
  std::printf("  mean gap               %.6g\n", o.mean_gap);
  if (cfg.friction.coefficient > 0) {
    std::printf("  friction coefficient   %.6g (dissipation)  %.6g (downhill)\n", o.friction_coefficient,
                o.friction_coefficient_downhill);
  }
  std::printf("  outputs in %s/\n", out_dir.c_str());
  return 0;
}

int cmd_sweep(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets_in,
              std::string plot, bool quiet, bool wait) {
  std::vector<std::string> sets;
  std::string param;
  std::vector<double> values;
  for (const auto& s : sets_in) {
    const auto eq = s.find('=');
    if (eq != std::string::npos && s.find(',', eq) != std::string::npos) {
      if (!param.empty())
        throw gfmd::InputError("--set " + s, "only one swept key per sweep (already sweeping " + param + ")");
      param = s.substr(0, eq);
      std::stringstream ss(s.substr(eq + 1));
      std::string tok;
      while (std::getline(ss, tok, ',')) {
        try {
          std::size_t used = 0;
          values.push_back(std::stod(tok, &used));
          if (used != tok.size()) throw std::invalid_argument(tok);
        } catch (const std::exception&) {
          throw gfmd::InputError("--set " + s, "'" + tok + "' is not a number");
        }
      }
    } else {
      sets.push_back(s);
    }
  }
  gfmd::Config cfg = gfmd::load_config(
      case_path, param.empty() ? sets : [&] {
        auto v = sets;
        v.push_back(param + "=" + gfmd::format_number(values.front()));
        return v;
      }());
  if (!param.empty()) {
    cfg.sweep.parameter = param;
    cfg.sweep.values = values;
  }
  if (!cfg.sweep.active())
    throw gfmd::InputError(case_path, "nothing to sweep: add --set section.key=v1,v2,... or a [sweep] table");
  if (plot.empty()) plot = cfg.sweep.plot;
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_sweep"))
                  .string();
  const gfmd::DirectoryLock lock(out_dir, wait, stop_requested);
  ProgressPrinter pp;
  pp.quiet = quiet;
  gfmd::SweepOptions so;
  so.overrides = sets;
  so.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  so.stop_request = stop_requested;
  const auto t0 = std::chrono::steady_clock::now();
  so.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!quiet)
      std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                   el / done * (total - done));
  };
  // The sweep re-reads the case for every point; [sweep] given on the command line is
  // passed on through the overrides-free config copy.
  const auto draw = [&] {
    return run_script("plot_sweep.py", {(std::filesystem::path(out_dir) / "sweep.csv").string(), "--y", plot},
                      false);
  };
  try {
    gfmd::run_sweep(case_path, cfg, out_dir, so);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    std::fprintf(stderr,
                 "gfmd: sweep interrupted (%s); finished points and a checkpoint are kept in %s/, run the "
                 "same command again to continue\n",
                 e.what(), out_dir.c_str());
    return 4;
  } catch (const gfmd::SolveError&) {
    // The finished points are kept: draw them before reporting the failure.
    pp.done();
    (void)draw_maps(runs_needing_maps(out_dir), {});
    if (std::filesystem::exists(std::filesystem::path(out_dir) / "sweep.csv") && draw())
      std::fprintf(stderr, "gfmd: the finished points are drawn in %s/sweep_%s.png\n", out_dir.c_str(),
                   plot.c_str());
    throw;
  }
  (void)draw_maps(runs_needing_maps(out_dir), {});
  std::printf("sweep of %s over %zu values: tables in %s/sweep.csv and sweep.json\n",
              cfg.sweep.parameter.c_str(), cfg.sweep.values.size(), out_dir.c_str());
  if (!draw())
    std::fprintf(stderr, "gfmd: warning: could not draw %s with matplotlib (%s)\n", plot.c_str(),
                 python_interpreter().c_str());
  else
    std::printf("  plot: %s/sweep_%s.png\n", out_dir.c_str(), plot.c_str());
  return 0;
}

int cmd_flow(const std::string& dir, const std::string& direction, double tol, const std::string& solver,
             bool wait) {
  gfmd::FlowSolver which;
  if (!gfmd::parse_flow_solver(solver, which))
    throw gfmd::InputError("--solver", "must be auto, amg or boomeramg, got '" + solver + "'");
  namespace fs = std::filesystem;
  const fs::path sp = fs::path(dir) / "summary.json";
  if (!fs::exists(sp)) throw gfmd::InputError(sp.string(), "no solved case here (run gfmd run first)");
  const std::string text = gfmd::read_regular_file(sp.string(), 64u << 20, "summary file");
  gfmd::require_regular_file((fs::path(dir) / "fields.nc").string(), "fields file");
  nlohmann::json s;
  try {
    s = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw gfmd::InputError(sp.string(), std::string("unreadable: ") + e.what());
  }
  gfmd::Grid g;
  try {
    const auto& gi = s.at("input").at("grid");
    g = gfmd::Grid{gi.at("nx").get<int>(), gi.at("ny").get<int>(), gi.at("lx").get<double>(),
                   gi.at("ly").get<double>()};
  } catch (const nlohmann::json::exception& e) {
    throw gfmd::InputError(sp.string(), std::string("not a gfmd summary (input.grid): ") + e.what());
  }
  int nx = 0, ny = 0;
  const std::vector<double> gap =
      gfmd::read_netcdf_field((fs::path(dir) / "fields.nc").string(), "gap", nx, ny);
  if (nx != g.nx || ny != g.ny) throw gfmd::InputError(dir, "fields.nc does not match summary.json");
  const std::vector<double> angles = gfmd::parse_flow_directions(direction);
  if (angles.empty())
    throw gfmd::InputError("--direction",
                           "must be x, y, both or an angle in degrees, got '" + direction + "'");
  const gfmd::DirectoryLock lock(dir, wait, stop_requested);
  const auto r = gfmd::compute_leakage(g, gap.data(), angles, tol, which, stop_requested);
  gfmd::write_leakage(g, r, dir, {{"relative_contact_area", s.value("relative_contact_area", 0.0)}});
  (void)draw_maps({dir}, {"--only", "current"});
  std::printf("%s/flow.json:\n%s\n", dir.c_str(), r.json.dump(2).c_str());
  return 0;
}

int cmd_percolation(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                    const std::string& direction, double area_tol, bool quiet, bool wait) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (direction != "x" && direction != "y") throw gfmd::InputError("--direction", "must be x or y");
  if (out_dir.empty())
    out_dir =
        (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_percolation"))
            .string();
  gfmd::PercolationOptions po;
  po.axis = direction == "x" ? 0 : 1;
  po.area_tolerance = area_tol;
  if (!quiet) po.log = [](const std::string& m) { std::fprintf(stderr, "  %s\n", m.c_str()); };
  po.stop_request = stop_requested;
  const gfmd::DirectoryLock lock(out_dir, wait, stop_requested);
  const nlohmann::json j = gfmd::find_percolation(cfg, po);
  gfmd::write_text_atomic((std::filesystem::path(out_dir) / "percolation.json").string(), j.dump(2) + "\n");
  std::printf(
      "critical relative contact area along %s: %.4f (pressure %.6g) after %d solves -> "
      "%s/percolation.json\n",
      direction.c_str(), j["critical_relative_contact_area"].get<double>(),
      j["critical_pressure"].get<double>(), j["solves"].get<int>(), out_dir.c_str());
  return 0;
}

int cmd_ensemble(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                 const std::string& seeds, bool quiet, bool wait) {
  int s0 = 0, s1 = 7, used = 0;
  if (std::sscanf(seeds.c_str(), "%d..%d%n", &s0, &s1, &used) != 2 ||
      used != static_cast<int>(seeds.size()) || s0 < 0 || s1 < s0)
    throw gfmd::InputError("--seeds", "expected FIRST..LAST, e.g. 0..7, got '" + seeds + "'");
  gfmd::EnsembleOptions eo;
  eo.first_seed = s0;
  eo.last_seed = s1;
  eo.overrides = sets;
  gfmd::check_ensemble(case_path, eo);  // before the output directory is made
  if (out_dir.empty())
    out_dir =
        (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_ensemble"))
            .string();
  const gfmd::DirectoryLock lock(out_dir, wait, stop_requested);
  eo.stop_request = stop_requested;
  if (!quiet) eo.on_seed = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  const nlohmann::json j = gfmd::run_ensemble(case_path, out_dir, eo);
  (void)draw_maps(runs_needing_maps(out_dir), {});
  const bool pairs = j.contains("frictionless");
  std::printf("%s/ensemble.json: K_x = %.4e, K_y = %.4e (Bruggeman over %d seeds)", out_dir.c_str(),
              j["conductivity_x"]["bruggeman"].get<double>(), j["conductivity_y"]["bruggeman"].get<double>(),
              s1 - s0 + 1);
  if (pairs)
    std::printf("; change through friction and coupling: x %+.1f %%, y %+.1f %%",
                100 * j["relative_change_x"].get<double>(), 100 * j["relative_change_y"].get<double>());
  std::printf("\n");
  return 0;
}

// The subdirectories of dir, sorted.
std::vector<fs::path> subdirs(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_directory(ec)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The columns of a CSV table's header line (gfmd's own tables: no quoted names).
std::vector<std::string> csv_columns(const fs::path& path) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> cols;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) cols.push_back(cell);
  return cols;
}

// gfmd plot DIR: redraws the figures of a run directory (maps from fields.nc, profiles.png
// from profiles.csv), of a sweep (its sweep_<y>.png plots, the default one if none, and the
// maps of its points), of an ensemble (its seeds' maps) or of a study (the maps and plots of
// its series; the study figure itself is drawn by gfmd study, which reuses every result).
int cmd_plot(const std::string& dir_in) {
  const fs::path dir(dir_in);
  const auto is_run = [](const fs::path& d) {
    return has_file(d, "summary.json") || has_file(d, "fields.nc") || has_file(d, gfmd::kMapsStagingFile);
  };
  const auto is_sweep = [](const fs::path& d) { return has_file(d, "sweep.csv"); };
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw gfmd::InputError(dir_in, "no such directory");
  const bool study = has_file(dir, "study.json"), ensemble = has_file(dir, "ensemble.json");
  if (!study && !ensemble && !is_sweep(dir) && !is_run(dir))
    throw gfmd::InputError(dir_in,
                           "not a gfmd run, sweep or study directory (no summary.json, fields.nc, sweep.csv, "
                           "study.json or ensemble.json in it)");
  const gfmd::DirectoryLock lock(dir_in, false, stop_requested);
  std::vector<fs::path> runs, sweeps;
  std::function<void(const fs::path&, int)> collect = [&](const fs::path& d, int depth) {
    if (is_sweep(d)) {
      sweeps.push_back(d);
      for (const auto& p : subdirs(d))
        if (is_run(p)) runs.push_back(p);
    } else if (is_run(d)) {
      runs.push_back(d);
    } else if (depth > 0) {
      for (const auto& p : subdirs(d)) collect(p, depth - 1);
    }
  };
  if (study || ensemble) {
    for (const auto& p : subdirs(dir)) collect(p, 1);
  } else {
    collect(dir, 0);
  }
  bool ok = true;
  int drawn = 0;
  std::vector<std::string> with_fields;
  for (const auto& d : runs) {
    if (has_file(d, "fields.nc") || has_file(d, gfmd::kMapsStagingFile)) {
      with_fields.push_back(d.string());
    } else if (has_file(d, "profiles.csv")) {
      if (run_script("plot_profiles.py", {(d / "profiles.csv").string()}, false))
        ++drawn;
      else
        ok = false;
      std::fprintf(stderr, "gfmd: note: %s has no fields.nc (output.fields = false): no maps drawn\n",
                   d.c_str());
    } else {
      std::fprintf(stderr, "gfmd: note: %s has no fields.nc (output.fields = false): nothing to draw\n",
                   d.c_str());
    }
  }
  if (!with_fields.empty()) {
    if (draw_maps(with_fields, {"--profiles"}))
      drawn += static_cast<int>(with_fields.size());
    else
      ok = false;
  }
  for (const auto& d : sweeps) {
    // The plots the sweep drew (sweep_<y>.png), else plot_sweep.py's default column.
    std::vector<std::string> ys;
    for (const auto& e : fs::directory_iterator(d, ec)) {
      const std::string name = e.path().filename().string();
      if (name.size() > 10 && name.rfind("sweep_", 0) == 0 && e.path().extension() == ".png" &&
          name.find(".tmp.") == std::string::npos)
        ys.push_back(name.substr(6, name.size() - 10));
    }
    std::sort(ys.begin(), ys.end());
    const auto cols = csv_columns(d / "sweep.csv");
    if (ys.empty() && std::find(cols.begin(), cols.end(), "friction_coefficient") != cols.end())
      ys.emplace_back("friction_coefficient");
    if (ys.empty())
      std::fprintf(stderr, "gfmd: note: %s: no sweep plot to redraw (draw one with gfmd sweep --plot KEY)\n",
                   d.c_str());
    for (const auto& y : ys) {
      if (run_script("plot_sweep.py", {(d / "sweep.csv").string(), "--y", y}, false)) {
        ++drawn;
      } else {
        ok = false;
        std::fprintf(stderr, "gfmd: warning: %s/sweep_%s.png not drawn\n", d.c_str(), y.c_str());
      }
    }
  }
  if (study) {
    std::string name = "the study";
    try {
      name = nlohmann::json::parse(
                 gfmd::read_regular_file((dir / "study.json").string(), 1u << 20, "study file"))
                 .at("study")
                 .get<std::string>();
    } catch (const std::exception&) {
      // The name is only for the note.
    }
    std::fprintf(stderr,
                 "gfmd: note: the figure of %s (%s/%s.png) is drawn by gfmd study with its study file, "
                 "which reuses every finished run\n",
                 name.c_str(), dir_in.c_str(), name.c_str());
  }
  std::printf("%s: %d figure sets redrawn (%zu run directories, %zu sweeps)%s\n", dir_in.c_str(), drawn,
              runs.size(), sweeps.size(), ok ? "" : "; some could not be drawn");
  return ok ? 0 : 1;
}

// Tabulates the dimensionless Green's tensor of SPEC §2 (frame with q along axis 1).
int cmd_green(const std::vector<double>& nus, double from, double to, int points, const std::string& out) {
  if (!(from > 0 && to > from) || points < 2)
    throw gfmd::InputError("gfmd green", "need 0 < --from < --to and --points >= 2");
  for (double nu : nus) gfmd::ElasticParams{1.0, nu, 1.0, true}.validate();
  std::ostringstream os;
  os.precision(12);
  os << "poisson,qh,phi11,phi22,phi33,im_phi13\n";
  for (double nu : nus)
    for (int i = 0; i < points; ++i) {
      const double qh = from * std::pow(to / from, static_cast<double>(i) / (points - 1));
      const gfmd::PhiRotated p = gfmd::phi_rotated(qh, nu);
      os << nu << "," << qh << "," << p.p11 << "," << p.p22 << "," << p.p33 << "," << p.p13 << "\n";
    }
  if (out.empty() || out == "-")
    std::fputs(os.str().c_str(), stdout);
  else
    gfmd::write_text_atomic(out, os.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gfmd: steady sliding contacts with full elastic coupling"};
  app.set_version_flag("--version", std::string(gfmd::kVersion) + " (" + gfmd::kGitCommit + ")");
  app.require_subcommand(1);

  std::string case_path, out_dir;
  std::vector<std::string> sets;
  bool quiet = false;
  auto* run = app.add_subcommand("run", "solve one case and write summary.json, fields.nc and PNG maps");
  run->add_option("case", case_path, "case file (TOML)")->required();
  run->add_option("-o,--output", out_dir, "output directory (default: out/<case name>)");
  run->add_option("--set", sets, "override a key: section.key=value (repeatable)");
  run->add_flag("-q,--quiet", quiet, "no progress display");
  bool verbose = false, resume = false;
  double checkpoint_s = 60.0;
  run->add_flag("-v,--verbose", verbose, "print every friction fixed-point step");
  run->add_flag("--resume", resume,
                "continue from DIR/checkpoint.bin (or do nothing if DIR holds the result)");
  run->add_option("--checkpoint-interval", checkpoint_s, "seconds between checkpoints (default 60)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(x >= 0.1 && x <= 1e9))
              return "must be a number of seconds in [0.1, 1e9], got '" + v + "'";
            return "";
          },
          "SECONDS"));
  bool wait = false;
  run->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  std::string plot;
  auto* sweep =
      app.add_subcommand("sweep", "solve a case for a list of values of one key, warm-starting each point");
  sweep->add_option("case", case_path, "case file (TOML)")->required();
  sweep->add_option("-o,--output", out_dir, "output directory (default: out/<case name>_sweep)");
  sweep->add_option("--set", sets, "override a key; one key may take a comma-separated list: the sweep");
  sweep->add_option("--plot", plot,
                    "summary key to plot against the swept value (default friction_coefficient)");
  sweep->add_flag("-q,--quiet", quiet, "no progress display");
  sweep->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  install_signal_handlers();
  std::vector<double> green_nu{0.0, 0.25, 0.49};
  double green_from = 1e-2, green_to = 1e2;
  int green_points = 121;
  auto* green = app.add_subcommand("green", "tabulate the Green's tensor Phi(qh) of a layer (CSV)");
  green->add_option("--poisson", green_nu, "Poisson ratios")->delimiter(',');
  green->add_option("--from", green_from, "smallest qh");
  green->add_option("--to", green_to, "largest qh");
  green->add_option("--points", green_points, "points per Poisson ratio (log spaced)");
  green->add_option("-o,--output", out_dir, "CSV file (default: standard output)");

  std::string flow_dir, direction = "both", seeds = "0..7";
  double flow_tol = 1e-10, area_tol = 0.002;
  std::string flow_solver = "auto";
  auto* flow = app.add_subcommand("flow", "Reynolds flow through the gap of a solved case directory");
  flow->add_option("dir", flow_dir, "a directory written by gfmd run")->required();
  flow->add_option("--direction", direction, "x, y or both (default)");
  flow->add_option("--tolerance", flow_tol, "relative residual of the linear solve (default 1e-10)");
  flow->add_option("--solver", flow_solver,
                   "linear solver: auto (ours, HYPRE's BoomerAMG if ours does not converge; default), amg or "
                   "boomeramg");
  flow->add_flag("--wait", wait, "if another gfmd run writes to the directory, wait for it");
  auto* perc =
      app.add_subcommand("percolation", "critical contact area at which the flow along a direction stops");
  perc->add_option("case", case_path, "case file (TOML)")->required();
  perc->add_option("--direction", direction, "x or y")->required();
  perc->add_option("-o,--output", out_dir, "output directory");
  perc->add_option("--set", sets, "override a key (repeatable)");
  perc->add_option("--area-tolerance", area_tol,
                   "stop when the bracket's contact areas differ by less (default 0.002)");
  perc->add_flag("-q,--quiet", quiet, "no log lines");
  perc->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");
  auto* ens =
      app.add_subcommand("ensemble", "flow over roughness seeds, Bruggeman average, friction on/off pairs");
  ens->add_option("case", case_path, "case file (TOML) with a selfaffine indenter")->required();
  ens->add_option("--seeds", seeds, "FIRST..LAST (default 0..7)");
  ens->add_option("-o,--output", out_dir, "output directory");
  ens->add_option("--set", sets, "override a key (repeatable)");
  ens->add_flag("-q,--quiet", quiet, "no log lines");
  ens->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  std::string plot_dir;
  auto* plot_cmd = app.add_subcommand(
      "plot", "redraw the figures (PNG maps, profiles, sweep plots) of a run, sweep or study directory");
  plot_cmd->add_option("dir", plot_dir, "a directory written by gfmd run, sweep, ensemble or study")
      ->required();

  std::string study_path;
  bool study_quick = false;
  auto* study = app.add_subcommand("study", "run a study of studies/ and draw its figure (matplotlib)");
  study->add_option("study", study_path, "study file (TOML)")->required();
  study->add_flag("--quick", study_quick, "reduced resolution that runs in minutes");
  study->add_option("-o,--output", out_dir, "output root (default out/studies)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help/version or the usage error
    return rc == 0 ? 0 : 2;
  }
  const auto with_sets = [&sets]() { return sets_note(sets); };
  try {
    if (run->parsed()) return cmd_run(case_path, out_dir, sets, quiet, verbose, resume, checkpoint_s, wait);
    if (sweep->parsed()) return cmd_sweep(case_path, out_dir, sets, plot, quiet, wait);
    if (flow->parsed()) return cmd_flow(flow_dir, direction, flow_tol, flow_solver, wait);
    if (perc->parsed()) return cmd_percolation(case_path, out_dir, sets, direction, area_tol, quiet, wait);
    if (ens->parsed()) return cmd_ensemble(case_path, out_dir, sets, seeds, quiet, wait);
    if (plot_cmd->parsed()) return cmd_plot(plot_dir);
    if (green->parsed()) return cmd_green(green_nu, green_from, green_to, green_points, out_dir);
    if (study->parsed()) {
      const std::string script = find_script("study.py");
      if (script.empty())
        throw gfmd::InputError("gfmd study", "study.py is not installed next to this program");
      std::vector<std::string> args = {python_interpreter(), script, study_path};
      if (study_quick) args.emplace_back("--quick");
      if (!out_dir.empty()) {
        args.emplace_back("-o");
        args.push_back(out_dir);
      }
      const int rc = run_child(args, false);
      if (stop_requested()) {
        // Ctrl-C reaches the driver and its runs too; finished runs are reused next time.
        std::fprintf(stderr, "gfmd: study interrupted; run the same command again to continue\n");
        return 4;
      }
      return rc == 0 ? 0 : 1;
    }
  } catch (const gfmd::InputError& e) {
    std::fprintf(stderr, "gfmd: error: %s%s\n", e.what(), with_sets().c_str());
    return 2;
  } catch (const gfmd::Interrupted& e) {
    std::fprintf(stderr, "gfmd: %s; stopped on request%s\n", e.what(), with_sets().c_str());
    return 4;
  } catch (const gfmd::SolveError& e) {
    std::fprintf(stderr, "gfmd: error: %s: %s%s%s\n", case_path.c_str(), e.what(), with_sets().c_str(),
                 run->parsed() ? "; no results written" : "");
    return 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "gfmd: error: out of memory%s (the memory check before the solve estimated less than was "
                 "available; lower grid.nx or free memory)\n",
                 with_sets().c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gfmd: error: %s%s\n", e.what(), with_sets().c_str());
    return 1;
  }
  return 0;
}
