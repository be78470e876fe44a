// The device stresses' stand-in in a build without CUDA: never on the device
// (elastic/device_stress.hpp); the callers compute on the host.
#include "gfmd/elastic/device_stress.hpp"

#if !GFMD_HAVE_CUDA
#include "stress_detail.hpp"

namespace gfmd {

std::optional<DeviceStressResult> device_surface_stress(const Grid&, const ElasticParams&,
                                                        const ContactFields&, const DeviceStressRequest&) {
  return std::nullopt;
}
std::optional<DeviceStressResult> device_paper_post_analysis_stress(const Grid&, const ElasticParams&,
                                                                    const ContactFields&, double, double,
                                                                    const DeviceStressRequest&) {
  return std::nullopt;
}
std::optional<DeviceStressResult> device_post_analysis_stress(const ElasticBody&, const RealField&, double,
                                                              double, const DeviceStressRequest&) {
  return std::nullopt;
}

std::optional<DeviceStressResult> device_subsurface_stress(const Grid&, const ElasticParams& el,
                                                           const ContactFields&, double depth,
                                                           const DeviceStressRequest&) {
  // The same argument checks as the device's, so that a bad depth is refused alike.
  el.validate();
  stress_detail::check_depth(el, depth);
  return std::nullopt;
}

}  // namespace gfmd
#endif
