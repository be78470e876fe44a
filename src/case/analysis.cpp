// Engineering statistics of a run. See include/gfmd/case/analysis.hpp.
#include "gfmd/case/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <sstream>

#include "indenter_types.hpp"

namespace gfmd {

namespace {

std::string g17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

nlohmann::json histogram_json(const Histogram& h) {
  return {{"samples", h.samples}, {"mean", h.mean}, {"min", h.min}, {"max", h.max}};
}

// The value below which a fraction f of the histogram's samples lie (linear within a bin).
double quantile(const Histogram& h, double f) {
  if (h.samples == 0) return 0.0;
  const double target = f * static_cast<double>(h.samples);
  double seen = 0.0;
  for (std::size_t k = 0; k < h.counts.size(); ++k) {
    if (seen + h.counts[k] >= target && h.counts[k] > 0)
      return h.edges[k] + (target - seen) / h.counts[k] * (h.edges[k + 1] - h.edges[k]);
    seen += h.counts[k];
  }
  return h.max;
}

}  // namespace

RunAnalysis analyse_run(const Topography& topo, const ContactFields& f) {
  RunAnalysis a;
  const Grid& g = topo.grid;
  const std::vector<unsigned char> contact = contact_mask(f);
  a.patches = contact_patches(g, contact);
  std::vector<unsigned char> open(contact.size());
  for (std::size_t i = 0; i < open.size(); ++i) open[i] = contact[i] ? 0 : 1;
  a.gap = histogram(f.gap.data(), f.gap.size(), kDistributionBins, open.data());
  a.pressure = histogram(f.pressure.data(), f.pressure.size(), kDistributionBins, contact.data());
  const PatchStats& p = a.patches;
  const double cell = g.lx * g.ly;
  a.largest_area_fraction = cell > 0 ? p.largest_area / cell : 0.0;
  a.mean_area = p.count ? p.contact_area / static_cast<double>(p.count) : 0.0;
  a.total_perimeter = std::accumulate(p.perimeters.begin(), p.perimeters.end(), 0.0);
  a.single_cell_patches =
      static_cast<std::size_t>(std::count(p.cells.begin(), p.cells.end(), std::size_t{1}));
  if (p.count > 0)  // areas are sorted descending
    a.median_area =
        p.count % 2 ? p.areas[p.count / 2] : 0.5 * (p.areas[p.count / 2 - 1] + p.areas[p.count / 2]);
  a.gap_median = quantile(a.gap, 0.5);
  a.pressure_median = quantile(a.pressure, 0.5);
  a.pressure_p90 = quantile(a.pressure, 0.9);
  a.psd = isotropic_psd(topo, 64);
  a.bands = band_statistics(topo);
  a.rough = config_detail::rough_indenter(topo.kind);
  if (a.rough) {
    const double L = std::max(g.lx, g.ly);
    const double q_lo = 2.0 * std::numbers::pi / (L / 2.0);
    const double q_hi = 2.0 * std::numbers::pi / (8.0 * std::max(g.dx(), g.dy()));
    try {
      if (q_hi > q_lo) a.hurst = fit_hurst(a.psd, q_lo, q_hi);
    } catch (const ParameterError&) {
      a.hurst = HurstFit{};  // too few bins in the range (a small grid): no fit
    }
  }
  return a;
}

nlohmann::json analysis_json(const RunAnalysis& a) {
  const PatchStats& p = a.patches;
  nlohmann::json patches = {{"count", p.count},
                            {"largest_area", p.largest_area},
                            {"largest_area_fraction", a.largest_area_fraction},
                            {"mean_area", a.mean_area},
                            {"total_perimeter", a.total_perimeter},
                            {"percolating", p.percolating},
                            {"percolates_x", p.percolates_x},
                            {"percolates_y", p.percolates_y},
                            {"single_cell_patches", a.single_cell_patches}};
  if (a.median_area) patches["median_area"] = *a.median_area;
  nlohmann::json j = {{"patches", patches},
                      {"gap", histogram_json(a.gap)},
                      {"pressure", histogram_json(a.pressure)},
                      {"files", {"patches.csv", "distributions.csv", "spectrum.csv", "bands.csv"}}};
  j["gap"]["median"] = a.gap_median;
  j["pressure"]["median"] = a.pressure_median;
  j["pressure"]["p90"] = a.pressure_p90;
  if (a.rough && a.hurst.points >= 2) {
    j["spectrum"] = {{"hurst", a.hurst.hurst},
                     {"prefactor", a.hurst.prefactor},
                     {"q_min", a.hurst.q_min},
                     {"q_max", a.hurst.q_max},
                     {"r2", a.hurst.r2},
                     {"bins", a.hurst.points},
                     {"fit",
                      "C(q) = prefactor q^(-2-2H), least squares in log-log over the PSD bins with "
                      "2 pi / (L/2) <= q <= 2 pi / (8 dx)"}};
  }
  nlohmann::json bands = nlohmann::json::array();
  for (const BandStats& b : a.bands)
    bands.push_back({{"lambda_min", b.lambda_min},
                     {"lambda_max", b.lambda_max},
                     {"rms_height", b.rms_height},
                     {"rms_gradient", b.rms_gradient},
                     {"rms_curvature", b.rms_curvature}});
  j["bands"] = bands;
  return j;
}

std::string patches_csv(const RunAnalysis& a) {
  std::ostringstream os;
  os << "patch,area,perimeter,cells\n";
  for (std::size_t k = 0; k < a.patches.count; ++k)
    os << k << ',' << g17(a.patches.areas[k]) << ',' << g17(a.patches.perimeters[k]) << ','
       << a.patches.cells[k] << '\n';
  return os.str();
}

std::string distributions_csv(const RunAnalysis& a) {
  std::ostringstream os;
  os << "quantity,bin_low,bin_high,count,pdf\n";
  for (const auto& [name, h] : {std::pair{"gap", &a.gap}, std::pair{"pressure", &a.pressure}})
    for (std::size_t k = 0; k < h->counts.size(); ++k)
      os << name << ',' << g17(h->edges[k]) << ',' << g17(h->edges[k + 1]) << ',' << g17(h->counts[k]) << ','
         << g17(h->pdf[k]) << '\n';
  return os.str();
}

std::string spectrum_csv(const RunAnalysis& a) {
  std::ostringstream os;
  os << "q,C,modes\n";
  for (std::size_t k = 0; k < a.psd.q.size(); ++k)
    os << g17(a.psd.q[k]) << ',' << g17(a.psd.c[k]) << ',' << a.psd.modes[k] << '\n';
  return os.str();
}

std::string bands_csv(const RunAnalysis& a) {
  std::ostringstream os;
  os << "lambda_min,lambda_max,rms_height,rms_gradient,rms_curvature\n";
  for (const BandStats& b : a.bands)
    os << g17(b.lambda_min) << ',' << g17(b.lambda_max) << ',' << g17(b.rms_height) << ','
       << g17(b.rms_gradient) << ',' << g17(b.rms_curvature) << '\n';
  return os.str();
}

}  // namespace gfmd
