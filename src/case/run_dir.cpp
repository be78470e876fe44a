// Run directories: checkpoints, status, the writer lock, clearing stale outputs.
// See include/gfmd/case/run_dir.hpp.
#include "gfmd/case/run_dir.hpp"

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
#include <set>
#include <sstream>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
namespace gfmd {

namespace fs = std::filesystem;

namespace {
// Version 2 adds the iterations and wall time done so far (a resumed run reports totals).
constexpr char kCheckpointMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', '2'};
}  // namespace

CheckpointStream::CheckpointStream(const std::string& path, const Config& cfg,
                                   const CheckpointProgress& progress)
    : file_(path), n_(cfg.grid.size()) {
  const std::string input = cfg.to_json().dump();
  std::string buf(kCheckpointMagic, 8);
  const auto put = [&buf](const void* p, std::size_t n) { buf.append(static_cast<const char*>(p), n); };
  const std::uint64_t len = input.size();
  const std::int32_t nx = cfg.grid.nx, ny = cfg.grid.ny;
  put(&nx, 4);
  put(&ny, 4);
  put(&len, 8);
  buf += input;
  put(&progress.iterations, 8);
  put(&progress.wall_time_s, 8);
  file_.append_bytes(buf.data(), buf.size());
}

void CheckpointStream::add(const RealField& field) {
  if (added_ == 3) throw std::logic_error("CheckpointStream: three fields only");
  ++added_;
  if (field.size() == n_) {
    file_.append_bytes(field.data(), n_ * sizeof(double));
    return;
  }
  const std::vector<double> zeros(n_, 0.0);
  file_.append_bytes(zeros.data(), n_ * sizeof(double));
}

void CheckpointStream::commit() {
  if (added_ != 3) throw std::logic_error("CheckpointStream: pressure, tx and ty are needed");
  file_.sync_tmp();
  file_.commit();
}

void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress) {
  CheckpointStream s(path, cfg, progress);
  for (const RealField* fld : {&f.pressure, &f.tx, &f.ty}) s.add(*fld);
  s.commit();
}

bool read_checkpoint(const std::string& path, const Config& cfg, ContactFields& f,
                     CheckpointProgress* progress) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  const auto get = [&](void* p, std::size_t n) {
    if (pos + n > data.size()) return false;
    std::memcpy(p, data.data() + pos, n);
    pos += n;
    return true;
  };
  char magic[8];
  std::int32_t nx = 0, ny = 0;
  std::uint64_t len = 0;
  if (!get(magic, 8) || std::memcmp(magic, kCheckpointMagic, 8) != 0) return false;
  if (!get(&nx, 4) || !get(&ny, 4) || !get(&len, 8)) return false;
  if (nx != cfg.grid.nx || ny != cfg.grid.ny || len > data.size()) return false;
  const std::string input = data.substr(pos, len);
  pos += len;
  if (input != cfg.to_json().dump()) return false;
  CheckpointProgress done;
  if (!get(&done.iterations, 8) || !get(&done.wall_time_s, 8)) return false;
  if (done.iterations < 0 || !(done.wall_time_s >= 0) || !std::isfinite(done.wall_time_s)) return false;
  const std::size_t n = cfg.grid.size();
  if (data.size() != pos + 3 * n * sizeof(double)) return false;
  for (RealField* fld : {&f.pressure, &f.tx, &f.ty}) {
    fld->resize(n);
    get(fld->data(), n * sizeof(double));
    for (double v : *fld)
      if (!std::isfinite(v)) return false;
  }
  if (progress) *progress = done;
  return true;
}

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

void write_status(const std::string& dir, const std::string& status, const std::string& reason) {
  nlohmann::json j = {{"status", status},
                      {"version", kVersion},
                      {"git_commit", kGitCommit},
                      {"pid", static_cast<long>(::getpid())}};
  if (!reason.empty()) j["reason"] = reason;
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
  static const std::set<std::string> kNames = {
      "summary.json",        "status.json",       "fields.nc",
      "flow.json",           "flow.nc",           "profiles.csv",
      "patches.csv",         "distributions.csv", "spectrum.csv",
      "bands.csv",           "analysis.png",      "profiles.png",
      "pressure.png",        "gap.png",           "slip_longitudinal.png",
      "slip_transverse.png", "dissipation.png",   "max_principal_stress.png",
      "von_mises.png",       "checkpoint.bin"};
  std::vector<std::string> removed;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec)) continue;
    const std::string name = e.path().filename().string();
    const bool ours = kNames.count(name) != 0 ||
                      (name.rfind("current_", 0) == 0 && name.size() > 12 &&
                       name.compare(name.size() - 4, 4, ".png") == 0) ||
                      name.find(".tmp.") != std::string::npos;
    if (!ours || (keep_checkpoint && name == "checkpoint.bin")) continue;
    if (fs::remove(e.path(), ec)) removed.push_back(name);
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

}  // namespace gfmd
