#include "gfmd/studies/percolation.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

nlohmann::json find_percolation(const Config& base, const PercolationOptions& opt) {
  struct Point {
    double p, ac;
    bool perc;
  };
  std::vector<Point> hist;
  ContactFields warm;
  bool have = false;
  // The surface, made once for every load: a height file is read once (rewritten while the
  // search runs, it changes none of its solves) and a generated surface is drawn once.
  const std::optional<MadeSurface> surface =
      base.indenter.type == "array" ? std::nullopt : std::optional<MadeSurface>(MadeSurface::of(base));
  const auto eval = [&](double p) {
    Config c = base;
    c.load = LoadParams{LoadMode::Pressure, p};
    c.stress.post_analysis.clear();
    c.stress.depths.clear();
    RunOptions ro;
    if (surface) surface->lend(ro);
    ro.keep_stress_fields = false;
    ro.stop_request = opt.stop_request;
    if (have) ro.warm_start = &warm;
    CaseResult r = run_case(c, ro);
    if (!r.info.converged)
      throw SolveError("percolation: solve at pressure " + format_number(p) + ": " + r.info.status);
    // Rank 0 holds the gap of a distributed run and tells the others.
    const bool perc = mpi::from_root(mpi::root() && percolates(c.grid, r.fields.gap.data(), opt.axis)) == 1;
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

nlohmann::json run_percolation(const Config& cfg, const PercolationOptions& opt, const std::string& dir) {
  std::optional<RunDirectory> rd;
  on_root([&] {
    OutputDirOptions as_percolation = opt.directory;
    as_percolation.kind = "percolation";
    rd.emplace(dir, as_percolation);
    rd->begin();
  });
  nlohmann::json j;
  try {
    j = find_percolation(cfg, opt);
  } catch (const Interrupted& e) {
    on_root([&] { (void)rd->interrupt(e.what()); });
    throw;
  } catch (const std::exception& e) {
    on_root([&] { (void)rd->fail(e.what()); });
    throw;
  }
  on_root([&] {
    write_text_atomic((std::filesystem::path(rd->staging()) / "percolation.json").string(), j.dump(2) + "\n");
    // A search that ran out of solves before its bracket met the tolerance says so.
    if (j["converged"] == true)
      rd->publish();
    else
      rd->publish(is_gfmd_output_name, "converged",
                  "the bracket's areas did not come within the area tolerance (" +
                      std::to_string(opt.max_solves) +
                      " solves at most, or its pressures met): percolation.json says converged false, its "
                      "bracket holds the threshold");
  });
  return j;
}

}  // namespace gfmd
