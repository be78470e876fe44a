// Child processes of the command line, by argument vector only (no shell), and the stop
// flag that SIGINT/SIGTERM set.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gfmd::cli {

// SIGINT/SIGTERM set a flag that every solve polls (no SA_RESTART: a wait returns early).
void install_signal_handlers();
bool stop_requested();

// This program's own path (for helper scripts next to it and for study.py to call back).
std::filesystem::path self_exe();
// The Python interpreter for the plotting helpers: $GFMD_PYTHON, else the one chosen at build
// time (Debian's, which has numpy and matplotlib).
std::string python_interpreter();
// A helper script installed beside the program: <prefix>/share/gfmd/scripts next to
// <prefix>/bin/gfmd, or share/gfmd/scripts in the build tree. Empty if not found.
std::string find_script(const std::string& name);
// Runs a program with an argument vector (never through a shell) and waits for it. Its
// standard output (and error, if quiet) go to /dev/null. Returns its exit status, or -1 if
// it could not be started or was killed. GFMD in its environment names this program.
int run_child(const std::vector<std::string>& args, bool quiet, bool keep_stdout = false);
// Runs a plotting helper; false (with nothing else done) if it is missing or fails.
bool run_script(const std::string& script, const std::vector<std::string>& args, bool quiet);

}  // namespace gfmd::cli
