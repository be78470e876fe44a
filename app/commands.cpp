#include "commands.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <new>
#include <sstream>

#include "child.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/studies/curve.hpp"
#include "gfmd/studies/ensemble.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/version.hpp"
#include "maps.hpp"

namespace gfmd::cli {

namespace fs = std::filesystem;

namespace {
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

}  // namespace

// " [with --set a=1 b=2]": errors name the overrides, the case file alone does not say what ran.
std::string sets_note(const std::vector<std::string>& sets) {
  if (sets.empty()) return "";
  std::string t = " [with --set";
  for (const auto& v : sets) t += " " + v;
  return t + "]";
}

namespace {
// The lock of an output directory: held by rank 0 alone under mpirun, its outcome (taken, or
// refused) agreed with the other processes; the lock itself in one process.
std::unique_ptr<gfmd::DirectoryLock> lock_on_root(const std::string& dir, DirFlags flags) {
  std::unique_ptr<gfmd::DirectoryLock> lock;
  gfmd::on_root([&] {
    gfmd::check_output_directory(dir, flags.force);
    lock = std::make_unique<gfmd::DirectoryLock>(dir, flags.wait, stop_requested);
  });
  return lock;
}

// What rank 0 of a distributed run tells the others once it has looked at the output
// directory: go on with the solve, stop (it failed), or stop with success (--resume of a
// case already solved).
constexpr int kDirectoryReady = 1, kDirectoryFailed = 2, kNothingToDo = 3;

// A rank other than 0 of a distributed run: waits for rank 0's directory, takes its part of
// the solves and leaves the outputs to rank 0. Its exit code follows the solve's outcome,
// which every rank shares.
int run_follower(const gfmd::Config& cfg) {
  switch (gfmd::mpi::from_root(0)) {
    case kDirectoryReady:
      break;
    case kNothingToDo:
      return 0;
    default:
      throw QuietExit{1};
  }
  gfmd::RunOptions opts;
  opts.stop_request = stop_requested;
  gfmd::CaseResult r;
  try {
    r = gfmd::run_case(cfg, opts);
  } catch (const gfmd::InputError&) {
    throw QuietExit{2};
  } catch (const gfmd::Interrupted&) {
    throw QuietExit{4};
  } catch (const gfmd::SolveError&) {
    throw QuietExit{3};
  }
  return r.info.converged ? 0 : 3;
}
}  // namespace

int cmd_run(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
            bool quiet, bool verbose, bool resume, double checkpoint_s, DirFlags dir_flags) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / std::filesystem::path(case_path).stem()).string();
  namespace fs = std::filesystem;
  // Validates the topography before anything is written.
  (void)gfmd::make_topography_here(cfg);
  if (gfmd::mpi::distributed() && !gfmd::mpi::root()) return run_follower(cfg);
  // Rank 0 of a distributed run tells the others what it found in the directory before they
  // start the solve: ready (it holds the lock and cleared it), nothing to do, or failed (if
  // anything below throws first).
  struct ReadyAgreement {
    bool told = false;
    void tell(int what) {
      told = true;
      (void)gfmd::mpi::from_root(what);
    }
    ~ReadyAgreement() {
      if (!told) (void)gfmd::mpi::from_root(kDirectoryFailed);
    }
  } ready;
  gfmd::RunDirectory rd(out_dir, {dir_flags.force, dir_flags.wait, stop_requested});
  const std::string ckpt = rd.checkpoint();
  gfmd::ContactFields warm;
  gfmd::CheckpointProgress done;
  bool have_warm = false;
  if (resume) {
    if (gfmd::finished_summary(out_dir, cfg)) {
      if (!quiet)
        std::printf("%s: already solved in %s/ (summary.json); nothing to do\n", case_path.c_str(),
                    out_dir.c_str());
      ready.tell(kNothingToDo);
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
  // The results go to a staging area first; the directory's previous result stays until the
  // new one is complete.
  if (!have_warm) {
    std::error_code ec;
    fs::remove(ckpt, ec);
  }
  rd.begin();
  ready.tell(kDirectoryReady);
  ProgressPrinter pp;
  pp.quiet = quiet;
  pp.verbose = verbose;
  gfmd::RunOptions opts;
  opts.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  opts.stop_request = stop_requested;
  opts.checkpoint_path = ckpt;
  opts.checkpoint_interval_s = checkpoint_s;
  opts.keep_stress_fields = gfmd::outputs_need_stress_fields(cfg);
  opts.whole_solution = false;  // the outputs ask for the fields they write (keep_stress_fields)
  if (have_warm) {
    opts.warm_start = &warm;
    opts.resumed = done;
  }
  // "; the previous complete result in DIR/ is kept unchanged", where there is one.
  const auto kept = [](const std::string& note) { return note.empty() ? std::string() : "; " + note; };
  // Every error from here on leaves status.json "failed" with the reason.
  const auto failed = [&](const std::string& why) {
    pp.done();
    return kept(rd.fail(why));
  };
  const auto interrupted = [&](const std::string& why) {
    pp.done();
    const std::string note = kept(rd.interrupt(why));
    std::fprintf(stderr, "gfmd: %s: %s; state saved in %s, continue with --resume%s\n", case_path.c_str(),
                 why.c_str(), ckpt.c_str(), note.c_str());
    return 4;
  };
  gfmd::CaseResult r;
  try {
    r = gfmd::run_case(cfg, opts);
  } catch (const gfmd::Interrupted& e) {
    return interrupted(e.what());
  } catch (const std::bad_alloc&) {
    const std::string note = failed("out of memory during the solve");
    if (!note.empty()) std::fprintf(stderr, "gfmd: %s\n", note.substr(2).c_str());
    throw;
  } catch (const std::exception& e) {
    const std::string note = failed(e.what());
    std::error_code ec;
    fs::remove(ckpt, ec);
    if (!note.empty()) std::fprintf(stderr, "gfmd: %s\n", note.substr(2).c_str());
    throw;
  }
  pp.done();
  if (r.map_report)
    for (const std::string& w : r.map_report->warnings)
      std::fprintf(stderr, "gfmd: warning: %s: %s\n", r.map_report->path.c_str(), w.c_str());
  for (const std::string& w :
       gfmd::plausibility_warnings(r.config, r.topography_stats, r.map_report ? &*r.map_report : nullptr))
    std::fprintf(stderr, "gfmd: warning: %s: %s\n", case_path.c_str(), w.c_str());
  if (!r.info.converged) {
    char why[512];
    std::snprintf(why, sizeof why,
                  "%s after %d iterations (pressure change %.3e, friction change %.3e, tolerance %.1e)",
                  r.info.status.c_str(), r.info.iterations, r.info.pk_error, r.info.friction_error,
                  cfg.solver.tolerance);
    const std::string note = failed(why);
    std::error_code ec;
    fs::remove(ckpt, ec);
    std::fprintf(stderr, "gfmd: error: %s: %s%s; no results written%s\n", case_path.c_str(), why,
                 sets_note(sets).c_str(), note.c_str());
    return 3;
  }
  // The data files, then the maps and profiles.png drawn from them (output.png), all in the
  // staging area; published together once complete.
  try {
    gfmd::publish_outputs(r, rd.staging(), [&] {
      if (cfg.output.png) (void)draw_maps({rd.staging()}, {"--profiles"});
    });
    if (stop_requested()) throw gfmd::Interrupted("interrupted while drawing the figures");
    rd.publish();
  } catch (const gfmd::Interrupted& e) {
    // The solve had finished: nothing is published, the same command solves it again.
    pp.done();
    const std::string note = kept(rd.interrupt(e.what()));
    std::fprintf(stderr, "gfmd: %s: %s; no results written%s\n", case_path.c_str(), e.what(), note.c_str());
    return 4;
  } catch (const std::exception& e) {
    const std::string note = failed(std::string("writing the outputs: ") + e.what());
    if (!note.empty()) std::fprintf(stderr, "gfmd: %s\n", note.substr(2).c_str());
    throw;
  }
  std::error_code ec;
  fs::remove(ckpt, ec);
  if (quiet) return 0;  // -q: only errors
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
    if (cfg.friction.rolling())
      std::printf("  tangential force       %.6g, %.6g (x, y)  traction coefficient %.6g\n",
                  o.tangential_force_x, o.tangential_force_y, o.traction_coefficient);
    if (o.stick_fraction > 0) std::printf("  stick fraction         %.6g of the contact\n", o.stick_fraction);
  }
  std::printf("  outputs in %s/\n", out_dir.c_str());
  return 0;
}

