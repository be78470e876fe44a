// gfmd command line: thin front end over the library.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "gfmd/error.hpp"
#include "gfmd/io.hpp"
#include "gfmd/run.hpp"
#include "gfmd/version.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }
void install_signal_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}
bool stop_requested() { return g_stop != 0; }

struct ProgressPrinter {
  bool tty = isatty(STDERR_FILENO) != 0;
  bool quiet = false;
  bool verbose = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last = start;
  void operator()(const gfmd::Progress& p) {
    if (quiet) return;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last).count();
    if (verbose && p.outer > 0) {
      std::fprintf(stderr, "  friction step %3d: %6d iterations, traction change %.3e\n", p.outer, p.iteration, p.error);
      return;
    }
    if (since < (tty ? 0.2 : 5.0)) return;
    last = now;
    const double el = std::chrono::duration<double>(now - start).count();
    if (tty)
      std::fprintf(stderr, "\r  iteration %6d  friction step %3d  change %.2e  %.1f s   ", p.iteration, p.outer,
                   p.error, el);
    else
      std::fprintf(stderr, "  iteration %d friction step %d change %.3e elapsed %.1f s\n", p.iteration, p.outer,
                   p.error, el);
  }
  void done() const {
    if (tty && !quiet) std::fprintf(stderr, "\r%80s\r", "");
  }
};

int cmd_run(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets, bool quiet,
            bool verbose, bool resume, double checkpoint_s) {
  const gfmd::Config cfg = gfmd::load_config(case_path, sets);
  if (out_dir.empty()) out_dir = (std::filesystem::path("out") / std::filesystem::path(case_path).stem()).string();
  namespace fs = std::filesystem;
  const std::string ckpt = (fs::path(out_dir) / "checkpoint.bin").string();
  gfmd::ContactFields warm;
  bool have_warm = false;
  if (resume) {
    const fs::path sp = fs::path(out_dir) / "summary.json";
    if (fs::exists(sp)) {
      std::ifstream in(sp);
      nlohmann::json old;
      try {
        old = nlohmann::json::parse(in);
      } catch (const std::exception&) {
      }
      if (old.is_object() && old.value("converged", false) && old["input"] == cfg.to_json()) {
        std::printf("%s: already solved in %s/ (summary.json); nothing to do\n", case_path.c_str(), out_dir.c_str());
        return 0;
      }
    }
    have_warm = gfmd::read_checkpoint(ckpt, cfg, warm);
    if (!quiet)
      std::fprintf(stderr, "%s\n", have_warm ? "resuming from the checkpoint" : "no usable checkpoint: starting afresh");
  }
  // Validates the topography before anything is written.
  (void)gfmd::make_topography(cfg);
  fs::create_directories(out_dir);
  gfmd::write_status(out_dir, "running");
  ProgressPrinter pp;
  pp.quiet = quiet;
  pp.verbose = verbose;
  gfmd::RunOptions opts;
  opts.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  opts.stop_request = stop_requested;
  opts.checkpoint_path = ckpt;
  opts.checkpoint_interval_s = checkpoint_s;
  if (have_warm) opts.warm_start = &warm;
  gfmd::CaseResult r;
  try {
    r = gfmd::run_case(cfg, opts);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    gfmd::write_status(out_dir, "interrupted", e.what());
    std::fprintf(stderr, "gfmd: %s: %s; state saved in %s, continue with --resume\n", case_path.c_str(), e.what(),
                 ckpt.c_str());
    return 4;
  } catch (const std::exception& e) {
    gfmd::write_status(out_dir, "failed", e.what());
    std::error_code ec;
    fs::remove(ckpt, ec);
    throw;
  }
  pp.done();
  if (!r.info.converged) {
    char why[512];
    std::snprintf(why, sizeof why,
                  "%s after %d iterations (pressure change %.3e, friction change %.3e, tolerance %.1e)",
                  r.info.status.c_str(), r.info.iterations, r.info.pk_error, r.info.friction_error,
                  cfg.solver.tolerance);
    gfmd::write_status(out_dir, "failed", why);
    std::error_code ec;
    fs::remove(ckpt, ec);
    std::fprintf(stderr, "gfmd: error: %s: %s; no results written\n", case_path.c_str(), why);
    return 3;
  }
  gfmd::write_outputs(r, out_dir);
  gfmd::write_status(out_dir, "converged");
  std::error_code ec;
  fs::remove(ckpt, ec);
  const auto& o = r.observables;
  std::printf("%s: %s in %d iterations (%.2f s, residual %.2e)\n", case_path.c_str(), r.info.status.c_str(),
              r.info.iterations, r.info.wall_time_s, r.info.residual);
  std::printf("  relative contact area  %.6g\n", o.relative_contact_area);
  std::printf("  normal force           %.6g\n", o.normal_force);
  std::printf("  mean / max pressure    %.6g / %.6g\n", o.mean_pressure, o.max_pressure);
  std::printf("  mean gap               %.6g\n", o.mean_gap);
  if (cfg.friction.coefficient > 0) {
    std::printf("  friction coefficient   %.6g (dissipation)  %.6g (downhill)\n", o.friction_coefficient,
                o.friction_coefficient_downhill);
  }
  std::printf("  outputs in %s/\n", out_dir.c_str());
  return 0;
}

