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
#include "gfmd/case/run_in_directory.hpp"
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
  ProgressPrinter pp;
  pp.quiet = quiet;
  pp.verbose = verbose;
  gfmd::DirectoryRunOptions opts;
  opts.resume = resume;
  opts.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  opts.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  opts.checkpoint_interval_s = checkpoint_s;
  opts.made_surface = std::move(surface);
  opts.made_report = std::move(report);
  // The data files, then the maps and profiles.png drawn from them (output.png).
  opts.draw = [&cfg](const std::string& staging) {
    if (cfg.output.png) (void)draw_maps({staging}, {"--profiles"});
  };
  opts.on_ready = [&ready](bool nothing_to_do) {
    ready.tell(nothing_to_do ? kNothingToDo : kDirectoryReady);
  };
  opts.log = [quiet](const std::string& m) {
    if (!quiet) std::fprintf(stderr, "%s\n", m.c_str());
  };
  opts.failure_note = [&pp](const std::string& note) {
    pp.done();
    std::fprintf(stderr, "gfmd: %s\n", note.c_str());
  };
  // "; the previous complete result in DIR/ is kept unchanged", where there is one.
  const auto kept = [](const std::string& note) { return note.empty() ? std::string() : "; " + note; };
  const gfmd::DirectoryRun run = gfmd::run_in_directory(cfg, out_dir, std::move(opts));
  pp.done();
  using Outcome = gfmd::DirectoryRun::Outcome;
  switch (run.outcome) {
    case Outcome::AlreadySolved:
      if (!quiet)
        std::printf("%s: already solved in %s/ (summary.json); nothing to do\n", case_path.c_str(),
                    out_dir.c_str());
      return 0;
    case Outcome::Interrupted:
      if (run.published)
        std::fprintf(stderr,
                     "gfmd: %s: %s; the results are in %s/ (summary.json and the data files), their figures "
                     "may be missing: gfmd plot %s draws them\n",
                     case_path.c_str(), run.why.c_str(), out_dir.c_str(), out_dir.c_str());
      else if (run.saved_state)
        std::fprintf(stderr, "gfmd: %s: %s; state saved in %s, continue with --resume%s\n", case_path.c_str(),
                     run.why.c_str(), run.checkpoint.c_str(), kept(run.note).c_str());
      else
        std::fprintf(stderr, "gfmd: %s: %s; no results written%s\n", case_path.c_str(), run.why.c_str(),
                     kept(run.note).c_str());
      return 4;
    case Outcome::NotConverged:  // its warnings first, below
    case Outcome::Solved:
      break;
  }
  const gfmd::CaseResult& r = run.result;
  if (r.map_report)
    for (const std::string& w : r.map_report->warnings)
      std::fprintf(stderr, "gfmd: warning: %s: %s\n", r.map_report->path.c_str(), w.c_str());
  for (const std::string& w :
       gfmd::plausibility_warnings(r.config, r.topography_stats, r.map_report ? &*r.map_report : nullptr))
    std::fprintf(stderr, "gfmd: warning: %s: %s\n", case_path.c_str(), w.c_str());
  if (r.info.converged)
    for (const std::string& w : gfmd::solution_warnings(r.observables))
      std::fprintf(stderr, "gfmd: warning: %s: %s\n", case_path.c_str(), w.c_str());
  if (run.outcome == Outcome::NotConverged) {
    std::fprintf(stderr, "gfmd: error: %s: %s%s; no results written%s\n", case_path.c_str(), run.why.c_str(),
                 sets_note(sets).c_str(), kept(run.note).c_str());
    return 3;
  }
  if (quiet) return 0;  // -q: only errors
  const auto& o = r.observables;
  std::printf("%s: %s in %d iterations (%.2f s, residual %.2e)\n", case_path.c_str(), r.info.status.c_str(),
              r.info.iterations, r.info.wall_time_s, r.info.residual);
  std::printf("  relative contact area  %.6g\n", o.relative_contact_area);
  std::printf("  normal force           %.6g\n", o.normal_force);
  std::printf("  mean / max pressure    %.6g / %.6g\n", o.mean_pressure, o.max_pressure);
  std::printf("  mean gap               %.6g\n", o.mean_gap);
  if (cfg.friction.coefficient > 0) {
    if (o.viscoelastic)  // its downhill force holds the body's hysteresis too (printed below)
      std::printf("  friction coefficient   %.6g (the interface's, from its dissipation)\n",
                  o.friction_coefficient);
    else
      std::printf("  friction coefficient   %.6g (dissipation)  %.6g (downhill)\n", o.friction_coefficient,
                  o.friction_coefficient_downhill);
    if (cfg.friction.rolling())
      std::printf("  tangential force       %.6g, %.6g (x, y)  traction coefficient %.6g\n",
                  o.tangential_force_x, o.tangential_force_y, o.traction_coefficient);
    if (o.stick_fraction > 0) std::printf("  stick fraction         %.6g of the contact\n", o.stick_fraction);
  }
  if (o.viscoelastic) {
    // The body's hysteresis: the force of the asymmetric pressure per normal force, and with
    // friction the interface's and the body's together (the drive's force per normal force).
    std::printf("  hysteresis friction    %.6g (the body's)\n", o.hysteresis_friction);
    if (o.friction)
      std::printf("  total friction coeff.  %.6g (interface + hysteresis)\n", o.total_friction_coefficient);
  }
  std::printf("  outputs in %s/\n", out_dir.c_str());
  return 0;
}

}  // namespace gfmd::cli
