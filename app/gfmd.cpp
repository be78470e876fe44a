// gfmd command line: the options of each subcommand (CLI11) and the mapping of errors to
// exit codes; the subcommands are in commands.cpp, child processes in child.cpp, pictures in
// maps.cpp.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "child.hpp"
#include "commands.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/version.hpp"
#include "maps.hpp"

using namespace gfmd::cli;

namespace {
// OpenMP threads that reach a barrier first spin before they sleep: libgomp spins 300 000
// times by default, long enough that two programs sharing the cores (two gfmd runs, a build)
// spin against each other's work (measured on 2 cores, two 128^2 runs at once: 19 s each
// against 0.12 s alone; BENCHMARKS.md). Unless the user chose a policy (OMP_WAIT_POLICY or
// GOMP_SPINCOUNT), gfmd starts itself again, once, with GOMP_SPINCOUNT=10000: the same speed
// alone, 3-6x faster shared. libgomp reads it only when it is loaded, hence the exec (of
// this program, by argument vector; if it fails, the run goes on with the default).
void bound_spin_wait(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (::setenv("GOMP_SPINCOUNT", gfmd::kSpinCount, 1) != 0) return;
  ::execv("/proc/self/exe", argv);
}

int run_main(int argc, char** argv) {
  CLI::App app{"gfmd: steady sliding contacts with full elastic coupling"};
  app.set_version_flag("--version", std::string(gfmd::kVersion) + " (" + gfmd::kGitCommit + ")");
  app.require_subcommand(1);

  std::string case_path, out_dir;
  std::vector<std::string> sets;
  // -o "" would fall back to the default directory without saying so: refused.
  const CLI::Validator non_empty(
      [](std::string& v) -> std::string { return v.empty() ? "must not be empty" : ""; }, "PATH");
  bool quiet = false;
  auto* run = app.add_subcommand("run", "solve one case and write summary.json, fields.nc and PNG maps");
  run->add_option("case", case_path, "case file (TOML)")->required();
  run->add_option("-o,--output", out_dir, "output directory (default: out/<case name>)")->check(non_empty);
  run->add_option("--set", sets, "override a key: section.key=value (repeatable)");
  run->add_flag("-q,--quiet", quiet, "no progress display");
  bool verbose = false, resume = false;
  double checkpoint_s = 60.0;
  run->add_flag("-v,--verbose", verbose, "print every friction fixed-point step");
  run->add_flag("--resume", resume,
                "continue from DIR/checkpoint.bin (or do nothing if DIR holds the result)");
  run->add_option("--checkpoint-interval", checkpoint_s, "seconds between checkpoints (default 60)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(x >= 0.1 && x <= 1e9))
              return "must be a number of seconds in [0.1, 1e9], got '" + v + "'";
            return "";
          },
          "SECONDS"));
  bool wait = false, force = false;
  const auto add_force = [&force](CLI::App* sub) {
    sub->add_flag("--force", force,
                  "write into a non-empty directory that gfmd did not create, or over another kind of gfmd "
                  "result (gfmd output names there are replaced)");
  };
  add_force(run);
  run->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  std::string plot;
  auto* sweep =
      app.add_subcommand("sweep", "solve a case for a list of values of one key, warm-starting each point");
  sweep->add_option("case", case_path, "case file (TOML)")->required();
  sweep->add_option("-o,--output", out_dir, "output directory (default: out/<case name>_sweep)")
      ->check(non_empty);
  sweep->add_option("--set", sets, "override a key; one key may take a comma-separated list: the sweep");
  sweep->add_option("--plot", plot,
                    "summary key to plot against the swept value (default friction_coefficient)");
  sweep->add_flag("-q,--quiet", quiet, "no progress display");
  add_force(sweep);
  sweep->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  std::string pressures, approaches;
  bool no_png = false, unload = false;
  auto* curve = app.add_subcommand(
      "curve", "load curves of a case: contact area, mean gap, friction and leakage against the pressure");
  curve->add_option("case", case_path, "case file (TOML)")->required();
  auto* pressures_opt =
      curve->add_option("--pressures", pressures,
                        "mean pressures in units of E*: P1,P2,... where an item may also be FROM:TO:N, N "
                        "log-spaced values from FROM to TO inclusive (0.001:1:10 gives 10 values; "
                        "0.001:0.01:4,0.05 mixes both); sorted ascending, each > 0, none twice");
  auto* approaches_opt = curve->add_option(
      "--approaches", approaches,
      "an approach path instead (load.approach, lengths): D1,D2,... where an item may also be FROM:TO:N, N "
      "evenly spaced values from FROM to TO inclusive; solved in the order given (negative values need "
      "interaction.model = \"adhesive\")");
  pressures_opt->excludes(approaches_opt);
  curve
      ->add_flag("--unload", unload,
                 "with --approaches: go back through the approaches after the last (unloading)")
      ->needs(approaches_opt);
  curve->add_option("-o,--output", out_dir, "output directory (default: out/<case name>_curve)")
      ->check(non_empty);
  curve->add_option("--set", sets, "override a key: section.key=value (repeatable; not load.*)");
  curve->add_flag("--no-png", no_png, "no curve.png (as output.png = false)");
  curve->add_flag("-q,--quiet", quiet, "no progress display");
  add_force(curve);
  curve->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");
  curve->footer(
      "Solves the case at each pressure (load.pressure, replacing the case's load), or at each approach "
      "along the path (load.approach), warm-starting each point from the previous one, with the leakage "
      "switched on (flow.enabled = true) even if the case has no [flow]. An approach path records the "
      "pull-off force (the most tensile force) in curve.json. Writes DIR/curve.csv (one row per pressure), "
      "DIR/curve.json (the rows, the "
      "percolation threshold: where the leakage stops, between the last open and the first sealed point, "
      "on a log axis) and DIR/curve.png (four panels, threshold marked); the runs of the points are kept "
      "in DIR/points/ and reused when the same command runs again.");

  install_signal_handlers();
  std::vector<double> green_nu{0.0, 0.25, 0.49};
  double green_from = 1e-2, green_to = 1e2;
  int green_points = 121;
  auto* green = app.add_subcommand("green", "tabulate the Green's tensor Phi(qh) of a layer (CSV)");
  green->add_option("--poisson", green_nu, "Poisson ratios")->delimiter(',');
  green->add_option("--from", green_from, "smallest qh");
  green->add_option("--to", green_to, "largest qh");
  green->add_option("--points", green_points, "points per Poisson ratio (log spaced)");
  green->add_option("-o,--output", out_dir, "CSV file (default: standard output)")->check(non_empty);
  green->add_flag("--force", force, "replace an existing file that is not a gfmd green table");

  std::string flow_dir, direction = "both", seeds = "0..7";
  double flow_tol = 1e-10, area_tol = 0.002;
  std::string flow_solver = "auto";
  auto* flow = app.add_subcommand("flow", "Reynolds flow through the gap of a solved case directory");
  flow->add_option("dir", flow_dir, "a directory written by gfmd run")->required();
  flow->add_option("--direction", direction, "x, y, both (default) or an angle in degrees");
  flow->add_option("--tolerance", flow_tol, "relative residual of the linear solve (default 1e-10)");
  flow->add_option("--solver", flow_solver,
                   "linear solver: auto (ours, HYPRE's BoomerAMG if ours does not converge; default), amg or "
                   "boomeramg");
  flow->add_flag("--wait", wait, "if another gfmd run writes to the directory, wait for it");
  auto* perc =
      app.add_subcommand("percolation", "critical contact area at which the flow along a direction stops");
  perc->add_option("case", case_path, "case file (TOML)")->required();
  perc->add_option("--direction", direction, "x or y")->required();
  perc->add_option("-o,--output", out_dir, "output directory")->check(non_empty);
  perc->add_option("--set", sets, "override a key (repeatable)");
  perc->add_option("--area-tolerance", area_tol,
                   "stop when the bracket's contact areas differ by less (default 0.002)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            // nan or a negative tolerance never ends the bracketing: a threshold from an
            // unfinished bracket came out with exit 0.
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (end == v.c_str() || *end != '\0' || !(x > 0 && x < 1))
              return "must be a contact-area fraction in (0, 1), got '" + v + "'";
            return "";
          },
          "FRACTION"));
  perc->add_flag("-q,--quiet", quiet, "no log lines");
  add_force(perc);
  perc->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");
  auto* ens =
      app.add_subcommand("ensemble", "flow over roughness seeds, Bruggeman average, friction on/off pairs");
  ens->add_option("case", case_path, "case file (TOML) with a selfaffine indenter")->required();
  ens->add_option("--seeds", seeds, "FIRST..LAST (default 0..7)");
  ens->add_option("-o,--output", out_dir, "output directory")->check(non_empty);
  ens->add_option("--set", sets, "override a key (repeatable)");
  ens->add_flag("-q,--quiet", quiet, "no log lines");
  add_force(ens);
  ens->add_flag("--wait", wait, "if another gfmd run writes to the output directory, wait for it");

  std::string plot_dir;
  auto* plot_cmd = app.add_subcommand(
      "plot", "redraw the figures (PNG maps, profiles, sweep plots) of a run, sweep or study directory");
  plot_cmd->add_option("dir", plot_dir, "a directory written by gfmd run, sweep, ensemble or study")
      ->required();

  std::string study_path;
  bool study_quick = false, study_draw_only = false, study_runs_only = false;
  auto* study = app.add_subcommand("study", "run a study of studies/ and draw its figure (matplotlib)");
  study->add_option("study", study_path, "study file (TOML)")->required();
  study->add_flag("--quick", study_quick, "reduced resolution that runs in minutes");
  auto* draw_only_flag = study->add_flag(
      "--draw-only", study_draw_only,
      "draw from the runs on disk and run nothing (sweep studies; a point that did not converge is "
      "not retried, a series without runs is left out)");
  study
      ->add_flag("--runs-only", study_runs_only,
                 "run (or reuse) every series and stop: no figure, no matplotlib needed (a machine that "
                 "computes without drawing; --draw-only draws later)")
      ->excludes(draw_only_flag);
  study->add_option("-o,--output", out_dir, "output root (default out/studies)")->check(non_empty);
  study->add_flag("-q,--quiet", quiet, "print only errors");
  add_force(study);
  study->add_option(
      "--set", sets,
      "a setting for every run of the study, after its own, e.g. solver.backend=\"cuda\" (repeatable)");

  // An unknown command is named (CLI11 would only say that an argument was not expected).
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      found = found || sub->get_name() == word;
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      if (gfmd::mpi::root())
        std::fprintf(stderr, "gfmd: error: unknown command '%s' (commands: %s; gfmd --help)\n", word.c_str(),
                     known.c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Prints help/version or the usage error: once, by rank 0, under mpirun.
    std::ostream none(nullptr);
    const bool prints = gfmd::mpi::root();
    const int rc = app.exit(e, prints ? std::cout : none, prints ? std::cerr : none);
    return rc == 0 ? 0 : 2;
  }
  const auto with_sets = [&sets]() { return sets_note(sets); };
  // Under mpirun the commands that solve cases are distributed (every process solves, rank
  // 0 writes); the others would have every process write the same directory.
  if (gfmd::mpi::distributed() &&
      !(run->parsed() || sweep->parsed() || curve->parsed() || perc->parsed() || ens->parsed())) {
    if (gfmd::mpi::root())
      std::fprintf(
          stderr,
          "gfmd: error: only `gfmd run`, `sweep`, `curve`, `percolation` and `ensemble` run under mpirun "
          "with more than one process (%d here); run this command without mpirun\n",
          gfmd::mpi::size());
    return 2;
  }
  // An error every process meets alike (the same input) is reported once, by rank 0.
  const bool report_common = gfmd::mpi::root();
  try {
    const DirFlags dir_flags{wait, force};
    if (run->parsed())
      return cmd_run(case_path, out_dir, sets, quiet, verbose, resume, checkpoint_s, dir_flags);
    if (sweep->parsed()) return cmd_sweep(case_path, out_dir, sets, plot, quiet, dir_flags);
    if (curve->parsed()) {
      if (pressures_opt->count() == 0 && approaches_opt->count() == 0) {
        std::fprintf(stderr, "gfmd curve: --pressures is required (or --approaches, an approach path)\n");
        return 2;
      }
      return cmd_curve(case_path, out_dir, sets, pressures, approaches_opt->count() > 0 ? approaches : "",
                       approaches_opt->count() > 0, unload, no_png, quiet, dir_flags);
    }
    if (flow->parsed()) return cmd_flow(flow_dir, direction, flow_tol, flow_solver, dir_flags);
    if (perc->parsed())
      return cmd_percolation(case_path, out_dir, sets, direction, area_tol, quiet, dir_flags);
    if (ens->parsed()) return cmd_ensemble(case_path, out_dir, sets, seeds, quiet, dir_flags);
    if (plot_cmd->parsed()) return cmd_plot(plot_dir);
    if (green->parsed()) return cmd_green(green_nu, green_from, green_to, green_points, out_dir, force);
    if (study->parsed())
      return cmd_study(study_path, study_quick, out_dir, sets, quiet, force, study_draw_only,
                       study_runs_only);
  } catch (const gfmd::InputError& e) {
    // A bare list ("--set load.force=1e-3,2e-3") is a sweep's: say so where another command got one.
    const bool list_given =
        !sweep->parsed() && std::any_of(sets.begin(), sets.end(), [](const std::string& v) {
          const auto eq = v.find('=');
          const std::string value = eq == std::string::npos ? "" : v.substr(eq + 1);
          return value.find(',') != std::string::npos && value.find_first_of("[\"'") == std::string::npos;
        });
    if (report_common)
      std::fprintf(stderr, "gfmd: error: %s%s%s\n", e.what(), with_sets().c_str(),
                   list_given
                       ? "\n  (a comma-separated list of values is for `gfmd sweep CASE --set key=a,b,c`)"
                       : "");
    return 2;
  } catch (const gfmd::Interrupted& e) {
    std::fprintf(stderr, "gfmd: %s; stopped on request%s\n", e.what(), with_sets().c_str());
    return 4;
  } catch (const gfmd::SolveError& e) {
    if (report_common)
      std::fprintf(stderr, "gfmd: error: %s: %s%s%s\n", case_path.c_str(), e.what(), with_sets().c_str(),
                   run->parsed() ? "; no results written" : "");
    return 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "gfmd: error: out of memory%s (the memory check before the solve estimated less than was "
                 "available; lower grid.nx or free memory)\n",
                 with_sets().c_str());
    return 1;
  } catch (const gfmd::cli::QuietExit& e) {
    return e.code;  // a follower rank whose reason rank 0 reports
  } catch (const gfmd::StoppedWithRoot& e) {
    return e.code();  // likewise, stopped inside the library
  } catch (const std::exception& e) {
    if (gfmd::mpi::distributed())
      std::fprintf(stderr, "gfmd (rank %d of %d): error: %s%s\n", gfmd::mpi::rank(), gfmd::mpi::size(),
                   e.what(), with_sets().c_str());
    else
      std::fprintf(stderr, "gfmd: error: %s%s\n", e.what(), with_sets().c_str());
    return 1;
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  bound_spin_wait(argv);
  // Started by mpirun: join the other processes first (core/mpi.hpp); every process then
  // exits with the same code.
  try {
    gfmd::mpi::init(&argc, &argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gfmd: error: %s\n", e.what());
    return 1;
  }
  const int code = gfmd::mpi::agree_exit(run_main(argc, argv));
  gfmd::mpi::finalize();
  return code;
}
