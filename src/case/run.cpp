#include "gfmd/case/run.hpp"

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
#include "gfmd/io/png.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

namespace fs = std::filesystem;

namespace {
std::string profiles_table(const CaseResult& r, const FFT& fft);

// Stresses, their summaries and the profiles table. With keep_fields false only the
// summaries and the table stay (the full fields are what fields.nc and the PNG maps show).
void compute_stresses(CaseResult& r, const FFT& fft, bool keep_fields) {
  const Config& cfg = r.config;
  r.stress = surface_stress(fft, cfg.elastic, r.fields);
  r.principal = principal(r.stress, keep_fields ? PrincipalParts::All : PrincipalParts::SummaryOnly);
  r.stress_summary = summarize(cfg.grid, r.principal, cfg.stress.high_tension_fraction);
  r.has_stress = true;
  // Fraction of the cells with s1 >= half its maximum (the full solution's here, while its
  // field is still there; each post-analysis's below).
  const auto above_half = [&cfg](const RealField& s1, double max) {
    if (!(max > 0)) return 0.0;
    std::size_t k = 0;
    for (double v : s1) k += v >= 0.5 * max ? 1 : 0;
    return static_cast<double>(k) / static_cast<double>(cfg.grid.size());
  };
  if (!cfg.stress.post_analysis.empty())
    r.area_above_half_max = above_half(r.principal.s1, r.stress_summary.max_tensile_stress);
  if (cfg.stress.profiles) r.profiles_csv = profiles_table(r, fft);
  if (!keep_fields) {
    r.stress = StressField{};
    r.principal = PrincipalField{};
  }
  if (!cfg.stress.post_analysis.empty()) {
    // The frictionless solution: the reference solve (kept for this alone), or the solution
    // itself without friction, or (no reference kept) a frictionless solve now.
    ContactFields rf;
    if (!r.reference_pressure.empty()) {
      rf.pressure = std::move(r.reference_pressure);
      rf.ux = std::move(r.reference_ux);
      rf.uy = std::move(r.reference_uy);
    } else if (cfg.friction.coefficient == 0) {
      rf.pressure = r.fields.pressure;
      rf.ux = r.fields.ux;
      rf.uy = r.fields.uy;
    }
    const ElasticBody body(cfg.grid, cfg.elastic);
    if (rf.pressure.empty()) {
      FrictionParams none = cfg.friction;
      none.coefficient = 0.0;
      ContactSolver ref(body, r.topography, cfg.interaction, none, cfg.solver);
      const SolveInfo info = ref.solve(cfg.load, rf);
      if (!info.converged) throw SolveError("post-analysis reference: " + info.status);
    }
    const double mu = cfg.friction.coefficient, angle = cfg.friction.direction_deg;
    for (const std::string& kind : cfg.stress.post_analysis) {
      PrincipalField pp;
      {
        const StressField ps = kind == "paper" ? paper_post_analysis_stress(fft, cfg.elastic, rf, mu, angle)
                                               : post_analysis_stress(fft, body, rf.pressure, mu, angle);
        pp = principal(ps, PrincipalParts::SummaryOnly);
      }
      CaseResult::PostAnalysis pa;
      pa.kind = kind;
      pa.summary = summarize(cfg.grid, pp, cfg.stress.high_tension_fraction);
      pa.area_above_half_max = above_half(pp.s1, pa.summary.max_tensile_stress);
      pa.s1 = std::move(pp.s1);
      r.post_analyses.push_back(std::move(pa));
    }
  }
  for (double d : cfg.stress.depths) {
    const PrincipalField pf =
        principal(subsurface_stress(fft, cfg.elastic, r.fields, d), PrincipalParts::SummaryOnly);
    r.subsurface.push_back(
        {d, summarize(cfg.grid, pf, cfg.stress.high_tension_fraction), pf.von_mises, pf.s1});
  }
}
}  // namespace

bool outputs_need_stress_fields(const Config& cfg) { return cfg.output.fields || cfg.output.png; }

