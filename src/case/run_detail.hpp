// The post-processing steps of run_case (src/case/run.cpp) in their own file: the line
// profiles and the stresses (surface, post-analyses, subsurface planes) of a solved case.
#pragma once

#include "gfmd/case/result.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::run_detail {

// The stage after the solve (run_after.cpp). On the fields where they are (every process of a
// distributed run calls it: collectives; grid is the fields' grid): observables, derived fields,
// plastic figures, stresses, the padded map's check, the leakage and the comparisons.
void after_solve_here(const Config& cfg, const RunOptions& opts, const Grid& grid, const Topography& topo,
                      CaseResult& r);
// On the whole cell in one process (rank 0): the run's analysis.
void after_solve_whole(const Config& cfg, CaseResult& r);

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
