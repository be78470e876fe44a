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
#include <optional>
#include <sstream>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
#include "run_detail.hpp"
namespace gfmd {

namespace fs = std::filesystem;
using run_detail::after_solve_here;
using run_detail::after_solve_whole;
using run_detail::collect_result;
using run_detail::resume_here;
using run_detail::surface_to_lead;
using run_detail::warm_fields_here;

bool outputs_need_stress_fields(const Config& cfg) { return cfg.output.fields || cfg.output.png; }

namespace {

// The interruption as the run reports it: the iterations of every solve of the run so far
// (earlier sessions and a finished frictionless reference included), as its checkpoint and
// summary.json's resumed.iterations_before count them.
Interrupted interrupted_after(const CheckpointProgress& p) {
  return Interrupted("interrupted after " + std::to_string(p.iterations) + " iterations");
}
// Approach control has no load to check before the solve (load_config checks force and
// pressure): a solution whose mean pressure exceeds kMaxPressureOverModulus E* is no contact
// problem and fails as a solve that did not converge (exit 3, nothing written), naming
// load.approach. A collective on a slab (the sum over every process's rows).
void refuse_excess_pressure(const Config& cfg, const Grid& grid, const RealField& pressure, SolveInfo& info) {
  if (cfg.load.mode != LoadMode::Approach || !info.converged) return;
  const double mean =
      grid_sum(grid, [&](std::size_t i) { return pressure[i]; }) / static_cast<double>(grid.size());
  const double ratio = mean / cfg.elastic.contact_modulus;
  if (!(ratio > kMaxPressureOverModulus)) return;
  char buf[256];
  std::snprintf(
      buf, sizeof buf,
      "load.approach = %s reached a mean pressure of %.3g E*, above the limit of %g E* of every load "
      "(not a contact problem; lower load.approach)",
      format_number(cfg.load.value).c_str(), ratio, kMaxPressureOverModulus);
  info.converged = false;
  info.status = buf;
}

}  // namespace

MadeSurface MadeSurface::of(const Config& cfg) {
  MadeSurface m;
  m.heights = std::make_shared<const Topography>(make_topography_here(cfg, &m.report));
  return m;
}

void MadeSurface::lend(RunOptions& ro) const {
  ro.made_surface = std::make_shared<Topography>(*heights);  // run_case takes it over
  ro.made_report = report;
}

const Backend& solve_backend(const Config& cfg) {
  const Placement place = Placement::of(cfg.grid);
  const Backend* chosen = find_backend(cfg.backend);
  if (chosen == nullptr) throw std::invalid_argument("run_case: unknown backend " + cfg.backend);
  if (place.split() && cfg.backend == "auto") chosen = &threads_backend();
  // "auto" also means the cores for the physics the device does not have (the solver refuses
  // "cuda" for it by name).
  if (cfg.backend == "auto" &&
      !device_lacks(cfg.interaction, cfg.friction, cfg.visco.enabled(), cfg.indenter.body.has_value())
           .first.empty())
    chosen = &threads_backend();
  if (chosen->name() == "cuda") {
    if (place.split())
      throw InputError("solver.backend", "\"cuda\" solves on one process; under mpirun use \"threads\"");
    // No device, or a grid too large for it: said before the surface is made.
    require_device_fits(cfg.grid, cfg.friction.coefficient > 0, cfg.interaction.adhesive(),
                        cfg.solver.anderson);
  }
  return *chosen;
}

CaseResult run_case(const Config& cfg, const RunOptions& options) {
  // Where the fields live: whole here, or (mpirun) slabs of rows, one per process, the lead
  // (rank 0) gathering what needs the whole cell (the analysis, field outputs).
  const Placement place = Placement::of(cfg.grid);
  // The lead's options hold for all: the post-processing's collectives depend on which fields
  // are kept.
  RunOptions opts = options;
  const int flags = place.agreed((opts.keep_stress_fields ? 1 : 0) | (opts.whole_solution ? 2 : 0));
  opts.keep_stress_fields = (flags & 1) != 0;
  opts.whole_solution = (flags & 2) != 0;
  set_threads(cfg.threads);
  const Backend* chosen = &solve_backend(cfg);
  // (solve_backend:) The CUDA solve runs on one process: "auto" means the cores under mpirun,
  // and "cuda" is refused there, or where no device is usable, before any work.
  const BackendScope on_backend(*chosen);
  CaseResult r;
  r.config = cfg;
  r.config.backend = std::string(chosen->name());  // "auto" resolved
  r.mpi_ranks = place.processes();
  // The heights the solves see (`here`): this process's rows when split (made on the slab; the
  // lead gathers the whole map after the solve for the analysis). Heights given whole stay
  // whole in r.topography on every process.
  Topography here;
  if (cfg.indenter.type == "array" && opts.topography) {
    const Grid& tg = opts.topography->grid;
    if (tg.nx != cfg.grid.nx || tg.ny != cfg.grid.ny || tg.lx != cfg.grid.lx || tg.ly != cfg.grid.ly)
      throw InputError("indenter", "the given heights are " + std::to_string(tg.nx) + " x " +
                                       std::to_string(tg.ny) + " on " + format_number(tg.lx) + " x " +
                                       format_number(tg.ly) + ", the grid " + std::to_string(cfg.grid.nx) +
                                       " x " + std::to_string(cfg.grid.ny) + " on " +
                                       format_number(cfg.grid.lx) + " x " + format_number(cfg.grid.ly));
    here = run_detail::given_heights_here(place, std::move(*opts.topography), r);
  } else {
    MapReport rep;
    if (opts.made_surface) {  // made once by the caller (the CLI's validation)
      here = std::move(*opts.made_surface);
      rep = opts.made_report;
    } else {
      here = make_topography_here(cfg, &rep);
    }
    if (cfg.indenter.type == "file" && place.lead()) r.map_report = std::move(rep);
  }
  r.topography_stats = statistics(here);
  // The body and the solvers live only as long as the solves: the stage after them
  // (stresses, flow) gets the memory back.
  auto body = std::make_unique<ElasticBody>(place.here(), cfg.elastic, cfg.visco,
                                            cfg.indenter.body ? &*cfg.indenter.body : nullptr);
  body->roll_both(cfg.friction.rolling());  // two bodies: both pass through the contact
  // The run starts warm when the lead has a warm start: each process takes its rows.
  const bool warm =
      place.agreed(opts.warm_start != nullptr && opts.warm_start->pressure.size() == cfg.grid.size());
  if (warm) r.fields = warm_fields_here(place, opts.warm_start);
  // Where a checkpoint's solves stood (read by the lead; its state goes with its fields): the
  // frictionless reference's result and the friction solve's restart point, this process's
  // part of them.
  SolveResume resume_rows;
  const SolveResume* resume =
      resume_here(place, warm && opts.resumed.state ? opts.resumed.state.get() : nullptr, resume_rows);
  const FrictionRestart* restart = resume && resume->friction ? &*resume->friction : nullptr;
  // With adhesion the adhesive traction goes with the warm start's net pressure.
  if (resume && resume->adhesive && resume->adhesion.size() == place.here().local_size())
    r.fields.adhesion = resume->adhesion;
  // Work counted into checkpoints: earlier sessions, the finished reference solve and the
  // solver running now (less what its restart point had done: counted before).
  const auto t_start = std::chrono::steady_clock::now();
  const ContactSolver* running = nullptr;
  std::int64_t finished_iterations = 0, running_from = 0;
  const auto progress_now = [&] {
    CheckpointProgress p = opts.resumed;
    p.state = nullptr;
    p.iterations += finished_iterations + (running ? running->iterations_done() - running_from : 0);
    p.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return p;
  };
  // The converged reference's result, kept for checkpoints (its pressure, where it is).
  std::optional<SolveResume::Reference> ref_kept;
  // Checkpoints hold the whole pressure and tractions, so that a run resumes on any number
  // of processes: a split run gathers them on the lead a field at a time (below). Every
  // process takes part when the lead has a checkpoint path.
  // With adhesion the adhesive traction goes too (the state's fields), so that a resumed solve
  // goes on along its branch.
  const bool checkpoints = place.agreed(!opts.checkpoint_path.empty());
  const bool adhesive = cfg.interaction.adhesive();
  const auto save = [&](const ContactFields& f) {
    if (!checkpoints) return;
    // The friction solve's restart point where it has one: its fields (the pressure at the
    // start of the step in progress) and its state; and the finished reference's result.
    const ContactSolver::RestartPoint* rp = running ? running->restart_point() : nullptr;
    // A frictionless adhesive solve's restart point: its net pressure and traction at the start of
    // the adhesive step in progress, and its state.
    // (A friction run's frictionless reference is solved again from the fields: none is kept.)
    const ContactSolver::AdhesiveRestartPoint* arp =
        !rp && running && adhesive && cfg.friction.coefficient == 0 ? running->adhesive_restart_point()
                                                                    : nullptr;
    const ContactFields& now = rp ? rp->fields : arp ? arp->fields : f;
    const FrictionRestart* fr = rp ? &rp->state : nullptr;
    const AdhesiveRestart* ar = arp ? &arp->state : nullptr;
    // An adhesive solve stopped inside its steps holds the repulsive pressure p + a: the file
    // takes the net one, p - a (a missing traction: zeros).
    RealField net, none;
    const RealField* adhesion = nullptr;
    if (adhesive) {
      if (now.adhesion.size() == now.pressure.size()) {
        adhesion = &now.adhesion;
      } else {
        none.assign(now.pressure.size(), 0.0);
        adhesion = &none;
      }
    }
    const RealField* pressure = &now.pressure;
    if (adhesive && !rp && !arp && running && running->pressure_is_repulsive()) {
      net.resize(now.pressure.size());
      for (std::size_t i = 0; i < net.size(); ++i) net[i] = now.pressure[i] - (*adhesion)[i];
      pressure = &net;
    }
    std::vector<const RealField*> fields = {pressure, &now.tx, &now.ty};
    for (const RealField* fld :
         resume_fields(ref_kept ? &ref_kept->pressure : nullptr,
                       ref_kept && adhesive ? &ref_kept->adhesion : nullptr, adhesion, fr, ar))
      fields.push_back(fld);
    // The lead writes the file a field at a time as it gathers them (8 bytes per point of the
    // cell at once). A checkpoint it could not write stops every process (none may wait for
    // it); the others go on gathering until then, so that the collectives stay paired.
    std::exception_ptr failure;
    std::optional<CheckpointStream> file;
    if (place.lead()) try {
        file.emplace(opts.checkpoint_path, cfg, progress_now());
      } catch (...) {
        failure = std::current_exception();
      }
    place.each_whole(fields, [&](std::size_t k, const RealField& whole) {
      if (!file || failure) return;
      try {
        if (k == 3) file->add_state(ref_kept ? &ref_kept->info : nullptr, fr, adhesive, ar);
        file->add(whole);
      } catch (...) {
        failure = std::current_exception();
      }
    });
    if (file && !failure) try {
        if (fields.size() == 3) file->add_state(nullptr, nullptr);
        file->commit();
      } catch (...) {
        failure = std::current_exception();
      }
    place.settle(failure);
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
    ContactSolver ref(*body, here, cfg.interaction, none, cfg.solver);
    hook(ref);
    ContactFields rf;
    SolveInfo ref_info;
    // A checkpoint's reference result is taken as it was (its displacements made again), not
    // solved again; on the device, and without one, it is solved (warm from what there is).
    bool ref_taken = false;
    if (resume && resume->reference) {
      rf.pressure = resume->reference->pressure;
      if (resume->adhesive) rf.adhesion = resume->reference->adhesion;
      ref_info = resume->reference->info;
      ref_taken = ref.finish(rf, ref_info);
      if (!ref_taken) rf.pressure = resume->reference->pressure;
    } else {
      rf = r.fields;
    }
    if (!ref_taken) try {
        ref_info = ref.solve(cfg.load, rf);
      } catch (const Interrupted&) {
        save(rf);
        throw interrupted_after(progress_now());
      }
    running = nullptr;
    if (!ref_taken) finished_iterations = ref_info.iterations;
    refuse_excess_pressure(cfg, place.here(), rf.pressure, ref_info);
    if (!ref_info.converged) {
      r.info = ref_info;
      r.info.status += " (frictionless reference)";
      surface_to_lead(place, cfg, here, r, true);
      return r;
    }
    if (checkpoints) ref_kept = SolveResume::Reference{rf.pressure, ref_info, rf.adhesion};
    CaseResult::Reference& rr = r.reference.emplace();
    rr.info = ref_info;
    // Its time was counted by the session that solved it.
    if (ref_taken) rr.info.wall_time_s = 0.0;
    // The reference's observables on the fields as they are (a slab in a distributed run);
    // its pressure and in-plane displacements are kept, where they are, for the post-analysis
    // stresses only.
    rr.observables = compute_observables(ref.fft(), here, none, rf, ref_info);
    if (!cfg.stress.post_analysis.empty()) {
      rr.pressure = rf.pressure;
      rr.ux = std::move(rf.ux);
      rr.uy = std::move(rf.uy);
    }
    // The sliding solve starts from the reference, unless warm: from a previous solution or a
    // checkpoint of it (one of the reference solve itself holds no reference).
    if (!warm || (resume && !resume->reference && !restart)) {
      r.fields.pressure = std::move(rf.pressure);
      r.fields.adhesion = std::move(rf.adhesion);  // with adhesion: its traction goes with it
      r.fields.tx.clear();
      r.fields.ty.clear();
    }
  }
  {
    ContactSolver solver(*body, here, cfg.interaction, cfg.friction, cfg.solver);
    hook(solver);
    // A restart point goes on where the interrupted solve was (the device solve starts warm
    // from the fields); its iterations up to there were counted before.
    const FrictionRestart* from = solver.on_device() || cfg.friction.coefficient == 0 ? nullptr : restart;
    // A frictionless adhesive solve's restart point likewise (with its fields' traction).
    const AdhesiveRestart* adh_from = !solver.on_device() && cfg.friction.coefficient == 0 && resume &&
                                              resume->adhesive_restart &&
                                              r.fields.adhesion.size() == place.here().local_size()
                                          ? &*resume->adhesive_restart
                                          : nullptr;
    running_from = from ? from->iterations : adh_from ? adh_from->iterations : 0;
    try {
      r.info = solver.solve(cfg.load, r.fields, from, adh_from);
    } catch (const Interrupted&) {
      save(r.fields);
      throw interrupted_after(progress_now());
    }
    running = nullptr;
    if (r.reference) {
      r.info.wall_time_s += r.reference->info.wall_time_s;
      r.info.transforms += r.reference->info.transforms;
      r.info.fft_seconds += r.reference->info.fft_seconds;
    }
    // A resumed run reports the totals of all its sessions: `iterations` counts the solve's
    // work (work an interruption lost included), as an uninterrupted run does; the earlier
    // sessions' work (resumed.iterations_before) may hold a reference solve, whose iterations
    // the summary reports apart (frictionless.iterations).
    const std::int64_t reference_before =
        resume && resume->reference ? resume->reference->info.iterations : 0;
    r.info.iterations += static_cast<int>(opts.resumed.iterations - running_from - reference_before);
    r.info.wall_time_s += opts.resumed.wall_time_s;
    r.resumed = opts.resumed;
    r.resumed.reference_iterations = reference_before;
    r.resumed.state = nullptr;
    refuse_excess_pressure(cfg, place.here(), r.fields.pressure, r.info);
  }
  body.reset();
  r.mpi_usage = run_detail::process_usage();
  // Every process post-processes the fields it holds; the lead reports an error of it (all
  // meet the same ones: the same inputs, the same reductions).
  std::exception_ptr failure;
  try {
    after_solve_here(cfg, opts, place.here(), here, r);
  } catch (...) {
    failure = std::current_exception();
  }
  place.settle_any(failure);
  collect_result(place, cfg, opts, here, r);
  // The lead does what needs the whole cell; the others wait for its outcome.
  place.on_lead([&] { after_solve_whole(cfg, r); });
  if (r.mpi_usage) r.mpi_usage->peak_bytes = run_detail::peak_resident_bytes();
  return r;
}

}  // namespace gfmd
