// The life cycle of an output directory: refusal, lock, staging, publication.
// See include/gfmd/case/run_directory.hpp.
#include "gfmd/case/run_directory.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"

namespace gfmd {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPublishingMarker = ".publishing";

// The canonical form of a path whose last parts may not exist yet ("" if it cannot be formed).
fs::path canonical_or_empty(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) return {};
  // "dir/" and "dir" are the same directory.
  if (!c.has_filename() && c.has_parent_path() && c != c.root_path()) c = c.parent_path();
  return c;
}

fs::path home_directory() {
  if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0') return canonical_or_empty(h);
  if (const passwd* pw = ::getpwuid(::getuid()); pw != nullptr && pw->pw_dir != nullptr)
    return canonical_or_empty(pw->pw_dir);
  return {};
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// Moves every entry of the staging area into dir (a folder replaces the folder of the same
// name); returns their names.
std::set<std::string> move_staged(const fs::path& staging, const fs::path& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(staging, ec)) {
    const std::string name = e.path().filename().string();
    if (name == kPublishingMarker) continue;
    const fs::path to = dir / name;
    if (fs::is_directory(e.path(), ec) && fs::exists(to, ec)) fs::remove_all(to, ec);
    fs::rename(e.path(), to, ec);
    if (ec) throw std::runtime_error(to.string() + ": cannot publish it: " + ec.message());
    names.insert(name);
  }
  return names;
}

}  // namespace

std::string result_kind(const std::string& dir) {
  // The main table of each kind of result (a sweep's sweep.csv stands in while its
  // sweep.json is not written: the finished points of a first attempt that stopped).
  static const std::pair<const char*, const char*> kMarks[] = {
      {"study.json", "study"}, {"ensemble.json", "ensemble"},
      {"curve.json", "curve"}, {"percolation.json", "percolation"},
      {"sweep.json", "sweep"}, {"sweep.csv", "sweep"},
      {"summary.json", "run"}};
  std::error_code ec;
  for (const auto& [file, kind] : kMarks)
    if (fs::is_regular_file(fs::path(dir) / file, ec)) return kind;
  // Results without their table yet: a curve stopped before curve.json (its points/), an
  // ensemble's first attempt stopped with its seeds staged, a study's series of seeds (a sweep
  // per seed).
  if (fs::is_directory(fs::path(dir) / "points", ec)) return "curve";
  for (const fs::path& where : {fs::path(dir), fs::path(dir) / kStagingName})
    for (const auto& e : fs::directory_iterator(where, ec)) {
      const std::string name = e.path().filename().string();
      if ((name.rfind("seed_", 0) == 0 || name.rfind("frictionless_seed_", 0) == 0) && e.is_directory(ec))
        return fs::is_regular_file(e.path() / "sweep.csv", ec) ? "study series" : "ensemble";
    }
  return "";
}

void check_output_directory(const std::string& dir, bool force, const std::string& kind) {
  if (dir.empty()) throw InputError("output directory", "must not be empty");
  const fs::path c = canonical_or_empty(dir);
  if (c.empty()) throw InputError(dir, "not a usable path for an output directory");
  if (c == c.root_path())
    throw InputError(dir, "refusing to write outputs into the root directory; name a new directory");
  if (const fs::path home = home_directory(); !home.empty() && c == home)
    throw InputError(dir, "refusing to write outputs into the home directory itself; name a new directory");
  std::error_code ec;
  if (const fs::path cwd = canonical_or_empty(fs::current_path(ec)); !ec && c == cwd)
    throw InputError(dir,
                     "refusing to write outputs into the working directory itself; name a new directory");
  const auto st = fs::status(c, ec);
  if (!fs::exists(st)) return;
  if (!fs::is_directory(st)) throw InputError(dir, "exists and is not a directory");
  if (force) return;
  // Another kind of result would be replaced (its outputs are gfmd's): only when asked to.
  if (const std::string held = result_kind(c.string()); !kind.empty() && !held.empty() && held != kind)
    throw InputError(dir, "holds a gfmd " + held + " result, which this " + kind +
                              " would replace; name another directory, or pass --force (Python: force=True) "
                              "to replace it");
  if (fs::exists(c / kDirectoryMarker, ec)) return;
  fs::directory_iterator it(c, ec);
  if (ec) throw InputError(dir, "cannot read the directory: " + ec.message());
  if (it != fs::directory_iterator())
    throw InputError(dir,
                     "the directory is not empty and was not made by gfmd (it has no " +
                         std::string(kDirectoryMarker) +
                         "); name a new or empty directory, or pass --force (Python: force=True) to write "
                         "into it anyway");
}

void make_gfmd_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create the directory: " + ec.message());
  const fs::path marker = fs::path(dir) / kDirectoryMarker;
  if (!fs::exists(marker, ec)) write_text_atomic(marker.string(), "");
}

