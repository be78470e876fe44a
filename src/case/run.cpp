// One case from configuration to result: the pipeline of run_case. See include/gfmd/case/run.hpp.
#include "gfmd/case/run.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <type_traits>

#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
namespace gfmd {

namespace fs = std::filesystem;

namespace {
// Line profiles through the pressure maximum along and across the sliding direction
// (nearest grid point on the line), as in the paper's SM Fig. 2. Needs the surface stress
// tensor; the principal values are evaluated at the line points only.
std::string profiles_table(const CaseResult& r) {
  const Grid& g = r.config.grid;
  const std::size_t n = g.size();
  std::size_t imax = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (r.fields.pressure[i] > r.fields.pressure[imax]) imax = i;
  const int cx = static_cast<int>(imax % g.nx), cy = static_cast<int>(imax / g.nx);
  const double th = r.config.friction.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const DerivedFields& d = r.derived;
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

// Stresses, their summaries and the profiles table. With keep_fields false only the
// summaries and the table stay (the full fields are what fields.nc and the PNG maps show).
void compute_stresses(CaseResult& r, const FFT& fft, bool keep_fields) {
  const Config& cfg = r.config;
  r.stress = surface_stress(fft, cfg.elastic, r.fields);
  r.principal = principal(r.stress, keep_fields ? PrincipalParts::All : PrincipalParts::SummaryOnly);
  r.stress_summary = summarize(cfg.grid, r.principal, cfg.stress.high_tension_fraction);
  // Fraction of the cells with s1 >= half its maximum (the full solution's here, while its
  // field is still there; each post-analysis's below).
  const auto above_half = [&cfg](const RealField& s1, double max) {
    if (!(max > 0)) return 0.0;
    std::size_t k = 0;
    for (double v : s1) k += v >= 0.5 * max ? 1 : 0;
    return static_cast<double>(k) / static_cast<double>(cfg.grid.size());
  };
  if (!cfg.stress.post_analysis.empty())
    r.area_above_half_max = above_half(r.principal.s1, r.stress_summary->max_tensile_stress);
  if (cfg.stress.profiles) r.profiles_csv = profiles_table(r);
  if (!keep_fields) {
    r.stress = StressField{};
    r.principal = PrincipalField{};
  }
  if (!cfg.stress.post_analysis.empty()) {
    // The frictionless solution: the reference solve (kept for this alone), or the solution
    // itself without friction, or (no reference kept) a frictionless solve now.
    ContactFields rf;
    if (r.reference && !r.reference->pressure.empty()) {
      rf.pressure = std::move(r.reference->pressure);
      rf.ux = std::move(r.reference->ux);
      rf.uy = std::move(r.reference->uy);
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
    PrincipalField pf;
    try {
      pf = principal(subsurface_stress(fft, cfg.elastic, r.fields, d), PrincipalParts::SummaryOnly);
    } catch (const ParameterError& e) {
      throw InputError("stress.depths", e.why() + " (depth " + format_number(d) + ")");
    }
    r.subsurface.push_back(
        {d, summarize(cfg.grid, pf, cfg.stress.high_tension_fraction), pf.von_mises, pf.s1});
  }
}
}  // namespace

bool outputs_need_stress_fields(const Config& cfg) { return cfg.output.fields || cfg.output.png; }

namespace {
// This process's rows of the warm start that rank 0 holds (a checkpoint it read, a sweep's
// previous point): pressure and tractions, scattered by rows.
ContactFields warm_start_rows(const Grid& slab, const ContactFields& whole) {
  ContactFields f;
  f.pressure = mpi::scatter(slab, whole.pressure);
  f.tx = mpi::scatter(slab, whole.tx);
  f.ty = mpi::scatter(slab, whole.ty);
  return f;
}
// The whole solution on rank 0 from the slabs (empty fields elsewhere).
ContactFields gather_fields(const Grid& slab, const ContactFields& f) {
  ContactFields w;
  for (auto [to, from] : {std::pair{&w.pressure, &f.pressure},
                          {&w.tx, &f.tx},
                          {&w.ty, &f.ty},
                          {&w.ux, &f.ux},
                          {&w.uy, &f.uy},
                          {&w.uz, &f.uz},
                          {&w.gap, &f.gap}})
    if (!from->empty()) *to = mpi::gather(slab, *from);
  if (!f.stick.empty()) w.stick = mpi::gather(slab, f.stick);
  return w;
}
// Everything after the solve, on the whole solution: observables, derived fields, stresses,
// the checks of a padded map, the run's analysis and the leakage.
void after_solve(const Config& cfg, const RunOptions& opts, CaseResult& r) {
  const FFT fft(cfg.grid, cfg.solver.fft_planner);
  r.observables = compute_observables(fft, r.topography, cfg.friction, r.fields, r.info);
  if (cfg.friction.coefficient > 0) r.derived = derived_fields(fft, cfg.friction, r.fields);
  if (r.info.converged) compute_stresses(r, fft, opts.keep_stress_fields);
  if (r.info.converged && r.map_report && r.map_report->periodize == "pad") {
    // The padding (every cell outside the map's corner quarter) must carry no load.
    const Grid& g = cfg.grid;
    double outside = 0.0, total = 0.0;
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        const double p = r.fields.pressure[static_cast<std::size_t>(iy) * g.nx + ix];
        total += p;
        if (ix >= g.nx / 2 || iy >= g.ny / 2) outside += p;
      }
    if (outside > 0.0)
      throw InputError(
          "indenter.periodize",
          "\"pad\": the padding around the map came into contact (" + format_number(100.0 * outside / total) +
              " % of the load): the body's deformation at this load exceeds the pad's depth; use "
              "periodize = \"mirror\"");
  }
  if (r.info.converged && cfg.output.analysis) {
    r.analysis = analyse_run(r.topography, r.fields);
    // A padded cell's spectrum is the pad's step, not the surface's: no Hurst fit.
    if (r.map_report && r.map_report->periodize == "pad") r.analysis->rough = false;
  }
  if (r.info.converged && cfg.flow.enabled) {
    r.leakage = compute_leakage(cfg.grid, r.fields.gap.data(), cfg.flow.angles, cfg.flow.tolerance,
                                cfg.flow.solver, opts.stop_request);
  }
  if (r.mpi_usage) r.mpi_usage->peak_bytes = mpi::peak_resident_bytes();
}

// The results a study decides on, from rank 0 to every process (a collective): the
// observables and the leakage's figures, so that every process takes the same next step.
void share_from_root(CaseResult& r) {
  static_assert(std::is_trivially_copyable_v<Observables>);
  std::string bytes(reinterpret_cast<const char*>(&r.observables), sizeof(Observables));
  bytes = mpi::from_root(bytes);
  std::memcpy(static_cast<void*>(&r.observables), bytes.data(), sizeof(Observables));
  const std::string leak = mpi::from_root(r.leakage ? r.leakage->json.dump() : std::string());
  if (!mpi::root() && !leak.empty()) r.leakage.emplace().json = nlohmann::json::parse(leak);
}
}  // namespace

void rethrow_from_root(const std::exception_ptr& failure) {
  if (!mpi::distributed()) return;
  enum Kind : int { kNone, kInput, kSolve, kInterrupted, kOther };
  int kind = kNone;
  if (failure) try {
      std::rethrow_exception(failure);
    } catch (const InputError&) {
      kind = kInput;
    } catch (const Interrupted&) {
      kind = kInterrupted;
    } catch (const SolveError&) {
      kind = kSolve;
    } catch (...) {
      kind = kOther;
    }
  kind = mpi::from_root(kind);
  if (kind == kNone) return;
  if (failure) std::rethrow_exception(failure);
  throw StoppedWithRoot(kind == kInput ? 2 : kind == kSolve ? 3 : kind == kInterrupted ? 4 : 1);
}

CaseResult run_case(const Config& cfg, const RunOptions& opts) {
  set_threads(cfg.threads);
  const Backend* chosen = find_backend(cfg.backend);
  if (chosen == nullptr) throw std::invalid_argument("run_case: unknown backend " + cfg.backend);
  const BackendScope on_backend(*chosen);
  CaseResult r;
  r.config = cfg;
  // A distributed run (mpirun): the solves run on slabs of rows, one per process; rank 0
  // gathers the solution and does everything after the solve (observables, stresses,
  // analysis, flow) on the whole grid.
  const bool distributed = mpi::distributed();
  r.mpi_ranks = mpi::size();
  const Grid slab = distributed ? mpi::slab_of(cfg.grid) : cfg.grid;
  if (cfg.indenter.type == "array" && opts.topography) {
    const Grid& tg = opts.topography->grid;
    if (tg.nx != cfg.grid.nx || tg.ny != cfg.grid.ny || tg.lx != cfg.grid.lx || tg.ly != cfg.grid.ly)
      throw InputError("indenter", "the given heights are " + std::to_string(tg.nx) + " x " +
                                       std::to_string(tg.ny) + " on " + format_number(tg.lx) + " x " +
                                       format_number(tg.ly) + ", the grid " + std::to_string(cfg.grid.nx) +
                                       " x " + std::to_string(cfg.grid.ny) + " on " +
                                       format_number(cfg.grid.lx) + " x " + format_number(cfg.grid.ly));
    r.topography = std::move(*opts.topography);
  } else if (cfg.indenter.type == "file") {
    MapReport rep;
    r.topography = make_topography(cfg, &rep);
    const Grid& tg = r.topography.grid;
    if (tg.nx != cfg.grid.nx || tg.ny != cfg.grid.ny || tg.lx != cfg.grid.lx || tg.ly != cfg.grid.ly)
      throw std::logic_error("run_case: the prepared height map does not match the case's grid");
    r.map_report = std::move(rep);
  } else {
    r.topography = make_topography(cfg);
  }
  r.topography_stats = statistics(r.topography);
  // The heights the solves see: this process's rows in a distributed run (rank 0 keeps the
  // whole map for the analysis; the other ranks give it back).
  Topography slab_topo;
  if (distributed) {
    slab_topo = Topography{slab, mpi::rows_of(slab, r.topography.h), r.topography.kind};
    if (!mpi::root()) RealField().swap(r.topography.h);
  }
  const Topography& topo = distributed ? slab_topo : r.topography;
  // The body and the solvers live only as long as the solves: the stage after them
  // (stresses, flow) gets the memory back.
  auto body = std::make_unique<ElasticBody>(slab, cfg.elastic);
  // A distributed run starts warm when rank 0 has a warm start: the others get its rows.
  bool warm = opts.warm_start && opts.warm_start->pressure.size() == cfg.grid.size();
  if (distributed) {
    warm = mpi::from_root(warm ? 1 : 0) == 1;
    if (warm) r.fields = warm_start_rows(slab, mpi::root() ? *opts.warm_start : ContactFields{});
  } else if (warm) {
    r.fields = *opts.warm_start;
  }
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
  // Checkpoints hold the whole pressure and tractions, so that a run resumes on any number
  // of processes: a distributed run gathers them on rank 0, which writes the file (24 bytes
  // per point of the cell there, and the file's image as much again, while it writes). Every
  // process takes part when rank 0 has a checkpoint path.
  const bool checkpoints =
      distributed ? mpi::from_root(opts.checkpoint_path.empty() ? 0 : 1) == 1 : !opts.checkpoint_path.empty();
  const auto save = [&](const ContactFields& f) {
    if (!checkpoints) return;
    if (!distributed) {
      write_checkpoint(opts.checkpoint_path, cfg, f, progress_now());
      return;
    }
    ContactFields whole;
    whole.pressure = mpi::gather(slab, f.pressure);
    whole.tx = mpi::gather(slab, f.tx);
    whole.ty = mpi::gather(slab, f.ty);
    // A checkpoint rank 0 could not write stops every process (none may wait for it).
    on_root([&] { write_checkpoint(opts.checkpoint_path, cfg, whole, progress_now()); });
  };
  const auto hook = [&](ContactSolver& s) {
    running = &s;
    if (opts.progress) s.set_progress(opts.progress);
    if (opts.stop_request) s.set_stop_request(opts.stop_request);
    if (checkpoints) s.set_checkpoint(save, opts.checkpoint_interval_s);
  };
  if (cfg.friction.coefficient > 0 && cfg.friction_reference) {
    // Frictionless reference at the same load; it also warm-starts the sliding solve.
    FrictionParams none = cfg.friction;
    none.coefficient = 0.0;
    ContactSolver ref(*body, topo, cfg.interaction, none, cfg.solver);
    hook(ref);
    ContactFields rf = r.fields;
    SolveInfo ref_info;
    try {
      ref_info = ref.solve(cfg.load, rf);
    } catch (const Interrupted&) {
      save(rf);
      throw;
    }
    running = nullptr;
    finished_iterations = ref_info.iterations;
    if (!ref_info.converged) {
      r.info = ref_info;
      r.info.status += " (frictionless reference)";
      return r;
    }
    CaseResult::Reference& rr = r.reference.emplace();
    rr.info = ref_info;
    if (distributed) {
      // Observables and stresses of the reference come from the whole fields on rank 0.
      ContactFields whole = gather_fields(slab, rf);
      if (mpi::root()) {
        const FFT whole_fft(cfg.grid, cfg.solver.fft_planner);
        rr.observables = compute_observables(whole_fft, r.topography, none, whole, ref_info);
        if (!cfg.stress.post_analysis.empty()) {
          rr.pressure = std::move(whole.pressure);
          rr.ux = std::move(whole.ux);
          rr.uy = std::move(whole.uy);
        }
      }
    } else {
      rr.observables = compute_observables(ref.fft(), r.topography, none, rf, ref_info);
      if (!cfg.stress.post_analysis.empty()) {
        rr.pressure = rf.pressure;
        rr.ux = std::move(rf.ux);
        rr.uy = std::move(rf.uy);
      }
    }
    if (!warm) r.fields.pressure = std::move(rf.pressure);
  }
  {
    ContactSolver solver(*body, topo, cfg.interaction, cfg.friction, cfg.solver);
    hook(solver);
    try {
      r.info = solver.solve(cfg.load, r.fields);
    } catch (const Interrupted&) {
      save(r.fields);
      throw;
    }
    running = nullptr;
    if (r.reference) {
      r.info.wall_time_s += r.reference->info.wall_time_s;
      r.info.transforms += r.reference->info.transforms;
      r.info.fft_seconds += r.reference->info.fft_seconds;
    }
    // A resumed run reports the totals of all its sessions.
    r.info.iterations += static_cast<int>(opts.resumed.iterations);
    r.info.wall_time_s += opts.resumed.wall_time_s;
    r.resumed = opts.resumed;
  }
  body.reset();
  if (mpi::launched())
    r.mpi_usage = CaseResult::MpiUsage{mpi::all_values(mpi::peak_resident_bytes()),
                                       mpi::all_values(mpi::reduction_seconds())};
  if (!distributed) {
    after_solve(cfg, opts, r);
    return r;
  }
  r.fields = gather_fields(slab, r.fields);
  slab_topo = Topography{};
  // Rank 0 holds the whole solution and does the rest; the others wait for the results the
  // studies decide on, or for its error.
  std::exception_ptr failure;
  if (mpi::root()) try {
      after_solve(cfg, opts, r);
    } catch (...) {
      failure = std::current_exception();
    }
  rethrow_from_root(failure);
  share_from_root(r);
  return r;
}

}  // namespace gfmd
