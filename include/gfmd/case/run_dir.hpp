// Run directories: checkpoints, status.json, the one-writer lock, clearing stale outputs.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gfmd/case/result.hpp"
#include "gfmd/core/files.hpp"

namespace gfmd {

// Checkpoints: the solver state with the input it belongs to, written atomically: the
// pressure and friction traction (a warm start) and, in progress.state, where the solves
// stood (SolveResume: the frictionless reference's result, the friction solve's restart
// point), so that a resumed run goes on where it stopped. read_checkpoint returns false if
// the file is missing, unreadable, of an older format or belongs to another input or grid;
// with `progress` it fills the counts and the state (whole-grid fields); with `why`, the reason
// it was not used (e.g. the keys whose values differ from the checkpoint's input).
void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress = {});
bool read_checkpoint(const std::string& path, const Config& cfg, ContactFields& f,
                     CheckpointProgress* progress = nullptr, std::string* why = nullptr);
// The same file written a field at a time, for a writer that holds one whole field at once
// (rank 0 of a distributed run): the header on construction, then add() the pressure, tx
// and ty in this order (each cfg.grid.size() values, or empty: zeros); then, with a state,
// add_state() with its numbers and add() each field resume_fields lists for it, in that order
// (whole fields; those on the mixing's support are stored there only); then commit(). Not
// committed, the file is not written (the temporary goes).
class CheckpointStream {
 public:
  CheckpointStream(const std::string& path, const Config& cfg, const CheckpointProgress& progress);
  void add(const RealField& field);
  // reference_info: the converged reference's (its pressure is the first state field);
  // friction: the restart point's numbers (its fields follow). Either may be null. adhesive:
  // adhesive tractions follow (resume_fields).
  // adhesive_restart: a frictionless adhesive solve's restart point (its fields follow).
  void add_state(const SolveInfo* reference_info, const FrictionRestart* friction, bool adhesive = false,
                 const AdhesiveRestart* adhesive_restart = nullptr);
  void commit();

 private:
  AtomicFile file_;
  std::size_t n_;
  int added_ = 0;
  bool state_ = false;
  std::string kinds_;                      // the state fields still expected: F whole, S support, C on it
  std::vector<unsigned char> on_support_;  // the support's points (from its field)
  std::size_t support_points_ = 0;
};
// A checkpoint state's per-point fields in file order: the reference's pressure (if any) and,
// with adhesion, its adhesive traction; with adhesion the fields' adhesive traction; then the
// friction restart's support, splitting variable (have_z), the mixer's last iterate and
// residual and each slot's df and dx (with a mixer); then an adhesive restart point's repulsive
// pressure, kept image and (with a mixer) last iterate, residual and each slot's df and dx.
// Fields as they are (not resized). The adhesive tractions are listed where given (non-null).
std::vector<const RealField*> resume_fields(const RealField* reference_pressure,
                                            const RealField* reference_adhesion, const RealField* adhesion,
                                            const FrictionRestart* friction,
                                            const AdhesiveRestart* adhesive_restart = nullptr);
std::vector<RealField*> resume_fields(RealField* reference_pressure, RealField* reference_adhesion,
                                      RealField* adhesion, FrictionRestart* friction,
                                      AdhesiveRestart* adhesive_restart = nullptr);
// Those of a state, as read (the adhesive tractions where state.adhesive).
std::vector<RealField*> resume_fields(SolveResume& state);
std::vector<const RealField*> resume_fields(const SolveResume& state);
// The state's numbers (the same on every process) as bytes and back (a distributed run
// hands rank 0's to the others); decode returns false on damaged bytes.
std::string encode_resume_numbers(const SolveInfo* reference_info, const FrictionRestart* friction,
                                  bool adhesive = false, const AdhesiveRestart* adhesive_restart = nullptr);
bool decode_resume_numbers(const std::string& bytes, SolveResume& state);

// The summary.json in dir if it holds a converged solve of exactly this input.
std::optional<nlohmann::json> finished_summary(const std::string& dir, const Config& cfg);

// DIR/status.json: {"status": running|converged|failed|interrupted, "reason": ..., "pid": ...,
// "result": what the directory's results are, when they are not this attempt's}.
void write_status(const std::string& dir, const std::string& status, const std::string& reason = "",
                  const std::string& result = "");
// DIR/status.json's status ("" when missing or unreadable).
std::string read_status(const std::string& dir);

// One writer per output directory: an advisory lock (flock) on DIR/.gfmd.lock, held while
// the object lives (and released by the kernel if the process dies). Creates DIR. Another
// holder makes the constructor throw InputError(DIR, "... in use by process N ...") or, with
// wait, poll until it is free (stop_request true: Interrupted).
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& dir, bool wait = false,
                         const std::function<bool()>& stop_request = {});
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// Removes what an earlier run wrote into dir (summary.json, fields.nc, flow.json, maps,
// tables, status, checkpoint, staged temporaries) so that a new run's outputs never mix with
// stale ones; other files are left alone. Returns the names removed.
std::vector<std::string> clear_run_outputs(const std::string& dir, bool keep_checkpoint = false);

}  // namespace gfmd
