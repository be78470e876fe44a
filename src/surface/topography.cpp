// Indenter topographies: analytic profiles, self-affine random surfaces, statistics, and
// height maps from files (read by io/height_map).
#include "gfmd/surface/topography.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/io/height_map.hpp"
#include "gfmd/surface/contmech.hpp"

namespace gfmd {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

void validate_grid(const Grid& g) {
  if (g.nx < 1 || g.ny < 1)
    throw ParameterError("grid", "nx and ny must be at least 1 (got nx = " + std::to_string(g.nx) +
                                     ", ny = " + std::to_string(g.ny) + ")");
  if (!(g.lx > 0.0 && std::isfinite(g.lx)) || !(g.ly > 0.0 && std::isfinite(g.ly)))
    throw InputError(
        "grid", "lx and ly must be positive and finite (got lx = " + num(g.lx) + ", ly = " + num(g.ly) + ")");
}

bool positive_finite(double v) { return v > 0.0 && std::isfinite(v); }

// Deterministic sum over the rows of the r2c half spectrum held here: f(ikx, iky, index), iky
// the global row, index into the local spectrum. Rows are summed serially and the row sums
// added in row order over every process (independent of the threads and processes).
template <class F>
double spectral_sum(const Grid& g, F&& f) {
  const int nxh = g.nxh();
  std::vector<double> rows(static_cast<std::size_t>(g.rows()));
  for_rows(g.rows(), [&](int row) {
    double s = 0.0;
    const std::size_t base = static_cast<std::size_t>(row) * nxh;
    for (int ikx = 0; ikx < nxh; ++ikx) s += f(ikx, g.y0 + row, base + ikx);
    rows[static_cast<std::size_t>(row)] = s;
  });
  return add_rows(g, std::move(rows), 1)[0];
}

struct SpectralMoments {
  double grad2 = 0.0;  // <|grad h|^2>
  double curv2 = 0.0;  // <(lap h / 2)^2>
};

SpectralMoments spectral_moments(const Grid& g, const FFT& fft, const RealField& h) {
  SpecField c = fft.spec_field();
  fft.forward(h.data(), c.data());
  const double n = static_cast<double>(g.size());
  const double inv_n2 = 1.0 / (n * n);
  SpectralMoments m;
  m.grad2 = spectral_sum(g,
                         [&](int ikx, int iky, std::size_t i) {
                           const double qx = g.qx_deriv(ikx), qy = g.qy_deriv(iky);
                           return g.weight(ikx) * std::norm(c[i]) * (qx * qx + qy * qy);
                         }) *
            inv_n2;
  m.curv2 = spectral_sum(g,
                         [&](int ikx, int iky, std::size_t i) {
                           const double qx = g.qx_deriv(ikx), qy = g.qy_deriv(iky);
                           const double lap_half = 0.5 * (qx * qx + qy * qy);
                           return g.weight(ikx) * std::norm(c[i]) * lap_half * lap_half;
                         }) *
            inv_n2;
  return m;
}

double real_mean(const Grid& g, const RealField& h) {
  return grid_sum(g, [&](std::size_t i) { return h[i]; }) / static_cast<double>(g.size());
}

double real_rms(const Grid& g, const RealField& h, double mean) {
  const double s = grid_sum(g, [&](std::size_t i) {
    const double d = h[i] - mean;
    return d * d;
  });
  return std::sqrt(s / static_cast<double>(g.size()));
}

void scale_field(RealField& h, double factor) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(h.size());
  parallel_for(n, [&](std::ptrdiff_t i) { h[i] *= factor; });
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Analytic profiles

Topography make_hertz(const Grid& grid, double rx, double ry) {
  validate_grid(grid);
  if (!positive_finite(rx))
    throw ParameterError("radius_x", "radius of curvature must be > 0 (got " + num(rx) + ")");
  if (!positive_finite(ry))
    throw ParameterError("radius_y", "radius of curvature must be > 0 (got " + num(ry) + ")");
  Topography t{grid, RealField(grid.local_size()), "hertz"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double dx = grid.dx(), dy = grid.dy();
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    const double hy = (y * y) / (2.0 * ry);
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double x = (ix - cx) * dx;
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = -(x * x) / (2.0 * rx) - hy;
    }
  });
  return t;
}

