// The output stage of a case: summary.json, fields.nc, PNG maps, profiles.csv, flow.json.
// It only serialises what run_case computed.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/case/result.hpp"

namespace gfmd {

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

// Flattens the scalar entries of a summary (numbers, booleans, strings; nested objects
// other than "input" as "object.key").
std::vector<std::pair<std::string, nlohmann::json>> summary_row(const nlohmann::json& summary);

}  // namespace gfmd
