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
// A measured master curve is a table of E'(omega), E''(omega) at a reference temperature,
// interpolated log-log, read at omega a_T for a temperature T (a_T: WLF or Arrhenius shift).
#pragma once

#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/core/grid.hpp"

namespace gfmd {

struct ViscoelasticParams {
  enum class Model { None, StandardLinearSolid, Prony, MasterCurve };
  Model model = Model::None;
  // Standard linear solid: the glassy (high-frequency) contact modulus E_inf and the relaxation
  // time tau; the relaxed modulus E0 is ElasticParams::contact_modulus.
  double high_frequency_modulus = 0.0;
  double relaxation_time = 0.0;
  // Prony series: the moduli E_i (contact moduli, > 0) and times tau_i (> 0) of its arms.
  std::vector<double> prony_moduli, prony_times;
  // Master curve: angular frequencies (ascending, > 0) with the storage and loss contact moduli
  // there (> 0) at the reference temperature, and the shift factor a_T of the body's temperature
  // (E(omega) is the table's E(omega a_T)). Its relaxed modulus E0 is the first storage modulus
  // (master_relaxed_modulus), which the body's contact_modulus must be. Between the rows
  // log E' and log E'' are linear in log omega; below the first E' stays and E'' falls in
  // proportion to omega (a liquid-like terminal zone has E'' ~ omega); above the last E' stays
  // and E'' falls as 1/omega (a glassy plateau's).
  std::vector<double> curve_omega, curve_storage, curve_loss;
  double shift_factor = 1.0;
  // Where the table came from and the shift's keys as given (the case's record of them).
  std::string curve_file;
  std::vector<std::pair<std::string, double>> shift_keys;
  // Which part of a layered body is viscoelastic (elastic.viscoelastic_part): the top layer (its
  // contact_modulus the relaxed E0), one of the layers beneath it ("layers[i]": its
  // contact_modulus the relaxed E0; an adhesive interlayer), the substrate
  // (substrate_contact_modulus the relaxed E0: a hard coating on a polymer), or all of it (every
  // layer's and the substrate's modulus times the one ratio E(omega)/E0 of the top layer's). The
  // other parts stay elastic. A homogeneous body is its top layer.
  enum class Part { Top, Layer, Substrate, All };
  Part part = Part::Top;
  int layer = 0;  // with Part::Layer: its index in ElasticParams::layers
  // Further viscoelastic parts of a layered body, each with its own model (and relaxed modulus:
  // its part's contact_modulus), given by elastic.viscoelastic_parts: a rubber coating on a
  // polymer substrate of another relaxation. Their parts differ from this one's and from each
  // other's and none is "all"; they move with this one's velocity and direction (their own are
  // unused), and have no further parts of their own.
  std::vector<ViscoelasticParams> further;
  // Sliding speed v0 (length per time unit of tau) and direction (degrees from +x; the
  // friction's sliding direction).
  double velocity = 0.0;
  double direction_deg = 0.0;

  [[nodiscard]] bool enabled() const { return model != Model::None; }
  // Every viscoelastic part: this one, then each of `further`, moving with this one's velocity
  // and direction (empty for an elastic body).
  [[nodiscard]] std::vector<ViscoelasticParams> parts() const;
  // The key of the relaxed modulus E0 (its part's contact_modulus), as errors name it.
  [[nodiscard]] std::string relaxed_key() const;
  // elastic.viscoelastic_part's value for this part: "top", "layers[i]" (its index), "substrate"
  // or "all".
  [[nodiscard]] std::string part_name() const;
  [[nodiscard]] double master_relaxed_modulus() const {
    return curve_storage.empty() ? 0.0 : curve_storage.front();
  }
  // E(omega) / E0 for the relaxed contact modulus E0.
  [[nodiscard]] std::complex<double> modulus_ratio(double omega, double relaxed_modulus) const;
  // Throws ParameterError naming the key (high_frequency_modulus, relaxation_time,
  // prony_moduli, prony_times, master_curve, velocity).
  void validate(double relaxed_modulus) const;
};

[[nodiscard]] const char* viscoelastic_model_name(ViscoelasticParams::Model m);

// A master curve's table from text (`name` the file, for messages): rows of three numbers,
// omega, E' and E'' (comma, semicolon, tab or space separated), '#' comments and blank lines
// skipped, one header line allowed before the first row; at most kMaxMasterCurveRows rows.
// Fills v.curve_*; throws InputError("<name>:<line>", why) at the first bad line (a missing
// column, a value that is not a number in [kMinCurveValue, kMaxCurveValue], omega not increasing).
inline constexpr std::size_t kMaxMasterCurveRows = 100000;
// Every value of the table in [kMinCurveValue, kMaxCurveValue]: ratios of them stay finite.
inline constexpr double kMinCurveValue = 1e-100, kMaxCurveValue = 1e100;
void parse_master_curve(const std::string& text, const std::string& name, ViscoelasticParams& v);
// The WLF shift factor, log10 a_T = -c1 (T - Tr)/(c2 + T - Tr), and Arrhenius's,
// ln a_T = A (1/T - 1/Tr) with A the activation energy over the gas constant (kelvin).
[[nodiscard]] double wlf_shift(double temperature, double reference, double c1, double c2);
[[nodiscard]] double arrhenius_shift(double temperature, double reference, double activation);

// The per-mode response factors E0/E(omega(q)) on the r2c half spectrum rows held here (on a
// Nyquist line the mean over the mode's aliases +-q there: real where the mode is its own
// conjugate).
[[nodiscard]] std::vector<std::complex<double>> viscoelastic_factors(const Grid& grid,
                                                                     const ViscoelasticParams& v,
                                                                     double relaxed_modulus);

}  // namespace gfmd
