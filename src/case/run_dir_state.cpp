// Run directories' state: status.json, the one-writer lock, a finished result of the same case,
// and clearing stale outputs (the checkpoints: run_dir.cpp). See include/gfmd/case/run_dir.hpp.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

namespace fs = std::filesystem;

std::optional<nlohmann::json> finished_summary(const std::string& dir, const Config& cfg) {
  std::ifstream in(fs::path(dir) / "summary.json");
  if (!in) return std::nullopt;
  nlohmann::json old;
  try {
    old = nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (old.is_object() && old.contains("input") && old["input"] == cfg.to_json() &&
      old.value("converged", false))
    return old;
  return std::nullopt;
}

void write_status(const std::string& dir, const std::string& status, const std::string& reason,
                  const std::string& result) {
  nlohmann::json j = {{"status", status},
                      {"version", kVersion},
                      {"git_commit", kGitCommit},
                      {"pid", static_cast<long>(::getpid())}};
  if (!reason.empty()) j["reason"] = reason;
  if (!result.empty()) j["result"] = result;
  write_text_atomic((fs::path(dir) / "status.json").string(), j.dump(2) + "\n");
}

std::string read_status(const std::string& dir) {
  std::ifstream in(fs::path(dir) / "status.json");
  if (!in) return "";
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    return j.is_object() && j.contains("status") && j["status"].is_string() ? j["status"].get<std::string>()
                                                                            : "";
  } catch (const std::exception&) {
    return "";
  }
}

DirectoryLock::DirectoryLock(const std::string& dir, bool wait, const std::function<bool()>& stop_request) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create the output directory: " + ec.message());
  const std::string path = (fs::path(dir) / ".gfmd.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0)
    throw InputError(dir, "cannot create the lock file .gfmd.lock: " + std::string(std::strerror(errno)));
  bool told = false;
  while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK && errno != EINTR) {
      const int err = errno;
      ::close(fd_);
      throw InputError(dir, "cannot lock the output directory: " + std::string(std::strerror(err)));
    }
    char buf[32] = {0};
    const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
    const std::string holder = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string("?");
    if (!wait) {
      ::close(fd_);
      throw InputError(dir, "the output directory is in use by another gfmd run (process " + holder +
                                "); wait for it, use another -o directory, or pass --wait");
    }
    if (!told) {
      std::fprintf(stderr, "gfmd: waiting for process %s to finish writing %s\n", holder.c_str(),
                   dir.c_str());
      told = true;
    }
    if (stop_request && stop_request()) {
      ::close(fd_);
      throw Interrupted("interrupted while waiting for the output directory " + dir);
    }
    ::usleep(200000);
  }
  const std::string pid = std::to_string(static_cast<long>(::getpid()));
  if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is only informative.
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

std::vector<std::string> clear_run_outputs(const std::string& dir, bool keep_checkpoint) {
  std::vector<std::string> removed;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec)) continue;
    const std::string name = e.path().filename().string();
    const bool ours = is_run_output_name(name);
    if (!ours || (keep_checkpoint && name == "checkpoint.bin")) continue;
    if (fs::remove(e.path(), ec)) removed.push_back(name);
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

}  // namespace gfmd
