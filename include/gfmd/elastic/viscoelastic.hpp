// Linear viscoelastic bodies in steady sliding (SPEC §9). The indenter moves at v0 along e_s
// over the body; in its frame every field is steady, exp(i q.x), so a material point X of the
// body sees exp(i q.(X - v0 e_s t)) = exp(i q.X) exp(i omega t) with omega = -(q . e_s) v0.
// With Poisson's ratio constant the whole response of that mode (normal, in-plane, coupled,
// any thickness) is the elastic one of the relaxed modulus E0 times E0/E(omega), E(omega) the
// modulus under exp(i omega t) loading (E'' > 0 for omega > 0: the material dissipates).
//
// The modulus is a generalised Maxwell (Prony) series in contact moduli:
//   E(omega) = E0 + sum_i E_i i omega tau_i / (1 + i omega tau_i),   E(0) = E0, E(inf) = E0 + sum E_i.
// The standard linear solid is the one-term series E_1 = E_inf - E0 (Hunter 1961's model).
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "gfmd/core/grid.hpp"

namespace gfmd {

struct ViscoelasticParams {
  enum class Model { None, StandardLinearSolid, Prony };
  Model model = Model::None;
  // Standard linear solid: the glassy (high-frequency) contact modulus E_inf and the relaxation
  // time tau; the relaxed modulus E0 is ElasticParams::contact_modulus.
  double high_frequency_modulus = 0.0;
  double relaxation_time = 0.0;
  // Prony series: the moduli E_i (contact moduli, > 0) and times tau_i (> 0) of its arms.
  std::vector<double> prony_moduli, prony_times;
  // Sliding speed v0 (length per time unit of tau) and direction (degrees from +x; the
  // friction's sliding direction).
  double velocity = 0.0;
  double direction_deg = 0.0;

  [[nodiscard]] bool enabled() const { return model != Model::None; }
  // E(omega) / E0 for the relaxed contact modulus E0.
  [[nodiscard]] std::complex<double> modulus_ratio(double omega, double relaxed_modulus) const;
  // Throws ParameterError naming the key (high_frequency_modulus, relaxation_time,
  // prony_moduli, prony_times, velocity).
  void validate(double relaxed_modulus) const;
};

[[nodiscard]] const char* viscoelastic_model_name(ViscoelasticParams::Model m);

// The per-mode response factors E0/E(omega(q)) on the r2c half spectrum rows held here (on a
// Nyquist line the mean over the mode's aliases +-q there: real where the mode is its own
// conjugate).
[[nodiscard]] std::vector<std::complex<double>> viscoelastic_factors(const Grid& grid,
                                                                     const ViscoelasticParams& v,
                                                                     double relaxed_modulus);

}  // namespace gfmd
