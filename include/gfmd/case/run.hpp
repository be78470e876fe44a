// One case from configuration to result: config -> topography + body -> solve -> fields
// -> observables -> stresses -> leakage (run_case). The outputs are case/outputs.hpp's.
#pragma once

#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "gfmd/case/result.hpp"
#include "gfmd/core/mpi.hpp"

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
// Under mpirun (every process calls it with the same case) the solve is distributed and
// rank 0 alone gets the whole result; the others get the fields empty but the solve's info,
// the observables and the leakage's figures (RunOptions are read on rank 0: its warm start
// and checkpoint path hold for all).
CaseResult run_case(const Config& cfg, const RunOptions& opts = {});

// Under mpirun: rank 0's error, if it had one (a collective): rethrown on rank 0, and on the
// others StoppedWithRoot with the exit code that error gives (rank 0 reports it). Nothing
// happens in a run of one process or when rank 0 had none.
void rethrow_from_root(const std::exception_ptr& failure);

// Runs f on rank 0 only (reading and writing a directory, where one writer is allowed) and
// agrees on its outcome with the others (rethrow_from_root). f itself in one process.
template <class F>
void on_root(F&& f) {
  if (!mpi::distributed()) {
    f();
    return;
  }
  std::exception_ptr failure;
  if (mpi::root()) try {
      f();
    } catch (...) {
      failure = std::current_exception();
    }
  rethrow_from_root(failure);
}

}  // namespace gfmd
