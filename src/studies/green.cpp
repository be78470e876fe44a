// The dimensionless Green's tensor tabulated over qh (gfmd green, Python's gfmd.green).
#include "gfmd/studies/green.hpp"

#include <cmath>
#include <sstream>

#include "gfmd/core/error.hpp"
#include "gfmd/elastic/elastic.hpp"

namespace gfmd {

std::string green_table_csv(const std::vector<double>& poisson, double from, double to, int points) {
  if (!(from > 0 && to > from && std::isfinite(to))) throw InputError("from", "need 0 < from < to (finite)");
  if (points < 2 || points > kMaxGreenPoints)
    throw InputError("points", "need 2 <= points <= " + std::to_string(kMaxGreenPoints));
  if (poisson.empty()) throw InputError("poisson", "give at least one Poisson ratio");
  for (double nu : poisson) {
    try {
      homogeneous_body(1.0, nu, 1.0, true).validate();
    } catch (const ParameterError& e) {
      throw InputError("poisson", e.why());
    }
  }
  std::ostringstream os;
  os.precision(12);
  os << "poisson,qh,phi11,phi22,phi33,im_phi13\n";
  for (double nu : poisson)
    for (int i = 0; i < points; ++i) {
      const double qh = from * std::pow(to / from, static_cast<double>(i) / (points - 1));
      const PhiRotated p = phi_rotated(qh, nu);
      os << nu << "," << qh << "," << p.p11 << "," << p.p22 << "," << p.p33 << "," << p.p13 << "\n";
    }
  return os.str();
}

}  // namespace gfmd