Topography make_powerlaw(const Grid& grid, double rx, double ry, double exponent) {
  validate_grid(grid);
  if (!positive_finite(rx)) throw ParameterError("radius_x", "must be > 0 (got " + num(rx) + ")");
  if (!positive_finite(ry)) throw ParameterError("radius_y", "must be > 0 (got " + num(ry) + ")");
  if (!(exponent >= 1.0 && exponent <= 20.0))
    throw ParameterError("exponent",
                         "must be in [1, 20] (1: a cone, 2: the paraboloid), got " + num(exponent));
  Topography t{grid, RealField(grid.local_size()), "powerlaw"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double dx = grid.dx(), dy = grid.dy(), r = std::sqrt(rx * ry);
  const double scale = 1.0 / (exponent * std::pow(r, exponent - 1.0));
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double x = (ix - cx) * dx;
      const double re2 = r * (x * x / rx + y * y / ry);
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = -scale * std::pow(re2, 0.5 * exponent);
    }
  });
  return t;
}

Topography make_sphere(const Grid& grid, double radius) {
  validate_grid(grid);
  if (!positive_finite(radius)) throw ParameterError("radius", "must be > 0 (got " + num(radius) + ")");
  Topography t{grid, RealField(grid.local_size()), "sphere"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double dx = grid.dx(), dy = grid.dy(), r2 = radius * radius;
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double x = (ix - cx) * dx, d2 = x * x + y * y;
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] =
          d2 < r2 ? -d2 / (radius + std::sqrt(r2 - d2)) : -radius;
    }
  });
  return t;
}

Topography make_cylinder(const Grid& grid, double radius, char axis) {
  validate_grid(grid);
  if (!positive_finite(radius)) throw ParameterError("radius", "must be > 0 (got " + num(radius) + ")");
  if (axis != 'x' && axis != 'y') throw ParameterError("axis", "must be \"x\" or \"y\"");
  Topography t{grid, RealField(grid.local_size()), "cylinder"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double dx = grid.dx(), dy = grid.dy();
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double x = (ix - cx) * dx, d = axis == 'y' ? x : y;
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = -(d * d) / (2.0 * radius);
    }
  });
  return t;
}

void check_step(const Grid& grid, double width, double depth, char axis) {
  if (axis != 'x' && axis != 'y') throw ParameterError("axis", "must be \"x\" or \"y\"");
  if (!positive_finite(width)) throw ParameterError("width", "must be > 0 (got " + num(width) + ")");
  if (!positive_finite(depth)) throw ParameterError("depth", "must be > 0 (got " + num(depth) + ")");
  const double d = axis == 'y' ? grid.dx() : grid.dy(), l = axis == 'y' ? grid.lx : grid.ly;
  if (width < 2 * d)
    throw ParameterError("width", "the strip's width " + num(width) + " spans fewer than 2 grid spacings (" +
                                      num(d) + "); refine the grid");
  if (width > l - 2 * d)
    throw ParameterError("width", "the strip (width " + num(width) +
                                      ") leaves less than 2 grid spacings of the " +
                                      "lower terrace in the cell (" + num(l) + ")");
}

Topography make_step(const Grid& grid, double width, double depth, char axis) {
  validate_grid(grid);
  check_step(grid, width, depth, axis);
  Topography t{grid, RealField(grid.local_size()), "step"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double dx = grid.dx(), dy = grid.dy(), half = 0.5 * width;
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double d = axis == 'y' ? (ix - cx) * dx : y;
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = std::abs(d) <= half ? 0.0 : -depth;
    }
  });
  return t;
}

