// The dimensionless Green's tensor of a layer on a rigid base (SPEC §2, frame with q along
// axis 1) tabulated over qh for some Poisson ratios: gfmd green, Python's gfmd.green, the
// green figure study.
#pragma once

#include <string>
#include <vector>

namespace gfmd {

// The table as CSV text (poisson,qh,phi11,phi22,phi33,im_phi13): `points` values of qh spaced
// logarithmically from `from` to `to` for each Poisson ratio. InputError naming "poisson" (a
// ratio a body cannot have), "from" (0 < from < to needed) or "points" (2 to kMaxGreenPoints),
// before any work.
inline constexpr int kMaxGreenPoints = 1000000;
std::string green_table_csv(const std::vector<double>& poisson, double from, double to, int points);
// Writes a table of green_table_csv to `path` atomically. An existing file is replaced only if it
// is such a table (its header) or with force; a directory, a file of another kind (a run's
// summary.json, a case file) and a path inside a directory that does not exist are refused with
// InputError naming the path, before anything is written.
void write_green_table(const std::string& path, const std::string& table, bool force);

}  // namespace gfmd
