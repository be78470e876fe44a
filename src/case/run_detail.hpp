// The post-processing steps of run_case (src/case/run.cpp) in their own file: the line
// profiles and the stresses (surface, post-analyses, subsurface planes) of a solved case.
#pragma once

#include "gfmd/case/result.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::run_detail {

// Line profiles through the pressure maximum along and across the sliding direction.
LineProfiles line_profiles(const Grid& g, const CaseResult& r);
// The stresses the case asks for, on the device where the backend has one, else here.
void compute_stresses(CaseResult& r, const FFT& fft, const Topography& topo, bool keep_fields);

}  // namespace gfmd::run_detail