bool is_run_output_name(const std::string& name) {
  static const std::set<std::string> kNames = {
      "summary.json",        "status.json",       "fields.nc",
      "flow.json",           "flow.nc",           "profiles.csv",
      "patches.csv",         "distributions.csv", "spectrum.csv",
      "bands.csv",           "analysis.png",      "profiles.png",
      "pressure.png",        "gap.png",           "slip_longitudinal.png",
      "slip_transverse.png", "dissipation.png",   "max_principal_stress.png",
      "von_mises.png",       "checkpoint.bin",    kStagingName};
  return kNames.count(name) != 0 ||
         (name.rfind("current_", 0) == 0 && name.size() > 12 && ends_with(name, ".png")) ||
         name.find(".tmp.") != std::string::npos;
}

bool is_sweep_output_name(const std::string& name) {
  int k = -1;
  return name == "sweep.csv" || name == "sweep.json" || name == "status.json" || name == kStagingName ||
         (name.rfind("sweep_", 0) == 0 && ends_with(name, ".png")) ||
         (name.rfind("point_", 0) == 0 && std::sscanf(name.c_str() + 6, "%d", &k) == 1) ||
         name.find(".tmp.") != std::string::npos;
}

bool is_gfmd_output_name(const std::string& name) {
  return is_run_output_name(name) || is_sweep_output_name(name) || name == "ensemble.json" ||
         name.rfind("seed_", 0) == 0 || name.rfind("frictionless_seed_", 0) == 0 || name == "curve.csv" ||
         name == "curve.json" || name == "curve.png" || name == "curve.pdf" || name == "points" ||
         name == "percolation.json";
}

RunDirectory::RunDirectory(const std::string& dir, const OutputDirOptions& opts, bool keep_staging)
    : dir_(dir),
      staging_((fs::path(dir) / kStagingName).string()),
      lock_((check_output_directory(dir, opts.force, opts.kind), dir), opts.wait, opts.stop_request),
      owns_status_(opts.owns_status) {
  // Results are only ever published complete: their main table marks them.
  std::error_code ec;
  had_result_ =
      fs::exists(fs::path(dir_) / "summary.json", ec) || fs::exists(fs::path(dir_) / "sweep.json", ec);
  if (!fs::exists(staging_, ec)) return;
  if (fs::exists(fs::path(staging_) / kPublishingMarker, ec)) {
    // A publication that a crash cut short: finish it (its set was complete).
    (void)move_staged(staging_, dir_);
    fs::remove_all(staging_, ec);
    if (owns_status_) write_status(dir_, "converged");
    had_result_ = true;
    return;
  }
  if (!keep_staging) fs::remove_all(staging_, ec);
}

RunDirectory::~RunDirectory() {
  if (!open_attempt_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
  // An attempt that an error ended before its caller published, failed or interrupted it
  // (one no branch of a study expects: a point's surface that cannot be made, a full disk):
  // status.json must not stay "running", which reads as a live or crashed writer.
  try {
    write_state("failed", "stopped by an error before it finished (its message went to the caller)");
  } catch (...) {
  }
}

std::string RunDirectory::checkpoint() const { return (fs::path(dir_) / "checkpoint.bin").string(); }

void RunDirectory::begin() {
  std::error_code ec;
  fs::create_directories(staging_, ec);
  if (ec) throw std::runtime_error(staging_ + ": cannot create the staging directory: " + ec.message());
  open_attempt_ = true;
  write_state("running", "");
}

std::string RunDirectory::kept_note() const {
  return had_result_ ? "the previous result in " + dir_ + "/ is kept unchanged" : "";
}

void RunDirectory::write_state(const std::string& status, const std::string& why) {
  if (!owns_status_) return;
  write_status(dir_, status, why, status == "converged" ? "" : kept_note());
}

void RunDirectory::publish(const std::function<bool(const std::string&)>& owned, const std::string& status,
                           const std::string& why) {
  write_text_atomic((fs::path(staging_) / kPublishingMarker).string(), "publishing\n");
  const std::set<std::string> names = move_staged(staging_, dir_);
  std::error_code ec;
  fs::remove_all(staging_, ec);
  open_attempt_ = false;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "status.json" && name != kDirectoryMarker && owned(name) && names.count(name) == 0)
      stale.push_back(e.path());
  }
  for (const fs::path& p : stale) fs::remove_all(p, ec);
  had_result_ = true;
  if (owns_status_) write_status(dir_, status, why);
}

std::string RunDirectory::fail(const std::string& why, bool keep_staging) {
  std::error_code ec;
  if (!keep_staging) fs::remove_all(staging_, ec);
  open_attempt_ = false;
  try {
    write_state("failed", why);
  } catch (const std::exception&) {
    // The status cannot be written either (disk full): the message on stderr remains.
  }
  return kept_note();
}

std::string RunDirectory::interrupt(const std::string& why, bool keep_staging) {
  std::error_code ec;
  if (!keep_staging) fs::remove_all(staging_, ec);
  open_attempt_ = false;
  try {
    write_state("interrupted", why);
  } catch (const std::exception&) {
  }
  return kept_note();
}

}  // namespace gfmd