int cmd_sweep(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets_in,
              std::string plot, bool quiet, DirFlags dir_flags) {
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
        if (values.size() >= static_cast<std::size_t>(gfmd::kMaxSweepPoints))
          throw gfmd::InputError("--set " + param,
                                 "at most " + std::to_string(gfmd::kMaxSweepPoints) + " values in a sweep");
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
  const gfmd::Config cfg = param.empty() ? gfmd::load_config(case_path, sets) : [&] {
    try {
      return gfmd::sweep_config(case_path, sets, param, values);
    } catch (const gfmd::InputError& e) {
      if (e.where() == "values") throw gfmd::InputError("--set " + param, e.why());
      throw;
    }
  }();
  if (!cfg.sweep.active())
    throw gfmd::InputError(case_path, "nothing to sweep: add --set section.key=v1,v2,... or a [sweep] table");
  // An explicit column (--plot or the case's sweep.plot) is checked; the default is drawn
  // only where the summaries have it.
  const bool plot_option = !plot.empty();
  const bool plot_given = plot_option || cfg.sweep.plot != gfmd::SweepConfig{}.plot;
  if (plot.empty()) plot = cfg.sweep.plot;
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_sweep"))
                  .string();
  // Under mpirun rank 0 alone holds the directory, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  ProgressPrinter pp;
  pp.quiet = quiet || !root;
  gfmd::SweepOptions so;
  so.overrides = sets;
  so.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  so.stop_request = stop_requested;
  so.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  const auto t0 = std::chrono::steady_clock::now();
  // An explicit column is checked by the sweep on its first point.
  if (plot_given) {
    so.plot_column = plot;
    so.plot_key = plot_option ? "--plot" : "sweep.plot";
  }
  so.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (pp.quiet) return;
    std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                 el / done * (total - done));
  };
  // The sweep plot, drawn from the tables in `dir` (the staging area before they are published).
  const auto draw = [&](const std::string& dir) {
    return run_script("plot_sweep.py", {(std::filesystem::path(dir) / "sweep.csv").string(), "--y", plot},
                      false);
  };
  bool drawn = false;
  so.before_publish = [&](const std::string& staging) {
    (void)draw_maps(runs_needing_maps(staging), {});
    drawn = draw(staging);
  };
  try {
    gfmd::run_sweep(case_path, cfg, out_dir, so);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    if (!root) return 4;
    std::fprintf(stderr,
                 "gfmd: sweep interrupted (%s); finished points and a checkpoint are kept, run the same "
                 "command again to continue%s\n",
                 e.what(),
                 gfmd::read_status(out_dir) == "interrupted" &&
                         std::filesystem::exists(std::filesystem::path(out_dir) / gfmd::kStagingName)
                     ? ("; the previous result in " + out_dir + "/ is kept unchanged").c_str()
                     : "");
    return 4;
  } catch (const gfmd::SolveError& e) {
    pp.done();
    if (!root) throw;
    // A first attempt publishes its finished points (the message says so): draw them before
    // reporting the failure.
    if (std::string(e.what()).find("finished points are kept in") != std::string::npos &&
        std::filesystem::exists(std::filesystem::path(out_dir) / "sweep.csv")) {
      (void)draw_maps(runs_needing_maps(out_dir), {});
      if (draw(out_dir))
        std::fprintf(stderr, "gfmd: the finished points are drawn in %s/sweep_%s.png\n", out_dir.c_str(),
                     plot.c_str());
    }
    throw;
  }
  if (!root || quiet) return 0;
  std::printf("sweep of %s over %zu values: tables in %s/sweep.csv and sweep.json\n",
              cfg.sweep.parameter.c_str(), cfg.sweep.values.size(), out_dir.c_str());
  if (!drawn)
    std::fprintf(stderr, "gfmd: warning: could not draw %s with matplotlib (%s)\n", plot.c_str(),
                 python_interpreter().c_str());
  else
    std::printf("  plot: %s/sweep_%s.png\n", out_dir.c_str(), plot.c_str());
  return 0;
}

