// Percolation thresholds (a study): nested intervals on the load, one contact solve and one
// connectivity test per step, until the flow along a direction stops.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run_directory.hpp"

namespace gfmd {

// Critical relative contact area a_c* along a direction (angle 0: x, 90: y): nested
// intervals on the mean pressure until the open (gap > 0) region stops wrapping around the
// cell along that direction, i.e. until the flow along it vanishes. Stops when the contact
// areas of the bracket differ by less than area_tolerance.
struct PercolationOptions {
  int axis = 0;  // 0: x, 1: y
  double area_tolerance = 0.002;
  int max_solves = 40;
  std::function<void(const std::string&)> log;
  std::function<bool()> stop_request;  // polled by every solve; true throws gfmd::Interrupted
  // run_percolation's output directory (its kind is "percolation"): force, wait, stop_request.
  OutputDirOptions directory;
};
nlohmann::json find_percolation(const Config& cfg, const PercolationOptions& opt);
// find_percolation into dir (a RunDirectory on the lead process: its lock, status.json
// "running", then percolation.json published with "converged", or "failed" / "interrupted" with
// the reason and the previous result kept).
nlohmann::json run_percolation(const Config& cfg, const PercolationOptions& opt, const std::string& dir);

}  // namespace gfmd
