// Load sweeps: one case over a list of values of one key, warm-started point to point.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/contact/solver.hpp"

namespace gfmd {

// Load sweeps: solves cfg.sweep.values of cfg.sweep.parameter in order, each warm-started
// from the previous point, into dir/point_NNN/ with dir/sweep.csv and dir/sweep.json (one row
// of every scalar summary key per point), through the directory's staging area: published
// together at the end (RunDirectory). Points whose summary.json already holds the same input
// are read back, not recomputed.
struct SweepOptions {
  std::function<void(const Progress&)> progress;
  std::function<void(int done, int total, const std::string& message)> on_point;
  std::vector<std::string> overrides;  // --set values applied to every point
  std::function<bool()> stop_request;  // as in RunOptions; the current point keeps a checkpoint
  double checkpoint_interval_s = 60.0;
  // A summary column the front end will draw (sweep_<column>.png; "" = none): a column the
  // summaries lack is bad input, found on the first point (InputError named plot_key, e.g.
  // "--plot"; that point is kept), not after the last.
  std::string plot_column, plot_key = "plot";
  // The output directory's treatment (force, wait; the sweep holds its lock) and what is drawn
  // from the staged tables before they are published (the staging directory as argument):
  // also the finished points of a first attempt that stops at a point that does not converge.
  OutputDirOptions directory;
  std::function<void(const std::string& staging)> before_publish;
};
// The case of a sweep of `parameter` (section.key) over `values`, given by a front end
// rather than the case's [sweep] table: the case file with the overrides and the first
// value applied, its sweep replaced by this one. Throws InputError (no values; bad case).
Config sweep_config(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::string& parameter, const std::vector<double>& values);

nlohmann::json run_sweep(const std::string& case_path, const Config& cfg, const std::string& dir,
                         const SweepOptions& opts);

// The run directory of the sweep's point i inside its directory: point_000, point_001, ...
std::string sweep_point_name(std::size_t i);

}  // namespace gfmd