int cmd_curve(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
              const std::string& pressures, bool no_png, bool quiet, DirFlags dir_flags) {
  // Library errors name the parameter "pressures"; here it is the option --pressures.
  const auto as_option = [](const gfmd::InputError& e) {
    return e.where() == "pressures" ? gfmd::InputError("--pressures", e.why()) : e;
  };
  gfmd::Config cfg;
  bool png = false;
  try {
    const std::vector<double> ps = gfmd::curve_pressures(gfmd::parse_pressures(pressures));
    // What the case asks for with the user's overrides (its load, flow and figure settings).
    const gfmd::Config asked = gfmd::load_config(case_path, sets);
    png = asked.output.png && !no_png;
    cfg = gfmd::curve_config(case_path, sets, ps);
    if (!quiet && gfmd::mpi::root()) {
      if (!asked.flow.enabled)
        std::fprintf(stderr, "gfmd: the leakage is switched on for the curve (flow.enabled=true)\n");
      if (asked.load.mode != gfmd::LoadMode::Pressure)
        std::fprintf(stderr, "gfmd: the case's load.%s = %s is replaced by the curve's pressures\n",
                     asked.load.mode == gfmd::LoadMode::Force ? "force" : "approach",
                     gfmd::format_number(asked.load.value).c_str());
    }
  } catch (const gfmd::InputError& e) {
    throw as_option(e);
  }
  // Validates the topography before anything is written.
  (void)gfmd::make_topography_here(cfg);
  if (out_dir.empty())
    out_dir = (fs::path("out") / (fs::path(case_path).stem().string() + "_curve")).string();
  // Under mpirun rank 0 alone holds the directories, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  const auto lock = lock_on_root(out_dir, dir_flags);
  ProgressPrinter pp;
  pp.quiet = quiet || !root;
  gfmd::CurveOptions co;
  co.sweep.overrides = sets;
  co.sweep.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  co.sweep.stop_request = stop_requested;
  // The points are a sweep of their own in DIR/points, which holds its lock.
  co.sweep.directory = {false, dir_flags.wait, stop_requested};
  const auto t0 = std::chrono::steady_clock::now();
  co.sweep.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!pp.quiet)
      std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                   done > 0 ? el / done * (total - done) : 0.0);
  };
  const std::string csv = (fs::path(out_dir) / "curve.csv").string();
  const auto draw = [&] { return png && run_script("plot_curve.py", {csv}, false); };
  nlohmann::json j;
  try {
    j = gfmd::run_curve(case_path, cfg, out_dir, co);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    if (!root) return 4;
    std::fprintf(stderr,
                 "gfmd: curve interrupted (%s); finished points (tabulated in %s/curve.csv) and a checkpoint "
                 "are kept in %s/points/, run the same command again to continue\n",
                 e.what(), out_dir.c_str(), out_dir.c_str());
    return 4;
  } catch (const gfmd::SolveError&) {
    // The finished points are tabulated: draw them before reporting the failure.
    pp.done();
    if (root && fs::exists(csv) && draw())
      std::fprintf(stderr, "gfmd: the finished points are drawn in %s/curve.png\n", out_dir.c_str());
    throw;
  }
  pp.done();
  if (!root) return 0;
  if (!quiet) {
    std::printf("curve of %s over %zu pressures: %s/curve.csv and curve.json (runs in points/)\n",
                case_path.c_str(), cfg.sweep.values.size(), out_dir.c_str());
    const nlohmann::json& perc = j["percolation"];
    std::printf("  percolation threshold: %s\n", perc["message"].get<std::string>().c_str());
    for (const auto& [tag, d] : perc["directions"].items())
      if (d["pressure"] != perc["pressure"] || d["status"] != perc["status"])
        std::printf("    along %s alone: %s\n", tag.c_str(), d["message"].get<std::string>().c_str());
  }
  if (png) {
    if (draw()) {
      if (!quiet) std::printf("  plot: %s/curve.png\n", out_dir.c_str());
    } else if (stop_requested()) {
      throw gfmd::Interrupted("interrupted while drawing curve.png");
    } else {
      std::fprintf(stderr, "gfmd: warning: could not draw curve.png with matplotlib (%s)\n",
                   python_interpreter().c_str());
    }
  }
  return 0;
}

