// Load sweeps: a case solved over a list of values, warm-started point to point.
// See include/gfmd/studies/sweep.hpp.
#include "gfmd/studies/sweep.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
namespace gfmd {

namespace fs = std::filesystem;

namespace {

std::string csv_cell(const nlohmann::json& v) {
  if (v.is_string()) {
    std::string s = v.get<std::string>();
    if (s.find_first_of(",\"\n") != std::string::npos) {
      std::string q = "\"";
      for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
    return s;
  }
  if (v.is_null()) return "";
  return v.dump();
}

void write_sweep_tables(const std::string& dir, const std::string& param, const std::vector<double>& values,
                        const std::vector<nlohmann::json>& summaries) {
  std::vector<std::string> cols;
  std::vector<std::vector<std::pair<std::string, nlohmann::json>>> rows;
  for (const auto& s : summaries) {
    rows.push_back(summary_row(s));
    for (const auto& [k, v] : rows.back())
      if (std::find(cols.begin(), cols.end(), k) == cols.end()) cols.push_back(k);
  }
  std::ostringstream csv;
  csv.precision(17);
  csv << param;
  for (const auto& c : cols) csv << "," << c;
  csv << "\n";
  nlohmann::json j;
  j["parameter"] = param;
  j["values"] = values;
  j["points"] = nlohmann::json::array();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    csv << format_number(values[i]);  // shortest text that reads back exactly
    nlohmann::json pj;
    pj[param] = values[i];
    for (const auto& c : cols) {
      csv << ",";
      for (const auto& [k, v] : rows[i])
        if (k == c) {
          csv << csv_cell(v);
          pj[c] = v;
        }
    }
    csv << "\n";
    j["points"].push_back(pj);
  }
  j["completed"] = rows.size();
  j["total"] = values.size();
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  if (!summaries.empty() && summaries.front().contains("input"))
    j["input_first_point"] = summaries.front()["input"];
  write_text_atomic((fs::path(dir) / "sweep.csv").string(), csv.str());
  write_text_atomic((fs::path(dir) / "sweep.json").string(), j.dump(2) + "\n");
}

// "" where the summary has `column` (or it is the swept parameter), else its numeric columns.
std::string missing_column(const nlohmann::json& summary, const std::string& column,
                           const std::string& param) {
  std::string columns;
  bool found = column == param;
  for (const auto& [k, v] : summary_row(summary)) {
    found = found || k == column;
    if (v.is_number()) columns += (columns.empty() ? "" : ", ") + k;
  }
  return found ? std::string() : columns;
}

std::string format_value(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

Config sweep_config(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::string& parameter, const std::vector<double>& values) {
  if (values.empty()) throw InputError("values", "give at least one value to sweep " + parameter + " over");
  if (values.size() > static_cast<std::size_t>(kMaxSweepPoints))
    throw InputError("values", "at most " + std::to_string(kMaxSweepPoints) + " values to sweep " +
                                   parameter + " over, got " + std::to_string(values.size()));
  std::vector<std::string> with_first = overrides;
  with_first.push_back(parameter + "=" + format_number(values.front()));
  Config cfg = load_config(case_path, with_first);
  cfg.sweep.parameter = parameter;
  cfg.sweep.values = values;
  return cfg;
}

nlohmann::json run_sweep(const std::string& case_path, const Config& base, const std::string& dir,
                         const SweepOptions& opts) {
  const SweepConfig& sw = base.sweep;
  if (!sw.active())
    throw InputError(case_path, "no sweep: give [sweep] parameter and values, or --set key=v1,v2,...");
  // Under mpirun every process takes part in every solve; rank 0 alone reads and writes the
  // directory and tells the others what it found there. The new points go to the staging
  // area (finished ones of an interrupted attempt stay there for reuse) and are published
  // together; published points of the same input are reused where they are.
  const int total = static_cast<int>(sw.values.size());
  // extra: settings before the swept value (the up-front check's grid, below).
  const auto point_config = [&](int i, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> sets = opts.overrides;
    sets.insert(sets.end(), extra.begin(), extra.end());
    sets.push_back(sw.parameter + "=" + format_value(sw.values[i]));
    return reparse_config(base, sets);  // the text the sweep started from, not the file now
  };
  // Whether every point has the first point's grid and heights (the swept key is neither the
  // grid's nor the indenter's).
  const bool surface_fixed = sw.parameter.rfind("indenter.", 0) != 0 && sw.parameter.rfind("grid.", 0) != 0;
  // Every point's case is read before the directory is touched: a bad value anywhere in the
  // list is refused with nothing written (a directory that held a result keeps its status),
  // and the message names the value. Each is read again when its point runs (not kept: a case
  // text may be large and a sweep has up to kMaxSweepPoints points).
  // A height file whose grid keys the case leaves out is read by each parse (for its size):
  // where the swept key is neither the grid's nor the indenter's, the check gives the grid
  // the first point found, so that the map is not read once per point before the sweep starts.
  std::vector<std::string> grid_sets;
  if (base.indenter.type == "file" && surface_fixed)
    grid_sets = {"grid.nx=" + std::to_string(base.grid.nx), "grid.ny=" + std::to_string(base.grid.ny),
                 "grid.lx=" + format_value(base.grid.lx), "grid.ly=" + format_value(base.grid.ly)};
  for (int i = 0; i < total; ++i) try {
      (void)point_config(i, grid_sets);
    } catch (const InputError& e) {
      throw InputError(e.where(), "the sweep's " + sweep_point_name(static_cast<std::size_t>(i)) + " (" +
                                      sw.parameter + " = " + format_number(sw.values[i]) + "): " + e.why());
    }
  const bool root = mpi::root();
  std::optional<RunDirectory> rd;
  on_root([&] {
    OutputDirOptions as_sweep = opts.directory;
    as_sweep.kind = "sweep";
    rd.emplace(dir, as_sweep, /*keep_staging=*/true);
    rd->begin();
  });
  const std::string stage = root ? rd->staging() : std::string();
  std::set<std::string> reused;
  std::vector<nlohmann::json> summaries;
  ContactFields warm;
  bool have_warm = false;
  // Rows are appended to the staged sweep.csv as points finish (the columns of the first);
  // the tables are written whole once, with every column, when the sweep ends.
  std::vector<std::string> csv_columns;
  const auto append_row = [&](double value, const nlohmann::json& summary) {
    const auto row = summary_row(summary);
    std::ostringstream os;
    os.precision(17);
    if (csv_columns.empty()) {
      for (const auto& kv : row) csv_columns.push_back(kv.first);
      os << sw.parameter;
      for (const auto& c : csv_columns) os << "," << c;
      os << "\n";
    }
    os << format_number(value);
    for (const auto& c : csv_columns) {
      os << ",";
      for (const auto& [k, v] : row)
        if (k == c) os << csv_cell(v);
    }
    os << "\n";
    std::ofstream f(fs::path(stage) / "sweep.csv", std::ios::app);
    f << os.str();
  };
  // A sweep that ends before its last point: where the directory had no result yet, what was
  // finished is published (with the status saying why it stopped); otherwise the previous
  // result stays and the finished points wait in the staging area for the same command.
  // draw: the figures of the finished points (before_publish) are published with them.
  const auto stop_early = [&](const std::string& status, const std::string& why, bool draw = false) {
    if (!root) return std::string();
    if (rd->had_result()) {
      // Points solved by this attempt wait for the same command; with none, nothing is kept.
      bool staged = false;
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(stage, ec))
        staged = staged || e.path().filename().string().rfind("point_", 0) == 0;
      if (status == "failed")
        (void)rd->fail(why, staged);
      else
        (void)rd->interrupt(why, staged);
      return std::string(staged ? "kept, staged" : "kept");
    }
    write_sweep_tables(stage, sw.parameter, sw.values, summaries);
    if (draw && opts.before_publish) opts.before_publish(stage);
    rd->publish([&](const std::string& n) { return is_gfmd_output_name(n) && reused.count(n) == 0; }, status,
                why);
    return std::string("published");
  };
  // The column to draw, checked on the first point (opts.plot_column).
  const auto check_column = [&](int point) {
    if (opts.plot_column.empty() || point != 0) return;
    const std::string columns = mpi::from_root(
        root && !summaries.empty() ? missing_column(summaries.front(), opts.plot_column, sw.parameter) : "");
    if (!columns.empty()) {
      (void)stop_early("failed", "the summaries have no column '" + opts.plot_column + "'");
      throw InputError(opts.plot_key, "the summaries have no column '" + opts.plot_column +
                                          "' (the first point is kept in " + dir +
                                          "/; numeric columns: " + columns + ")");
    }
  };
  // With adhesion each point's state depends on the path before it (its branch): finished
  // points are reused only when every point is, else the whole path is solved again (a point
  // after a reused one would start cold and could land on the other branch).
  bool reuse = true;
  if (base.interaction.adhesive() && root)
    for (int i = 0; i < total && reuse; ++i) {
      const Config cfg = point_config(i);
      const std::string name = sweep_point_name(static_cast<std::size_t>(i));
      reuse = finished_summary((fs::path(stage) / name).string(), cfg).has_value() ||
              finished_summary((fs::path(dir) / name).string(), cfg).has_value();
    }
  reuse = mpi::from_root(reuse ? 1 : 0) == 1;
  // The indenter's heights, made once for every point when the swept key is neither the
  // indenter's nor the grid's: a height file is read once (edited or removed while the sweep
  // runs, it changes no point) and a generated surface is not drawn again for each point.
  const bool one_surface = surface_fixed && base.indenter.type != "array";
  std::optional<MadeSurface> surface;
  for (int i = 0; i < total; ++i) {
    const std::string name = sweep_point_name(static_cast<std::size_t>(i));
    // Stop requests are honoured between points too (points that need no iterations never
    // poll inside the solve).
    if (mpi::from_root(root && opts.stop_request && opts.stop_request() ? 1 : 0) == 1) {
      const std::string why = "interrupted before " + name;
      (void)stop_early("interrupted", why);
      throw Interrupted(why);
    }
    Config cfg = point_config(i);
    const std::string sdir = root ? (fs::path(stage) / name).string() : std::string();
    const std::string pdir = (fs::path(dir) / name).string();
    std::optional<nlohmann::json> old;
    if (root && reuse) {
      old = finished_summary(sdir, cfg);
      if (!old && (old = finished_summary(pdir, cfg))) reused.insert(name);
    }
    if (mpi::from_root(old ? 1 : 0) == 1) {
      if (root) {
        append_row(sw.values[i], *old);
        summaries.push_back(std::move(*old));
      }
      check_column(i);
      have_warm = false;
      if (opts.on_point) opts.on_point(i + 1, total, name + " reused (finished earlier)");
      continue;
    }
    RunOptions ro;
    if (one_surface && !surface) surface = MadeSurface::of(cfg);
    // A height file that states its own size, rewritten with another while the sweep runs, gives
    // this point another grid than the surface read at the start.
    if (surface && (cfg.grid.nx != base.grid.nx || cfg.grid.ny != base.grid.ny ||
                    cfg.grid.lx != base.grid.lx || cfg.grid.ly != base.grid.ly)) {
      const std::string why = name +
                              ": the grid changed while the sweep ran (a height file rewritten with "
                              "another size?); run the sweep again";
      (void)stop_early("failed", why);
      throw InputError(case_path, why);
    }
    ro.progress = opts.progress;
    ro.stop_request = opts.stop_request;
    ro.checkpoint_interval_s = opts.checkpoint_interval_s;
    ro.keep_stress_fields = outputs_need_stress_fields(cfg);
    on_root([&] { make_gfmd_directory(sdir); });
    ro.checkpoint_path = (fs::path(sdir) / "checkpoint.bin").string();
    // An interrupted point's checkpoint: in the staging area, or published with the finished
    // points of a first attempt.
    ContactFields resumed;
    CheckpointProgress progress;  // with the solver's restart point (rank 0's, handed out by rows)
    const bool from_checkpoint =
        mpi::from_root(root && (read_checkpoint(ro.checkpoint_path, cfg, resumed, &progress) ||
                                read_checkpoint((fs::path(pdir) / "checkpoint.bin").string(), cfg, resumed,
                                                &progress))) == 1;
    if (from_checkpoint) {
      ro.warm_start = &resumed;
      ro.resumed = progress;
    } else if (have_warm) {
      ro.warm_start = &warm;
    }
    // status.json of the point and of the sweep say where an interrupted sweep stopped (the
    // point keeps its checkpoint; the same command continues from it).
    const auto solve_point = [&] {
      if (surface) surface->lend(ro);  // a copy for each solve, a retry too
      try {
        return run_case(cfg, ro);
      } catch (const Interrupted& e) {
        on_root([&] {
          write_status(sdir, "interrupted", e.what());
          (void)stop_early("interrupted", name + ": " + e.what());
        });
        throw;
      }
    };
    CaseResult r = solve_point();
    bool retried = false;
    if (!r.info.converged && !from_checkpoint && have_warm) {
      // Started from the previous point's solution, the friction fixed point can fall into
      // a limit cycle that a start from the frictionless solution avoids: try that once.
      if (opts.on_point)
        opts.on_point(i, total, name + ": " + r.info.status + "; retrying from a cold start");
      ro.warm_start = nullptr;
      r = solve_point();
      retried = true;
    }
    std::error_code ec;
    if (root) fs::remove(ro.checkpoint_path, ec);
    if (!r.info.converged) {
      std::string why =
          name + " (" + sw.parameter + " = " + format_number(sw.values[i]) + "): " + r.info.status;
      on_root([&] {
        fs::remove_all(sdir, ec);  // no bare point directory is left behind
        const std::string what = stop_early("failed", why, /*draw=*/true);
        if (what == "published")
          why += "; the " + std::to_string(i) + " finished points are kept in " + dir + "/";
        else
          why += "; the previous sweep in " + dir + "/ is kept unchanged" +
                 (what == "kept, staged"
                      ? "; the points finished now wait in " + stage + "/ for the same command"
                      : std::string());
      });
      throw SolveError(why);
    }
    on_root([&] {
      clear_run_outputs(sdir);       // a point recomputed owns its directory, as a run does
      publish_outputs(r, sdir, {});  // with status.json "converged", as gfmd run writes it
      summaries.push_back(summary_json(r));
      append_row(sw.values[i], summaries.back());
    });
    check_column(i);
    warm = std::move(r.fields);
    have_warm = cfg.grid.size() == base.grid.size();
    if (opts.on_point) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "%s: %s = %.6g, %d iterations, %.2f s%s", name.c_str(),
                    sw.parameter.c_str(), sw.values[i], r.info.iterations, r.info.wall_time_s,
                    retried ? " (cold start)" : "");
      opts.on_point(i + 1, total, msg);
    }
  }
  on_root([&] {
    write_sweep_tables(stage, sw.parameter, sw.values, summaries);
    // The figures drawn from the staged tables are published with them.
    if (opts.before_publish) opts.before_publish(stage);
    if (opts.stop_request && opts.stop_request()) {
      (void)rd->interrupt("interrupted while drawing the figures", /*keep_staging=*/true);
      throw Interrupted("interrupted while drawing the figures");
    }
    rd->publish([&](const std::string& n) { return is_gfmd_output_name(n) && reused.count(n) == 0; });
  });
  nlohmann::json j;
  j["points"] = summaries.size();
  return j;
}

std::string sweep_point_name(std::size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "point_%03zu", i);
  return name;
}

}  // namespace gfmd
