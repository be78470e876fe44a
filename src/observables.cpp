#include "gfmd/observables.hpp"

#include <cmath>
#include <numbers>

#include "gfmd/reduce.hpp"

namespace gfmd {

namespace {
// out = (e_s . grad) in, spectrally.
void directional_derivative(const FFT& fft, double ex, double ey, const RealField& in, RealField& out) {
  const Grid& g = fft.grid();
  SpecField s = fft.spec_field();
  fft.forward(in.data(), s.data());
  const int nxh = g.nxh();
#pragma omp parallel for schedule(static)
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(iky) * nxh + ikx;
      s[k] *= cplx(0.0, ex * g.qx_deriv(ikx) + ey * g.qy_deriv(iky));
    }
  out.resize(in.size());
  fft.backward(s.data(), out.data());
}
}  // namespace

void slip_velocity(const FFT& fft, const FrictionParams& fric, const RealField& ux, const RealField& uy,
                   RealField& vx, RealField& vy) {
  const double th = fric.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  directional_derivative(fft, ex, ey, ux, vx);
  directional_derivative(fft, ex, ey, uy, vy);
  for (auto& v : vx) v += ex;
  for (auto& v : vy) v += ey;
}

Observables compute_observables(const FFT& fft, const Topography& topo, const FrictionParams& fric,
                                const ContactFields& f, const SolveInfo& info) {
  const Grid& g = fft.grid();
  const double n = static_cast<double>(g.size());
  const double da = g.cell_area();
  Observables o;
  o.relative_contact_area = grid_sum(g, [&](std::size_t i) { return f.pressure[i] > 0 ? 1.0 : 0.0; }) / n;
  o.normal_force = grid_sum(g, [&](std::size_t i) { return f.pressure[i]; }) * da;
  o.mean_pressure = o.normal_force / g.area();
  o.max_pressure = grid_max(g, [&](std::size_t i) { return f.pressure[i]; }, 0.0);
  o.mean_gap = grid_sum(g, [&](std::size_t i) { return f.gap[i]; }) / n;
  o.approach = info.approach;
  const double mu = fric.coefficient;
  if (mu > 0) {
    RealField vx, vy, dh;
    slip_velocity(fft, fric, f.ux, f.uy, vx, vy);
    const double th = fric.direction_deg * std::numbers::pi / 180.0;
    directional_derivative(fft, std::cos(th), std::sin(th), topo.h, dh);
    o.friction_force = mu * da * grid_sum(g, [&](std::size_t i) { return f.pressure[i] * std::hypot(vx[i], vy[i]); });
    o.downhill_force = -da * grid_sum(g, [&](std::size_t i) { return f.pressure[i] * dh[i]; });
    o.friction_force_downhill = mu * o.normal_force + o.downhill_force;
    o.friction_coefficient = o.friction_force / o.normal_force;
    o.friction_coefficient_downhill = o.friction_force_downhill / o.normal_force;
    o.energy_balance_error = std::abs(o.friction_force - o.friction_force_downhill) / o.friction_force;
    o.mean_tangential_traction_x = grid_sum(g, [&](std::size_t i) { return f.tx[i]; }) / n;
    o.mean_tangential_traction_y = grid_sum(g, [&](std::size_t i) { return f.ty[i]; }) / n;
  }
  return o;
}

nlohmann::json to_json(const Observables& o) {
  nlohmann::json j = {{"relative_contact_area", o.relative_contact_area},
                      {"normal_force", o.normal_force},
                      {"mean_pressure", o.mean_pressure},
                      {"max_pressure", o.max_pressure},
                      {"mean_gap", o.mean_gap},
                      {"approach", o.approach}};
  if (o.friction_force > 0) {
    j["friction_force"] = o.friction_force;
    j["friction_force_downhill"] = o.friction_force_downhill;
    j["downhill_force"] = o.downhill_force;
    j["friction_coefficient"] = o.friction_coefficient;
    j["friction_coefficient_downhill"] = o.friction_coefficient_downhill;
    j["energy_balance_error"] = o.energy_balance_error;
  }
  return j;
}

}  // namespace gfmd