int cmd_flow(const std::string& dir, const std::string& direction, double tol, const std::string& solver,
             DirFlags dir_flags) {
  gfmd::FlowSolver which;
  if (!gfmd::parse_flow_solver(solver, which))
    throw gfmd::InputError("--solver", "must be auto, amg or boomeramg, got '" + solver + "'");
  namespace fs = std::filesystem;
  const fs::path sp = fs::path(dir) / "summary.json";
  if (!fs::exists(sp)) throw gfmd::InputError(sp.string(), "no solved case here (run gfmd run first)");
  const std::string text = gfmd::read_regular_file(sp.string(), 64u << 20, "summary file");
  const std::string fields = (fs::path(dir) / "fields.nc").string();
  if (!fs::exists(fields))
    throw gfmd::InputError(fields,
                           "no fields file: the run was made with output.fields = false (rerun it with "
                           "--set output.fields=true, or solve the leakage in the run itself: [flow] "
                           "enabled = true)");
  gfmd::require_regular_file(fields, "fields file");
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
  const std::vector<double> gap = gfmd::read_netcdf_field(fields, "gap", nx, ny);
  if (nx != g.nx || ny != g.ny) throw gfmd::InputError(dir, "fields.nc does not match summary.json");
  const std::vector<double> angles = gfmd::parse_flow_directions(direction);
  if (angles.empty())
    throw gfmd::InputError("--direction",
                           "must be x, y, both or an angle in degrees, got '" + direction + "'");
  gfmd::RunDirectory rd(dir, {dir_flags.force, dir_flags.wait, stop_requested, /*owns_status=*/false});
  const auto r = gfmd::compute_leakage(g, gap.data(), angles, tol, which, stop_requested);
  std::string unit;  // the case's grid.unit, if it named one
  if (const auto gi = s["input"]["grid"]; gi.contains("unit") && gi["unit"].is_string())
    unit = gi["unit"].get<std::string>();
  // flow.json, flow.nc and the current maps are staged and published together; the maps are
  // drawn there beside links to the run's summary and fields (the same files, published back
  // onto themselves).
  rd.begin();
  try {
    gfmd::write_leakage(g, r, rd.staging(),
                        {{"relative_contact_area", s.value("relative_contact_area", 0.0)}}, unit);
    for (const char* name : {"summary.json", "fields.nc"}) {
      std::error_code ec;
      fs::create_hard_link(fs::path(dir) / name, fs::path(rd.staging()) / name, ec);
      if (ec) fs::copy_file(fs::path(dir) / name, fs::path(rd.staging()) / name, ec);
    }
    (void)draw_maps({rd.staging()}, {"--only", "current"});
    if (stop_requested()) throw gfmd::Interrupted("interrupted while drawing the current maps");
    rd.publish([](const std::string& n) {
      return n == "flow.json" || n == "flow.nc" ||
             (n.rfind("current_", 0) == 0 && n.size() > 12 && n.compare(n.size() - 4, 4, ".png") == 0);
    });
  } catch (const gfmd::Interrupted& e) {
    (void)rd.interrupt(e.what());
    throw;
  } catch (const std::exception& e) {
    (void)rd.fail(std::string("gfmd flow: ") + e.what());
    throw;
  }
  std::printf("%s/flow.json:\n%s\n", dir.c_str(), r.json.dump(2).c_str());
  return 0;
}

