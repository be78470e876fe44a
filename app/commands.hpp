// The subcommands of the gfmd command line, each a thin call into the library: the options
// parsed by app/gfmd.cpp in, an exit status out (errors are thrown to main, which maps them
// to exit codes).
#pragma once

#include <string>
#include <vector>

namespace gfmd::cli {

// Ends a follower rank of a distributed run with `code`, its reason reported by rank 0.
struct QuietExit {
  int code;
};

// How a command treats its output directory: wait for another writer (--wait), write into a
// non-empty directory gfmd did not create (--force).
struct DirFlags {
  bool wait = false;
  bool force = false;
};

// " [with --set a=1 b=2]": errors name the overrides, the case file alone does not say what ran.
std::string sets_note(const std::vector<std::string>& sets);

int cmd_run(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
            bool quiet, bool verbose, bool resume, double checkpoint_s, DirFlags dir_flags);
int cmd_sweep(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets_in,
              std::string plot, bool quiet, DirFlags dir_flags);
// gfmd curve: the load curves (area, gap, friction, leakage) of a case over --pressures, with
// the percolation threshold, or along an approach path (--approaches, --unload: back through
// them; adhesion's loading and unloading, with the pull-off); curve.csv, curve.json and
// curve.png (unless no_png or output.png is off) in out_dir. by_approach: the approaches are
// the curve's (--approaches given), else the pressures.
int cmd_curve(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
              const std::string& pressures, const std::string& approaches, bool by_approach, bool unload,
              bool no_png, bool quiet, DirFlags dir_flags);
int cmd_flow(const std::string& dir, const std::string& direction, double tol, const std::string& solver,
             DirFlags dir_flags);
int cmd_percolation(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                    const std::string& direction, double area_tol, bool quiet, DirFlags dir_flags);
int cmd_ensemble(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets,
                 const std::string& seeds, bool quiet, DirFlags dir_flags);
// Tabulates the dimensionless Green's tensor of SPEC §2 (frame with q along axis 1).
int cmd_green(const std::vector<double>& nus, double from, double to, int points, const std::string& out,
              bool force = false);
// Runs scripts/study.py (the figure studies) with this program's Python; draw_only: its
// --draw-only (draw from the runs on disk, run nothing); runs_only: its --runs-only (run every
// series, draw nothing).
int cmd_study(const std::string& study_path, bool quick, const std::string& out_dir,
              const std::vector<std::string>& sets, bool quiet, bool force, bool draw_only = false,
              bool runs_only = false);

}  // namespace gfmd::cli
