// Load curves: one case over a list of mean pressures (a warm-started load sweep with the
// leakage switched on), tabulated as contact area, mean gap, friction and leakage against
// the load, with the percolation threshold (where the flow through the gap stops).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/studies/sweep.hpp"

namespace gfmd {

// The pressures of a curve from text: comma-separated items, each a number or FROM:TO:N
// (N log-spaced values from FROM to TO, both included; N >= 2), e.g. "0.001:0.1:5,0.2".
// Throws InputError("pressures", ...) for an empty list, a word that is not a number, a
// range that is not FROM:TO:N with positive FROM, TO and an integer N in [2, 10000].
// Values are returned as given (checked and sorted by curve_pressures).
std::vector<double> parse_pressures(const std::string& text);

// The pressures a curve solves: sorted ascending (a curve is drawn and warm-started from the
// smallest load up). Throws InputError("pressures", ...) if the list is empty or longer than
// kMaxSweepPoints, a value is not positive and finite, or a value appears twice.
std::vector<double> curve_pressures(std::vector<double> pressures);

// Approach-controlled curves (load paths; adhesion's loading and unloading): the approaches
// from text, comma-separated items, each a number or FROM:TO:N (N evenly spaced values, both
// ends included; any sign), kept in the order given. Throws InputError("approaches", ...).
std::vector<double> parse_approaches(const std::string& text);
// The path of an approach curve: the approaches as given and, with `unload`, back through them
// in reverse (the turning point once). Throws InputError("approaches", ...) if empty or longer
// than kMaxSweepPoints.
std::vector<double> approach_path(std::vector<double> approaches, bool unload);
// Each point's branch: "load" where the value grew from the previous point (the first point
// too), "unload" where it fell, the previous one's where it stayed.
std::vector<std::string> curve_branches(const std::vector<double>& values);
// The case of an approach curve: as curve_config, the sweep over load.approach along `path`
// (in its order: each point warm-starts from the one before, so unloading follows the
// branch it came from). Throws InputError("approaches", ...) for an approach the case does
// not admit (a negative one without adhesion).
Config curve_config_approaches(const std::string& case_path, const std::vector<std::string>& overrides,
                               const std::vector<double>& path);

// The overrides a curve adds to the user's (in this order, after them): the flow switched on
// (flow.enabled=true: the leakage is computed for every point even if the case has no [flow]
// table), no PNG maps per point (output.png=false; the curve draws one figure). The load is
// set per point as load.pressure=P, which replaces the case's load.force / load.approach.
std::vector<std::string> curve_overrides();

// The case of a curve: the case file with the user's overrides, curve_overrides() and the
// first pressure applied, its sweep replaced by load.pressure over the (sorted) pressures.
// Throws InputError naming the key: a bad case; "--set load.*" (the curve sets the load) or
// "--set flow.enabled" (the curve needs the flow); a pressure above 1000 E* ("pressures").
Config curve_config(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::vector<double>& pressures);

struct CurveOptions {
  SweepOptions sweep;  // progress, on_point, stop_request, checkpoint_interval_s; overrides: the user's
};

// Solves the curve's points (run_sweep into dir/points/: point_NNN run directories,
// sweep.csv, sweep.json; finished points are reused when the same curve is run again) and
// writes dir/curve.csv and dir/curve.json (atomically). If a point fails (SolveError) or the
// run is stopped (Interrupted), the tables of the points finished so far are written and the
// error is rethrown. The caller holds dir's DirectoryLock. Returns curve.json's contents.
//
// curve.csv columns (one row per finished point, in the order solved: pressures ascending, or
// the approach path):
//   pressure                       the imposed mean pressure (E*), or the solution's (approaches)
//   relative_contact_area          contact area fraction A/A0
//   mean_gap                       mean gap between indenter and deformed surface (length)
//   approach                       indenter displacement from first touch (length)
//   friction_coefficient           mu from the dissipation (empty when frictionless)
//   friction_coefficient_downhill  mu from mu_c F + downhill force (empty when frictionless)
//   conductivity_<d>               leakage: K_eff along d (x, y or <angle>deg) (length^3)
//   flow_factor_<d>                K_eff / <g>^3 along d
//   percolates_<d>                 1 if the open gap wraps around the cell along d, else 0
//   open                           1 if the gap percolates along any direction, else 0
//   iterations                     iterations of the contact solve
//   branch                         load or unload (curve_branches)
//   normal_force                   net normal force (negative in tension)
//   adhesive_force                 adhesive pull (empty without adhesion)
// curve.json: case, overrides (the user's), curve_overrides, parameter (load.pressure or
//   load.approach), leakage_switched_on, load_replaced, pressures or approaches, pull_off_force
//   (the most tensile force on the path, or null), pull_off_approach, jump_off_approach (the first
//   unloading point out of contact, or null), completed, total, columns (name -> meaning), points (the rows),
//   percolation (threshold over all directions) with directions.<d> (each direction's own),
//   points_dir, units, input_first_point, version, git_commit.
nlohmann::json run_curve(const std::string& case_path, const Config& cfg, const std::string& dir,
                         const CurveOptions& opts);

// The percolation threshold of a curve: the points' pressures (ascending) and whether the
// gap is open at each. Between the last open point and the first sealed one after it, the
// threshold is the midpoint on a log axis (the geometric mean of the two pressures), and the
// contact area there is interpolated linearly in log p between the two points' areas.
// Keys: status ("bracketed", "not_reached" when the gap is still open at the largest
// pressure, "sealed_throughout" when it is sealed at the smallest, "no_points"), reached,
// pressure and relative_contact_area (null unless bracketed), bracket {open, sealed}
// ({pressure, relative_contact_area}), monotonic (false if a sealed point precedes an open
// one), message (a line for people, e.g. "not reached in the range 0.001 .. 0.1").
nlohmann::json curve_threshold(const std::vector<double>& pressures, const std::vector<double>& areas,
                               const std::vector<bool>& open);

}  // namespace gfmd
