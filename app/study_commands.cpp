// gfmd sweep, curve, percolation and ensemble: the studies over a case, each into its directory.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <new>
#include <sstream>

#include "child.hpp"
#include "command_util.hpp"
#include "commands.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/studies/curve.hpp"
#include "gfmd/studies/ensemble.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/version.hpp"
#include "maps.hpp"

namespace gfmd::cli {

namespace fs = std::filesystem;

int cmd_sweep(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets_in,
              std::string plot, bool quiet, DirFlags dir_flags) {
  std::vector<std::string> sets;
  std::string param;
  std::vector<double> values;
  // key=v1,v2,... sweeps the key; a TOML array, table or string (key=[a, b], key={...},
  // key="a,b") is one value, set as in gfmd run.
  const auto one_toml_value = [](const std::string& value) {
    const auto first = value.find_first_not_of(" \t");
    return first != std::string::npos && std::string("[{\"'").find(value[first]) != std::string::npos;
  };
  for (const auto& s : sets_in) {
    const auto eq = s.find('=');
    if (eq != std::string::npos && s.find(',', eq) != std::string::npos &&
        !one_toml_value(s.substr(eq + 1))) {
      if (!param.empty())
        throw gfmd::InputError("--set " + s, "only one swept key per sweep (already sweeping " + param + ")");
      param = s.substr(0, eq);
      std::stringstream ss(s.substr(eq + 1));
      std::string tok;
      while (std::getline(ss, tok, ',')) {
        if (values.size() >= static_cast<std::size_t>(gfmd::kMaxSweepPoints))
          throw gfmd::InputError("--set " + param,
                                 "at most " + std::to_string(gfmd::kMaxSweepPoints) + " values in a sweep");
        try {
          std::size_t used = 0;
          values.push_back(std::stod(tok, &used));
          if (used != tok.size()) throw std::invalid_argument(tok);
        } catch (const std::exception&) {
          throw gfmd::InputError("--set " + s,
                                 "'" + tok +
                                     "' is not a number (a sweep's values are numbers; for other "
                                     "settings run the case once per setting)");
        }
      }
    } else {
      sets.push_back(s);
    }
  }
  const gfmd::Config cfg = param.empty() ? gfmd::load_config(case_path, sets) : [&] {
    try {
      return gfmd::sweep_config(case_path, sets, param, values);
    } catch (const gfmd::InputError& e) {
      if (e.where() == "values") throw gfmd::InputError("--set " + param, e.why());
      throw;
    }
  }();
  if (!cfg.sweep.active())
    throw gfmd::InputError(case_path, "nothing to sweep: add --set section.key=v1,v2,... or a [sweep] table");
  // An explicit column (--plot or the case's sweep.plot) is checked; the default is drawn
  // only where the summaries have it.
  const bool plot_option = !plot.empty();
  const bool plot_given = plot_option || cfg.sweep.plot != gfmd::SweepConfig{}.plot;
  if (plot.empty()) plot = cfg.sweep.plot;
  // The default column follows the physics: a viscoelastic body draws its friction (the
  // hysteresis, plus Coulomb's where there is friction); without friction (and not sweeping it)
  // there is no friction coefficient to draw: an approach sweep draws the force it finds,
  // another the area.
  if (!plot_given && cfg.visco.enabled())
    plot = cfg.friction.coefficient > 0 ? "total_friction_coefficient" : "hysteresis_friction";
  else if (!plot_given && !(cfg.friction.coefficient > 0) && cfg.sweep.parameter.rfind("friction.", 0) != 0)
    plot = cfg.sweep.parameter == "load.approach" ? "normal_force" : "relative_contact_area";
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_sweep"))
                  .string();
  // Under mpirun rank 0 alone holds the directory, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  ProgressPrinter pp;
  pp.quiet = quiet || !root;
  gfmd::SweepOptions so;
  so.overrides = sets;
  so.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  so.stop_request = stop_requested;
  so.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  const auto t0 = std::chrono::steady_clock::now();
  // An explicit column is checked by the sweep on its first point.
  if (plot_given) {
    so.plot_column = plot;
    so.plot_key = plot_option ? "--plot" : "sweep.plot";
  }
  so.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (pp.quiet) return;
    std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                 el / done * (total - done));
  };
  // The sweep plot, drawn from the tables in `dir` (the staging area before they are published).
  const auto draw = [&](const std::string& dir) {
    return run_script("plot_sweep.py", {(std::filesystem::path(dir) / "sweep.csv").string(), "--y", plot},
                      false);
  };
  bool drawn = false;
  so.before_publish = [&](const std::string& staging) {
    (void)draw_maps(runs_needing_maps(staging), {});
    drawn = draw(staging);
  };
  try {
    gfmd::run_sweep(case_path, cfg, out_dir, so);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    if (!root) return 4;
    std::fprintf(stderr,
                 "gfmd: sweep interrupted (%s); finished points and a checkpoint are kept, run the same "
                 "command again to continue%s\n",
                 e.what(),
                 gfmd::read_status(out_dir) == "interrupted" &&
                         std::filesystem::exists(std::filesystem::path(out_dir) / gfmd::kStagingName)
                     ? ("; the previous result in " + out_dir + "/ is kept unchanged").c_str()
                     : "");
    return 4;
  } catch (const gfmd::SolveError&) {
    pp.done();
    // A first attempt publishes its finished points, drawn before (before_publish).
    if (root && drawn)
      std::fprintf(stderr, "gfmd: the finished points are drawn in %s/sweep_%s.png\n", out_dir.c_str(),
                   plot.c_str());
    throw;
  }
  if (!root || quiet) return 0;
  std::printf("sweep of %s over %zu values: tables in %s/sweep.csv and sweep.json\n",
              cfg.sweep.parameter.c_str(), cfg.sweep.values.size(), out_dir.c_str());
  if (!drawn)
    std::fprintf(stderr, "gfmd: warning: could not draw %s with matplotlib (%s)\n", plot.c_str(),
                 python_interpreter().c_str());
  else
    std::printf("  plot: %s/sweep_%s.png\n", out_dir.c_str(), plot.c_str());
  return 0;
}

