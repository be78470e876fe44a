#include "maps.hpp"

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
#include "gfmd/io/netcdf.hpp"
#include "gfmd/studies/ensemble.hpp"
#include "gfmd/studies/percolation.hpp"
#include "gfmd/studies/sweep.hpp"
#include "gfmd/version.hpp"

namespace gfmd::cli {

namespace fs = std::filesystem;

namespace {
bool has_file(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  return fs::is_regular_file(dir / name, ec);
}
}  // namespace

// Draws the PNG maps of run directories with plot_maps.py (matplotlib) from their fields.nc,
// or from the staging file write_outputs leaves when output.fields is off (removed here,
// drawn or not). `options` go before the directories (e.g. --profiles, --only current).
// Never throws: a failure is a warning (the data files are complete); returns false then.
bool draw_maps(const std::vector<std::string>& dirs, const std::vector<std::string>& options) {
  if (dirs.empty()) return true;
  bool ok = false, staged = false;
  try {
    const std::vector<std::string> args = gfmd::plot_maps_arguments(dirs, options);
    for (const auto& d : dirs) staged = staged || has_file(d, gfmd::kMapsStagingFile);
    ok = !find_script("plot_maps.py").empty() && run_script("plot_maps.py", args, false);
  } catch (const std::exception&) {
    ok = false;
  }
  // The maps' own staging files go once drawn, or once drawing failed for good; a stop keeps
  // them, so that the next attempt (a study reusing its finished runs, gfmd plot on a result
  // published without its figures) draws from them.
  if (ok || !stop_requested())
    for (const auto& d : dirs) {
      std::error_code ec;
      fs::remove(fs::path(d) / gfmd::kMapsStagingFile, ec);
    }
  if (!ok && !stop_requested()) {  // stopped: the caller reports the interruption
    // A staging area is named by the directory it is published into.
    std::string where = dirs.size() == 1 ? dirs.front() : std::to_string(dirs.size()) + " directories";
    if (const fs::path p(where); p.filename() == gfmd::kStagingName) where = p.parent_path().string();
    std::fprintf(stderr,
                 "gfmd: warning: the PNG maps of %s were not (all) drawn (plot_maps.py with %s and "
                 "matplotlib)%s\n",
                 where.c_str(), python_interpreter().c_str(),
                 staged ? "" : "; the data files are complete: redraw with gfmd plot DIR");
  }
  return ok;
}

namespace {
// The subdirectories of dir, sorted.
std::vector<fs::path> subdirs(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_directory(ec)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The columns of a CSV table's header line (gfmd's own tables: no quoted names).
std::vector<std::string> csv_columns(const fs::path& path) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> cols;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) cols.push_back(cell);
  return cols;
}

// The columns of the sweep plots a sweep directory holds (sweep_<column>.png), sorted.
std::vector<std::string> sweep_plot_columns(const fs::path& dir) {
  std::vector<std::string> ys;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 10 && name.rfind("sweep_", 0) == 0 && e.path().extension() == ".png" &&
        name.find(".tmp.") == std::string::npos)
      ys.push_back(name.substr(6, name.size() - 10));
  }
  std::sort(ys.begin(), ys.end());
  return ys;
}

}  // namespace

