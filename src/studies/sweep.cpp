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
  // directory and tells the others what it found there.
  const bool root = mpi::root();
  on_root([&] {
    fs::create_directories(dir);
    // What an earlier, longer or differently plotted sweep left: points beyond this sweep's
    // last and its plots (the tables are rewritten below).
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      int k = -1;
      if (name.size() == 9 && name.rfind("point_", 0) == 0 && std::sscanf(name.c_str() + 6, "%3d", &k) == 1 &&
          k >= static_cast<int>(sw.values.size()))
        fs::remove_all(e.path(), ec);
      else if (name.rfind("sweep_", 0) == 0 && e.path().extension() == ".png")
        fs::remove(e.path(), ec);
    }
    write_status(dir, "running");
  });
  std::vector<nlohmann::json> summaries;
  ContactFields warm;
  bool have_warm = false;
  const int total = static_cast<int>(sw.values.size());
  // The column to draw, checked on the first point (opts.plot_column).
  const auto check_column = [&](int point) {
    if (opts.plot_column.empty() || point != 0) return;
    const std::string columns = mpi::from_root(
        root && !summaries.empty() ? missing_column(summaries.front(), opts.plot_column, sw.parameter) : "");
    if (!columns.empty())
      throw InputError(opts.plot_key, "the summaries have no column '" + opts.plot_column +
                                          "' (the first point is kept in " + dir +
                                          "/; numeric columns: " + columns + ")");
  };
  for (int i = 0; i < total; ++i) {
    std::vector<std::string> sets = opts.overrides;
    sets.push_back(sw.parameter + "=" + format_value(sw.values[i]));
    Config cfg = load_config(case_path, sets);
    char name[32];
    std::snprintf(name, sizeof name, "point_%03d", i);
    const std::string pdir = (fs::path(dir) / name).string();
    std::optional<nlohmann::json> old;
    if (root) old = finished_summary(pdir, cfg);
    if (mpi::from_root(old ? 1 : 0) == 1) {
      if (root) summaries.push_back(std::move(*old));
      check_column(i);
      have_warm = false;
      if (opts.on_point) opts.on_point(i + 1, total, std::string(name) + " reused (finished earlier)");
      continue;
    }
    RunOptions ro;
    ro.progress = opts.progress;
    ro.stop_request = opts.stop_request;
    ro.checkpoint_interval_s = opts.checkpoint_interval_s;
    ro.keep_stress_fields = outputs_need_stress_fields(cfg);
    on_root([&] { fs::create_directories(pdir); });
    ro.checkpoint_path = (fs::path(pdir) / "checkpoint.bin").string();
    ContactFields resumed;
    const bool from_checkpoint =
        mpi::from_root(root && read_checkpoint(ro.checkpoint_path, cfg, resumed)) == 1;
    if (from_checkpoint) {
      ro.warm_start = &resumed;
    } else if (have_warm) {
      ro.warm_start = &warm;
    }
    // status.json of the point and of the sweep say where an interrupted sweep stopped (the
    // point keeps its checkpoint; the same command continues from it).
    const auto solve_point = [&] {
      try {
        return run_case(cfg, ro);
      } catch (const Interrupted& e) {
        on_root([&] {
          write_status(pdir, "interrupted", e.what());
          write_status(dir, "interrupted", std::string(name) + ": " + e.what());
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
        opts.on_point(i, total, std::string(name) + ": " + r.info.status + "; retrying from a cold start");
      ro.warm_start = nullptr;
      r = solve_point();
      retried = true;
    }
    std::error_code ec;
    if (root) fs::remove(ro.checkpoint_path, ec);
    if (!r.info.converged) {
      const std::string why = std::string(name) + " (" + sw.parameter + " = " + format_number(sw.values[i]) +
                              "): " + r.info.status + "; the " + std::to_string(i) +
                              " finished points are kept";
      on_root([&] {
        fs::remove(pdir, ec);  // only if empty: no bare point directory is left behind
        write_sweep_tables(dir, sw.parameter, sw.values, summaries);
        write_status(dir, "failed", why);
      });
      throw SolveError(why);
    }
    on_root([&] {
      clear_run_outputs(pdir);       // a point recomputed owns its directory, as a run does
      publish_outputs(r, pdir, {});  // with status.json "converged", as gfmd run writes it
      summaries.push_back(summary_json(r));
      write_sweep_tables(dir, sw.parameter, sw.values, summaries);
    });
    check_column(i);
    warm = std::move(r.fields);
    have_warm = cfg.grid.size() == base.grid.size();
    if (opts.on_point) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "%s: %s = %.6g, %d iterations, %.2f s%s", name, sw.parameter.c_str(),
                    sw.values[i], r.info.iterations, r.info.wall_time_s, retried ? " (cold start)" : "");
      opts.on_point(i + 1, total, msg);
    }
  }
  on_root([&] {
    write_sweep_tables(dir, sw.parameter, sw.values, summaries);
    write_status(dir, "converged");
  });
  nlohmann::json j;
  j["points"] = summaries.size();
  return j;
}

}  // namespace gfmd