int cmd_curve(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
              const std::string& pressures, const std::string& approaches, bool by_approach, bool unload,
              bool no_png, bool quiet, DirFlags dir_flags) {
  // Library errors name the parameter "pressures" or "approaches"; here they are options.
  const auto as_option = [](const gfmd::InputError& e) {
    if (e.where() == "pressures" || e.where() == "approaches")
      return gfmd::InputError("--" + e.where(), e.why());
    return e;
  };
  gfmd::Config cfg;
  bool png = false;
  try {
    // What the case asks for with the user's overrides (its load, flow and figure settings).
    const gfmd::Config asked = gfmd::load_config(case_path, sets);
    png = asked.output.png && !no_png;
    if (by_approach)
      cfg = gfmd::curve_config_approaches(case_path, sets,
                                          gfmd::approach_path(gfmd::parse_approaches(approaches), unload));
    else
      cfg = gfmd::curve_config(case_path, sets, gfmd::curve_pressures(gfmd::parse_pressures(pressures)));
    const gfmd::LoadMode own = by_approach ? gfmd::LoadMode::Approach : gfmd::LoadMode::Pressure;
    if (!quiet && gfmd::mpi::root()) {
      if (!asked.flow.enabled)
        std::fprintf(stderr, "gfmd: the leakage is switched on for the curve (flow.enabled=true)\n");
      if (asked.load.mode != own)
        std::fprintf(stderr, "gfmd: the case's load.%s = %s is replaced by the curve's %s\n",
                     asked.load.mode == gfmd::LoadMode::Force      ? "force"
                     : asked.load.mode == gfmd::LoadMode::Pressure ? "pressure"
                                                                   : "approach",
                     gfmd::format_number(asked.load.value).c_str(), by_approach ? "approaches" : "pressures");
    }
  } catch (const gfmd::InputError& e) {
    throw as_option(e);
  }
  // Validates the topography before anything is written.
  (void)gfmd::make_topography_here(cfg);
  if (out_dir.empty())
    out_dir = (fs::path("out") / (fs::path(case_path).stem().string() + "_curve")).string();
  // Under mpirun rank 0 alone holds the directories, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  const auto lock = lock_on_root(out_dir, dir_flags, "curve");
  ProgressPrinter pp;
  pp.quiet = quiet || !root;
  gfmd::CurveOptions co;
  co.sweep.overrides = sets;
  co.sweep.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  co.sweep.stop_request = stop_requested;
  // The points are a sweep of their own in DIR/points, which holds its lock.
  co.sweep.directory = {false, dir_flags.wait, stop_requested};
  const auto t0 = std::chrono::steady_clock::now();
  co.sweep.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!pp.quiet)
      std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                   done > 0 ? el / done * (total - done) : 0.0);
  };
  const std::string csv = (fs::path(out_dir) / "curve.csv").string();
  const auto draw = [&] { return png && run_script("plot_curve.py", {csv}, false); };
  nlohmann::json j;
  try {
    j = gfmd::run_curve(case_path, cfg, out_dir, co);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    if (!root) return 4;
    std::fprintf(stderr,
                 "gfmd: curve interrupted (%s); finished points (tabulated in %s/curve.csv) and a checkpoint "
                 "are kept in %s/points/, run the same command again to continue\n",
                 e.what(), out_dir.c_str(), out_dir.c_str());
    return 4;
  } catch (const gfmd::SolveError&) {
    // The finished points are tabulated: draw them before reporting the failure.
    pp.done();
    if (root && fs::exists(csv) && draw())
      std::fprintf(stderr, "gfmd: the finished points are drawn in %s/curve.png\n", out_dir.c_str());
    throw;
  }
  pp.done();
  if (!root) return 0;
  if (!quiet) {
    std::printf("curve of %s over %zu %s: %s/curve.csv and curve.json (runs in points/)\n", case_path.c_str(),
                cfg.sweep.values.size(), by_approach ? "approaches" : "pressures", out_dir.c_str());
    if (j["pull_off_force"].is_number())
      std::printf("  pull-off force (the most tensile on the path): %s at approach %s%s\n",
                  gfmd::format_number(j["pull_off_force"].get<double>()).c_str(),
                  gfmd::format_number(j["pull_off_approach"].get<double>()).c_str(),
                  j["pull_off_at_path_end"] == true
                      ? " (the path's end or turning point: the force may fall further; extend --approaches)"
                      : "");
    const nlohmann::json& perc = j["percolation"];
    // An approach path that never pressed (an adhesive tip pulled off, say) whose case did not ask
    // for the leakage has no threshold to report: curve.json still says why.
    const bool unasked = j["leakage_switched_on"] == true && perc["status"] == "no_points";
    if (!unasked) {
      std::printf("  percolation threshold: %s\n", perc["message"].get<std::string>().c_str());
      for (const auto& [tag, d] : perc["directions"].items())
        if (d["pressure"] != perc["pressure"] || d["status"] != perc["status"])
          std::printf("    along %s alone: %s\n", tag.c_str(), d["message"].get<std::string>().c_str());
    }
  }
  if (png) {
    if (draw()) {
      if (!quiet) std::printf("  plot: %s/curve.png\n", out_dir.c_str());
    } else if (stop_requested()) {
      throw gfmd::Interrupted("interrupted while drawing curve.png");
    } else {
      std::fprintf(stderr, "gfmd: warning: could not draw curve.png with matplotlib (%s)\n",
                   python_interpreter().c_str());
    }
  }
  return 0;
}