// gfmd plot DIR: redraws the figures of a run directory (maps from fields.nc, profiles.png
// from profiles.csv), of a sweep (its sweep_<y>.png plots, the default one if none, and the
// maps of its points), of an ensemble (its seeds' maps) or of a study (the maps and plots of
// its series; the study figure itself is drawn by gfmd study, which reuses every result).
int cmd_plot(const std::string& dir_in) {
  const fs::path dir(dir_in);
  const auto is_run = [](const fs::path& d) {
    return has_file(d, "summary.json") || has_file(d, "fields.nc") || has_file(d, gfmd::kMapsStagingFile);
  };
  const auto is_sweep = [](const fs::path& d) { return has_file(d, "sweep.csv"); };
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw gfmd::InputError(dir_in, "no such directory");
  const bool study = has_file(dir, "study.json"), ensemble = has_file(dir, "ensemble.json");
  const bool curve = has_file(dir, "curve.csv");  // gfmd curve: curve.png, its points in points/
  // A folder of runs or sweeps without a table of its own (a study's series of seeds, one
  // seed's sweep each): their figures.
  bool group = false;
  if (!study && !ensemble && !curve && !is_sweep(dir) && !is_run(dir))
    for (const auto& p : subdirs(dir)) group = group || is_sweep(p) || is_run(p);
  const bool drawable = study || ensemble || curve || group || is_sweep(dir) || is_run(dir);
  if (!drawable && has_file(dir, "percolation.json")) {
    // A percolation search has no figure: its result is the table.
    std::printf("%s holds a gfmd percolation result: it has no figures (its result is %s/percolation.json)\n",
                dir_in.c_str(), dir_in.c_str());
    return 0;
  }
  if (!drawable)
    throw gfmd::InputError(dir_in,
                           "not a gfmd run, sweep, curve or study directory (no summary.json, fields.nc, "
                           "sweep.csv, curve.csv, study.json or ensemble.json in it)");
  // The lock is gfmd's marker too: a folder of runs that is not gfmd's own (a study's series)
  // is not marked; its runs and sweeps, which are, are locked each.
  std::vector<std::unique_ptr<gfmd::DirectoryLock>> locks;
  if (group) {
    for (const auto& p : subdirs(dir))
      if (has_file(p, gfmd::kDirectoryMarker))
        locks.push_back(std::make_unique<gfmd::DirectoryLock>(p.string(), false, stop_requested));
  } else {
    locks.push_back(std::make_unique<gfmd::DirectoryLock>(dir_in, false, stop_requested));
  }
  std::vector<fs::path> runs, sweeps;
  std::function<void(const fs::path&, int)> collect = [&](const fs::path& d, int depth) {
    if (is_sweep(d)) {
      sweeps.push_back(d);
      for (const auto& p : subdirs(d))
        if (is_run(p)) runs.push_back(p);
    } else if (is_run(d)) {
      runs.push_back(d);
    } else if (depth > 0) {
      for (const auto& p : subdirs(d)) collect(p, depth - 1);
    }
  };
  if (study || ensemble || group) {
    for (const auto& p : subdirs(dir)) collect(p, 1);
  } else if (curve) {
    collect(dir / "points", 0);
    // The curve's points are a sweep of its own making; they count as one only where a sweep
    // plot was drawn there.
    std::erase_if(sweeps, [](const fs::path& d) { return sweep_plot_columns(d).empty(); });
  } else {
    collect(dir, 0);
  }
  bool ok = true;
  int drawn = 0, profiles_only = 0;
  // Ctrl-C reaches the drawing scripts too (they leave no temporary and publish a directory's
  // figures together or not at all): stop at once, exit 4.
  const auto check_stop = [&dir_in] {
    if (stop_requested()) throw gfmd::Interrupted("interrupted while drawing the figures of " + dir_in);
  };
  std::vector<std::string> with_fields;
  // Runs without fields.nc (output.fields = false): one note for all of them (a study has
  // dozens).
  std::vector<std::string> profiles_note, nothing_note;
  for (const auto& d : runs) {
    if (has_file(d, "fields.nc") || has_file(d, gfmd::kMapsStagingFile)) {
      with_fields.push_back(d.string());
    } else if (has_file(d, "profiles.csv")) {
      if (run_script("plot_profiles.py", {(d / "profiles.csv").string()}, false))
        ++profiles_only;
      else
        ok = false;
      check_stop();
      profiles_note.push_back(d.string());
    } else {
      nothing_note.push_back(d.string());
    }
  }
  const auto note = [](const std::vector<std::string>& ds, const char* what) {
    if (ds.size() == 1)
      std::fprintf(stderr, "gfmd: note: %s has no fields.nc (output.fields = false): %s\n",
                   ds.front().c_str(), what);
    else if (ds.size() > 1)
      std::fprintf(stderr, "gfmd: note: %zu runs (%s, ...) have no fields.nc (output.fields = false): %s\n",
                   ds.size(), ds.front().c_str(), what);
  };
  note(profiles_note, "profiles.png only, no maps");
  note(nothing_note, "nothing to draw");
  if (!with_fields.empty()) {
    if (draw_maps(with_fields, {"--profiles"})) {
      drawn += static_cast<int>(with_fields.size());
      // A result published without its figures (a stop while they were drawn) has them now.
      for (const std::string& d : with_fields) try {
          std::ifstream in(fs::path(d) / "status.json");
          const nlohmann::json st = nlohmann::json::parse(in);
          if (st.value("status", "") == "converged" && st.value("reason", "") == gfmd::kFiguresNotDrawn)
            gfmd::write_status(d, "converged");
        } catch (const std::exception&) {
          // No readable status: nothing to clear.
        }
    } else {
      ok = false;
    }
    check_stop();
  }
  for (const auto& d : sweeps) {
    // The plots the sweep drew (sweep_<y>.png), else the column gfmd sweep draws by default
    // (cmd_sweep), the first of these the table has.
    std::vector<std::string> ys = sweep_plot_columns(d);
    const auto cols = csv_columns(d / "sweep.csv");
    const auto has = [&cols](const std::string& c) {
      return std::find(cols.begin(), cols.end(), c) != cols.end();
    };
    for (const char* c :
         {"total_friction_coefficient", "friction_coefficient", "hysteresis_friction",
          !cols.empty() && cols.front() == "load.approach" ? "normal_force" : "relative_contact_area"})
      if (ys.empty() && has(c)) ys.emplace_back(c);
    if (ys.empty())
      std::fprintf(stderr, "gfmd: note: %s: no sweep plot to redraw (draw one with gfmd sweep --plot KEY)\n",
                   d.c_str());
    for (const auto& y : ys) {
      const bool done = run_script("plot_sweep.py", {(d / "sweep.csv").string(), "--y", y}, false);
      check_stop();
      if (done) {
        ++drawn;
      } else {
        ok = false;
        std::fprintf(stderr, "gfmd: warning: %s/sweep_%s.png not drawn\n", d.c_str(), y.c_str());
      }
    }
  }
  if (curve) {
    const bool done = run_script("plot_curve.py", {(dir / "curve.csv").string()}, false);
    check_stop();
    if (done) {
      ++drawn;
    } else {
      ok = false;
      std::fprintf(stderr, "gfmd: warning: %s/curve.png not drawn\n", dir_in.c_str());
    }
  }
  if (study) {
    std::string name = "the study";
    try {
      name = nlohmann::json::parse(
                 gfmd::read_regular_file((dir / "study.json").string(), 1u << 20, "study file"))
                 .at("study")
                 .get<std::string>();
    } catch (const std::exception&) {
      // The name is only for the note.
    }
    std::fprintf(stderr,
                 "gfmd: note: the figure of %s (%s/%s.png) is drawn by gfmd study with its study file, "
                 "which reuses every finished run\n",
                 name.c_str(), dir_in.c_str(), name.c_str());
  }
  std::printf("%s: %d figure sets redrawn (%zu run directories, %zu sweeps%s)", dir_in.c_str(), drawn,
              runs.size(), sweeps.size(), curve ? ", a curve" : "");
  if (profiles_only > 0)
    std::printf("; profiles.png only in %d run directories without fields.nc", profiles_only);
  std::printf("%s\n", ok ? "" : "; some could not be drawn");
  return ok ? 0 : 1;
}

}  // namespace gfmd::cli
