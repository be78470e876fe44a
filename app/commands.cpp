// gfmd flow, green and study, and the note that names the overrides (sets_note). The other
// subcommands: run_command.cpp (gfmd run), study_commands.cpp (sweep, curve, percolation, ensemble).
#include "commands.hpp"

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
#include "gfmd/studies/green.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/version.hpp"
#include "maps.hpp"

namespace gfmd::cli {

namespace fs = std::filesystem;

// " [with --set a=1 b=2]": errors name the overrides, the case file alone does not say what ran.
std::string sets_note(const std::vector<std::string>& sets) {
  if (sets.empty()) return "";
  std::string t = " [with --set";
  for (const auto& v : sets) t += " " + v;
  return t + "]";
}

int cmd_flow(const std::string& dir, const std::string& direction, double tol, const std::string& solver,
             DirFlags dir_flags) {
  gfmd::FlowSolver which;
  if (!gfmd::parse_flow_solver(solver, which))
    throw gfmd::InputError("--solver", "must be auto, amg or boomeramg, got '" + solver + "'");
  namespace fs = std::filesystem;
  const fs::path sp = fs::path(dir) / "summary.json";
  if (!fs::exists(sp)) throw gfmd::InputError(sp.string(), "no solved case here (run gfmd run first)");
  const std::string text = gfmd::read_regular_file(sp.string(), 64u << 20, "summary file");
  const std::string fields = (fs::path(dir) / "fields.nc").string();
  if (!fs::exists(fields))
    throw gfmd::InputError(fields,
                           "no fields file: the run was made with output.fields = false (rerun it with "
                           "--set output.fields=true, or solve the leakage in the run itself: [flow] "
                           "enabled = true)");
  gfmd::require_regular_file(fields, "fields file");
  nlohmann::json s;
  try {
    s = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw gfmd::InputError(sp.string(), std::string("unreadable: ") + e.what());
  }
  gfmd::Grid g;
  try {
    const auto& gi = s.at("input").at("grid");
    g = gfmd::Grid{gi.at("nx").get<int>(), gi.at("ny").get<int>(), gi.at("lx").get<double>(),
                   gi.at("ly").get<double>()};
  } catch (const nlohmann::json::exception& e) {
    throw gfmd::InputError(sp.string(), std::string("not a gfmd summary (input.grid): ") + e.what());
  }
  int nx = 0, ny = 0;
  const std::vector<double> gap = gfmd::read_netcdf_field(fields, "gap", nx, ny);
  if (nx != g.nx || ny != g.ny) throw gfmd::InputError(dir, "fields.nc does not match summary.json");
  const std::vector<double> angles = gfmd::parse_flow_directions(direction);
  if (angles.empty())
    throw gfmd::InputError("--direction",
                           "must be x, y, both or an angle in degrees, got '" + direction + "'");
  gfmd::RunDirectory rd(dir, {dir_flags.force, dir_flags.wait, stop_requested, /*owns_status=*/false, "run"});
  const auto r = gfmd::compute_leakage(g, gap.data(), angles, tol, which, stop_requested);
  std::string unit;  // the case's grid.unit, if it named one
  if (const auto gi = s["input"]["grid"]; gi.contains("unit") && gi["unit"].is_string())
    unit = gi["unit"].get<std::string>();
  // flow.json, flow.nc and the current maps are staged and published together; the maps are
  // drawn there beside links to the run's summary and fields (the same files, published back
  // onto themselves).
  rd.begin();
  try {
    gfmd::write_leakage(g, r, rd.staging(),
                        {{"relative_contact_area", s.value("relative_contact_area", 0.0)}}, unit);
    for (const char* name : {"summary.json", "fields.nc"}) {
      std::error_code ec;
      fs::create_hard_link(fs::path(dir) / name, fs::path(rd.staging()) / name, ec);
      if (ec) fs::copy_file(fs::path(dir) / name, fs::path(rd.staging()) / name, ec);
    }
    (void)draw_maps({rd.staging()}, {"--only", "current"});
    if (stop_requested()) throw gfmd::Interrupted("interrupted while drawing the current maps");
    rd.publish([](const std::string& n) {
      return n == "flow.json" || n == "flow.nc" ||
             (n.rfind("current_", 0) == 0 && n.size() > 12 && n.compare(n.size() - 4, 4, ".png") == 0);
    });
  } catch (const gfmd::Interrupted& e) {
    (void)rd.interrupt(e.what());
    throw;
  } catch (const std::exception& e) {
    (void)rd.fail(std::string("gfmd flow: ") + e.what());
    throw;
  }
  std::printf("%s/flow.json:\n%s\n", dir.c_str(), r.json.dump(2).c_str());
  return 0;
}

// Tabulates the dimensionless Green's tensor of SPEC §2 (frame with q along axis 1).
int cmd_green(const std::vector<double>& nus, double from, double to, int points, const std::string& out,
              bool force) {
  std::string table;
  try {
    table = gfmd::green_table_csv(nus, from, to, points);
  } catch (const gfmd::InputError& e) {
    if (e.where() == "poisson") throw gfmd::InputError("gfmd green --poisson", e.why());
    throw gfmd::InputError("gfmd green", "need 0 < --from < --to and --points >= 2");
  }
  if (out.empty() || out == "-")
    std::fputs(table.c_str(), stdout);
  else
    gfmd::write_green_table(out, table, force);
  return 0;
}

int cmd_study(const std::string& study_path, bool quick, const std::string& out_dir,
              const std::vector<std::string>& sets, bool quiet, bool force, bool draw_only, bool runs_only) {
  const std::string script = find_script("study.py");
  if (script.empty()) throw gfmd::InputError("gfmd study", "study.py is not installed next to this program");
  std::vector<std::string> args = {python_interpreter(), script, study_path};
  if (quick) args.emplace_back("--quick");
  if (quiet) args.emplace_back("--quiet");
  if (force) args.emplace_back("--force");
  if (draw_only) args.emplace_back("--draw-only");
  if (runs_only) args.emplace_back("--runs-only");
  if (!out_dir.empty()) {
    args.emplace_back("-o");
    args.push_back(out_dir);
  }
  for (const std::string& kv : sets) {
    args.emplace_back("--set");
    args.push_back(kv);
  }
  const int rc = run_child(args, false, /*keep_stdout=*/true);
  if (stop_requested() || rc == 4) {
    // Ctrl-C reaches the driver and its runs too; finished runs are reused next time. The
    // driver says so itself when it saw the request.
    if (rc != 4) std::fprintf(stderr, "gfmd: study interrupted; run the same command again to continue\n");
    return 4;
  }
  // The driver reports its own errors: bad input (2), a failed run (3), others (1).
  return rc == 0 || rc == 2 || rc == 3 ? rc : 1;
}

}  // namespace gfmd::cli
