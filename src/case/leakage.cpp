#include "gfmd/case/leakage.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

namespace fs = std::filesystem;

std::string direction_tag(double angle) {
  if (angle == 0.0) return "x";
  if (angle == 90.0) return "y";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%gdeg", angle);
  return buf;
}

void append_current_fields(const LeakageResult& r, std::vector<NamedField>& fields,
                           const std::string& length_unit) {
  const std::string cubed = length_units(length_unit) + "^3";
  for (std::size_t k = 0; k < r.flows.size(); ++k) {
    const FlowResult& f = r.flows[k];
    const std::string s = direction_tag(f.angle_deg);
    fields.push_back(
        {"current_x_" + s, f.qx.data(), "current density x for a unit gradient along " + s, cubed});
    fields.push_back(
        {"current_y_" + s, f.qy.data(), "current density y for a unit gradient along " + s, cubed});
    fields.push_back(
        {"current_" + s, r.magnitude[k].data(), "current density magnitude, gradient along " + s, cubed});
  }
}

LeakageResult compute_leakage(const Grid& g, const double* gap, const std::vector<double>& angles, double tol,
                              FlowSolver solver, const std::function<bool()>& stop_request) {
  LeakageResult r;
  nlohmann::json& j = r.json;
  double cons = 0.0;
  int its = 0;
  FlowOptions fo;
  fo.tolerance = tol;
  fo.solver = solver;
  fo.stop_request = stop_request;
  r.flows = solve_flow(g, gap, angles, fo);  // one preconditioner set-up for all directions
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const double a = angles[k];
    FlowResult& f = r.flows[k];
    if (!f.percolates) {
      // No open path wraps around the cell along d: the net flux is exactly zero (the
      // solve leaves round-off of order 1e-14).
      f.conductivity = f.flow_factor = 0.0;
    }
    RealField m(f.qx.size());  // the rows held here (a slab in a distributed run)
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = std::hypot(f.qx[i], f.qy[i]);
    r.magnitude.push_back(std::move(m));
    const std::string s = direction_tag(a);
    j["flow_factor_" + s] = f.flow_factor;
    j["conductivity_" + s] = f.conductivity;
    j["conductivity_transverse_" + s] = f.conductivity_transverse;
    j["percolates_" + s] = f.percolates;
    j["iterations_" + s] = f.iterations;
    j["residual_" + s] = f.residual;
    j["setup_seconds_" + s] = f.setup_s;
    j["solve_seconds_" + s] = f.solve_s;
    cons = std::max(cons, f.conservation_error);
    its += f.iterations;
    j["mean_gap"] = f.mean_gap;
    j["mean_gap_cubed"] = f.mean_gap_cubed;
  }
  j["conservation_error"] = cons;
  j["iterations"] = its;
  if (!r.flows.empty()) {
    j["linear_solver"] = r.flows.front().solver;
    j["faces_closed_by_cutoff"] = r.flows.front().faces_cut;
  }
  j["normalisation"] =
      "conductivity = <current density along d> / |mean pressure gradient| with local conductivity g^3 "
      "(i.e. 12 eta times the flux per unit width and gradient); flow_factor = conductivity / <g>^3, the "
      "flow "
      "relative to a uniform gap equal to the mean gap";
  return r;
}

void write_leakage(const Grid& g, const LeakageResult& r, const std::string& dir, const nlohmann::json& extra,
                   const std::string& length_unit) {
  fs::create_directories(dir);
  std::vector<NamedField> fields;
  append_current_fields(r, fields, length_unit);
  write_fields_netcdf((fs::path(dir) / "flow.nc").string(), g, fields,
                      {{"gfmd_version", kVersion}, {"git_commit", kGitCommit}}, length_units(length_unit));
  nlohmann::json j = r.json;
  j.update(extra);
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  write_text_atomic((fs::path(dir) / "flow.json").string(), j.dump(2) + "\n");
}

}  // namespace gfmd