int cmd_sweep(const std::string& case_path, std::string out_dir, const std::vector<std::string>& sets_in,
              std::string plot, bool quiet) {
  std::vector<std::string> sets;
  std::string param;
  std::vector<double> values;
  for (const auto& s : sets_in) {
    const auto eq = s.find('=');
    if (eq != std::string::npos && s.find(',', eq) != std::string::npos) {
      if (!param.empty())
        throw gfmd::InputError("--set " + s, "only one swept key per sweep (already sweeping " + param + ")");
      param = s.substr(0, eq);
      std::stringstream ss(s.substr(eq + 1));
      std::string tok;
      while (std::getline(ss, tok, ',')) {
        try {
          std::size_t used = 0;
          values.push_back(std::stod(tok, &used));
          if (used != tok.size()) throw std::invalid_argument(tok);
        } catch (const std::exception&) {
          throw gfmd::InputError("--set " + s, "'" + tok + "' is not a number");
        }
      }
    } else {
      sets.push_back(s);
    }
  }
  gfmd::Config cfg = gfmd::load_config(case_path, param.empty() ? sets : [&] {
    auto v = sets;
    v.push_back(param + "=" + std::to_string(values.front()));
    return v;
  }());
  if (!param.empty()) {
    cfg.sweep.parameter = param;
    cfg.sweep.values = values;
  }
  if (!cfg.sweep.active())
    throw gfmd::InputError(case_path, "nothing to sweep: add --set section.key=v1,v2,... or a [sweep] table");
  if (plot.empty()) plot = cfg.sweep.plot;
  if (out_dir.empty())
    out_dir = (std::filesystem::path("out") / (std::filesystem::path(case_path).stem().string() + "_sweep")).string();
  ProgressPrinter pp;
  pp.quiet = quiet;
  gfmd::SweepOptions so;
  so.overrides = sets;
  so.progress = [&pp](const gfmd::Progress& p) { pp(p); };
  so.stop_request = stop_requested;
  const auto t0 = std::chrono::steady_clock::now();
  so.on_point = [&](int done, int total, const std::string& msg) {
    pp.done();
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!quiet)
      std::fprintf(stderr, "[%d/%d] %s (elapsed %.1f s, about %.0f s left)\n", done, total, msg.c_str(), el,
                   el / done * (total - done));
  };
  // The sweep re-reads the case for every point; [sweep] given on the command line is
  // passed on through the overrides-free config copy.
  try {
    gfmd::run_sweep(case_path, cfg, out_dir, so);
  } catch (const gfmd::Interrupted& e) {
    pp.done();
    std::fprintf(stderr, "gfmd: sweep interrupted (%s); finished points and a checkpoint are kept in %s/, run the "
                 "same command again to continue\n", e.what(), out_dir.c_str());
    return 4;
  }
  std::printf("sweep of %s over %zu values: tables in %s/sweep.csv and sweep.json\n", cfg.sweep.parameter.c_str(),
              cfg.sweep.values.size(), out_dir.c_str());
  const std::string cmd = std::string("\"") + GFMD_PYTHON + "\" \"" + GFMD_SCRIPTS_DIR + "/plot_sweep.py\" \"" +
                          out_dir + "/sweep.csv\" --y \"" + plot + "\" > /dev/null";
  if (std::system(cmd.c_str()) != 0)
    std::fprintf(stderr, "gfmd: warning: could not draw %s with matplotlib (%s)\n", plot.c_str(), GFMD_PYTHON);
  else
    std::printf("  plot: %s/sweep_%s.png\n", out_dir.c_str(), plot.c_str());
  return 0;
}

