// Histograms and probability densities of a field (the gap over the non-contact points, the
// pressure over the contact points, ...). Serial and deterministic: one pass for the range
// and the mean, one for the counts, both in index order.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"

namespace gfmd {

struct Histogram {
  std::vector<double> edges;   // bins + 1 bin edges, equal width, edges[0] = lo, edges[bins] = hi
  std::vector<double> counts;  // samples per bin; bin k is [edges[k], edges[k+1]), the last one closed
  std::vector<double> pdf;     // counts / (samples * width): sum(pdf * width) = 1 (all 0 without samples)
  double mean = 0.0, min = 0.0, max = 0.0;  // of the samples counted (0 without samples)
  std::size_t samples = 0;                  // values counted: finite and, with a mask, mask[i] != 0
};

// Histogram of the finite values v[i], i < n, with mask[i] != 0 where a mask is given, in
// `bins` equal bins between the smallest (lo) and largest (hi) of them. When lo == hi the
// range is widened to lo -/+ |lo|/2 (-/+ 1/2 for lo = 0), the value in the middle bin(s).
// Without samples the range is [0, 1] and the counts and pdf are zero.
// Throws ParameterError("bins") for bins < 1 and ("v") for v == nullptr with n > 0.
inline Histogram histogram(const double* v, std::size_t n, int bins, const unsigned char* mask = nullptr) {
  if (bins < 1) throw ParameterError("bins", "need at least one bin (got " + std::to_string(bins) + ")");
  if (v == nullptr && n > 0) throw ParameterError("v", "null data pointer with n = " + std::to_string(n));
  auto counted = [&](std::size_t i) { return (mask == nullptr || mask[i] != 0) && std::isfinite(v[i]); };

  Histogram h;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!counted(i)) continue;
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
    sum += v[i];
    ++h.samples;
  }
  if (h.samples > 0) {
    h.mean = sum / static_cast<double>(h.samples);
    h.min = lo;
    h.max = hi;
  } else {
    lo = 0.0;
    hi = 1.0;
  }
  if (!(hi > lo)) {
    const double half = lo != 0.0 ? 0.5 * std::abs(lo) : 0.5;
    lo -= half;
    hi += half;
  }

  const std::size_t nb = static_cast<std::size_t>(bins);
  h.edges.resize(nb + 1);
  for (std::size_t k = 0; k < nb; ++k) h.edges[k] = lo + (hi - lo) * (static_cast<double>(k) / bins);
  h.edges[nb] = hi;
  h.counts.assign(nb, 0.0);
  h.pdf.assign(nb, 0.0);
  if (h.samples == 0) return h;

  const double scale = bins / (hi - lo);
  for (std::size_t i = 0; i < n; ++i) {
    if (!counted(i)) continue;
    const double x = v[i];
    std::size_t k = static_cast<std::size_t>(std::clamp((x - lo) * scale, 0.0, static_cast<double>(nb - 1)));
    // The bin whose edges (as stored) hold x, whatever the rounding of the division.
    while (k > 0 && x < h.edges[k]) --k;
    while (k + 1 < nb && x >= h.edges[k + 1]) ++k;
    h.counts[k] += 1.0;
  }
  const double width = (hi - lo) / bins;
  for (std::size_t k = 0; k < nb; ++k) h.pdf[k] = h.counts[k] / (static_cast<double>(h.samples) * width);
  return h;
}

}  // namespace gfmd
