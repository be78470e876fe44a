// One case from configuration to result: config -> topography + body -> solve -> fields
// -> observables -> stresses -> leakage (run_case). The outputs are case/outputs.hpp's.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "gfmd/case/result.hpp"

namespace gfmd {

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
  // Heights given by the calling program (indenter.type = "array", e.g. Python's
  // gfmd.solve), on the case's grid; moved into the result (not copied).
  std::shared_ptr<Topography> topography;
};

// Whether the configured outputs show stress fields (fields.nc, PNG maps).
bool outputs_need_stress_fields(const Config& cfg);

// Solves a case. Throws InputError for bad input and SolveError for a failed solve.
CaseResult run_case(const Config& cfg, const RunOptions& opts = {});

}  // namespace gfmd
