// The post-processing steps of run_case (src/case/run.cpp) in their own file: the line
// profiles and the stresses (surface, post-analyses, subsurface planes) of a solved case.
#pragma once

#include <optional>

#include "gfmd/case/result.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/placement.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::run_detail {

// The stage after the solve (run_after.cpp). On the fields where they are (every process of a
// distributed run calls it: collectives; grid is the fields' grid): observables, derived fields,
// plastic figures, stresses, the padded map's check, the leakage and the comparisons.
void after_solve_here(const Config& cfg, const RunOptions& opts, const Grid& grid, const Topography& topo,
                      CaseResult& r);
// On the whole cell in one process (rank 0): the run's analysis.
void after_solve_whole(const Config& cfg, CaseResult& r);

// The case's aggregates through the placement (run_placement.cpp): what the lead holds whole
// handed out as this process's rows, and the result gathered on the lead. In one process each
// is the aggregate itself.
// Heights the caller gave whole (an array), taken over: in one process they are the heights
// here; split, r.topography keeps them whole on every process and this process's rows are
// returned.
Topography given_heights_here(const Placement& place, Topography&& given, CaseResult& r);
// This process's warm start: in one process the fields as they are; split, its rows of the
// pressure, the tractions and (with adhesion) the adhesive traction the lead holds.
ContactFields warm_fields_here(const Placement& place, const ContactFields* whole_on_lead);
// This process's part of the lead's resume state (its numbers and its rows of its fields, in
// `rows`); null where the lead has none.
const SolveResume* resume_here(const Placement& place, const SolveResume* whole_on_lead, SolveResume& rows);
// The surface on the lead after the solves (`here` is taken over): its kind always (summary.json),
// its heights where `heights` (a collective when split; heights given whole are kept).
void surface_to_lead(const Placement& place, const Config& cfg, Topography& here, CaseResult& r,
                     bool heights);
// After the post-processing on the fields where they are: what the lead needs whole (every field
// of the registry where the whole solution is asked for, else what the analysis reads), the
// heights included; split, the rest is dropped so that the lead holds no more than the others.
void collect_result(const Placement& place, const Config& cfg, const RunOptions& opts, Topography& here,
                    CaseResult& r);
// Each process's peak memory and time in reductions, in a run mpirun launched (else none).
std::optional<CaseResult::MpiUsage> process_usage();
double peak_resident_bytes();

// Line profiles through the pressure maximum along and across the sliding direction.
LineProfiles line_profiles(const Grid& g, const CaseResult& r);
// The stresses the case asks for, on the device where the backend has one, else here.
void compute_stresses(CaseResult& r, const FFT& fft, const Topography& topo, bool keep_fields);

// An elastic indenter (run_indenter.cpp), on the fields held here: its own tractions and
// surface displacement in its frame (z' = -z: the traction (-tx, -ty, -p));
ContactFields indenter_fields(const FFT& fft, const ElasticParams& indenter, const ContactFields& f);
// its deformed face as rigid heights (the downhill force acts on it);
RealField deformed_indenter(const Topography& topo, const ContactFields& own);
// its stresses: the surface's summary and those of the planes of stress.depths inside it.
void indenter_stresses(CaseResult& r, const FFT& fft, const ContactFields& own);

}  // namespace gfmd::run_detail
