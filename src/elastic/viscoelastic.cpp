// Viscoelastic bodies in steady sliding: the modulus of a Prony series (the standard linear
// solid its one-term case) and the per-mode response factors E0/E(omega). See
// include/gfmd/elastic/viscoelastic.hpp.
#include "gfmd/elastic/viscoelastic.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>
#include <string>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

const char* viscoelastic_model_name(ViscoelasticParams::Model m) {
  switch (m) {
    case ViscoelasticParams::Model::StandardLinearSolid:
      return "sls";
    case ViscoelasticParams::Model::Prony:
      return "prony";
    case ViscoelasticParams::Model::MasterCurve:
      return "master_curve";
    case ViscoelasticParams::Model::None:
      break;
  }
  return "none";
}

std::string ViscoelasticParams::relaxed_key() const {
  if (part == Part::Substrate) return "substrate_contact_modulus";
  if (part == Part::Layer) return part_name() + ".contact_modulus";
  return "contact_modulus";
}

std::string ViscoelasticParams::part_name() const {
  switch (part) {
    case Part::Substrate:
      return "substrate";
    case Part::All:
      return "all";
    case Part::Layer:
      return "layers[" + std::to_string(layer) + "]";
    case Part::Top:
      break;
  }
  return "top";
}

std::vector<ViscoelasticParams> ViscoelasticParams::parts() const {
  std::vector<ViscoelasticParams> all;
  if (!enabled()) return all;
  all.reserve(1 + further.size());
  all.push_back(*this);
  all.back().further.clear();
  for (const ViscoelasticParams& f : further) {
    all.push_back(f);
    all.back().further.clear();
    all.back().velocity = velocity;
    all.back().direction_deg = direction_deg;
  }
  return all;
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
  if (model == Model::MasterCurve && !curve_omega.empty()) {
    const double w = std::abs(omega) * shift_factor;
    const std::vector<double>& om = curve_omega;
    double storage, loss;
    if (w <= om.front()) {
      storage = curve_storage.front();
      loss = curve_loss.front() * w / om.front();
    } else if (w >= om.back()) {
      storage = curve_storage.back();
      loss = curve_loss.back() * om.back() / w;
    } else {
      const std::size_t i = static_cast<std::size_t>(std::upper_bound(om.begin(), om.end(), w) - om.begin());
      const double t = std::log(w / om[i - 1]) / std::log(om[i] / om[i - 1]);
      const auto lerp = [t](double a, double b) { return std::exp((1 - t) * std::log(a) + t * std::log(b)); };
      storage = lerp(curve_storage[i - 1], curve_storage[i]);
      loss = lerp(curve_loss[i - 1], curve_loss[i]);
    }
    e = std::complex<double>(storage, omega < 0 ? -loss : loss);
  }
  return e / relaxed_modulus;
}

void parse_master_curve(const std::string& text, const std::string& name, ViscoelasticParams& v) {
  v.curve_omega.clear();
  v.curve_storage.clear();
  v.curve_loss.clear();
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool header_allowed = true;
  while (std::getline(in, line)) {
    ++number;
    const auto bad = [&](const std::string& why) {
      throw InputError(name + ":" + std::to_string(number), why);
    };
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& ch : line)
      if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
    std::istringstream fields(line);
    std::vector<std::string> cols;
    for (std::string f; fields >> f;) cols.push_back(f);
    if (cols.empty()) continue;
    std::vector<double> x;
    for (const std::string& c : cols) {
      char* end = nullptr;
      const double d = std::strtod(c.c_str(), &end);
      if (end == c.c_str() || *end != '\0') break;
      x.push_back(d);
    }
    if (x.size() != cols.size() && header_allowed && v.curve_omega.empty()) {
      header_allowed = false;  // one header line: the columns' names
      continue;
    }
    if (cols.size() != 3)
      bad("expected three columns (omega, storage modulus E', loss modulus E''), got " +
          std::to_string(cols.size()));
    if (x.size() != 3) bad("'" + cols[x.size()] + "' is not a number");
    for (int k = 0; k < 3; ++k)
      if (!(x[k] >= kMinCurveValue && x[k] <= kMaxCurveValue))
        bad(std::string(k == 0   ? "omega"
                        : k == 1 ? "the storage modulus"
                                 : "the loss modulus") +
            " must be a positive number in [1e-100, 1e100]");
    if (!v.curve_omega.empty() && !(x[0] > v.curve_omega.back()))
      bad("omega must increase from row to row (a master curve is one value per frequency)");
    if (v.curve_omega.size() >= kMaxMasterCurveRows)
      bad("more than " + std::to_string(kMaxMasterCurveRows) + " rows");
    v.curve_omega.push_back(x[0]);
    v.curve_storage.push_back(x[1]);
    v.curve_loss.push_back(x[2]);
  }
  if (v.curve_omega.size() < 2)
    throw InputError(name, "a master curve needs at least two rows of omega, E', E''");
}

double wlf_shift(double temperature, double reference, double c1, double c2) {
  return std::pow(10.0, -c1 * (temperature - reference) / (c2 + temperature - reference));
}

double arrhenius_shift(double temperature, double reference, double activation) {
  return std::exp(activation * (1.0 / temperature - 1.0 / reference));
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
                           std::string("the glassy modulus E_inf must be finite and at least the relaxed one "
                                       "(elastic.") +
                               relaxed_key() + ")");
    if (!(relaxation_time > 0) || !std::isfinite(relaxation_time))
      throw ParameterError("relaxation_time", "must be a positive finite time");
  } else if (model == Model::MasterCurve) {
    const std::size_t n = curve_omega.size();
    if (n < 2 || curve_storage.size() != n || curve_loss.size() != n)
      throw ParameterError("master_curve", "needs at least two rows of omega, E', E''");
    for (std::size_t i = 0; i < n; ++i)
      if (!(curve_omega[i] > 0 && curve_storage[i] > 0 && curve_loss[i] > 0) ||
          !std::isfinite(curve_omega[i]) || !std::isfinite(curve_storage[i]) ||
          !std::isfinite(curve_loss[i]) || (i > 0 && !(curve_omega[i] > curve_omega[i - 1])))
        throw ParameterError("master_curve", "omega must increase and every value be positive and finite");
    if (!(shift_factor > 0) || !std::isfinite(shift_factor))
      throw ParameterError("temperature", "the shift factor a_T must be positive and finite");
    if (std::abs(relaxed_modulus - master_relaxed_modulus()) > 1e-12 * master_relaxed_modulus())
      throw ParameterError(relaxed_key(),
                           "must be the master curve's relaxed modulus, its first storage modulus");
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
