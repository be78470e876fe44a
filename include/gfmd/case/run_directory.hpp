// The life cycle of an output directory, for every front end: which directories may be
// written (gfmd's own, or any with force), the one-writer lock, a staging directory the new
// results are written into, and their publication in place of the previous ones only when
// they are complete. A failed or interrupted attempt leaves the previous result untouched.
#pragma once

#include <functional>
#include <string>

#include "gfmd/case/run_dir.hpp"

namespace gfmd {

struct OutputDirOptions {
  bool force = false;  // write into a non-empty directory that gfmd did not create
  bool wait = false;   // wait for another writer instead of refusing
  std::function<bool()> stop_request;
  // Whether status.json follows this writer's attempts (not for an addition to a finished run,
  // such as gfmd flow's files, which leaves the run's status alone).
  bool owns_status = true;
  // What this writer makes ("run", "sweep", "ensemble"): a directory holding another kind of
  // result (result_kind) is refused unless force; "" checks none.
  std::string kind = "";
};

// The marker of a directory gfmd created (every gfmd writer leaves it): its lock file.
inline constexpr const char* kDirectoryMarker = ".gfmd.lock";
// Where a directory's next results are written before they are published (inside it, so that
// a publication is a rename on one file system and the lock covers it).
inline constexpr const char* kStagingName = ".gfmd-staging";

// Creates dir (and its parents) as gfmd's: with the marker, so that later writers (gfmd flow
// on a sweep point, a re-run) accept it. For the directories a study makes inside its own.
void make_gfmd_directory(const std::string& dir);

// Refuses an output directory that must not be written, with InputError naming it: "" ; the
// root directory, the home directory and the working directory (always); an existing
// non-directory; a non-empty directory without gfmd's marker, or one holding another kind of
// result than `kind` ("run", "sweep", ...: result_kind; "" checks none) (unless force).
// Creates nothing.
void check_output_directory(const std::string& dir, bool force, const std::string& kind = "");
// The kind of gfmd result a directory holds, by its main table: "study", "ensemble", "curve",
// "percolation", "sweep", "run" (summary.json), or "" (none).
std::string result_kind(const std::string& dir);

// Whether a file or folder name in a run directory is one of gfmd's outputs (summary.json,
// fields.nc, the maps, tables, flow files, the checkpoint, the staging area, temporaries).
bool is_run_output_name(const std::string& name);
// The same for a sweep's own files (sweep.csv, sweep.json, sweep_*.png, point_NNN folders).
bool is_sweep_output_name(const std::string& name);
// Any output of any gfmd writer (a run's, a sweep's, an ensemble's, a curve's, a percolation
// search's): a new result published into a directory replaces every kind, so that a run
// written where a sweep was leaves no point of it beside its own files.
bool is_gfmd_output_name(const std::string& name);

// status.json's reason of a result published without (all) its figures: a stop came while they
// were drawn (the data files are whole).
inline constexpr const char* kFiguresNotDrawn =
    "interrupted while drawing the figures: the results are whole, their figures may be missing (gfmd "
    "plot DIR draws them)";

class RunDirectory {
 public:
  // Checks dir (check_output_directory), creates it, takes its lock and finishes or removes
  // what an earlier attempt left in the staging area (keep_staging: an interrupted study's
  // finished parts stay for reuse). Throws InputError (refused, in use) or Interrupted.
  explicit RunDirectory(const std::string& dir, const OutputDirOptions& opts = {}, bool keep_staging = false);
  // An attempt neither published nor ended (fail, interrupt): its staging area goes and
  // status.json says "failed" (an error the caller did not settle), not "running".
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  [[nodiscard]] const std::string& dir() const { return dir_; }
  // The staging area (created on first use by begin()).
  [[nodiscard]] const std::string& staging() const { return staging_; }
  // The solver's checkpoint of this directory (beside the published result, not staged: a
  // resumed attempt reads it; publish() removes it with the other outputs the new set lacks).
  [[nodiscard]] std::string checkpoint() const;
  // Whether the directory held a complete result (status.json "converged") when it was opened.
  [[nodiscard]] bool had_result() const { return had_result_; }

  // Starts an attempt: the staging area exists, status.json says "running".
  void begin();
  // Moves what was staged into the directory, replacing files of the same name; then removes
  // the directory's outputs (owned) that the new set does not have, and the staging area;
  // status.json: `status` ("converged"; a study that publishes what it finished before it
  // failed or was stopped says so, with the reason). A crash in the middle is finished by the
  // next opening.
  void publish(const std::function<bool(const std::string&)>& owned = is_gfmd_output_name,
               const std::string& status = "converged", const std::string& why = "");
  // Ends a failed attempt: staging removed (unless keep_staging: a study's finished parts wait
  // there for the same command), status.json "failed" with the reason and whether an earlier
  // result is still there. Returns the sentence for the user ("" if none kept).
  std::string fail(const std::string& why, bool keep_staging = false);
  // Ends an interrupted attempt: status "interrupted"; the staging area stays only if
  // keep_staging (its finished parts are reused by the same command), else it goes.
  std::string interrupt(const std::string& why, bool keep_staging = false);

 private:
  void write_state(const std::string& status, const std::string& why);
  std::string kept_note() const;
  std::string dir_, staging_;
  DirectoryLock lock_;
  bool owns_status_ = true;
  bool had_result_ = false, open_attempt_ = false;
};

}  // namespace gfmd
