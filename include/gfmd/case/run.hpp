// One case from configuration to result: config -> topography + body -> solve -> fields
// -> observables -> stresses -> leakage (run_case). The outputs are case/outputs.hpp's.
#pragma once

#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "gfmd/case/result.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/placement.hpp"

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
  // Under mpirun: whether rank 0 gets the whole solution (every field gathered: a study's
  // warm start, a library caller). false (gfmd run without field outputs): the
  // post-processing runs on the slabs and rank 0 gathers only what the analysis and the
  // leakage read, so that it holds about what the other processes hold.
  bool whole_solution = true;
  // Counts of the earlier sessions of a resumed run (from read_checkpoint): added to the
  // result's iterations and wall time, and carried into the next checkpoint.
  CheckpointProgress resumed;
  // Heights given by the calling program (indenter.type = "array", e.g. Python's
  // gfmd.solve), on the case's grid; moved into the result (not copied).
  std::shared_ptr<Topography> topography;
  // This process's heights of the case's indenter, made by make_topography_here (the CLI
  // makes them once to validate the case before it writes anything; its MapReport with them):
  // taken over by run_case instead of making them again. Ignored for "array".
  std::shared_ptr<Topography> made_surface;
  MapReport made_report;
};

// Whether the configured outputs show stress fields (fields.nc, PNG maps).
bool outputs_need_stress_fields(const Config& cfg);

// Solves a case. Throws InputError for bad input and SolveError for a failed solve.
// Under mpirun (every process calls it with the same case) the solve and the
// post-processing (observables, stresses, profiles) are distributed; rank 0 alone gets the
// whole fields (see RunOptions::whole_solution) and does the analysis and the leakage; every
// process gets the solve's info, the observables, the stress summaries and the leakage's
// figures (RunOptions are read on rank 0: its warm start and checkpoint path hold for all).
CaseResult run_case(const Config& cfg, const RunOptions& opts = {});

// The backend run_case solves cfg on ("auto" resolved); InputError naming solver.backend where
// "cuda" cannot run it (no usable device, a grid too large for it, under mpirun), so that a
// front end refuses the case before it makes an output directory.
const Backend& solve_backend(const Config& cfg);

// The indenter's heights this process holds: the whole map in one process; under mpirun the
// rows of its slab (mpi::slab_of), made on the slab (analytic and self-affine surfaces: every
// process makes its rows, a collective), or, for a height map, read and prepared by rank 0
// alone and scattered (its errors agreed: rethrow_from_root). `report` is filled where the
// map was read (rank 0). The CLI validates a case's topography with it before writing.
Topography make_topography_here(const Config& cfg, MapReport* report = nullptr);

// This process's heights of a case made once for many of its solves (a sweep's points, a
// percolation search's loads): a height file read once, a generated surface drawn once. Each
// solve takes over a copy (lend: RunOptions::made_surface and made_report), a retried one too.
struct MadeSurface {
  std::shared_ptr<const Topography> heights;
  MapReport report;
  static MadeSurface of(const Config& cfg);  // make_topography_here (a collective under mpirun)
  void lend(RunOptions& ro) const;
};

// rethrow_from_root and on_root (rank 0's outcome agreed by every process) are
// core/placement.hpp's.

}  // namespace gfmd
