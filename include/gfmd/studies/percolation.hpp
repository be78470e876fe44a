// Percolation thresholds (a study): nested intervals on the load, one contact solve and one
// connectivity test per step, until the flow along a direction stops.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/config.hpp"

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
};
nlohmann::json find_percolation(const Config& cfg, const PercolationOptions& opt);
// find_percolation, its result then written to dir/percolation.json (atomically); the caller
// holds dir's DirectoryLock.
nlohmann::json run_percolation(const Config& cfg, const PercolationOptions& opt, const std::string& dir);

}  // namespace gfmd