// Tabulates the dimensionless Green's tensor of SPEC §2 (frame with q along axis 1).
int cmd_green(const std::vector<double>& nus, double from, double to, int points, const std::string& out) {
  if (!(from > 0 && to > from) || points < 2) throw gfmd::InputError("gfmd green", "need 0 < --from < --to and --points >= 2");
  for (double nu : nus) gfmd::ElasticParams{1.0, nu, 1.0, true}.validate();
  std::ostringstream os;
  os.precision(12);
  os << "poisson,qh,phi11,phi22,phi33,im_phi13\n";
  for (double nu : nus)
    for (int i = 0; i < points; ++i) {
      const double qh = from * std::pow(to / from, static_cast<double>(i) / (points - 1));
      const gfmd::PhiRotated p = gfmd::phi_rotated(qh, nu);
      os << nu << "," << qh << "," << p.p11 << "," << p.p22 << "," << p.p33 << "," << p.p13 << "\n";
    }
  if (out.empty() || out == "-")
    std::fputs(os.str().c_str(), stdout);
  else
    gfmd::write_text_atomic(out, os.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gfmd: steady sliding contacts with full elastic coupling"};
  app.set_version_flag("--version", std::string(gfmd::kVersion) + " (" + gfmd::kGitCommit + ")");
  app.require_subcommand(1);

  std::string case_path, out_dir;
  std::vector<std::string> sets;
  bool quiet = false;
  auto* run = app.add_subcommand("run", "solve one case and write summary.json, fields.nc and PNG maps");
  run->add_option("case", case_path, "case file (TOML)")->required();
  run->add_option("-o,--output", out_dir, "output directory (default: out/<case name>)");
  run->add_option("--set", sets, "override a key: section.key=value (repeatable)");
  run->add_flag("-q,--quiet", quiet, "no progress display");
  bool verbose = false, resume = false;
  double checkpoint_s = 60.0;
  run->add_flag("-v,--verbose", verbose, "print every friction fixed-point step");
  run->add_flag("--resume", resume, "continue from DIR/checkpoint.bin (or do nothing if DIR holds the result)");
  run->add_option("--checkpoint-interval", checkpoint_s, "seconds between checkpoints (default 60)");

  std::string plot;
  auto* sweep = app.add_subcommand("sweep", "solve a case for a list of values of one key, warm-starting each point");
  sweep->add_option("case", case_path, "case file (TOML)")->required();
  sweep->add_option("-o,--output", out_dir, "output directory (default: out/<case name>_sweep)");
  sweep->add_option("--set", sets, "override a key; one key may take a comma-separated list: the sweep");
  sweep->add_option("--plot", plot, "summary key to plot against the swept value (default friction_coefficient)");
  sweep->add_flag("-q,--quiet", quiet, "no progress display");

  install_signal_handlers();
  std::vector<double> green_nu{0.0, 0.25, 0.49};
  double green_from = 1e-2, green_to = 1e2;
  int green_points = 121;
  auto* green = app.add_subcommand("green", "tabulate the Green's tensor Phi(qh) of a layer (CSV)");
  green->add_option("--poisson", green_nu, "Poisson ratios")->delimiter(',');
  green->add_option("--from", green_from, "smallest qh");
  green->add_option("--to", green_to, "largest qh");
  green->add_option("--points", green_points, "points per Poisson ratio (log spaced)");
  green->add_option("-o,--output", out_dir, "CSV file (default: standard output)");

  std::string study_path;
  bool study_quick = false;
  auto* study = app.add_subcommand("study", "run a study of studies/ and draw its figure (matplotlib)");
  study->add_option("study", study_path, "study file (TOML)")->required();
  study->add_flag("--quick", study_quick, "reduced resolution that runs in minutes");
  study->add_option("-o,--output", out_dir, "output root (default out/studies)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help/version or the usage error
    return rc == 0 ? 0 : 2;
  }
  try {
    if (run->parsed()) return cmd_run(case_path, out_dir, sets, quiet, verbose, resume, checkpoint_s);
    if (sweep->parsed()) return cmd_sweep(case_path, out_dir, sets, plot, quiet);
    if (green->parsed()) return cmd_green(green_nu, green_from, green_to, green_points, out_dir);
    if (study->parsed()) {
      std::string cmd = std::string("\"") + GFMD_PYTHON + "\" \"" + GFMD_SCRIPTS_DIR + "/study.py\" \"" + study_path + "\"";
      if (study_quick) cmd += " --quick";
      if (!out_dir.empty()) cmd += " -o \"" + out_dir + "\"";
      const int rc = std::system(cmd.c_str());
      return (rc == 0) ? 0 : 1;
    }
  } catch (const gfmd::InputError& e) {
    std::fprintf(stderr, "gfmd: error: %s\n", e.what());
    return 2;
  } catch (const gfmd::SolveError& e) {
    std::fprintf(stderr, "gfmd: error: %s: %s; no results written\n", case_path.c_str(), e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gfmd: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
