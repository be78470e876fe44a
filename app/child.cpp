#include "child.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>

#include "gfmd/version.hpp"

extern char** environ;

namespace gfmd::cli {

namespace {
volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }
}  // namespace

// SIGINT/SIGTERM set a flag that every solve polls (no SA_RESTART: a wait returns early).
void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
bool stop_requested() { return g_stop != 0; }

// This program's own path (for helper scripts next to it and for study.py to call back).
std::filesystem::path self_exe() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path("gfmd") : p;
}

// The Python interpreter for the plotting helpers: $GFMD_PYTHON, else the one chosen at build
// time (Debian's, which has numpy and matplotlib).
std::string python_interpreter() {
  const char* env = std::getenv("GFMD_PYTHON");
  return env && *env ? env : GFMD_PYTHON;
}

// A helper script installed beside the program: <prefix>/share/gfmd/scripts next to
// <prefix>/bin/gfmd, or share/gfmd/scripts in the build tree. Empty if not found.
std::string find_script(const std::string& name) {
  const auto dir = self_exe().parent_path();
  for (const auto& cand :
       {dir / ".." / "share" / "gfmd" / "scripts" / name, dir / "share" / "gfmd" / "scripts" / name}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(cand, ec)) return cand.lexically_normal().string();
  }
  return "";
}

// Runs a program with an argument vector (never through a shell) and waits for it. Its
// standard output (unless keep_stdout; and error, if quiet) go to /dev/null. A stop request
// that reached this process alone (kill PID, timeout) is passed on to it as SIGTERM. Returns
// its exit status, or -1 if it could not be started or was killed. GFMD in its environment
// names this program.
int run_child(const std::vector<std::string>& args, bool quiet, bool keep_stdout) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> env_store;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::strncmp(*e, "GFMD=", 5) != 0) env_store.emplace_back(*e);
  env_store.push_back("GFMD=" + self_exe().string());
  std::vector<char*> envp;
  for (auto& e : env_store) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (!keep_stdout) posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  if (quiet) posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  // A Ctrl-C at a terminal reaches the child itself; a signal sent to this process alone is
  // passed on if the child has not ended a second after it.
  int polls_since_stop = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) return -1;
    if (stop_requested() && ++polls_since_stop == 50) ::kill(pid, SIGTERM);
    ::usleep(20000);
  }
  // Our children (the drawing scripts, study.py) exit 4 when they were interrupted: so is this
  // program then, whoever got the signal.
  if (WIFEXITED(status) && WEXITSTATUS(status) == 4) g_stop = 1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs a plotting helper; false (with nothing else done) if it is missing or fails.
bool run_script(const std::string& script, const std::vector<std::string>& args, bool quiet) {
  const std::string path = find_script(script);
  if (path.empty()) return false;
  std::vector<std::string> argv = {python_interpreter(), path};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_child(argv, quiet) == 0;
}

}  // namespace gfmd::cli