CaseResult run_case(const Config& cfg, const RunOptions& opts) {
  set_threads(cfg.threads);
  CaseResult r;
  r.config = cfg;
  r.topography = make_topography(cfg);
  r.topography_stats = statistics(r.topography);
  // The body and the solvers live only as long as the solves: the stage after them
  // (stresses, flow) gets the memory back.
  auto body = std::make_unique<ElasticBody>(cfg.grid, cfg.elastic);
  if (opts.warm_start && opts.warm_start->pressure.size() == cfg.grid.size()) r.fields = *opts.warm_start;
  // Work counted into checkpoints: earlier sessions, the finished reference solve and the
  // solver running now.
  const auto t_start = std::chrono::steady_clock::now();
  const ContactSolver* running = nullptr;
  std::int64_t finished_iterations = 0;
  const auto progress_now = [&] {
    CheckpointProgress p = opts.resumed;
    p.iterations += finished_iterations + (running ? running->iterations_done() : 0);
    p.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return p;
  };
  const auto save = [&](const ContactFields& f) {
    if (!opts.checkpoint_path.empty()) write_checkpoint(opts.checkpoint_path, cfg, f, progress_now());
  };
  const auto hook = [&](ContactSolver& s) {
    running = &s;
    if (opts.progress) s.set_progress(opts.progress);
    if (opts.stop_request) s.set_stop_request(opts.stop_request);
    if (!opts.checkpoint_path.empty()) s.set_checkpoint(save, opts.checkpoint_interval_s);
  };
  if (cfg.friction.coefficient > 0 && cfg.friction_reference) {
    // Frictionless reference at the same load; it also warm-starts the sliding solve.
    FrictionParams none = cfg.friction;
    none.coefficient = 0.0;
    ContactSolver ref(*body, r.topography, cfg.interaction, none, cfg.solver);
    hook(ref);
    ContactFields rf = r.fields;
    try {
      r.reference_info = ref.solve(cfg.load, rf);
    } catch (const Interrupted&) {
      save(rf);
      throw;
    }
    running = nullptr;
    finished_iterations = r.reference_info.iterations;
    if (!r.reference_info.converged) {
      r.info = r.reference_info;
      r.info.status += " (frictionless reference)";
      return r;
    }
    r.reference = compute_observables(ref.fft(), r.topography, none, rf, r.reference_info);
    r.has_reference = true;
    if (!cfg.stress.post_analysis.empty()) {
      r.reference_pressure = rf.pressure;
      r.reference_ux = std::move(rf.ux);
      r.reference_uy = std::move(rf.uy);
    }
    if (!opts.warm_start) r.fields.pressure = std::move(rf.pressure);
  }
  {
    ContactSolver solver(*body, r.topography, cfg.interaction, cfg.friction, cfg.solver);
    hook(solver);
    try {
      r.info = solver.solve(cfg.load, r.fields);
    } catch (const Interrupted&) {
      save(r.fields);
      throw;
    }
    running = nullptr;
    if (r.has_reference) {
      r.info.wall_time_s += r.reference_info.wall_time_s;
      r.info.transforms += r.reference_info.transforms;
      r.info.fft_seconds += r.reference_info.fft_seconds;
    }
    // A resumed run reports the totals of all its sessions.
    r.info.iterations += static_cast<int>(opts.resumed.iterations);
    r.info.wall_time_s += opts.resumed.wall_time_s;
    r.resumed = opts.resumed;
  }
  body.reset();
  const FFT fft(cfg.grid, cfg.solver.fft_planner);
  r.observables = compute_observables(fft, r.topography, cfg.friction, r.fields, r.info);
  if (r.info.converged) compute_stresses(r, fft, opts.keep_stress_fields);
  if (r.info.converged && cfg.flow.enabled) {
    r.leakage = compute_leakage(cfg.grid, r.fields.gap.data(), cfg.flow.angles, cfg.flow.tolerance,
                                cfg.flow.solver, opts.stop_request);
    r.has_leakage = true;
  }
  return r;
}

namespace {
// Version 2 adds the iterations and wall time done so far (a resumed run reports totals).
constexpr char kCheckpointMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', '2'};
}  // namespace

