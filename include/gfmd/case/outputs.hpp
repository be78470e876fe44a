// The output stage of a case: summary.json, fields.nc, profiles.csv, flow.json/flow.nc.
// It only serialises what run_case computed; the PNG maps (output.png) are drawn from these
// files by the front ends (gfmd run/sweep/flow/plot and Python's run(output=) start
// scripts/plot_maps.py after write_outputs).
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
// A topography's statistics by their summary.json names (summary.json's "topography" adds "kind").
// What a file indenter's map went through (MapReport), as summary.json's topography.preprocessing.
nlohmann::json map_report_json(const MapReport& m);
nlohmann::json topography_stats_json(const TopographyStats& s);

// The file the maps are drawn from when output.png is on but output.fields is off:
// DIR/.maps.tmp.nc, written by write_outputs with the fields the maps show; the front end
// that draws the maps removes it. Its name holds ".tmp.", so clear_run_outputs removes one
// that a crash left behind.
inline constexpr const char* kMapsStagingFile = ".maps.tmp.nc";

// The arguments (after the script) with which scripts/plot_maps.py draws the maps of run
// directories, for every front end: `options`, then, when there is one directory holding a
// staging file, --fields and that file, then "--" and the directories.
std::vector<std::string> plot_maps_arguments(const std::vector<std::string>& dirs,
                                             const std::vector<std::string>& options);

// The run directories below dir (point_NNN of a sweep, seed_N of an ensemble) whose maps
// are still to be drawn: a staging file of the maps, or output.png on, fields.nc there and
// no pressure.png (points finished earlier whose maps were not drawn are caught up too).
std::vector<std::string> runs_needing_maps(const std::string& dir);

// The fields of fields.nc (with maps_only: those the maps are drawn from), named and
// described as there: views into r, except the masks (contact, stick), which are made here
// and held by the set. Valid while r and the set live; a set is moved, never copied.
struct FieldSet {
  std::vector<NamedField> fields;
  std::vector<RealField> masks;
  FieldSet() = default;
  FieldSet(FieldSet&&) = default;
  FieldSet& operator=(FieldSet&&) = default;
  FieldSet(const FieldSet&) = delete;
  FieldSet& operator=(const FieldSet&) = delete;
};
FieldSet result_fields(const CaseResult& r, bool maps_only = false);

// The registry of a result's per-point fields (src/case/result_fields.cpp): every field a result
// may hold, once, in fields.nc's order, with its name, description, units, whether the maps draw
// it and whether this result shows it (friction fields with friction, adhesion's with adhesion,
// ...). visit(info, storage) gets the field's storage, or null for a mask result_fields derives
// (contact, attraction, stick). result_fields lists the shown ones (after the topography; the
// leakage's currents after them); a distributed run gathers every one's storage on rank 0.
struct ResultField {
  std::string name, description, units;
  bool in_maps = false;
  bool shown = true;
};
void for_each_result_field(const CaseResult& r,
                           const std::function<void(const ResultField&, const RealField*)>& visit);
void for_each_result_field(CaseResult& r, const std::function<void(const ResultField&, RealField*)>& visit);

// Warnings about a solution itself (summary.json's warnings, printed by gfmd run): an adhesive
// cohesive zone narrower than kMinCohesiveZoneCells cells.
inline constexpr double kMinCohesiveZoneCells = 2.0;
std::vector<std::string> solution_warnings(const Observables& o);

// Writes the contents of fields.nc to path (atomically): every field, or with maps_only
// only those the maps are drawn from (pressure, gap, contact, stick, slip, dissipation,
// sigma_1, von_mises).
void write_fields_file(const CaseResult& r, const std::string& path, bool maps_only = false);

// Writes summary.json (+ fields.nc as configured; with output.png but not output.fields
// the staging file kMapsStagingFile) into dir. Every file is staged and renamed into place,
// so a crash leaves complete files only.
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
