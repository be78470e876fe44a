// The dimensionless Green's tensor tabulated over qh (gfmd green, Python's gfmd.green).
#include "gfmd/studies/green.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/elastic/elastic.hpp"

namespace gfmd {

namespace {
constexpr const char* kGreenHeader = "poisson,qh,phi11,phi22,phi33,im_phi13";
}  // namespace

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
  os << kGreenHeader << "\n";
  for (double nu : poisson)
    for (int i = 0; i < points; ++i) {
      const double qh = from * std::pow(to / from, static_cast<double>(i) / (points - 1));
      const PhiRotated p = phi_rotated(qh, nu);
      os << nu << "," << qh << "," << p.p11 << "," << p.p22 << "," << p.p33 << "," << p.p13 << "\n";
    }
  return os.str();
}

void write_green_table(const std::string& path, const std::string& table, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st)) throw InputError(path, "is a directory; give the CSV file's path");
  if (fs::exists(st)) {
    if (!fs::is_regular_file(st)) throw InputError(path, "exists and is not a regular file");
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    if (first != kGreenHeader && !force)
      throw InputError(
          path, "exists and is not a table of gfmd green (its first line is not \"" +
                    std::string(kGreenHeader) +
                    "\"); it is kept: choose another file, or --force (Python: force=True) to replace it");
  }
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw InputError(path, "its directory " + parent.string() + " does not exist");
  write_text_atomic(path, table);
}

}  // namespace gfmd