void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress) {
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
  const std::size_t n = cfg.grid.size();
  for (const RealField* fld : {&f.pressure, &f.tx, &f.ty}) {
    if (fld->size() == n)
      put(fld->data(), n * sizeof(double));
    else
      buf.append(n * sizeof(double), '\0');
  }
  write_text_atomic(path, buf);
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
  static const std::set<std::string> kNames = {"summary.json",
                                               "status.json",
                                               "fields.nc",
                                               "flow.json",
                                               "flow.nc",
                                               "profiles.csv",
                                               "profiles.png",
                                               "pressure.png",
                                               "gap.png",
                                               "slip_longitudinal.png",
                                               "slip_transverse.png",
                                               "dissipation.png",
                                               "max_principal_stress.png",
                                               "von_mises.png",
                                               "checkpoint.bin"};
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

void publish_outputs(const CaseResult& r, const std::string& dir, const std::function<void()>& extra) {
  try {
    write_outputs(r, dir);
    if (extra) extra();
    write_status(dir, "converged");
  } catch (const std::exception& e) {
    clear_run_outputs(dir);
    try {
      write_status(dir, "failed", std::string("writing the outputs: ") + e.what());
    } catch (const std::exception&) {
      // The status cannot be written either (disk full): the error itself still goes up.
    }
    throw;
  }
}

nlohmann::json summary_json(const CaseResult& r) {
  nlohmann::json j = to_json(r.observables);
  j["iterations"] = r.info.iterations;
  j["outer_iterations"] = r.info.outer_iterations;
  if (r.config.friction.coefficient > 0) {
    j["tangential_iterations"] = r.info.tangential_iterations;
    j["friction_law"] = r.config.friction.regularized() ? "regularized" : "coulomb";
  }
  j["converged"] = r.info.converged;
  j["status"] = r.info.status;
  j["residual"] = r.info.residual;
  j["residual_bound"] = r.info.residual_bound;
  if (r.resumed.iterations > 0 || r.resumed.wall_time_s > 0)
    j["resumed"] = {{"iterations_before", r.resumed.iterations},
                    {"wall_time_s_before", r.resumed.wall_time_s}};
  j["pressure_change"] = r.info.pk_error;
  if (r.config.friction.coefficient > 0) j["friction_change"] = r.info.friction_error;
  j["wall_time_s"] = r.info.wall_time_s;
  const Grid& g = r.config.grid;
  const auto stress_json = [&g](const StressSummary& s) {
    return nlohmann::json{{"max_tensile_stress", s.max_tensile_stress},
                          {"max_tensile_stress_location", {g.x(s.max_tensile_ix), g.y(s.max_tensile_iy)}},
                          {"max_von_mises", s.max_von_mises},
                          {"max_von_mises_location", {g.x(s.max_von_mises_ix), g.y(s.max_von_mises_iy)}},
                          {"high_tension_area_fraction", s.high_tension_area_fraction},
                          {"high_tension_fraction_of", s.high_tension_fraction_of}};
  };
  if (r.has_stress) j.update(stress_json(r.stress_summary));
  if (!r.post_analyses.empty()) {
    // The first kind as "post_analysis" (its keys as before, plus kind, the area above half
    // the maximum and the full/post ratios), every kind as "post_analysis_<kind>".
    const auto pa_json = [&](const CaseResult::PostAnalysis& pa) {
      nlohmann::json e = stress_json(pa.summary);
      e["kind"] = pa.kind;
      e["area_fraction_above_half_max"] = pa.area_above_half_max;
      const auto ratio = [](double a, double b) { return b > 0 ? nlohmann::json(a / b) : nlohmann::json(); };
      e["ratio_max_tensile_stress"] =
          ratio(r.stress_summary.max_tensile_stress, pa.summary.max_tensile_stress);
      e["ratio_max_von_mises"] = ratio(r.stress_summary.max_von_mises, pa.summary.max_von_mises);
      e["ratio_area_above_half_max"] = ratio(r.area_above_half_max, pa.area_above_half_max);
      return e;
    };
    j["post_analysis"] = pa_json(r.post_analyses.front());
    for (const auto& pa : r.post_analyses) j["post_analysis_" + pa.kind] = pa_json(pa);
    j["area_fraction_above_half_max"] = r.area_above_half_max;
  }
  if (r.has_leakage) j["flow"] = r.leakage.json;
  if (!r.post_analyses.empty() && r.post_analyses.front().summary.max_tensile_stress > 0)
    j["tensile_stress_ratio_to_post_analysis"] =
        r.stress_summary.max_tensile_stress / r.post_analyses.front().summary.max_tensile_stress;
  if (!r.subsurface.empty()) {
    j["subsurface"] = nlohmann::json::array();
    for (const auto& ss : r.subsurface) {
      nlohmann::json e = stress_json(ss.summary);
      e["depth"] = ss.depth;
      j["subsurface"].push_back(e);
    }
  }
  if (r.config.friction.coefficient > 0) {
    const double mu = r.config.friction.coefficient;
    j["delta_mu_over_mu_c"] = (r.observables.friction_coefficient - mu) / mu;
    j["delta_mu_over_mu_c_downhill"] = (r.observables.friction_coefficient_downhill - mu) / mu;
  }
  if (r.has_reference) {
    j["frictionless"] = to_json(r.reference);
    j["frictionless"]["iterations"] = r.reference_info.iterations;
    j["delta_area_over_area"] = r.observables.relative_contact_area / r.reference.relative_contact_area - 1.0;
  }
  j["time_per_iteration_s"] = r.info.iterations > 0 ? r.info.wall_time_s / r.info.iterations : 0.0;
  j["fft_count"] = r.info.transforms;
  j["fft_time_s"] = r.info.fft_seconds;  // time inside the transforms (part of wall_time_s)
  j["interaction_stiffness"] =
      std::isinf(r.info.stiffness) ? nlohmann::json("inf") : nlohmann::json(r.info.stiffness);
  j["threads"] = threads();
  const auto& s = r.topography_stats;
  j["topography"] = {{"kind", r.topography.kind},
                     {"mean", s.mean},
                     {"rms_height", s.rms_height},
                     {"rms_gradient", s.rms_gradient},
                     {"rms_curvature", s.rms_curvature},
                     {"min", s.min},
                     {"max", s.max}};
  j["input"] = r.config.to_json();
  j["units"] =
      "lengths in the unit of grid.lx; pressures, stresses and E* in the unit of elastic.contact_modulus; "
      "forces = pressure x length^2";
  j["conventions"] = {
      {"topography", "indenter height towards the body (peaks are maxima); initial gap g0 = max(h) - h"},
      {"z", "out of the body towards the indenter; uz < 0 is a depression"},
      {"approach",
       "indenter displacement towards the body from first touch; for h = inf relative to the mean "
       "surface (mean uz pinned to 0)"}};
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  return j;
}

namespace {
// Line profiles through the pressure maximum along and across the sliding direction
// (nearest grid point on the line), as in the paper's SM Fig. 2. Needs the surface stress
// tensor; the principal values are evaluated at the line points only.
std::string profiles_table(const CaseResult& r, const FFT& fft) {
  const Grid& g = r.config.grid;
  const std::size_t n = g.size();
  std::size_t imax = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (r.fields.pressure[i] > r.fields.pressure[imax]) imax = i;
  const int cx = static_cast<int>(imax % g.nx), cy = static_cast<int>(imax / g.nx);
  const double th = r.config.friction.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  DerivedFields d;
  if (r.config.friction.coefficient > 0) d = derived_fields(fft, r.config.friction, r.fields);
  std::vector<std::pair<std::string, const double*>> cols = {{"ux", r.fields.ux.data()},
                                                             {"uy", r.fields.uy.data()},
                                                             {"uz", r.fields.uz.data()},
                                                             {"pressure", r.fields.pressure.data()}};
  if (!d.dissipation.empty()) {
    cols.push_back({"dissipation", d.dissipation.data()});
    cols.push_back({"slip_longitudinal", d.slip_longitudinal.data()});
    cols.push_back({"slip_transverse", d.slip_transverse.data()});
  }
  const StressField& st = r.stress;
  for (const auto& c : std::vector<std::pair<std::string, const RealField*>>{{"sigma_xx", &st.xx},
                                                                             {"sigma_yy", &st.yy},
                                                                             {"sigma_zz", &st.zz},
                                                                             {"sigma_xy", &st.xy},
                                                                             {"sigma_xz", &st.xz},
                                                                             {"sigma_yz", &st.yz}})
    cols.push_back({c.first, c.second->data()});
  static const char* const kPrincipal[] = {"sigma_1", "von_mises", "e1_x", "e1_y", "e1_z"};
  const auto principal_at = [&](std::size_t i) {
    const Principal3 e = principal(st.xx[i], st.yy[i], st.zz[i], st.xy[i], st.xz[i], st.yz[i]);
    return std::array<double, 5>{e.s1, von_mises(st.xx[i], st.yy[i], st.zz[i], st.xy[i], st.xz[i], st.yz[i]),
                                 e.e1[0], e.e1[1], e.e1[2]};
  };
  std::ostringstream os;
  os.precision(10);
  os << "# profiles through the pressure maximum at (" << g.x(cx) << ", " << g.y(cy)
     << "); s = distance along the line; longitudinal = along the sliding direction, transverse = across\n";
  os << "s";
  for (const char* dir_name : {"longitudinal", "transverse"}) {
    for (const auto& c : cols) os << "," << c.first << "_" << dir_name;
    for (const char* c : kPrincipal) os << "," << c << "_" << dir_name;
  }
  os << "\n";
  const int half = std::min(g.nx, g.ny) / 2;
  const double ds = std::min(g.dx(), g.dy());
  const auto at = [&](double sx, double sy) {
    const int ix = ((cx + static_cast<int>(std::lround(sx / g.dx()))) % g.nx + g.nx) % g.nx;
    const int iy = ((cy + static_cast<int>(std::lround(sy / g.dy()))) % g.ny + g.ny) % g.ny;
    return static_cast<std::size_t>(iy) * g.nx + ix;
  };
  for (int k = -half; k < half; ++k) {
    const double sdist = k * ds;
    os << sdist;
    for (const std::size_t i : {at(sdist * ex, sdist * ey), at(-sdist * ey, sdist * ex)}) {
      for (const auto& c : cols) os << "," << c.second[i];
      for (double v : principal_at(i)) os << "," << v;
    }
    os << "\n";
  }
  return os.str();
}
}  // namespace

void write_outputs(const CaseResult& r, const std::string& dir) {
  fs::create_directories(dir);
  const Grid& g = r.config.grid;
  const std::size_t n = g.size();
  if (r.config.output.fields) {
    RealField cm(n);
    for (std::size_t i = 0; i < n; ++i) cm[i] = r.fields.pressure[i] > 0 ? 1.0 : 0.0;
    std::vector<NamedField> fields = {
        {"topography", r.topography.h.data(), "indenter height towards the body", "length"},
        {"pressure", r.fields.pressure.data(), "contact pressure on the body (compressive positive)", "E*"},
        {"gap", r.fields.gap.data(), "gap between indenter and deformed surface", "length"},
        {"ux", r.fields.ux.data(), "surface displacement along x", "length"},
        {"uy", r.fields.uy.data(), "surface displacement along y", "length"},
        {"uz", r.fields.uz.data(), "surface displacement along z (out of the body)", "length"},
        {"contact", cm.data(), "contact mask (1 = in contact)", "1"}};
    DerivedFields d;
    if (r.config.friction.coefficient > 0) {
      FFT fft(g);
      d = derived_fields(fft, r.config.friction, r.fields);
      fields.push_back({"traction_x", r.fields.tx.data(), "friction traction on the body along x", "E*"});
      fields.push_back({"traction_y", r.fields.ty.data(), "friction traction on the body along y", "E*"});
      fields.push_back({"slip_longitudinal", d.slip_longitudinal.data(),
                        "relative longitudinal slip velocity v_l^rel/v0 - 1 = (e_s.grad) u_s", "1"});
      fields.push_back({"slip_transverse", d.slip_transverse.data(),
                        "transverse slip velocity / v0 = (e_s.grad) u_perp", "1"});
      fields.push_back({"dissipation", d.dissipation.data(),
                        "dissipated power density / v0 = tau . v_slip / v0 (mu_c p |v|/v0 where slipping)",
                        "E*"});
    }
    RealField sm;
    if (r.fields.stick.size() == n) {
      sm.resize(n);
      for (std::size_t i = 0; i < n; ++i) sm[i] = r.fields.stick[i] ? 1.0 : 0.0;
      fields.push_back(
          {"stick", sm.data(), "stick mask (1 = contact point that sticks: zero slip velocity)", "1"});
    }
    if (!r.principal.s1.empty()) {
      const StressField& st = r.stress;
      const PrincipalField& pr = r.principal;
      for (const NamedField& nf : std::vector<NamedField>{
               {"sigma_xx", st.xx.data(), "surface stress xx (tensile positive)", "E*"},
               {"sigma_yy", st.yy.data(), "surface stress yy", "E*"},
               {"sigma_zz", st.zz.data(), "surface stress zz (= -p)", "E*"},
               {"sigma_xy", st.xy.data(), "surface stress xy", "E*"},
               {"sigma_xz", st.xz.data(), "surface stress xz (= friction traction x)", "E*"},
               {"sigma_yz", st.yz.data(), "surface stress yz", "E*"},
               {"sigma_1", pr.s1.data(), "maximum principal (most tensile) surface stress sigma_I", "E*"},
               {"sigma_2", pr.s2.data(), "middle principal surface stress", "E*"},
               {"sigma_3", pr.s3.data(), "minimum principal surface stress", "E*"},
               {"e1_x", pr.e1x.data(), "eigenvector of sigma_I, x", "1"},
               {"e1_y", pr.e1y.data(), "eigenvector of sigma_I, y", "1"},
               {"e1_z", pr.e1z.data(), "eigenvector of sigma_I, z", "1"},
               {"von_mises", pr.von_mises.data(), "von Mises surface stress", "E*"}})
        fields.push_back(nf);
      if (!r.post_analyses.empty()) {
        fields.push_back({"post_analysis_sigma_1", r.post_analyses.front().s1.data(),
                          "sigma_I of the post-analysis reference (" + r.post_analyses.front().kind +
                              "; the first of [stress] post_analysis)",
                          "E*"});
        for (const auto& pa : r.post_analyses)
          fields.push_back(
              {"post_analysis_" + pa.kind + "_sigma_1", pa.s1.data(),
               pa.kind == "paper"
                   ? "sigma_I of the paper's post-analysis (frictionless fields, sigma_az = mu p)"
                   : "sigma_I of the consistent post-analysis (frictionless p + mu p with its strain)",
               "E*"});
      }
      for (std::size_t k = 0; k < r.subsurface.size(); ++k) {
        const std::string depth = std::to_string(r.subsurface[k].depth);
        fields.push_back({"von_mises_depth_" + std::to_string(k), r.subsurface[k].von_mises.data(),
                          "von Mises stress at depth " + depth, "E*"});
        fields.push_back({"sigma_1_depth_" + std::to_string(k), r.subsurface[k].s1.data(),
                          "maximum principal stress at depth " + depth, "E*"});
      }
    }
    if (r.has_leakage) append_current_fields(r.leakage, fields);
    write_fields_netcdf(
        (fs::path(dir) / "fields.nc").string(), g, fields,
        {{"gfmd_version", kVersion},
         {"git_commit", kGitCommit},
         {"input_toml", r.config.to_toml()},
         {"normalisation", "lengths in units of grid.lx, pressures in units of E* (contact_modulus)"}},
        "length");
  }
  if (r.config.output.png) {
    std::vector<unsigned char> mask(n);
    for (std::size_t i = 0; i < n; ++i) mask[i] = r.fields.pressure[i] > 0;
    PngOptions po;
    po.colormap = "inferno";
    po.title = "pressure";
    write_png_map((fs::path(dir) / "pressure.png").string(), g, r.fields.pressure.data(), po);
    PngOptions pg;
    pg.colormap = "viridis";
    pg.title = "gap";
    pg.mask = mask.data();
    write_png_map((fs::path(dir) / "gap.png").string(), g, r.fields.gap.data(), pg);
    if (r.config.friction.coefficient > 0) {
      FFT fft(g);
      const DerivedFields d = derived_fields(fft, r.config.friction, r.fields);
      std::vector<double> vl(n), vt(n);
      for (std::size_t i = 0; i < n; ++i) {
        // Slip fields are shown inside the contact only.
        vl[i] = mask[i] ? d.slip_longitudinal[i] : 0.0;
        vt[i] = mask[i] ? d.slip_transverse[i] : 0.0;
      }
      PngOptions ps;
      ps.colormap = "coolwarm";
      ps.symmetric = true;
      // Outline: the stick zone where there is one, else the contact.
      const bool any_stick =
          std::any_of(r.fields.stick.begin(), r.fields.stick.end(), [](auto v) { return v != 0; });
      ps.mask = any_stick ? r.fields.stick.data() : mask.data();
      ps.title = any_stick ? "longitudinal slip excess (outline: stick)" : "longitudinal slip excess";
      write_png_map((fs::path(dir) / "slip_longitudinal.png").string(), g, vl.data(), ps);
      ps.title = any_stick ? "transverse slip (outline: stick)" : "transverse slip";
      write_png_map((fs::path(dir) / "slip_transverse.png").string(), g, vt.data(), ps);
      PngOptions pd;
      pd.colormap = "inferno";
      pd.title = "dissipation";
      write_png_map((fs::path(dir) / "dissipation.png").string(), g, d.dissipation.data(), pd);
    }
  }
  if (r.config.output.png && !r.principal.s1.empty()) {
    PngOptions ps;
    ps.colormap = "coolwarm";
    ps.symmetric = true;
    ps.title = "max principal stress";
    write_png_map((fs::path(dir) / "max_principal_stress.png").string(), g, r.principal.s1.data(), ps);
    PngOptions pv;
    pv.colormap = "inferno";
    pv.title = "von mises";
    write_png_map((fs::path(dir) / "von_mises.png").string(), g, r.principal.von_mises.data(), pv);
  }
  if (r.config.stress.profiles && !r.profiles_csv.empty())
    write_text_atomic((fs::path(dir) / "profiles.csv").string(), r.profiles_csv);
  if (r.has_leakage)
    write_leakage(g, r.leakage, dir, {{"relative_contact_area", r.observables.relative_contact_area}});
  // summary.json last: its presence marks a complete run directory.
  write_text_atomic((fs::path(dir) / "summary.json").string(), summary_json(r).dump(2) + "\n");
}

}  // namespace gfmd

