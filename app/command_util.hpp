// Helpers shared by the subcommands (app/commands.cpp, run_command.cpp, study_commands.cpp):
// the progress display and the output-directory lock of a distributed command.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "child.hpp"
#include "commands.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/mpi.hpp"

namespace gfmd::cli {

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
      std::fprintf(stderr, "  friction step %3d: %6d iterations, traction change %.3e\n", p.outer,
                   p.iteration, p.error);
      return;
    }
    if (since < (tty ? 0.2 : 5.0)) return;
    last = now;
    const double el = std::chrono::duration<double>(now - start).count();
    if (tty)
      std::fprintf(stderr, "\r  iteration %6d  friction step %3d  change %.2e  %.1f s   ", p.iteration,
                   p.outer, p.error, el);
    else
      std::fprintf(stderr, "  iteration %d friction step %d change %.3e elapsed %.1f s\n", p.iteration,
                   p.outer, p.error, el);
  }
  void done() const {
    if (tty && !quiet) std::fprintf(stderr, "\r%80s\r", "");
  }
};

// The lock of an output directory: held by rank 0 alone under mpirun, its outcome (taken, or
// refused) agreed with the other processes; the lock itself in one process.
// kind: what the command makes there (gfmd::check_output_directory).
inline std::unique_ptr<gfmd::DirectoryLock> lock_on_root(const std::string& dir, DirFlags flags,
                                                         const std::string& kind) {
  std::unique_ptr<gfmd::DirectoryLock> lock;
  gfmd::on_root([&] {
    gfmd::check_output_directory(dir, flags.force, kind);
    lock = std::make_unique<gfmd::DirectoryLock>(dir, flags.wait, stop_requested);
  });
  return lock;
}

}  // namespace gfmd::cli
