// Leakage through the deformed gap of a solved case (SPEC §6): flow along requested
// directions, the flow fields and flow.json. Percolation thresholds: percolation.hpp.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/core/grid.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/io/netcdf.hpp"

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

// Appends the current-density components and magnitude of every flow (views into r);
// length_unit: the case's length unit (grid.unit; "" = none named, written as "length").
void append_current_fields(const LeakageResult& r, std::vector<NamedField>& fields,
                           const std::string& length_unit);

// Writes flow.json and flow.nc (current density components and magnitude per direction)
// into dir. The maps current_<x|y|angle>.png are drawn from flow.nc by the front ends
// (scripts/plot_maps.py).
void write_leakage(const Grid& g, const LeakageResult& r, const std::string& dir, const nlohmann::json& extra,
                   const std::string& length_unit);

// The units attribute of a length in the outputs: the case's unit, or "length" without one.
inline std::string length_units(const std::string& length_unit) {
  return length_unit.empty() ? std::string("length") : length_unit;
}

}  // namespace gfmd
