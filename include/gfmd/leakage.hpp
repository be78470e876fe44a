// Leakage through the deformed gap of a solved case (SPEC §6): flow along requested
// directions, percolation thresholds by nested intervals on the load, seed ensembles.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/config.hpp"
#include "gfmd/flow.hpp"
#include "gfmd/grid.hpp"
#include "gfmd/io.hpp"

namespace gfmd {

// Flow through the gap along each angle. flow.json keys: flow_factor_x/_y (K_eff / <g>^3),
// conductivity_x/_y (K_eff = <current . d>/G, length^3), percolates_x/_y,
// conservation_error (max over directions), iterations, mean_gap, normalisation.
struct LeakageResult {
  std::vector<FlowResult> flows;
  std::vector<RealField> magnitude;  // |current density| of each flow
  nlohmann::json json;
};
// stop_request (optional) is polled between the stages and PCG iterations of the linear
// solves; true throws gfmd::Interrupted.
LeakageResult compute_leakage(const Grid& g, const double* gap, const std::vector<double>& angles, double tol,
                              FlowSolver solver = FlowSolver::Auto,
                              const std::function<bool()>& stop_request = {});

// "x" for 0 degrees, "y" for 90, "<angle>deg" otherwise: the suffix of keys, fields and files.
std::string direction_tag(double angle_deg);

// Appends the current-density components and magnitude of every flow (views into r).
void append_current_fields(const LeakageResult& r, std::vector<NamedField>& fields);

// Writes flow.json, flow.nc (current density components and magnitude per direction) and
// current_<x|y|angle>.png into dir.
void write_leakage(const Grid& g, const LeakageResult& r, const std::string& dir,
                   const nlohmann::json& extra);

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

}  // namespace gfmd
