// Viscoelastic bodies in steady sliding: the modulus of a Prony series (the standard linear
// solid its one-term case) and the per-mode response factors E0/E(omega). See
// include/gfmd/elastic/viscoelastic.hpp.
#include "gfmd/elastic/viscoelastic.hpp"

#include <cmath>
#include <numbers>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

const char* viscoelastic_model_name(ViscoelasticParams::Model m) {
  switch (m) {
    case ViscoelasticParams::Model::StandardLinearSolid:
      return "sls";
    case ViscoelasticParams::Model::Prony:
      return "prony";
    case ViscoelasticParams::Model::None:
      break;
  }
  return "none";
}

std::complex<double> ViscoelasticParams::modulus_ratio(double omega, double relaxed_modulus) const {
  // Called once per mode and alias when a body is made: no allocation here.
  std::complex<double> e(relaxed_modulus, 0.0);
  const auto arm = [&](double ei, double ti) {
    const std::complex<double> iwt(0.0, omega * ti);
    e += ei * iwt / (1.0 + iwt);
  };
  if (model == Model::StandardLinearSolid) arm(high_frequency_modulus - relaxed_modulus, relaxation_time);
  if (model == Model::Prony)
    for (std::size_t i = 0; i < prony_moduli.size() && i < prony_times.size(); ++i)
      arm(prony_moduli[i], prony_times[i]);
  return e / relaxed_modulus;
}

void ViscoelasticParams::validate(double relaxed_modulus) const {
  if (!(velocity >= 0) || !std::isfinite(velocity))
    throw ParameterError("velocity", "must be a non-negative finite speed");
  if (!enabled()) {
    if (velocity != 0.0)
      throw ParameterError("velocity",
                           "a sliding speed needs a viscoelastic body (elastic.viscoelastic = \"sls\" or "
                           "\"prony\"): an elastic body's steady state does not depend on it");
    return;
  }
  if (model == Model::StandardLinearSolid) {
    if (!(high_frequency_modulus >= relaxed_modulus) || !std::isfinite(high_frequency_modulus))
      throw ParameterError("high_frequency_modulus",
                           "the glassy modulus E_inf must be finite and at least the relaxed one "
                           "(elastic.contact_modulus)");
    if (!(relaxation_time > 0) || !std::isfinite(relaxation_time))
      throw ParameterError("relaxation_time", "must be a positive finite time");
  } else {
    if (prony_moduli.empty()) throw ParameterError("prony_moduli", "must list at least one modulus");
    if (prony_moduli.size() != prony_times.size())
      throw ParameterError("prony_times", "must list one time per modulus in elastic.prony_moduli");
    for (const double e : prony_moduli)
      if (!(e > 0) || !std::isfinite(e))
        throw ParameterError("prony_moduli", "each modulus must be a positive finite number");
    for (const double t : prony_times)
      if (!(t > 0) || !std::isfinite(t))
        throw ParameterError("prony_times", "each time must be positive and finite");
  }
}

std::vector<std::complex<double>> viscoelastic_factors(const Grid& grid, const ViscoelasticParams& v,
                                                       double relaxed_modulus) {
  std::vector<std::complex<double>> c(grid.spectral_size(), 1.0);
  if (!v.enabled()) return c;
  const double th = v.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const int nxh = grid.nxh();
  // On a Nyquist line (an even grid's kx = nx/2 column or ky = ny/2 row) +q and -q along that
  // axis are one mode: its factor is the mean over the two aliases, as the upwind slip
  // derivative's symbol is. That keeps real fields real (the kx = nx/2 column is its own
  // conjugate: the mean is real there) and fast sliding glassy on those modes too.
  for_rows(grid.rows(), [&](int row) {
    const int iky = grid.y0 + row;
    const bool ny_line = grid.ny % 2 == 0 && iky == grid.ny / 2;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const bool nx_line = grid.nx % 2 == 0 && ikx == grid.nx / 2;
      std::complex<double> sum = 0.0;
      int terms = 0;
      for (const double sx : {1.0, -1.0}) {
        if (sx < 0 && !nx_line) continue;
        for (const double sy : {1.0, -1.0}) {
          if (sy < 0 && !ny_line) continue;
          const double qs = sx * grid.qx(ikx) * ex + sy * grid.qy(iky) * ey;
          sum += 1.0 / v.modulus_ratio(-qs * v.velocity, relaxed_modulus);
          ++terms;
        }
      }
      c[static_cast<std::size_t>(row) * nxh + ikx] = sum / static_cast<double>(terms);
    }
  });
  return c;
}

}  // namespace gfmd
