// One case from configuration to outputs: config -> topography + body -> solve ->
// fields -> observables -> summary.json, fields.nc, PNG maps.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/config.hpp"
#include "gfmd/observables.hpp"

namespace gfmd {

struct CaseResult {
  Config config;
  Topography topography;
  TopographyStats topography_stats;
  ContactFields fields;
  SolveInfo info;
  Observables observables;
};

struct RunOptions {
  std::function<void(const Progress&)> progress;  // called every few iterations
};

// Solves a case. Throws InputError for bad input and SolveError for a failed solve.
CaseResult run_case(const Config& cfg, const RunOptions& opts = {});

// summary.json contents.
nlohmann::json summary_json(const CaseResult& r);

// Writes summary.json (+ fields.nc and PNG maps as configured) into dir. Every file is
// staged and renamed into place, so a crash leaves complete files only.
void write_outputs(const CaseResult& r, const std::string& dir);

}  // namespace gfmd
