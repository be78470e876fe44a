// One case from configuration to outputs: config -> topography + body -> solve ->
// fields -> observables -> summary.json, fields.nc, PNG maps.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/contact/observables.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd {

// Work done before a checkpoint: a resumed run reports cumulative counts.
struct CheckpointProgress {
  std::int64_t iterations = 0;
  double wall_time_s = 0.0;
};

struct CaseResult {
  Config config;
  Topography topography;
  TopographyStats topography_stats;
  ContactFields fields;
  SolveInfo info;
  Observables observables;
  // Frictionless solve at the same load (with friction and friction_reference).
  bool has_reference = false;
  Observables reference;
  SolveInfo reference_info;
  RealField reference_pressure;          // frictionless pressure (with friction_reference)
  RealField reference_ux, reference_uy;  // and its in-plane displacements (post_analysis "paper")
  // Stresses (SPEC §5): summaries when has_stress (a converged solve); the fields only if
  // RunOptions::keep_stress_fields.
  bool has_stress = false;
  std::string profiles_csv;  // profiles.csv (stress.profiles)
  StressField stress;
  PrincipalField principal;
  StressSummary stress_summary;
  // Post-analysis references, one per kind of [stress] post_analysis, in its order (empty:
  // none asked for); the outputs show the first also under the names of earlier versions.
  struct PostAnalysis {
    std::string kind;  // "paper" or "consistent"
    StressSummary summary;
    double area_above_half_max = 0;  // fraction of cells with s1 >= 0.5 max s1 of this field
    RealField s1;                    // sigma_I
  };
  std::vector<PostAnalysis> post_analyses;
  double area_above_half_max = 0;  // the full solution's, as PostAnalysis::area_above_half_max
  struct Subsurface {
    double depth;
    StressSummary summary;
    RealField von_mises, s1;
  };
  std::vector<Subsurface> subsurface;
  bool has_leakage = false;
  LeakageResult leakage;       // [flow]
  CheckpointProgress resumed;  // earlier sessions' work, included in info (RunOptions::resumed)
};

struct RunOptions {
  std::function<void(const Progress&)> progress;  // called every few iterations
  const ContactFields* warm_start = nullptr;      // a previous solution on the same grid
  std::function<bool()> stop_request;             // polled; true stops with gfmd::Interrupted
  std::string checkpoint_path;                    // "" = no checkpoints
  double checkpoint_interval_s = 60.0;
  // false: the stress fields are reduced to their summaries (less memory); the CLI sets
  // it from outputs_need_stress_fields.
  bool keep_stress_fields = true;
  // Counts of the earlier sessions of a resumed run (from read_checkpoint): added to the
  // result's iterations and wall time, and carried into the next checkpoint.
  CheckpointProgress resumed;
};

// Whether the configured outputs show stress fields (fields.nc, PNG maps).
bool outputs_need_stress_fields(const Config& cfg);

// Checkpoints: the solver state (pressure and friction traction) with the input it
// belongs to, written atomically. read_checkpoint returns false if the file is missing,
// unreadable or belongs to another input or grid.
void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress = {});
bool read_checkpoint(const std::string& path, const Config& cfg, ContactFields& f,
                     CheckpointProgress* progress = nullptr);

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

// Solves a case. Throws InputError for bad input and SolveError for a failed solve.
CaseResult run_case(const Config& cfg, const RunOptions& opts = {});

// summary.json contents.
nlohmann::json summary_json(const CaseResult& r);

// Writes summary.json (+ fields.nc and PNG maps as configured) into dir. Every file is
// staged and renamed into place, so a crash leaves complete files only.
void write_outputs(const CaseResult& r, const std::string& dir);

// A run directory's last stage, for the CLI and Python alike (the caller holds its
// DirectoryLock): write_outputs, then `extra` (e.g. a plot drawn from them), then
// status.json "converged". On any error the partial set is removed (clear_run_outputs),
// status.json says "failed" with the reason (if it can still be written) and the error is
// rethrown.
void publish_outputs(const CaseResult& r, const std::string& dir, const std::function<void()>& extra = {});

// Load sweeps: solves cfg.sweep.values of cfg.sweep.parameter in order, each warm-started
// from the previous point, into dir/point_NNN/, and after every point rewrites
// dir/sweep.csv and dir/sweep.json (one row of every scalar summary key per point).
// Points whose summary.json already holds the same input are read back, not recomputed.
struct SweepOptions {
  std::function<void(const Progress&)> progress;
  std::function<void(int done, int total, const std::string& message)> on_point;
  std::vector<std::string> overrides;  // --set values applied to every point
  std::function<bool()> stop_request;  // as in RunOptions; the current point keeps a checkpoint
  double checkpoint_interval_s = 60.0;
};
nlohmann::json run_sweep(const std::string& case_path, const Config& cfg, const std::string& dir,
                         const SweepOptions& opts);

// Flattens the scalar entries of a summary (numbers, booleans, strings; nested objects
// other than "input" as "object.key").
std::vector<std::pair<std::string, nlohmann::json>> summary_row(const nlohmann::json& summary);

}  // namespace gfmd
