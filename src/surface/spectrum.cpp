// Isotropic PSD, Hurst fit and band statistics of a topography (see surface/spectrum.hpp).
#include "gfmd/surface/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"

namespace gfmd {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void check_topography(const Topography& t, const char* where) {
  const Grid& g = t.grid;
  if (g.nx < 1 || g.ny < 1 || t.h.size() != g.size())
    throw std::invalid_argument(std::string(where) + ": the height field does not match the grid");
}

// k sums over the r2c half spectrum: f(ikx, iky, index, acc) adds into acc[0..k-1]. Each row
// is summed serially and the row sums added in row order (independent of the backend).
template <class F>
std::vector<double> spectral_sums(const Grid& g, std::size_t k, F&& f) {
  const int nxh = g.nxh();
  std::vector<double> rows(static_cast<std::size_t>(g.ny) * k, 0.0);
  for_rows(g.ny, [&](int iky) {
    double* s = rows.data() + static_cast<std::size_t>(iky) * k;
    const std::size_t base = static_cast<std::size_t>(iky) * nxh;
    for (int ikx = 0; ikx < nxh; ++ikx) f(ikx, iky, base + ikx, s);
  });
  std::vector<double> total(k, 0.0);
  for (int iky = 0; iky < g.ny; ++iky)
    for (std::size_t j = 0; j < k; ++j) total[j] += rows[static_cast<std::size_t>(iky) * k + j];
  return total;
}

SpecField transform(const Topography& t) {
  FFT fft(t.grid);
  SpecField c = fft.spec_field();
  fft.forward(t.h.data(), c.data());
  return c;
}

double mode_q(const Grid& g, int ikx, int iky) {
  const double qx = g.qx(ikx), qy = g.qy(iky);
  return std::sqrt(qx * qx + qy * qy);
}

}  // namespace

IsotropicPsd isotropic_psd(const Topography& t, int bins) {
  check_topography(t, "isotropic_psd");
  if (bins < 1) throw ParameterError("bins", "need at least one bin (got " + std::to_string(bins) + ")");
  const Grid& g = t.grid;
  IsotropicPsd psd;
  if (g.size() < 2) return psd;

  // Smallest and largest nonzero |q|: rows serially, then the rows in order.
  std::vector<double> row_lo(static_cast<std::size_t>(g.ny)), row_hi(static_cast<std::size_t>(g.ny));
  for_rows(g.ny, [&](int iky) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (int ikx = 0; ikx < g.nxh(); ++ikx) {
      const double q = mode_q(g, ikx, iky);
      if (q > 0.0) lo = std::min(lo, q);
      hi = std::max(hi, q);
    }
    row_lo[iky] = lo;
    row_hi[iky] = hi;
  });
  const double q_lo = *std::min_element(row_lo.begin(), row_lo.end());
  const double q_top = *std::max_element(row_hi.begin(), row_hi.end()) * (1.0 + 1e-12);

  const std::size_t nb = static_cast<std::size_t>(bins);
  std::vector<double> edges(nb + 1);
  const double log_ratio = std::log(q_top / q_lo);
  for (std::size_t k = 0; k < nb; ++k) edges[k] = q_lo * std::exp(log_ratio * static_cast<double>(k) / bins);
  edges[nb] = q_top;

  const SpecField spec = transform(t);
  const double n = static_cast<double>(g.size());
  const double norm = g.lx * g.ly / (kTwoPi * kTwoPi) / (n * n);
  // Sums per bin: [2k] C times multiplicity, [2k+1] multiplicity.
  const std::vector<double> sums = spectral_sums(g, 2 * nb, [&](int ikx, int iky, std::size_t i, double* s) {
    const double q = mode_q(g, ikx, iky);
    if (!(q > 0.0)) return;
    auto k = static_cast<std::size_t>(
        std::clamp(std::floor(std::log(q / q_lo) / log_ratio * bins), 0.0, static_cast<double>(nb - 1)));
    while (k > 0 && q < edges[k]) --k;
    while (k + 1 < nb && q >= edges[k + 1]) ++k;
    const double w = g.weight(ikx);
    s[2 * k] += w * norm * std::norm(spec[i]);
    s[2 * k + 1] += w;
  });
  for (std::size_t k = 0; k < nb; ++k) {
    const double m = sums[2 * k + 1];
    if (m == 0.0) continue;
    psd.q.push_back(std::sqrt(edges[k] * edges[k + 1]));
    psd.c.push_back(sums[2 * k] / m);
    psd.modes.push_back(static_cast<std::size_t>(m));
  }
  return psd;
}