int cmd_percolation(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                    const std::string& direction, double area_tol, bool quiet, DirFlags dir_flags) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (direction != "x" && direction != "y") throw gfmd::InputError("--direction", "must be x or y");
  if (out_dir.empty())
    out_dir =
        (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_percolation"))
            .string();
  gfmd::PercolationOptions po;
  po.axis = direction == "x" ? 0 : 1;
  po.area_tolerance = area_tol;
  // Under mpirun rank 0 alone holds the directory and prints; every process solves.
  const bool root = gfmd::mpi::root();
  if (!quiet && root) po.log = [](const std::string& m) { std::fprintf(stderr, "  %s\n", m.c_str()); };
  po.stop_request = stop_requested;
  const auto lock = lock_on_root(out_dir, dir_flags);
  const nlohmann::json j = gfmd::run_percolation(cfg, po, out_dir);
  if (!root || quiet) return 0;
  std::printf(
      "critical relative contact area along %s: %.4f (pressure %.6g) after %d solves -> "
      "%s/percolation.json\n",
      direction.c_str(), j["critical_relative_contact_area"].get<double>(),
      j["critical_pressure"].get<double>(), j["solves"].get<int>(), out_dir.c_str());
  return 0;
}

int cmd_ensemble(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                 const std::string& seeds, bool quiet, DirFlags dir_flags) {
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
  // Under mpirun rank 0 alone holds the directory, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  eo.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  eo.before_publish = [](const std::string& staging) { (void)draw_maps(runs_needing_maps(staging), {}); };
  eo.stop_request = stop_requested;
  if (!quiet && root)
    eo.on_seed = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  const nlohmann::json j = gfmd::run_ensemble(case_path, out_dir, eo);
  if (!root || quiet) return 0;
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

// Tabulates the dimensionless Green's tensor of SPEC §2 (frame with q along axis 1).
int cmd_green(const std::vector<double>& nus, double from, double to, int points, const std::string& out) {
  if (!(from > 0 && to > from) || points < 2)
    throw gfmd::InputError("gfmd green", "need 0 < --from < --to and --points >= 2");
  for (double nu : nus) {
    try {
      gfmd::ElasticParams{1.0, nu, 1.0, true}.validate();
    } catch (const gfmd::ParameterError& e) {
      throw gfmd::InputError("gfmd green --poisson", e.why());
    }
  }
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

int cmd_study(const std::string& study_path, bool quick, const std::string& out_dir,
              const std::vector<std::string>& sets, bool quiet, bool force) {
  const std::string script = find_script("study.py");
  if (script.empty()) throw gfmd::InputError("gfmd study", "study.py is not installed next to this program");
  std::vector<std::string> args = {python_interpreter(), script, study_path};
  if (quick) args.emplace_back("--quick");
  if (quiet) args.emplace_back("--quiet");
  if (force) args.emplace_back("--force");
  if (!out_dir.empty()) {
    args.emplace_back("-o");
    args.push_back(out_dir);
  }
  for (const std::string& kv : sets) {
    args.emplace_back("--set");
    args.push_back(kv);
  }
  const int rc = run_child(args, false, /*keep_stdout=*/true);
  if (stop_requested() || rc == 4) {
    // Ctrl-C reaches the driver and its runs too; finished runs are reused next time. The
    // driver says so itself when it saw the request.
    if (rc != 4) std::fprintf(stderr, "gfmd: study interrupted; run the same command again to continue\n");
    return 4;
  }
  // The driver reports its own errors: bad input (2), a failed run (3), others (1).
  return rc == 0 || rc == 2 || rc == 3 ? rc : 1;
}

}  // namespace gfmd::cli
