// A case solved into its run directory (gfmd run -o DIR [--resume]) for every front end.
#include "gfmd/case/run_in_directory.hpp"

#include <cstdio>
#include <filesystem>
#include <new>
#include <utility>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

namespace fs = std::filesystem;

DirectoryRun run_in_directory(const Config& cfg, const std::string& dir, DirectoryRunOptions opts) {
  const auto log = [&](const std::string& m) {
    if (opts.log && !m.empty()) opts.log(m);
  };
  if (!opts.made_surface)
    opts.made_surface = std::make_shared<Topography>(make_topography_here(cfg, &opts.made_report));
  const std::function<bool()> stop = opts.directory.stop_request;
  OutputDirOptions as_run = opts.directory;
  as_run.kind = "run";
  // A backend that cannot run the case is refused before the directory is made, unless the
  // directory holds this case's finished result, which a resume reuses without solving.
  try {
    (void)solve_backend(cfg);
  } catch (const InputError&) {
    if (!(opts.resume && finished_summary(dir, cfg))) throw;
  }
  RunDirectory rd(dir, as_run);
  DirectoryRun out;
  out.checkpoint = rd.checkpoint();
  ContactFields warm;
  CheckpointProgress done;
  bool have_warm = false;
  if (opts.resume) {
    if (auto finished = finished_summary(dir, cfg)) {
      if (opts.on_ready) opts.on_ready(true);
      out.outcome = DirectoryRun::Outcome::AlreadySolved;
      out.finished = std::move(*finished);
      return out;
    }
    const std::string before = read_status(dir);
    std::string why;
    have_warm = read_checkpoint(out.checkpoint, cfg, warm, &done, &why);
    // This writer holds the lock, so a "running" status was left by a process that died.
    if (before == "running")
      log("the previous run in " + dir + "/ did not finish (it crashed or was killed)");
    log(have_warm ? "resuming from the checkpoint" : "no usable checkpoint (" + why + "): starting afresh");
  }
  std::error_code ec;
  if (!have_warm) fs::remove(out.checkpoint, ec);
  // The results go to a staging area first; the directory's previous result stays until the
  // new one is complete.
  rd.begin();
  if (opts.on_ready) opts.on_ready(false);
  RunOptions ro;
  ro.progress = opts.progress;
  ro.stop_request = stop;
  ro.checkpoint_path = out.checkpoint;
  ro.checkpoint_interval_s = opts.checkpoint_interval_s;
  ro.keep_stress_fields = opts.keep_all_fields || outputs_need_stress_fields(cfg);
  ro.whole_solution = false;  // the outputs ask for the fields they write (keep_stress_fields)
  ro.made_surface = std::move(opts.made_surface);
  ro.made_report = std::move(opts.made_report);
  if (have_warm) {
    ro.warm_start = &warm;
    ro.resumed = done;
  }
  // Every error from here on leaves status.json "failed" with the reason.
  const auto failed = [&](const std::string& why) {
    const std::string note = rd.fail(why);
    if (opts.failure_note && !note.empty()) opts.failure_note(note);
  };
  try {
    out.result = run_case(cfg, ro);
  } catch (const Interrupted& e) {
    out.outcome = DirectoryRun::Outcome::Interrupted;
    out.why = e.what();
    out.note = rd.interrupt(e.what());
    out.saved_state = true;
    return out;
  } catch (const std::bad_alloc&) {
    failed("out of memory during the solve");
    throw;
  } catch (const std::exception& e) {
    failed(e.what());
    fs::remove(out.checkpoint, ec);
    throw;
  }
  if (!out.result.info.converged) {
    const auto& i = out.result.info;
    // The status whole (a long one names its cure and the docs' section), then the counts.
    char counts[160];
    std::snprintf(counts, sizeof counts,
                  " after %d iterations (pressure change %.3e, friction change %.3e, tolerance %.1e)",
                  i.iterations, i.pk_error, i.friction_error, cfg.solver.tolerance);
    out.outcome = DirectoryRun::Outcome::NotConverged;
    out.why = i.status + counts;
    out.note = rd.fail(out.why);
    fs::remove(out.checkpoint, ec);
    return out;
  }
  // The data files, then the figures drawn from them, all in the staging area; published
  // together once complete. A stop while the figures are drawn does not throw the finished
  // solve away (on a long run the figures are seconds, the solve hours): the data files are
  // whole and are published, with status.json saying the figures may be missing; `gfmd plot
  // DIR` draws them, and a resumed call finds the result.
  bool drawing_stopped = false, while_drawing = false;
  try {
    publish_outputs(out.result, rd.staging(), [&] {
      if (!opts.draw) return;
      try {
        opts.draw(rd.staging());
      } catch (const Interrupted&) {
        while_drawing = true;
      }
    });
    drawing_stopped = while_drawing || (stop && stop());
    if (drawing_stopped)
      rd.publish(is_gfmd_output_name, "converged", std::string(kFiguresNotDrawn));
    else
      rd.publish();
  } catch (const std::exception& e) {
    failed(std::string("writing the outputs: ") + e.what());
    throw;
  }
  fs::remove(out.checkpoint, ec);
  if (drawing_stopped) {
    out.outcome = DirectoryRun::Outcome::Interrupted;
    out.why = while_drawing ? "interrupted while drawing the figures"
                            : "interrupted after the solve, as its outputs were written";
    out.published = true;
  }
  return out;
}

}  // namespace gfmd