void add_waviness(Topography& t, double amplitude, double wavelength, char axis) {
  const Grid& g = t.grid;
  if (!positive_finite(amplitude))
    throw ParameterError("waviness_amplitude", "must be > 0 (got " + num(amplitude) + ")");
  if (!positive_finite(wavelength))
    throw ParameterError("waviness_wavelength", "must be > 0 (got " + num(wavelength) + ")");
  const bool along_x = axis == 'x';
  const double l = along_x ? g.lx : g.ly;
  const int n = along_x ? g.nx : g.ny;
  const double r = l / wavelength, m = std::round(r);
  if (m < 1.0 || std::abs(r - m) > 1e-9 * r)
    throw ParameterError("waviness_wavelength", "the wavelength " + num(wavelength) +
                                                    " must divide the cell size " + (along_x ? "lx" : "ly") +
                                                    " = " + num(l) + " so that the surface stays periodic");
  if (wavelength < 2.0 * l / n * (1.0 - 1e-12))
    throw ParameterError("waviness_wavelength", "is shorter than two grid spacings");
  // cos(2 pi i m / n) with i the offset from the centre node, reduced modulo n in integers.
  const long long periods = static_cast<long long>(m);
  std::vector<double> wave(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const long long k = ((static_cast<long long>(i - n / 2) * periods) % n + n) % n;
    wave[static_cast<std::size_t>(i)] = amplitude * std::cos(kTwoPi * static_cast<double>(k) / n);
  }
  for_rows(g.rows(), [&](int row) {
    for (int ix = 0; ix < g.nx; ++ix)
      t.h[static_cast<std::size_t>(row) * g.nx + ix] +=
          wave[static_cast<std::size_t>(along_x ? ix : g.y0 + row)];
  });
}

void check_flatpunch(const Grid& grid, double radius, double depth) {
  if (!positive_finite(radius)) throw ParameterError("radius", "must be > 0 (got " + num(radius) + ")");
  if (!positive_finite(depth)) throw ParameterError("depth", "must be > 0 (got " + num(depth) + ")");
  const double d = std::max(grid.dx(), grid.dy());
  if (radius < 2 * d)
    throw ParameterError("radius", "the punch radius " + num(radius) +
                                       " spans fewer than 2 grid spacings (dx = " + num(d) +
                                       "); refine the grid");
  if (2 * radius > 0.5 * std::min(grid.lx, grid.ly))
    throw ParameterError("radius", "the punch (diameter " + num(2 * radius) +
                                       ") is wider than half the cell (" + num(std::min(grid.lx, grid.ly)) +
                                       "): periodic images would interfere; enlarge grid.lx");
}

Topography make_flatpunch(const Grid& grid, double radius, double depth) {
  validate_grid(grid);
  check_flatpunch(grid, radius, depth);
  const double dx = grid.dx(), dy = grid.dy();
  Topography t{grid, RealField(grid.local_size()), "flatpunch"};
  const int cx = grid.nx / 2, cy = grid.ny / 2;
  const double r2 = radius * radius;
  for_rows(grid.rows(), [&](int row) {
    const double y = (grid.y0 + row - cy) * dy;
    for (int ix = 0; ix < grid.nx; ++ix) {
      const double x = (ix - cx) * dx;
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = x * x + y * y <= r2 ? 0.0 : -depth;
    }
  });
  return t;
}

