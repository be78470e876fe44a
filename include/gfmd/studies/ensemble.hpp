// Seed ensembles: a self-affine case with flow solved for a range of seeds (with friction:
// each seed also frictionless), conductivities combined by Bruggeman's effective medium.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run_directory.hpp"

namespace gfmd {

inline constexpr int kMaxEnsembleSeeds = 10000;

struct EnsembleOptions {
  int first_seed = 0, last_seed = 7;
  std::vector<std::string> overrides;               // --set values applied to every seed
  std::function<bool()> stop_request;               // polled; true stops with gfmd::Interrupted
  std::function<void(const std::string&)> on_seed;  // one line per finished seed
  OutputDirOptions directory;                       // force, wait: run_ensemble holds dir's lock
  std::function<void(const std::string& staging)> before_publish;  // e.g. the maps of the new seeds
};

// Solves seeds first_seed..last_seed of the case (indenter.seed set, flow in both
// directions) into dir/seed_N/ (and dir/frictionless_seed_N/ when the case has friction),
// reusing seeds whose summary.json holds a converged solve of the same input, and writes
// dir/ensemble.json (returned): per seed a_c, K_x, K_y; mean, sample std and Bruggeman
// value of each; with friction the relative change of the conductivities through friction
// and coupling, through dir's staging area (RunDirectory: published together at the end). Throws InputError
// (the case is not self-affine, bad seeds) and SolveError (a seed did not converge). The checks run_ensemble
// makes before it solves anything (seed range, a self-affine indenter), for front ends that want them before
// creating the output directory. Returns the case with the overrides applied. Throws InputError.
Config check_ensemble(const std::string& case_path, const EnsembleOptions& opts);

nlohmann::json run_ensemble(const std::string& case_path, const std::string& dir,
                            const EnsembleOptions& opts);

}  // namespace gfmd
