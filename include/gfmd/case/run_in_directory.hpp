// A case solved into its run directory, as `gfmd run CASE -o DIR [--resume]` does, for every
// front end (the CLI, Python's gfmd.run and the figure studies): a finished result reused,
// an interrupted one continued from its checkpoint, the outputs staged and published whole.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/result.hpp"
#include "gfmd/case/run_directory.hpp"

namespace gfmd {

struct DirectoryRunOptions {
  // Reuse a finished result of the same case (nothing is solved) and continue an interrupted
  // one from its checkpoint; otherwise the case is solved afresh.
  bool resume = false;
  OutputDirOptions directory;  // force, wait; its stop_request is also the solve's
  std::function<void(const Progress&)> progress;
  double checkpoint_interval_s = 60.0;
  // Heights made by the caller (make_topography_here, which validates the case before
  // anything is written); made here when empty.
  std::shared_ptr<Topography> made_surface;
  MapReport made_report;
  // Draws the figures into the staging area before the outputs are published (the PNG maps
  // of output.png); may be empty. A stop request (Interrupted) while it draws publishes the
  // data files without the figures (DirectoryRun::published).
  std::function<void(const std::string& staging)> draw;
  // Called once the directory is looked at: nothing_to_do (a finished result reused) or the
  // solve begins (a distributed run tells its other processes).
  std::function<void(bool nothing_to_do)> on_ready;
  // Messages for the user on resuming: an earlier attempt that did not finish, whether the
  // checkpoint is used.
  std::function<void(const std::string&)> log;
  // Before an error of the solve or of writing is rethrown: the note on the previous result
  // that is kept ("the previous complete result in DIR/ is kept unchanged"), where there is one.
  std::function<void(const std::string&)> failure_note;
  // The result keeps every field (the stresses too), whatever the outputs write: for a caller
  // that hands the fields on (Python's gfmd.run(output=...)).
  bool keep_all_fields = false;
};

struct DirectoryRun {
  enum class Outcome {
    Solved,         // solved and published
    AlreadySolved,  // resume: DIR holds this case's result; nothing was done
    NotConverged,   // nothing published; status.json says why
    Interrupted,    // stopped; the solve's state is in the checkpoint (saved_state) or not, or the
                    // result is published without its figures (published)
  };
  Outcome outcome = Outcome::Solved;
  CaseResult result;         // Solved, NotConverged (its info)
  nlohmann::json finished;   // AlreadySolved: the summary.json found in DIR
  std::string why;           // NotConverged, Interrupted
  std::string note;          // "the previous complete result in DIR/ is kept unchanged", or ""
  std::string checkpoint;    // the checkpoint's path
  bool saved_state = false;  // Interrupted during the solve: continue with resume
  bool published = false;    // Interrupted while drawing: the results are published (kFiguresNotDrawn)
};

// Solves cfg into dir (RunDirectory: one writer, staged outputs). Bad input throws InputError
// before anything is written; an error of the solve or of writing marks status.json "failed",
// tells failure_note the note on the kept result and is rethrown.
DirectoryRun run_in_directory(const Config& cfg, const std::string& dir, DirectoryRunOptions opts);

}  // namespace gfmd
