// The stresses of a solved state on the CUDA device (solver.backend = "cuda"): the
// tensor (at the surface or on a plane below it), its principal values and their summary, with
// the formulas of stress.hpp, the
// fields uploaded once and only what the caller asks for brought back. Each function returns
// nothing (and the caller computes on the host) where no device is usable or the work does
// not fit its free memory; in a build without CUDA always nothing. docs/gpu.md.
#pragma once

#include <cstddef>
#include <optional>

#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd {

struct DeviceStressRequest {
  double high_tension_fraction = 0.9;  // summarize's threshold
  bool tensor = false;                 // bring the tensor back
  // All: every principal field back; SummaryOnly: s1 back only when `s1` is set.
  PrincipalParts parts = PrincipalParts::SummaryOnly;
  bool s1 = false;
  bool von_mises = false;  // bring the von Mises map back (SummaryOnly)
};

struct DeviceStressResult {
  StressField tensor;            // empty unless asked
  PrincipalField principal;      // as asked
  StressSummary summary;         // summarize(grid, principal, high_tension_fraction)
  double above_half = 0.0;       // fraction of the cells with s1 >= max(s1) / 2 (0 if max <= 0)
  std::size_t device_bytes = 0;  // peak device memory of the evaluation
};

// surface_stress(fft, el, f) with principal() and summarize() on the device.
std::optional<DeviceStressResult> device_surface_stress(const Grid& g, const ElasticParams& el,
                                                        const ContactFields& f,
                                                        const DeviceStressRequest& req);
// paper_post_analysis_stress(fft, el, frictionless, mu, angle_deg), the same way.
std::optional<DeviceStressResult> device_paper_post_analysis_stress(const Grid& g, const ElasticParams& el,
                                                                    const ContactFields& frictionless,
                                                                    double mu, double angle_deg,
                                                                    const DeviceStressRequest& req);
// post_analysis_stress(fft, body, pressure, mu, angle_deg), the same way.
std::optional<DeviceStressResult> device_post_analysis_stress(const ElasticBody& body,
                                                              const RealField& pressure, double mu,
                                                              double angle_deg,
                                                              const DeviceStressRequest& req);

// subsurface_stress(fft, el, f, depth) with principal() and summarize() on the device. A depth
// the body does not have throws ParameterError (as on the host) before anything is made.
std::optional<DeviceStressResult> device_subsurface_stress(const Grid& g, const ElasticParams& el,
                                                           const ContactFields& f, double depth,
                                                           const DeviceStressRequest& req);

}  // namespace gfmd