Topography make_eggcrate(const Grid& grid, double wavelength, double amplitude) {
  validate_grid(grid);
  if (!positive_finite(wavelength))
    throw ParameterError("wavelength", "must be > 0 (got " + num(wavelength) + ")");
  if (!positive_finite(amplitude))
    throw ParameterError("amplitude", "must be > 0 (got " + num(amplitude) + ")");
  // Number of periods per cell side; must be an integer for a periodic surface.
  auto periods = [&](double l, const char* side) {
    const double r = l / wavelength;
    const double m = std::round(r);
    if (m < 1.0 || std::abs(r - m) > 1e-9 * r)
      throw ParameterError("wavelength", "the wavelength " + num(wavelength) + " must divide the cell size " +
                                             std::string(side) + " = " + num(l) + " (ratio " + num(r) +
                                             ") so that the surface is periodic");
    return static_cast<long long>(m);
  };
  const long long mx = periods(grid.lx, "lx"), my = periods(grid.ly, "ly");
  // cos(2 pi x / lambda) with x/lambda = ix * mx / nx, reduced modulo one period with
  // integer arithmetic: exactly periodic, exactly 1 at the origin.
  std::vector<double> cx(static_cast<std::size_t>(grid.nx)), cy(static_cast<std::size_t>(grid.ny));
  for (int ix = 0; ix < grid.nx; ++ix)
    cx[ix] = std::cos(kTwoPi * static_cast<double>((ix * mx) % grid.nx) / grid.nx);
  for (int iy = 0; iy < grid.ny; ++iy)
    cy[iy] = std::cos(kTwoPi * static_cast<double>((iy * my) % grid.ny) / grid.ny);
  Topography t{grid, RealField(grid.local_size()), "eggcrate"};
  for_rows(grid.rows(), [&](int row) {
    for (int ix = 0; ix < grid.nx; ++ix)
      t.h[static_cast<std::size_t>(row) * grid.nx + ix] = amplitude * (cx[ix] + cy[grid.y0 + row]);
  });
  return t;
}

// ---------------------------------------------------------------------------------------
// Self-affine surfaces

void check_selfaffine(const Grid& g, const SelfAffineParams& p) {
  if (!(p.hurst > 0.0 && p.hurst < 1.0))
    throw ParameterError("hurst", "the Hurst exponent must satisfy 0 < H < 1 (got " + num(p.hurst) + ")");
  if (!(p.peklenik >= 1e-3 && p.peklenik <= 1e3))
    throw ParameterError(
        "peklenik", "the Peklenik number must be in [1e-3, 1e3] (1: isotropic; got " + num(p.peklenik) + ")");
  // With a Peklenik number the wavelengths along x are sqrt(gamma) times the isotropic ones and
  // along y 1/sqrt(gamma) times: the cell and the grid must hold them in their own direction.
  const double sx = std::sqrt(p.peklenik), sy = 1.0 / sx;
  const double lmin = std::min(g.lx / sx, g.ly / sy), lmax = std::max(g.lx, g.ly);
  if (!positive_finite(p.lambda_long))
    throw ParameterError("lambda_long", "must be > 0 (got " + num(p.lambda_long) + ")");
  if (p.lambda_long > lmin * (1.0 + 1e-12))
    throw ParameterError(
        "lambda_long",
        "must not exceed the cell size min(lx, ly) = " + num(lmin) +
            (p.peklenik != 1.0 ? " (with the Peklenik number: min(lx/sqrt(gamma), ly sqrt(gamma)))" : "") +
            " (got " + num(p.lambda_long) + ")");
  if (!positive_finite(p.lambda_short))
    throw ParameterError("lambda_short", "must be > 0 (got " + num(p.lambda_short) + ")");
  if (!(p.lambda_short < p.lambda_long))
    throw ParameterError("lambda_short", "must be smaller than lambda_long = " + num(p.lambda_long) +
                                             " (got " + num(p.lambda_short) + ")");
  const double spacing = std::max(g.dx() / sx, g.dy() / sy);
  if (p.lambda_short < 2.0 * spacing * (1.0 - 1e-12))
    throw ParameterError(
        "lambda_short",
        "lambda_short = " + num(p.lambda_short) + " is shorter than twice the grid spacing (2 * " +
            num(spacing) + " = " + num(2.0 * spacing) +
            "): the grid spacing is too coarse to resolve it; refine the grid or raise lambda_short");
  const bool rolloff = p.lambda_rolloff != 0.0;
  if (rolloff) {
    if (!positive_finite(p.lambda_rolloff) || !(p.lambda_rolloff > p.lambda_long))
      throw ParameterError("lambda_rolloff", "must be 0 (no roll-off) or larger than lambda_long = " +
                                                 num(p.lambda_long) + " (got " + num(p.lambda_rolloff) + ")");
    if (p.lambda_rolloff > lmax * (1.0 + 1e-12))
      throw ParameterError("lambda_rolloff", "must not exceed the cell size max(lx, ly) = " + num(lmax) +
                                                 " (got " + num(p.lambda_rolloff) + ")");
  }
  if (p.generator != "gfmd" && p.generator != "contmech")
    throw ParameterError("generator", "unknown generator \"" + p.generator +
                                          "\"; one of gfmd (ours), contmech (the paper authors' code)");
  if (p.generator == "contmech" && p.peklenik != 1.0)
    throw ParameterError("peklenik",
                         "the contmech generator (the paper's surfaces) is isotropic; leave peklenik out");
  if (p.generator == "contmech" && rolloff)
    throw ParameterError(
        "lambda_rolloff",
        "the contmech generator (the paper's surfaces) has no roll-off; leave lambda_rolloff out");
  if (p.generator == "contmech" && p.seed > kContmechMaxSeed)
    throw ParameterError("seed", "the contmech generator takes the paper code's seed, an int: 0 ... " +
                                     std::to_string(kContmechMaxSeed) + " (got " + std::to_string(p.seed) +
                                     ")");
  if (std::isnan(p.rms_height) || p.rms_height < 0.0 || std::isinf(p.rms_height))
    throw ParameterError("rms_height", "must be a finite number >= 0 (got " + num(p.rms_height) + ")");
  if (std::isnan(p.rms_gradient) || p.rms_gradient < 0.0 || std::isinf(p.rms_gradient))
    throw ParameterError("rms_gradient", "must be a finite number >= 0 (got " + num(p.rms_gradient) + ")");
  if ((p.rms_height > 0.0) == (p.rms_gradient > 0.0))
    throw ParameterError("rms_height",
                         "give exactly one of rms_height and rms_gradient (> 0) to normalise "
                         "the surface (got rms_height = " +
                             num(p.rms_height) + ", rms_gradient = " + num(p.rms_gradient) + ")");
}

