// Engineering statistics of every run: contact patches, gap and pressure distributions,
// the indenter's power spectrum with a Hurst fit and its rms slopes and curvatures per band.
// Computed by run_case after a converged solve; serialised by the output stage.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gfmd/contact/patches.hpp"
#include "gfmd/core/fields.hpp"
#include "gfmd/core/histogram.hpp"
#include "gfmd/surface/spectrum.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd {

struct RunAnalysis {
  PatchStats patches;
  Histogram gap;       // over the points out of contact
  Histogram pressure;  // over the points in contact
  IsotropicPsd psd;
  bool rough = false;  // a random or measured surface: the Hurst fit means something
  HurstFit hurst;      // fitted between lambda = L/2 and 8 grid spacings (rough surfaces only)
  std::vector<BandStats> bands;
  // Figures of the above (summary.json "analysis"): patch areas over the cell, the median
  // patch area (none without contact), perimeters, one-cell patches; distribution quantiles
  // (linear within a bin).
  double largest_area_fraction = 0, mean_area = 0, total_perimeter = 0;
  std::optional<double> median_area;
  std::size_t single_cell_patches = 0;
  double gap_median = 0, pressure_median = 0, pressure_p90 = 0;
};

// The bins of the gap and pressure distributions.
inline constexpr int kDistributionBins = 50;

RunAnalysis analyse_run(const Topography& topo, const ContactFields& fields);

// summary.json's "analysis": scalars and the fit; the per-patch, per-bin and per-band
// tables are in the CSV files below.
nlohmann::json analysis_json(const RunAnalysis& a);
// patches.csv: one row per contact patch, largest first (area, perimeter, cells).
std::string patches_csv(const RunAnalysis& a);
// distributions.csv: the gap and pressure histograms (bin centre, count, pdf).
std::string distributions_csv(const RunAnalysis& a);
// spectrum.csv: the isotropic PSD (q, C(q), modes); bands.csv: rms per octave band.
std::string spectrum_csv(const RunAnalysis& a);
std::string bands_csv(const RunAnalysis& a);

}  // namespace gfmd