namespace gfmd {

std::vector<std::pair<std::string, nlohmann::json>> summary_row(const nlohmann::json& summary) {
  std::vector<std::pair<std::string, nlohmann::json>> row;
  for (const auto& [k, v] : summary.items()) {
    if (k == "input" || k == "units" || k == "conventions") continue;
    if (v.is_object()) {
      for (const auto& [k2, v2] : v.items())
        if (v2.is_primitive()) row.emplace_back(k + "." + k2, v2);
    } else if (v.is_primitive()) {
      row.emplace_back(k, v);
    }
  }
  return row;
}

namespace {

std::string csv_cell(const nlohmann::json& v) {
  if (v.is_string()) {
    std::string s = v.get<std::string>();
    if (s.find_first_of(",\"\n") != std::string::npos) {
      std::string q = "\"";
      for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
    return s;
  }
  if (v.is_null()) return "";
  return v.dump();
}

void write_sweep_tables(const std::string& dir, const std::string& param, const std::vector<double>& values,
                        const std::vector<nlohmann::json>& summaries) {
  std::vector<std::string> cols;
  std::vector<std::vector<std::pair<std::string, nlohmann::json>>> rows;
  for (const auto& s : summaries) {
    rows.push_back(summary_row(s));
    for (const auto& [k, v] : rows.back())
      if (std::find(cols.begin(), cols.end(), k) == cols.end()) cols.push_back(k);
  }
  std::ostringstream csv;
  csv.precision(17);
  csv << param;
  for (const auto& c : cols) csv << "," << c;
  csv << "\n";
  nlohmann::json j;
  j["parameter"] = param;
  j["values"] = values;
  j["points"] = nlohmann::json::array();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    csv << values[i];
    nlohmann::json pj;
    pj[param] = values[i];
    for (const auto& c : cols) {
      csv << ",";
      for (const auto& [k, v] : rows[i])
        if (k == c) {
          csv << csv_cell(v);
          pj[c] = v;
        }
    }
    csv << "\n";
    j["points"].push_back(pj);
  }
  j["completed"] = rows.size();
  j["total"] = values.size();
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  if (!summaries.empty() && summaries.front().contains("input"))
    j["input_first_point"] = summaries.front()["input"];
  write_text_atomic((fs::path(dir) / "sweep.csv").string(), csv.str());
  write_text_atomic((fs::path(dir) / "sweep.json").string(), j.dump(2) + "\n");
}

std::string format_value(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

nlohmann::json run_sweep(const std::string& case_path, const Config& base, const std::string& dir,
                         const SweepOptions& opts) {
  const SweepConfig& sw = base.sweep;
  if (!sw.active())
    throw InputError(case_path, "no sweep: give [sweep] parameter and values, or --set key=v1,v2,...");
  fs::create_directories(dir);
  {
    // What an earlier, longer or differently plotted sweep left: points beyond this sweep's
    // last and its plots (the tables are rewritten below).
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      int k = -1;
      if (name.size() == 9 && name.rfind("point_", 0) == 0 && std::sscanf(name.c_str() + 6, "%3d", &k) == 1 &&
          k >= static_cast<int>(sw.values.size()))
        fs::remove_all(e.path(), ec);
      else if (name.rfind("sweep_", 0) == 0 && e.path().extension() == ".png")
        fs::remove(e.path(), ec);
    }
  }
  std::vector<nlohmann::json> summaries;
  ContactFields warm;
  bool have_warm = false;
  const int total = static_cast<int>(sw.values.size());
  for (int i = 0; i < total; ++i) {
    std::vector<std::string> sets = opts.overrides;
    sets.push_back(sw.parameter + "=" + format_value(sw.values[i]));
    Config cfg = load_config(case_path, sets);
    char name[32];
    std::snprintf(name, sizeof name, "point_%03d", i);
    const std::string pdir = (fs::path(dir) / name).string();
    if (auto old = finished_summary(pdir, cfg)) {
      summaries.push_back(std::move(*old));
      have_warm = false;
      if (opts.on_point) opts.on_point(i + 1, total, std::string(name) + " reused (finished earlier)");
      continue;
    }
    RunOptions ro;
    ro.progress = opts.progress;
    ro.stop_request = opts.stop_request;
    ro.checkpoint_interval_s = opts.checkpoint_interval_s;
    ro.keep_stress_fields = outputs_need_stress_fields(cfg);
    fs::create_directories(pdir);
    ro.checkpoint_path = (fs::path(pdir) / "checkpoint.bin").string();
    ContactFields resumed;
    if (read_checkpoint(ro.checkpoint_path, cfg, resumed)) {
      ro.warm_start = &resumed;
    } else if (have_warm) {
      ro.warm_start = &warm;
    }
    CaseResult r = run_case(cfg, ro);
    bool retried = false;
    if (!r.info.converged && ro.warm_start == &warm) {
      // Started from the previous point's solution, the friction fixed point can fall into
      // a limit cycle that a start from the frictionless solution avoids: try that once.
      if (opts.on_point)
        opts.on_point(i, total, std::string(name) + ": " + r.info.status + "; retrying from a cold start");
      ro.warm_start = nullptr;
      r = run_case(cfg, ro);
      retried = true;
    }
    std::error_code ec;
    fs::remove(ro.checkpoint_path, ec);
    if (!r.info.converged) {
      fs::remove(pdir, ec);  // only if empty: no bare point directory is left behind
      write_sweep_tables(dir, sw.parameter, sw.values, summaries);
      throw SolveError(std::string(name) + " (" + sw.parameter + " = " + format_number(sw.values[i]) +
                       "): " + r.info.status + "; the " + std::to_string(i) + " finished points are kept");
    }
    clear_run_outputs(pdir);  // a point recomputed owns its directory, as a run does
    write_outputs(r, pdir);
    summaries.push_back(summary_json(r));
    write_sweep_tables(dir, sw.parameter, sw.values, summaries);
    warm = std::move(r.fields);
    have_warm = cfg.grid.size() == base.grid.size();
    if (opts.on_point) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "%s: %s = %.6g, %d iterations, %.2f s%s", name, sw.parameter.c_str(),
                    sw.values[i], r.info.iterations, r.info.wall_time_s, retried ? " (cold start)" : "");
      opts.on_point(i + 1, total, msg);
    }
  }
  write_sweep_tables(dir, sw.parameter, sw.values, summaries);
  nlohmann::json j;
  j["points"] = summaries.size();
  return j;
}

}  // namespace gfmd
