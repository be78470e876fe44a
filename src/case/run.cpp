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
#include <initializer_list>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
#include "run_detail.hpp"
namespace gfmd {

namespace fs = std::filesystem;
using run_detail::after_solve_here;
using run_detail::after_solve_whole;

bool outputs_need_stress_fields(const Config& cfg) { return cfg.output.fields || cfg.output.png; }

namespace {

// The interruption as the run reports it: the iterations of every solve of the run so far
// (earlier sessions and a finished frictionless reference included), as its checkpoint and
// summary.json's resumed.iterations_before count them.
Interrupted interrupted_after(const CheckpointProgress& p) {
  return Interrupted("interrupted after " + std::to_string(p.iterations) + " iterations");
}
// This process's rows of the warm start that rank 0 holds (a checkpoint it read, a sweep's
// previous point): pressure and tractions, scattered by rows.
ContactFields warm_start_rows(const Grid& slab, const ContactFields& whole) {
  ContactFields f;
  f.pressure = mpi::scatter(slab, whole.pressure);
  f.tx = mpi::scatter(slab, whole.tx);
  f.ty = mpi::scatter(slab, whole.ty);
  // An adhesive state's cohesive zone (its branch on a load path) goes with it.
  if (mpi::from_root(whole.adhesion.empty() ? 0 : 1) == 1) f.adhesion = mpi::scatter(slab, whole.adhesion);
  return f;
}

// Gathers on rank 0 each field of the list that any process holds (a collective: a process
// with no rows holds empty fields); rank 0 then holds the whole fields, the others none.
template <class Vec>
void gather_on_root(const Grid& slab, std::initializer_list<Vec*> fields) {
  for (Vec* f : fields)
    if (mpi::any_bits(f->empty() ? 0u : 1u) != 0) *f = mpi::gather(slab, *f);
}

// The surface on rank 0 after a distributed solve: its kind always (summary.json), its heights
// where something reads them (a collective then).
Topography surface_on_root(const Config& cfg, const Grid& slab, const Topography& slab_topo, bool heights) {
  return Topography{cfg.grid, heights ? mpi::gather(slab, slab_topo.h) : RealField(), slab_topo.kind};
}

// What rank 0 of a distributed run needs whole after the distributed post-processing: every
// field when the whole solution is asked for (outputs with fields, a study's warm start, a
// library caller), else only what the analysis reads (pressure, gap and heights); the
// leakage's current fields always (flow.nc). The rest stays in slabs and is dropped.
void gather_for_root(const Config& cfg, const RunOptions& opts, const Grid& slab, Topography& slab_topo,
                     CaseResult& r) {
  if (r.leakage)
    for (std::size_t k = 0; k < r.leakage->flows.size(); ++k)
      gather_on_root(slab, {&r.leakage->flows[k].qx, &r.leakage->flows[k].qy, &r.leakage->magnitude[k]});
  const bool lean = !opts.whole_solution && !opts.keep_stress_fields;
  const bool analysis = r.info.converged && cfg.output.analysis;
  // The summary names the surface's kind; its heights the analysis and the field outputs read.
  if (cfg.indenter.type != "array") r.topography = surface_on_root(cfg, slab, slab_topo, !lean || analysis);
  if (lean) {
    if (analysis) gather_on_root(slab, {&r.fields.pressure, &r.fields.gap});
    // Nothing else whole: the slabs go, so that rank 0 holds no more than the others.
    ContactFields kept;
    if (analysis && mpi::root()) {
      kept.gap = std::move(r.fields.gap);
      kept.pressure = std::move(r.fields.pressure);
    }
    r.fields = std::move(kept);
    r.derived = DerivedFields{};
    for (auto& pa : r.post_analyses) RealField().swap(pa.s1);
    for (auto& ss : r.subsurface) {
      RealField().swap(ss.s1);
      RealField().swap(ss.von_mises);
    }
    return;
  }
  // Every field of the registry (for_each_result_field: the fields fields.nc, Python and the
  // maps name) that has storage, once each, in the registry's order on every process; and the
  // stick flags, whose mask rank 0 derives.
  std::set<RealField*> gathered;
  for_each_result_field(r, [&](const ResultField&, RealField* storage) {
    if (storage && gathered.insert(storage).second) gather_on_root(slab, {storage});
  });
  gather_on_root(slab, {&r.fields.stick});
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

Topography make_topography_here(const Config& cfg, MapReport* report) {
  if (!mpi::distributed()) return make_topography(cfg, report);
  const Grid slab = mpi::slab_of(cfg.grid);
  if (surface_made_on_slabs(cfg)) {
    // The slabs' transforms have one process's bits on any grid (core/fft.hpp), so each
    // process makes its rows alone: the same heights as the rows of the whole map.
    Config on_slab = cfg;
    on_slab.grid = slab;
    return make_topography(on_slab, report);
  }
  // A height map: rank 0 reads and prepares it (the whole map, there only) and hands out rows.
  Topography whole;
  on_root([&] { whole = make_topography(cfg, report); });
  return Topography{slab, mpi::scatter(slab, whole.h), "file"};
}

MadeSurface MadeSurface::of(const Config& cfg) {
  MadeSurface m;
  m.heights = std::make_shared<const Topography>(make_topography_here(cfg, &m.report));
  return m;
}

void MadeSurface::lend(RunOptions& ro) const {
  ro.made_surface = std::make_shared<Topography>(*heights);  // run_case takes it over
  ro.made_report = report;
}

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

CaseResult run_case(const Config& cfg, const RunOptions& options) {
  // Under mpirun rank 0's options hold for all: the post-processing's collectives depend on
  // which fields are kept.
  RunOptions opts = options;
  if (mpi::distributed()) {
    const int flags = mpi::from_root((opts.keep_stress_fields ? 1 : 0) | (opts.whole_solution ? 2 : 0));
    opts.keep_stress_fields = (flags & 1) != 0;
    opts.whole_solution = (flags & 2) != 0;
  }
  set_threads(cfg.threads);
  const Backend* chosen = find_backend(cfg.backend);
  if (chosen == nullptr) throw std::invalid_argument("run_case: unknown backend " + cfg.backend);
  // The CUDA solve runs on one process: "auto" means the cores under mpirun, and "cuda" is
  // refused there, or where no device is usable, before any work.
  if (mpi::distributed() && cfg.backend == "auto") chosen = &threads_backend();
  // "auto" also means the cores for the physics the device does not have (the solver refuses
  // "cuda" for it by name).
  if (cfg.backend == "auto" &&
      !device_lacks(cfg.interaction, cfg.friction, cfg.visco.enabled(), cfg.indenter.body.has_value())
           .first.empty())
    chosen = &threads_backend();
  if (chosen->name() == "cuda") {
    if (mpi::distributed())
      throw InputError("solver.backend", "\"cuda\" solves on one process; under mpirun use \"threads\"");
    // No device, or a grid too large for it: said before the surface is made.
    require_device_fits(cfg.grid, cfg.friction.coefficient > 0, cfg.interaction.adhesive(),
                        cfg.solver.anderson);
  }
  const BackendScope on_backend(*chosen);
  CaseResult r;
  r.config = cfg;
  r.config.backend = std::string(chosen->name());  // "auto" resolved
  // A distributed run (mpirun): the solves and the post-processing run on slabs of rows, one
  // per process; rank 0 gathers what needs the whole cell (the analysis, field outputs).
  const bool distributed = mpi::distributed();
  r.mpi_ranks = mpi::size();
  const Grid slab = distributed ? mpi::slab_of(cfg.grid) : cfg.grid;
  // The heights the solves see: this process's rows in a distributed run (made on the slab;
  // rank 0 gathers the whole map after the solve for the analysis).
  Topography slab_topo;
  if (cfg.indenter.type == "array" && opts.topography) {
    const Grid& tg = opts.topography->grid;
    if (tg.nx != cfg.grid.nx || tg.ny != cfg.grid.ny || tg.lx != cfg.grid.lx || tg.ly != cfg.grid.ly)
      throw InputError("indenter", "the given heights are " + std::to_string(tg.nx) + " x " +
                                       std::to_string(tg.ny) + " on " + format_number(tg.lx) + " x " +
                                       format_number(tg.ly) + ", the grid " + std::to_string(cfg.grid.nx) +
                                       " x " + std::to_string(cfg.grid.ny) + " on " +
                                       format_number(cfg.grid.lx) + " x " + format_number(cfg.grid.ly));
    r.topography = std::move(*opts.topography);
    if (distributed) slab_topo = Topography{slab, mpi::rows_of(slab, r.topography.h), r.topography.kind};
  } else {
    MapReport rep;
    Topography& made = distributed ? slab_topo : r.topography;
    if (opts.made_surface) {  // made once by the caller (the CLI's validation)
      made = std::move(*opts.made_surface);
      rep = opts.made_report;
    } else {
      made = make_topography_here(cfg, &rep);
    }
    if (cfg.indenter.type == "file" && mpi::root()) r.map_report = std::move(rep);
  }
  const Topography& topo = distributed ? slab_topo : r.topography;
  r.topography_stats = statistics(topo);
  // The body and the solvers live only as long as the solves: the stage after them
  // (stresses, flow) gets the memory back.
  auto body = std::make_unique<ElasticBody>(slab, cfg.elastic, cfg.visco,
                                            cfg.indenter.body ? &*cfg.indenter.body : nullptr);
  body->roll_both(cfg.friction.rolling());  // two bodies: both pass through the contact
  // A distributed run starts warm when rank 0 has a warm start: the others get its rows.
  bool warm = opts.warm_start && opts.warm_start->pressure.size() == cfg.grid.size();
  if (distributed) {
    warm = mpi::from_root(warm ? 1 : 0) == 1;
    if (warm) r.fields = warm_start_rows(slab, mpi::root() ? *opts.warm_start : ContactFields{});
  } else if (warm) {
    r.fields = *opts.warm_start;
  }
  // Where a checkpoint's solves stood (read by rank 0; its state goes with its fields): the
  // frictionless reference's result and the friction solve's restart point, this process's
  // rows of their fields in a distributed run.
  const SolveResume* resume = warm && opts.resumed.state ? opts.resumed.state.get() : nullptr;
  SolveResume resume_rows;
  if (distributed) {
    const SolveResume* whole = mpi::root() ? resume : nullptr;
    const auto numbers_of = [](const SolveResume& st) {
      return encode_resume_numbers(st.reference ? &st.reference->info : nullptr,
                                   st.friction ? &*st.friction : nullptr, st.adhesive,
                                   st.adhesive_restart ? &*st.adhesive_restart : nullptr);
    };
    const std::string numbers = mpi::from_root(whole ? numbers_of(*whole) : std::string());
    resume = nullptr;
    if (!numbers.empty()) {
      if (!decode_resume_numbers(numbers, resume_rows))
        throw std::runtime_error("run_case: a damaged resume state");
      const auto mine = resume_fields(resume_rows);
      std::vector<const RealField*> theirs;
      if (whole) theirs = resume_fields(*whole);
      for (std::size_t k = 0; k < mine.size(); ++k)
        *mine[k] = mpi::scatter(slab, k < theirs.size() ? *theirs[k] : RealField{});
      resume = &resume_rows;
    }
  }
  const FrictionRestart* restart = resume && resume->friction ? &*resume->friction : nullptr;
  // With adhesion the adhesive traction goes with the warm start's net pressure.
  if (resume && resume->adhesive && resume->adhesion.size() == slab.local_size())
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
  // of processes: a distributed run gathers them on rank 0 a field at a time (below). Every
  // process takes part when rank 0 has a checkpoint path.
  // With adhesion the adhesive traction goes too (the state's fields), so that a resumed solve
  // goes on along its branch.
  const bool checkpoints =
      distributed ? mpi::from_root(opts.checkpoint_path.empty() ? 0 : 1) == 1 : !opts.checkpoint_path.empty();
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
    // Rank 0 writes the file a field at a time as it gathers them (8 bytes per point of the
    // cell at once). A checkpoint it could not write stops every process (none may wait for
    // it); the others go on gathering until then, so that the collectives stay paired.
    std::exception_ptr failure;
    std::optional<CheckpointStream> file;
    if (mpi::root()) try {
        file.emplace(opts.checkpoint_path, cfg, progress_now());
      } catch (...) {
        failure = std::current_exception();
      }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (k == 3 && file && !failure) try {
          file->add_state(ref_kept ? &ref_kept->info : nullptr, fr, adhesive, ar);
        } catch (...) {
          failure = std::current_exception();
        }
      const RealField whole = distributed ? mpi::gather(slab, *fields[k]) : RealField();
      if (file && !failure) try {
          file->add(distributed ? whole : *fields[k]);
        } catch (...) {
          failure = std::current_exception();
        }
    }
    if (file && !failure) try {
        if (fields.size() == 3) file->add_state(nullptr, nullptr);
        file->commit();
      } catch (...) {
        failure = std::current_exception();
      }
    if (!distributed && failure) std::rethrow_exception(failure);
    rethrow_from_root(failure);
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
    refuse_excess_pressure(cfg, slab, rf.pressure, ref_info);
    if (!ref_info.converged) {
      r.info = ref_info;
      r.info.status += " (frictionless reference)";
      if (distributed) r.topography = surface_on_root(cfg, slab, slab_topo, true);
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
    rr.observables = compute_observables(ref.fft(), topo, none, rf, ref_info);
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
    ContactSolver solver(*body, topo, cfg.interaction, cfg.friction, cfg.solver);
    hook(solver);
    // A restart point goes on where the interrupted solve was (the device solve starts warm
    // from the fields); its iterations up to there were counted before.
    const FrictionRestart* from = solver.on_device() || cfg.friction.coefficient == 0 ? nullptr : restart;
    // A frictionless adhesive solve's restart point likewise (with its fields' traction).
    const AdhesiveRestart* adh_from = !solver.on_device() && cfg.friction.coefficient == 0 && resume &&
                                              resume->adhesive_restart &&
                                              r.fields.adhesion.size() == slab.local_size()
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
    r.resumed.state = nullptr;
    refuse_excess_pressure(cfg, slab, r.fields.pressure, r.info);
  }
  body.reset();
  if (mpi::launched())
    r.mpi_usage = CaseResult::MpiUsage{mpi::all_values(mpi::peak_resident_bytes()),
                                       mpi::all_values(mpi::reduction_seconds())};
  if (!distributed) {
    after_solve_here(cfg, opts, cfg.grid, r.topography, r);
    after_solve_whole(cfg, r);
    if (r.mpi_usage) r.mpi_usage->peak_bytes = mpi::peak_resident_bytes();
    return r;
  }
  // Every process post-processes its slab; rank 0 alone reports an error of it (they all meet
  // the same ones: the same inputs, the same reductions).
  std::exception_ptr failure;
  try {
    after_solve_here(cfg, opts, slab, slab_topo, r);
  } catch (...) {
    failure = std::current_exception();
  }
  if (mpi::any_bits(failure ? 1u : 0u) != 0) {
    rethrow_from_root(mpi::root() ? failure : nullptr);
    // Rank 0 went through: a process of its own failed (it reports), the others stop.
    if (failure) std::rethrow_exception(failure);
    throw StoppedWithRoot(1);
  }
  gather_for_root(cfg, opts, slab, slab_topo, r);
  slab_topo = Topography{};
  // Rank 0 does what needs the whole cell; the others wait for its outcome.
  if (mpi::root()) try {
      after_solve_whole(cfg, r);
    } catch (...) {
      failure = std::current_exception();
    }
  rethrow_from_root(failure);
  if (r.mpi_usage) r.mpi_usage->peak_bytes = mpi::peak_resident_bytes();
  return r;
}

}  // namespace gfmd
