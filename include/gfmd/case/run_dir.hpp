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

// Checkpoints: the solver state (pressure and friction traction) with the input it
// belongs to, written atomically. read_checkpoint returns false if the file is missing,
// unreadable or belongs to another input or grid.
void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress = {});
bool read_checkpoint(const std::string& path, const Config& cfg, ContactFields& f,
                     CheckpointProgress* progress = nullptr);
// The same file written a field at a time, for a writer that holds one whole field at once
// (rank 0 of a distributed run): the header on construction, then add() the pressure, tx
// and ty in this order (each cfg.grid.size() values, or empty: zeros), then commit(). Not
// committed, the file is not written (the temporary goes).
class CheckpointStream {
 public:
  CheckpointStream(const std::string& path, const Config& cfg, const CheckpointProgress& progress);
  void add(const RealField& field);
  void commit();

 private:
  AtomicFile file_;
  std::size_t n_;
  int added_ = 0;
};

// The summary.json in dir if it holds a converged solve of exactly this input.
std::optional<nlohmann::json> finished_summary(const std::string& dir, const Config& cfg);

// DIR/status.json: {"status": running|converged|failed|interrupted, "reason": ..., "pid": ...}.
void write_status(const std::string& dir, const std::string& status, const std::string& reason = "");
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