HurstFit fit_hurst(const IsotropicPsd& psd, double q_min, double q_max) {
  if (!(q_min <= q_max))
    throw ParameterError(
        "q_max", "must not be below q_min = " + format_number(q_min) + " (got " + format_number(q_max) + ")");
  std::vector<double> x, y;
  const std::size_t n = std::min(psd.q.size(), psd.c.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (psd.q[k] >= q_min && psd.q[k] <= q_max && psd.c[k] > 0.0 && std::isfinite(psd.c[k])) {
      x.push_back(std::log(psd.q[k]));
      y.push_back(std::log(psd.c[k]));
    }
  }
  const auto m = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= m;
  my /= m;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
    syy += (y[k] - my) * (y[k] - my);
  }
  if (x.size() < 2 || !(sxx > 0.0))
    throw ParameterError("q_min", "fewer than two PSD bins with distinct q and C > 0 lie in [" +
                                      format_number(q_min) + ", " + format_number(q_max) + "]");
  const double slope = sxy / sxx, intercept = my - slope * mx;
  HurstFit f;
  f.hurst = -0.5 * slope - 1.0;
  f.prefactor = std::exp(intercept);
  f.q_min = std::exp(*std::min_element(x.begin(), x.end()));
  f.q_max = std::exp(*std::max_element(x.begin(), x.end()));
  double ss_res = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double r = y[k] - (intercept + slope * x[k]);
    ss_res += r * r;
  }
  f.r2 = syy > 0.0 ? 1.0 - ss_res / syy : 1.0;
  f.points = x.size();
  return f;
}

std::vector<BandStats> band_statistics(const Topography& t) {
  check_topography(t, "band_statistics");
  const Grid& g = t.grid;
  const double big = std::max(g.lx, g.ly), rx = big / g.lx, ry = big / g.ly;
  const double octaves = std::log2(big / (2.0 * std::min(g.dx(), g.dy())));
  const int bands = static_cast<int>(std::clamp(std::floor(octaves + 1e-9), 1.0, 60.0));
  const auto nb = static_cast<std::size_t>(bands);

  // Octave of a mode: floor(log2(s)) with s^2 = (kx rx)^2 + (ky ry)^2 >= 1, from the binary
  // exponent of s^2 (exact for s^2 = 4^k; 1e-12 guards rounding for non-square cells).
  auto band_of = [&](int ikx, int iky) -> int {
    const double sx = g.kx(ikx) * rx, sy = g.ky(iky) * ry;
    const double s2 = sx * sx + sy * sy;
    if (s2 == 0.0) return -1;
    int e = 0;
    std::frexp(s2 * (1.0 + 1e-12), &e);  // s2 = m 2^e, m in [0.5, 1)
    return std::clamp((e - 1) / 2, 0, bands - 1);
  };

  const SpecField spec = transform(t);
  const double n = static_cast<double>(g.size());
  const double inv_n2 = 1.0 / (n * n);
  // Sums per band: [4k] height^2, [4k+1] gradient^2, [4k+2] curvature^2, [4k+3] modes.
  const std::vector<double> sums = spectral_sums(g, 4 * nb, [&](int ikx, int iky, std::size_t i, double* s) {
    const int b = band_of(ikx, iky);
    if (b < 0) return;
    const double w = g.weight(ikx), p = w * std::norm(spec[i]) * inv_n2;
    const double qx = g.qx_deriv(ikx), qy = g.qy_deriv(iky);
    const double q2 = qx * qx + qy * qy, lap_half = 0.5 * q2;
    double* acc = s + 4 * static_cast<std::size_t>(b);
    acc[0] += p;
    acc[1] += p * q2;
    acc[2] += p * lap_half * lap_half;
    acc[3] += w;
  });

  // Shortest wavelength on the grid: the corner mode (nx/2, ny/2).
  const double sx_max = (g.nx / 2) * rx, sy_max = (g.ny / 2) * ry;
  const double s2_max = sx_max * sx_max + sy_max * sy_max;
  const double lambda_shortest = s2_max > 0.0 ? big / std::sqrt(s2_max) : big;
  std::vector<BandStats> out(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    BandStats& b = out[k];
    b.lambda_max = std::ldexp(big, -static_cast<int>(k));
    b.lambda_min = std::ldexp(big, -static_cast<int>(k) - 1);
    if (k + 1 == nb) b.lambda_min = std::min(b.lambda_min, lambda_shortest);
    b.rms_height = std::sqrt(sums[4 * k]);
    b.rms_gradient = std::sqrt(sums[4 * k + 1]);
    b.rms_curvature = std::sqrt(sums[4 * k + 2]);
    b.modes = static_cast<std::size_t>(sums[4 * k + 3]);
  }
  return out;
}

}  // namespace gfmd
