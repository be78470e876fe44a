// The case's aggregates through the distribution seam (core/placement.hpp): what run_case
// hands out to, and gathers from, the processes of a split run. See src/case/run_detail.hpp.
#include <set>
#include <stdexcept>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/mpi.hpp"
#include "run_detail.hpp"

namespace gfmd {

Topography make_topography_here(const Config& cfg, MapReport* report) {
  const Placement place = Placement::of(cfg.grid);
  if (!place.split()) return make_topography(cfg, report);
  if (surface_made_on_slabs(cfg)) {
    // The slabs' transforms have one process's bits on any grid (core/fft.hpp), so each
    // process makes its rows alone: the same heights as the rows of the whole map.
    Config on_slab = cfg;
    on_slab.grid = place.here();
    return make_topography(on_slab, report);
  }
  // A height map: the lead reads and prepares it (the whole map, there only) and hands out rows.
  Topography whole;
  place.on_lead([&] { whole = make_topography(cfg, report); });
  return Topography{place.here(), place.spread(whole.h), "file"};
}

namespace run_detail {

Topography given_heights_here(const Placement& place, Topography&& given, CaseResult& r) {
  if (!place.split()) return std::move(given);
  r.topography = std::move(given);
  return Topography{place.here(), place.rows(r.topography.h), r.topography.kind};
}

ContactFields warm_fields_here(const Placement& place, const ContactFields* whole_on_lead) {
  // One process: the warm start as it is.
  if (!place.split()) return *whole_on_lead;
  static const ContactFields none;
  const ContactFields& whole = place.lead() ? *whole_on_lead : none;
  ContactFields f;
  f.pressure = place.spread(whole.pressure);
  f.tx = place.spread(whole.tx);
  f.ty = place.spread(whole.ty);
  // An adhesive state's cohesive zone (its branch on a load path) goes with it.
  if (place.agreed(!whole.adhesion.empty())) f.adhesion = place.spread(whole.adhesion);
  return f;
}

const SolveResume* resume_here(const Placement& place, const SolveResume* whole_on_lead, SolveResume& rows) {
  if (!place.split()) return whole_on_lead;
  const SolveResume* whole = place.lead() ? whole_on_lead : nullptr;
  const auto numbers_of = [](const SolveResume& st) {
    return encode_resume_numbers(st.reference ? &st.reference->info : nullptr,
                                 st.friction ? &*st.friction : nullptr, st.adhesive,
                                 st.adhesive_restart ? &*st.adhesive_restart : nullptr);
  };
  const std::string numbers = place.agreed(whole ? numbers_of(*whole) : std::string());
  if (numbers.empty()) return nullptr;
  if (!decode_resume_numbers(numbers, rows)) throw std::runtime_error("run_case: a damaged resume state");
  const auto mine = resume_fields(rows);
  std::vector<const RealField*> theirs;
  if (whole) theirs = resume_fields(*whole);
  for (std::size_t k = 0; k < mine.size(); ++k)
    *mine[k] = place.spread(k < theirs.size() ? *theirs[k] : RealField{});
  return &rows;
}

void surface_to_lead(const Placement& place, const Config& cfg, Topography& here, CaseResult& r,
                     bool heights) {
  if (!place.split()) {
    r.topography = std::move(here);
    return;
  }
  // Heights given whole to every process (an array) are there already.
  if (cfg.indenter.type == "array") return;
  r.topography = Topography{cfg.grid, heights ? place.whole_of(here.h) : RealField(), here.kind};
}

// Split: every field when the whole solution is asked for (outputs with fields, a study's warm
// start, a library caller), else only what the analysis reads (pressure, gap and heights); the
// leakage's current fields always (flow.nc). The rest stays in slabs and is dropped.
void collect_result(const Placement& place, const Config& cfg, const RunOptions& opts, Topography& here,
                    CaseResult& r) {
  const bool lean = !opts.whole_solution && !opts.keep_stress_fields;
  const bool analysis = r.info.converged && cfg.output.analysis;
  if (!place.split()) {
    surface_to_lead(place, cfg, here, r, true);
    return;
  }
  if (r.leakage)
    for (std::size_t k = 0; k < r.leakage->flows.size(); ++k)
      place.collect({&r.leakage->flows[k].qx, &r.leakage->flows[k].qy, &r.leakage->magnitude[k]});
  // The summary names the surface's kind; its heights the analysis and the field outputs read.
  surface_to_lead(place, cfg, here, r, !lean || analysis);
  here = Topography{};
  if (lean) {
    if (analysis) place.collect({&r.fields.pressure, &r.fields.gap});
    // Nothing else whole: the slabs go, so that the lead holds no more than the others.
    ContactFields kept;
    if (analysis && place.lead()) {
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
  // stick flags, whose mask the lead derives.
  std::set<RealField*> gathered;
  for_each_result_field(r, [&](const ResultField&, RealField* storage) {
    if (storage && gathered.insert(storage).second) place.collect({storage});
  });
  place.collect(r.fields.stick);
}

std::optional<CaseResult::MpiUsage> process_usage() {
  if (!mpi::launched()) return std::nullopt;
  return CaseResult::MpiUsage{mpi::all_values(mpi::peak_resident_bytes()),
                              mpi::all_values(mpi::reduction_seconds())};
}

double peak_resident_bytes() { return mpi::peak_resident_bytes(); }

}  // namespace run_detail
}  // namespace gfmd
