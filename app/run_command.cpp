// gfmd run: one case into its run directory (RunDirectory), on one process or under mpirun.
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
#include "command_util.hpp"
#include "commands.hpp"
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
// What rank 0 of a distributed run tells the others once it has looked at the output
// directory: go on with the solve, stop (it failed), or stop with success (--resume of a
// case already solved).
constexpr int kDirectoryReady = 1, kDirectoryFailed = 2, kNothingToDo = 3;

// A rank other than 0 of a distributed run: waits for rank 0's directory, takes its part of
// the solves and leaves the outputs to rank 0. Its exit code follows the solve's outcome,
// which every rank shares.
int run_follower(const gfmd::Config& cfg, std::shared_ptr<gfmd::Topography> surface) {
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
  opts.made_surface = std::move(surface);
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
  // Validates the topography before anything is written; the solve takes these heights over.
  gfmd::MapReport report;
  auto surface = std::make_shared<gfmd::Topography>(gfmd::make_topography_here(cfg, &report));
  if (gfmd::mpi::distributed() && !gfmd::mpi::root()) return run_follower(cfg, std::move(surface));
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
  opts.made_surface = std::move(surface);
  opts.made_report = std::move(report);
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
  if (r.info.converged)
    for (const std::string& w : gfmd::solution_warnings(r.observables))
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

}  // namespace gfmd::cli
