// The device stresses' stand-in in a build without CUDA: never on the device
// (elastic/device_stress.hpp); the callers compute on the host.
#include "gfmd/elastic/device_stress.hpp"

#if !GFMD_HAVE_CUDA
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

std::optional<DeviceStressResult> device_subsurface_stress(const Grid&, const ElasticParams&,
                                                           const ContactFields&, double,
                                                           const DeviceStressRequest&) {
  return std::nullopt;
}

}  // namespace gfmd
#endif
