// Spectral analysis of a topography: the isotropic power spectral density, a Hurst-exponent
// fit to it, and the rms height, gradient and curvature by octave bands of wavelength.
//
// PSD normalisation (that of the Python Topography.psd): C(q) = lx ly / (2 pi)^2 |h~(q)|^2 /
// (nx ny)^2 with h~ the unnormalised discrete transform, so that (2 pi)^2 / (lx ly) times
// the sum of C over all modes q != 0 is the variance of h. Derivatives follow statistics()
// (surface/topography.hpp): the multipliers i qx_deriv, i qy_deriv of Grid (Nyquist
// derivative dropped), curvature = lap h / 2.
#pragma once

#include <cstddef>
#include <vector>

#include "gfmd/surface/topography.hpp"

namespace gfmd {

// Radially averaged C(q): the modes of the full spectrum with q = |q| > 0 are put into `bins`
// logarithmic bins [e_k, e_k+1), e_k = q_lo (q_hi (1 + 1e-12) / q_lo)^(k / bins) between the
// smallest (q_lo) and the largest (q_hi) nonzero |q| of the grid; q is the bin's geometric
// centre sqrt(e_k e_k+1), c the mean of C over its modes, modes their number (a mode and its
// mirror -q count as two). Empty bins are dropped.
struct IsotropicPsd {
  std::vector<double> q, c;
  std::vector<std::size_t> modes;
};
// Throws ParameterError("bins") for bins < 1, std::invalid_argument if h does not match the
// grid. Empty for a 1 x 1 grid.
IsotropicPsd isotropic_psd(const Topography& t, int bins = 64);

// Least squares of log c = log prefactor - (2 + 2 hurst) log q over the bins with
// q_min <= q <= q_max and c > 0 (equal weights per bin). q_min, q_max of the result: the
// smallest and largest q of the bins fitted; r2: coefficient of determination of the fit in
// the log-log plane (1 when the points lie on the line); points: bins fitted.
struct HurstFit {
  double hurst = 0.0, prefactor = 0.0, q_min = 0.0, q_max = 0.0, r2 = 0.0;
  std::size_t points = 0;
};
// Throws ParameterError("q_max") unless q_min <= q_max, ("q_min") when fewer than two bins
// (with distinct q) lie in the range.
HurstFit fit_hurst(const IsotropicPsd& psd, double q_min, double q_max);

// Octave bands of wavelength lambda = 2 pi / |q|. With L = max(lx, ly) and
// s = L |q| / (2 pi) = sqrt((kx L / lx)^2 + (ky L / ly)^2), band k holds the modes with
// 2^k <= s < 2^(k+1), i.e. L / 2^(k+1) < lambda <= L / 2^k: band 0 starts at the cell size.
// There are K = max(1, floor(log2(L / (2 min(dx, dy))))) bands, nominally down to two grid
// spacings; the last band also takes every shorter wavelength of the grid (the Nyquist and
// corner modes), its lambda_min is the shortest wavelength on the grid. rms_*: the rms height,
// gradient and curvature of the modes of the band alone, so that the sums of their squares
// over the bands equal statistics(t).rms_height^2, rms_gradient^2 and rms_curvature^2
// (Parseval; the mean, q = 0, is in no band). modes: modes of the full spectrum in the band.
struct BandStats {
  double lambda_min = 0.0, lambda_max = 0.0, rms_height = 0.0, rms_gradient = 0.0, rms_curvature = 0.0;
  std::size_t modes = 0;
};
// Bands ordered from the longest wavelengths to the shortest. Throws std::invalid_argument if
// h does not match the grid.
std::vector<BandStats> band_statistics(const Topography& t);

}  // namespace gfmd