Topography make_selfaffine(const Grid& g, const SelfAffineParams& p) {
  validate_grid(g);
  check_selfaffine(g, p);
  if (p.generator == "contmech") return make_selfaffine_contmech(g, p);
  const bool rolloff = p.lambda_rolloff != 0.0;
  const double expo = -1.0 - p.hurst;  // |h~| ∝ q^(-1-H)
  const double q_l = kTwoPi / p.lambda_long, q_s = kTwoPi / p.lambda_short;
  const double q_r = rolloff ? kTwoPi / p.lambda_rolloff : q_l;
  const double band_lo = q_l * (1.0 - 1e-12), band_hi = q_s * (1.0 + 1e-12), roll_lo = q_r * (1.0 - 1e-12);
  const double plateau = std::pow(q_l, expo);
  const double gamma = p.peklenik;
  auto amplitude = [&](int ikx, int iky) {
    const double qx = g.qx(ikx), qy = g.qy(iky);
    const double q =
        gamma == 1.0 ? std::sqrt(qx * qx + qy * qy) : std::sqrt(gamma * qx * qx + qy * qy / gamma);
    if (q >= band_lo && q <= band_hi) return std::pow(q, expo);
    if (rolloff && q >= roll_lo && q < band_lo) return plateau;
    return 0.0;
  };

  const int nxh = g.nxh();
  const std::size_t ns = g.spectral_size();
  const std::size_t first = static_cast<std::size_t>(g.y0) * nxh;
  // Phases: one uniform per half-spectrum mode of the whole cell, iky outer, ikx inner (the
  // documented order). A slab keeps its own rows' draws, and those of the two columns whose
  // modes pair with another row's (kx = 0 and nx/2, for the Hermitian symmetry below): every
  // process draws the whole sequence, at 8 bytes per mode of its rows.
  const int last_col = g.nx % 2 == 0 && g.nx / 2 > 0 ? g.nx / 2 : -1;
  std::vector<double> u(ns), u_first(static_cast<std::size_t>(g.ny)), u_last(static_cast<std::size_t>(g.ny));
  {
    Rng rng(p.seed);
    for (int iky = 0; iky < g.ny; ++iky)
      for (int ikx = 0; ikx < nxh; ++ikx) {
        const double v = rng.uniform();
        const std::size_t i = static_cast<std::size_t>(iky) * nxh + ikx;
        if (i >= first && i - first < ns) u[i - first] = v;
        if (ikx == 0) u_first[static_cast<std::size_t>(iky)] = v;
        if (ikx == last_col) u_last[static_cast<std::size_t>(iky)] = v;
      }
  }
  const auto mode = [&](int ikx, int iky, double phase) {
    const double a = amplitude(ikx, iky);
    const double phi = kTwoPi * phase;
    return a == 0.0 ? cplx(0.0, 0.0) : cplx(a * std::cos(phi), a * std::sin(phi));
  };

  FFT fft(g);
  SpecField spec = fft.spec_field();
  std::vector<double> in_band(static_cast<std::size_t>(g.rows()), 0.0);
  for_rows(g.rows(), [&](int row) {
    int count = 0;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t i = static_cast<std::size_t>(row) * nxh + ikx;
      spec[i] = mode(ikx, g.y0 + row, u[i]);
      count += amplitude(ikx, g.y0 + row) != 0.0;
    }
    in_band[static_cast<std::size_t>(row)] = count;
  });
  if (add_rows(g, std::move(in_band), 1)[0] == 0.0)
    throw InputError(
        "indenter.lambda_short",
        "no Fourier mode of the grid has a wavelength between lambda_short = " + num(p.lambda_short) +
            " and lambda_long = " + num(p.lambda_long) + "; widen the band");

  // Hermitian symmetry on the columns that hold both q and -q: kx = 0 and kx = nx/2.
  for (int col : {0, last_col}) {
    if (col < 0) continue;
    const std::vector<double>& uc = col == 0 ? u_first : u_last;
    for (int row = 0; row < g.rows(); ++row) {
      const int iky = g.y0 + row;
      const std::size_t i = static_cast<std::size_t>(row) * nxh + col;
      const int partner = (g.ny - iky) % g.ny;
      if (partner == iky) {  // self-conjugate: ky = 0 or ky = ny/2
        const double a = amplitude(col, iky);
        spec[i] = cplx(std::cos(kTwoPi * uc[static_cast<std::size_t>(iky)]) >= 0.0 ? a : -a, 0.0);
      } else if (g.ky(iky) < 0) {
        spec[i] = std::conj(mode(col, partner, uc[static_cast<std::size_t>(partner)]));
      }
    }
  }

  Topography t{g, RealField(g.local_size()), "selfaffine"};
  fft.backward(spec.data(), t.h.data());

  double factor = 1.0;
  if (p.rms_height > 0.0) {
    const double rms = real_rms(g, t.h, real_mean(g, t.h));
    factor = p.rms_height / rms;
  } else {
    const double grad = std::sqrt(spectral_moments(g, fft, t.h).grad2);
    factor = p.rms_gradient / grad;
  }
  scale_field(t.h, factor);
  return t;
}

// ---------------------------------------------------------------------------------------
// Statistics

TopographyStats statistics(const Topography& t) {
  const Grid& g = t.grid;
  if (g.nx < 1 || g.ny < 1 || t.h.size() != g.local_size())
    throw std::invalid_argument("statistics: the height field does not match the grid");
  TopographyStats s;
  s.mean = real_mean(g, t.h);
  s.rms_height = real_rms(g, t.h, s.mean);
  s.max = grid_max(
      g, [&](std::size_t i) { return t.h[i]; }, -std::numeric_limits<double>::infinity());
  s.min = -grid_max(
      g, [&](std::size_t i) { return -t.h[i]; }, -std::numeric_limits<double>::infinity());
  FFT fft(g);
  const SpectralMoments m = spectral_moments(g, fft, t.h);
  s.rms_gradient = std::sqrt(m.grad2);
  s.rms_curvature = std::sqrt(m.curv2);
  return s;
}

Topography read_topography(const std::string& path, double lx, double ly) {
  HeightMap m = read_height_map(path, lx, ly);
  Topography t;
  t.grid = Grid{m.nx, m.ny, m.lx, m.ly};
  t.h = std::move(m.h);
  t.kind = "file";
  return t;
}

}  // namespace gfmd
