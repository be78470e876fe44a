// gfmd._core's runs into directories as the CLI writes them, interruptible: one case (gfmd run
// --resume), sweeps, percolation, curves and seed ensembles over a case file (gfmd
// sweep/percolation/curve/ensemble), the Green's table (gfmd green).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <string>
#include <vector>

#include "_core_detail.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_in_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/studies/curve.hpp"
#include "gfmd/studies/ensemble.hpp"
#include "gfmd/studies/green.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"

namespace gfmd_python {

namespace {

// The studies below run interruptible: on Ctrl-C what a study keeps on disk stays, as with the CLI.
py::object sweep_case(const std::string& case_path, const std::string& parameter,
                      const std::vector<double>& values, const std::vector<std::string>& set,
                      const std::string& dir, const std::string& plot, bool force) {
  // No parameter: the case's own [sweep] table.
  const gfmd::Config cfg = parameter.empty() ? gfmd::load_config(case_path, set)
                                             : gfmd::sweep_config(case_path, set, parameter, values);
  if (!cfg.sweep.active())
    throw gfmd::InputError(case_path,
                           "nothing to sweep: give a parameter and its values, or a [sweep] table");
  return json_to_py(interruptible([&](const std::function<bool()>& stop) {
    gfmd::SweepOptions so;
    so.overrides = set;
    so.stop_request = stop;
    so.directory = {force, false, stop};
    // The points' maps (output.png) and the plot, drawn from the staged table, are published
    // with the tables, as the command line does (also the finished points of a sweep that stops).
    so.before_publish = [&plot](const std::string& where) {
      draw_maps(gfmd::runs_needing_maps(where), {});
      if (plot.empty()) return;
      py::gil_scoped_acquire acquire;
      const std::string problem = run_plot_script(
          "plot_sweep.py", {(std::filesystem::path(where) / "sweep.csv").string(), "--y", plot});
      if (!problem.empty())
        PySys_WriteStderr("gfmd: warning: could not draw sweep_%.200s.png: %.1500s\n", plot.c_str(),
                          problem.c_str());
    };
    so.plot_column = plot;  // checked on the first point ("" = none)
    return gfmd::run_sweep(case_path, cfg, dir, so);
  }));
}

py::object percolation_case(const std::string& case_path, const std::string& direction,
                            const std::vector<std::string>& set, double area_tolerance,
                            const std::string& dir, bool force) {
  if (direction != "x" && direction != "y") throw gfmd::InputError("direction", "must be \"x\" or \"y\"");
  const gfmd::Config cfg = gfmd::load_config(case_path, set);
  return json_to_py(interruptible([&](const std::function<bool()>& stop) {
    gfmd::PercolationOptions po;
    po.axis = direction == "x" ? 0 : 1;
    po.area_tolerance = area_tolerance;
    po.stop_request = stop;
    if (dir.empty()) return gfmd::find_percolation(cfg, po);
    po.directory.force = force;
    po.directory.stop_request = stop;
    return gfmd::run_percolation(cfg, po, dir);
  }));
}

// by_approach: `values` is an approach path (unload: back through it), else the pressures.
py::object curve_case(const std::string& case_path, const std::vector<double>& values,
                      const std::vector<std::string>& set, const std::string& dir, bool force,
                      bool by_approach, bool unload) {
  const gfmd::Config cfg =
      by_approach ? gfmd::curve_config_approaches(case_path, set, gfmd::approach_path(values, unload))
                  : gfmd::curve_config(case_path, set, gfmd::curve_pressures(values));
  // curve.png where the case asks for figures (output.png), as `gfmd curve` draws it; also of
  // the finished points of a curve that stopped.
  const bool png = gfmd::load_config(case_path, set).output.png;
  const auto draw = [&] {
    const std::string csv = (std::filesystem::path(dir) / "curve.csv").string();
    if (!png || !std::filesystem::exists(csv)) return;
    py::gil_scoped_acquire acquire;
    const std::string problem = run_plot_script("plot_curve.py", {csv});
    if (!problem.empty())
      PySys_WriteStderr("gfmd: warning: could not draw curve.png: %.1500s\n", problem.c_str());
  };
  return json_to_py(interruptible([&](const std::function<bool()>& stop) {
    gfmd::check_output_directory(dir, force, "curve");
    const gfmd::DirectoryLock lock(dir);
    gfmd::CurveOptions co;
    co.sweep.overrides = set;
    co.sweep.stop_request = stop;
    co.sweep.directory = {false, false, stop};  // DIR/points: the curve's own sweep
    nlohmann::json j;
    try {
      j = gfmd::run_curve(case_path, cfg, dir, co);
    } catch (const gfmd::SolveError&) {
      draw();
      throw;
    }
    draw();
    return j;
  }));
}

py::object ensemble_case(const std::string& case_path, int first, int last,
                         const std::vector<std::string>& set, const std::string& dir, bool force) {
  gfmd::EnsembleOptions eo;
  eo.first_seed = first;
  eo.last_seed = last;
  eo.overrides = set;
  (void)gfmd::check_ensemble(case_path, eo);
  return json_to_py(interruptible([&](const std::function<bool()>& stop) {
    eo.stop_request = stop;
    eo.directory = {force, false, stop};
    eo.before_publish = [](const std::string& staging) { draw_maps(gfmd::runs_needing_maps(staging), {}); };
    return gfmd::run_ensemble(case_path, dir, eo);
  }));
}

// One case into its run directory as `gfmd run CASE -o DIR [--resume]` (run_in_directory):
// {'status': 'solved' | 'reused', 'summary'}; SolveError where it does not converge (nothing
// published), KeyboardInterrupt when stopped (the checkpoint kept).
py::dict run_directory(const std::string& path, const std::vector<std::string>& set,
                       const std::string& output, bool resume, bool force, double checkpoint_interval,
                       bool fields) {
  const gfmd::Config cfg = gfmd::load_config(path, set);
  const auto solve_into = [&](const std::function<bool()>& stop) {
    gfmd::DirectoryRunOptions o;
    o.resume = resume;
    o.directory = {force, false, stop};
    o.checkpoint_interval_s = checkpoint_interval;
    o.keep_all_fields = fields;
    o.draw = [&cfg](const std::string& staging) {
      if (!cfg.output.png) return;
      try {
        draw_maps({staging}, {"--profiles"});
      } catch (py::error_already_set& e) {
        py::gil_scoped_acquire acquire;
        if (!e.matches(PyExc_KeyboardInterrupt)) throw;
        throw gfmd::Interrupted("interrupted while drawing the maps");
      }
    };
    o.failure_note = [](const std::string& note) {
      py::gil_scoped_acquire acquire;
      PySys_WriteStderr("gfmd: %.1500s\n", note.c_str());
    };
    gfmd::DirectoryRun r = gfmd::run_in_directory(cfg, output, std::move(o));
    using Outcome = gfmd::DirectoryRun::Outcome;
    const std::string kept = r.note.empty() ? "" : "; " + r.note;
    if (r.outcome == Outcome::NotConverged) {
      std::string with;
      for (const auto& kv : set) with += (with.empty() ? " [with set " : " ") + kv;
      throw gfmd::SolveError(path + ": " + r.why + (with.empty() ? "" : with + "]") + "; no results written" +
                             kept);
    }
    if (r.outcome == Outcome::Interrupted) {  // what is kept, then KeyboardInterrupt (interruptible)
      py::gil_scoped_acquire acquire;
      PySys_WriteStderr(
          "gfmd: %.200s: %.300s; %.300s%.500s\n", path.c_str(), r.why.c_str(),
          r.published
              ? ("the results are in " + output + "/ without (all) their figures: gfmd plot draws them")
                    .c_str()
          : r.saved_state ? ("state saved in " + r.checkpoint + ", continue with resume=True").c_str()
                          : "no results written",
          kept.c_str());
      throw gfmd::Interrupted(r.why);
    }
    return r;
  };
  // A failure to write (a full disk, a file-size limit) is OSError naming the file, as
  // Result.save's; bad input, a solve that failed and a stop keep their own exceptions.
  const gfmd::DirectoryRun run = [&] {
    try {
      return interruptible(solve_into);
    } catch (const gfmd::InputError&) {
      throw;
    } catch (const gfmd::SolveError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (py::error_already_set&) {
      throw;
    } catch (const std::runtime_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
      throw py::error_already_set();
    }
  }();
  py::dict d;
  const bool reused = run.outcome == gfmd::DirectoryRun::Outcome::AlreadySolved;
  d["status"] = reused ? "reused" : "solved";
  if (fields && !reused) return result(run.result);
  d["summary"] = json_to_py(reused ? run.finished : gfmd::summary_json(run.result));
  return d;
}

// The Green's tensor table as CSV text; written atomically to `output` where one is given.
std::string green_table(const std::vector<double>& poisson, double from, double to, int points,
                        const std::string& output, bool force) {
  std::string table = gfmd::green_table_csv(poisson, from, to, points);
  if (!output.empty()) gfmd::write_green_table(output, table, force);
  return table;
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("run_directory", &run_directory, py::arg("case"), py::arg("set"), py::arg("output"),
        py::arg("resume") = true, py::arg("force") = false, py::arg("checkpoint_interval") = 60.0,
        py::arg("fields") = false,
        "Solve a case file into its run directory as `gfmd run CASE -o OUTPUT [--resume]`: with resume a "
        "finished result of the same case is reused and an interrupted one continued from its checkpoint. "
        "Returns {'status': 'solved' | 'reused', 'summary': dict}; SolveError if it does not converge "
        "(nothing published), KeyboardInterrupt on Ctrl-C (or SIGTERM where Python handles it). fields=True "
        "(a case solved, not reused): {'summary', 'fields'} as run() returns them.");
  m.def("parse_approaches", &gfmd::parse_approaches, py::arg("text"),
        "An approach list as `gfmd curve --approaches` reads it (D1,D2,... or FROM:TO:N).");
  m.def("parse_pressures", &gfmd::parse_pressures, py::arg("text"),
        "A pressure list as `gfmd curve --pressures` reads it (P1,P2,... or FROM:TO:N, log spaced).");
  m.def("green_table", &green_table, py::arg("poisson"), py::arg("qh_from"), py::arg("qh_to"),
        py::arg("points"), py::arg("output") = "", py::arg("force") = false);
  m.def("sweep_case", &sweep_case, py::arg("case"), py::arg("parameter"), py::arg("values"), py::arg("set"),
        py::arg("output"), py::arg("plot") = "", py::arg("force") = false);
  m.def("percolation_case", &percolation_case, py::arg("case"), py::arg("direction"), py::arg("set"),
        py::arg("area_tolerance"), py::arg("output"), py::arg("force") = false);
  m.def("curve_case", &curve_case, py::arg("case"), py::arg("values"), py::arg("set"), py::arg("output"),
        py::arg("force") = false, py::arg("by_approach") = false, py::arg("unload") = false);
  m.def("ensemble_case", &ensemble_case, py::arg("case"), py::arg("first_seed"), py::arg("last_seed"),
        py::arg("set"), py::arg("output"), py::arg("force") = false);
}

}  // namespace gfmd_python
