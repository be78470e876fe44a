#include "gfmd/leakage.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gfmd/error.hpp"
#include "gfmd/io.hpp"
#include "gfmd/run.hpp"
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

void append_current_fields(const LeakageResult& r, std::vector<NamedField>& fields) {
  for (std::size_t k = 0; k < r.flows.size(); ++k) {
    const FlowResult& f = r.flows[k];
    const std::string s = direction_tag(f.angle_deg);
    fields.push_back(
        {"current_x_" + s, f.qx.data(), "current density x for a unit gradient along " + s, "length^3"});
    fields.push_back(
        {"current_y_" + s, f.qy.data(), "current density y for a unit gradient along " + s, "length^3"});
    fields.push_back({"current_" + s, r.magnitude[k].data(), "current density magnitude, gradient along " + s,
                      "length^3"});
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
    RealField m(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) m[i] = std::hypot(f.qx[i], f.qy[i]);
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

void write_leakage(const Grid& g, const LeakageResult& r, const std::string& dir,
                   const nlohmann::json& extra) {
  fs::create_directories(dir);
  std::vector<NamedField> fields;
  append_current_fields(r, fields);
  write_fields_netcdf((fs::path(dir) / "flow.nc").string(), g, fields,
                      {{"gfmd_version", kVersion}, {"git_commit", kGitCommit}}, "length");
  for (std::size_t k = 0; k < r.flows.size(); ++k) {
    PngOptions po;
    po.colormap = "inferno";
    const std::string tag = direction_tag(r.flows[k].angle_deg);
    po.title = "current density " + tag;
    write_png_map((fs::path(dir) / ("current_" + tag + ".png")).string(), g, r.magnitude[k].data(), po);
  }
  nlohmann::json j = r.json;
  j.update(extra);
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  write_text_atomic((fs::path(dir) / "flow.json").string(), j.dump(2) + "\n");
}

nlohmann::json find_percolation(const Config& base, const PercolationOptions& opt) {
  struct Point {
    double p, ac;
    bool perc;
  };
  std::vector<Point> hist;
  ContactFields warm;
  bool have = false;
  const auto eval = [&](double p) {
    Config c = base;
    c.load = LoadParams{LoadMode::Pressure, p};
    c.stress.post_analysis.clear();
    c.stress.depths.clear();
    RunOptions ro;
    ro.keep_stress_fields = false;
    ro.stop_request = opt.stop_request;
    if (have) ro.warm_start = &warm;
    CaseResult r = run_case(c, ro);
    if (!r.info.converged)
      throw SolveError("percolation: solve at pressure " + format_number(p) + ": " + r.info.status);
    const bool perc = percolates(c.grid, r.fields.gap.data(), opt.axis);
    hist.push_back({p, r.observables.relative_contact_area, perc});
    warm = std::move(r.fields);
    have = true;
    if (opt.log) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "pressure %.6g: a_c = %.5f, %s", p, hist.back().ac,
                    perc ? "percolates" : "sealed");
      opt.log(buf);
    }
    return hist.back();
  };
  double p0 = base.load.mode == LoadMode::Pressure ? base.load.value
              : base.load.mode == LoadMode::Force  ? base.load.value / base.grid.area()
                                                   : 0.01 * base.elastic.contact_modulus;
  Point lo{}, hi{};
  Point first = eval(p0);
  if (first.perc) {
    lo = first;
    for (hi = first; hi.perc;) {
      if (static_cast<int>(hist.size()) >= opt.max_solves)
        throw SolveError("percolation: no sealing load found");
      lo = hi;
      hi = eval(hi.p * 2.0);
    }
  } else {
    hi = first;
    for (lo = first; !lo.perc;) {
      if (static_cast<int>(hist.size()) >= opt.max_solves)
        throw SolveError("percolation: no open load found");
      hi = lo;
      lo = eval(lo.p / 2.0);
    }
  }
  while (hi.ac - lo.ac > opt.area_tolerance && static_cast<int>(hist.size()) < opt.max_solves &&
         hi.p / lo.p > 1.0 + 1e-9) {
    const Point m = eval(std::sqrt(lo.p * hi.p));
    (m.perc ? lo : hi) = m;
  }
  nlohmann::json j;
  j["direction"] = opt.axis == 0 ? "x" : "y";
  j["critical_relative_contact_area"] = 0.5 * (lo.ac + hi.ac);
  j["critical_pressure"] = std::sqrt(lo.p * hi.p);
  j["bracket"] = {{"open", {{"pressure", lo.p}, {"relative_contact_area", lo.ac}}},
                  {"sealed", {{"pressure", hi.p}, {"relative_contact_area", hi.ac}}}};
  j["area_tolerance"] = opt.area_tolerance;
  j["converged"] = hi.ac - lo.ac <= opt.area_tolerance;
  j["history"] = nlohmann::json::array();
  for (const auto& h : hist)
    j["history"].push_back({{"pressure", h.p}, {"relative_contact_area", h.ac}, {"percolates", h.perc}});
  j["solves"] = hist.size();
  j["input"] = base.to_json();
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  return j;
}

}  // namespace gfmd