int cmd_percolation(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                    const std::string& direction, double area_tol, bool quiet, DirFlags dir_flags) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (direction != "x" && direction != "y") throw gfmd::InputError("--direction", "must be x or y");
  if (out_dir.empty())
    out_dir =
        (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_percolation"))
            .string();
  gfmd::PercolationOptions po;
  po.axis = direction == "x" ? 0 : 1;
  po.area_tolerance = area_tol;
  // Under mpirun rank 0 alone holds the directory and prints; every process solves.
  const bool root = gfmd::mpi::root();
  if (!quiet && root) po.log = [](const std::string& m) { std::fprintf(stderr, "  %s\n", m.c_str()); };
  po.stop_request = stop_requested;
  po.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  const nlohmann::json j = gfmd::run_percolation(cfg, po, out_dir);
  if (!root || quiet) return 0;
  std::printf(
      "critical relative contact area along %s: %.4f (pressure %.6g) after %d solves -> "
      "%s/percolation.json\n",
      direction.c_str(), j["critical_relative_contact_area"].get<double>(),
      j["critical_pressure"].get<double>(), j["solves"].get<int>(), out_dir.c_str());
  return 0;
}

int cmd_ensemble(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                 const std::string& seeds, bool quiet, DirFlags dir_flags) {
  int s0 = 0, s1 = 7, used = 0;
  if (std::sscanf(seeds.c_str(), "%d..%d%n", &s0, &s1, &used) != 2 ||
      used != static_cast<int>(seeds.size()) || s0 < 0 || s1 < s0)
    throw gfmd::InputError("--seeds", "expected FIRST..LAST, e.g. 0..7, got '" + seeds + "'");
  gfmd::EnsembleOptions eo;
  eo.first_seed = s0;
  eo.last_seed = s1;
  eo.overrides = sets;
  gfmd::check_ensemble(case_path, eo);  // before the output directory is made
  if (out_dir.empty())
    out_dir =
        (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_ensemble"))
            .string();
  // Under mpirun rank 0 alone holds the directory, prints and draws; every process solves.
  const bool root = gfmd::mpi::root();
  eo.directory = {dir_flags.force, dir_flags.wait, stop_requested};
  eo.before_publish = [](const std::string& staging) { (void)draw_maps(runs_needing_maps(staging), {}); };
  eo.stop_request = stop_requested;
  if (!quiet && root)
    eo.on_seed = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  const nlohmann::json j = gfmd::run_ensemble(case_path, out_dir, eo);
  if (!root || quiet) return 0;
  const bool pairs = j.contains("frictionless");
  std::printf("%s/ensemble.json: K_x = %.4e, K_y = %.4e (Bruggeman over %d seeds)", out_dir.c_str(),
              j["conductivity_x"]["bruggeman"].get<double>(), j["conductivity_y"]["bruggeman"].get<double>(),
              s1 - s0 + 1);
  if (pairs)
    std::printf("; change through friction and coupling: x %+.1f %%, y %+.1f %%",
                100 * j["relative_change_x"].get<double>(), 100 * j["relative_change_y"].get<double>());
  std::printf("\n");
  return 0;
}

}  // namespace gfmd::cli
