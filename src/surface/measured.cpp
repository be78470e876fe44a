// Measured topographies: units, crop, detrend, missing points, periodicity, resampling.
// See include/gfmd/surface/measured.hpp.
#include "gfmd/surface/measured.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/io/height_map.hpp"

namespace gfmd {

namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::size_t at(int nx, int ix, int iy) { return static_cast<std::size_t>(iy) * nx + ix; }

// Least-squares plane a + b x + c y over the valid (non-NaN) points; x, y in cell units.
void fit_plane(const Grid& g, const RealField& h, double& a, double& b, double& c) {
  double s[3][3] = {}, r[3] = {};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double v = h[at(g.nx, ix, iy)];
      if (std::isnan(v)) continue;
      const double f[3] = {1.0, g.x(ix), g.y(iy)};
      for (int i = 0; i < 3; ++i) {
        r[i] += f[i] * v;
        for (int j = 0; j < 3; ++j) s[i][j] += f[i] * f[j];
      }
    }
  // Solve the 3x3 normal equations (Cramer's rule; the matrix is well conditioned for
  // maps of 2 x 2 points or more).
  const auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det3(s);
  double out[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    double m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = j == k ? r[i] : s[i][j];
    out[k] = d != 0.0 ? det3(m) / d : 0.0;
  }
  if (d == 0.0) out[0] = s[0][0] > 0 ? r[0] / s[0][0] : 0.0;  // a line or a point: the mean only
  a = out[0];
  b = out[1];
  c = out[2];
}

// Harmonic (Laplace) fill of the NaN points from their valid neighbours inside the map
// (not across its edges): successive over-relaxation until the largest change is below
// 1e-12 of the height range. Returns the sweeps used.
int harmonic_fill(const std::string& path, const Grid& g, RealField& h, double mean, double range) {
  std::vector<std::size_t> holes;
  for (std::size_t i = 0; i < h.size(); ++i)
    if (std::isnan(h[i])) {
      holes.push_back(i);
      h[i] = mean;
    }
  const double tol = 1e-12 * std::max(range, std::numeric_limits<double>::min());
  // Over-relaxation near its optimum 2 / (1 + pi / w) for holes of width w ~ sqrt(count):
  // sweeps grow like w, not w^2.
  const double w = std::max(2.0, std::sqrt(static_cast<double>(holes.size())));
  const double omega = 2.0 / (1.0 + std::numbers::pi / w);
  const int max_sweeps = 100000;
  for (int sweep = 1; sweep <= max_sweeps; ++sweep) {
    double change = 0.0;
    for (const std::size_t i : holes) {
      const int ix = static_cast<int>(i % g.nx), iy = static_cast<int>(i / g.nx);
      double sum = 0.0;
      int n = 0;
      if (ix > 0) sum += h[i - 1], ++n;
      if (ix + 1 < g.nx) sum += h[i + 1], ++n;
      if (iy > 0) sum += h[i - g.nx], ++n;
      if (iy + 1 < g.ny) sum += h[i + g.nx], ++n;
      const double next = h[i] + omega * (sum / n - h[i]);
      change = std::max(change, std::abs(next - h[i]));
      h[i] = next;
    }
    if (change <= tol) return sweep;
  }
  throw InputError(path,
                   "the harmonic fill of " + std::to_string(holes.size()) +
                       " missing points did not converge in 100000 sweeps; use indenter.missing = \"mean\"");
}

// Root mean square jump across the cell's edges (last column to first, last row to first).
double edge_jump(const Grid& g, const RealField& h) {
  double s = 0.0;
  for (int iy = 0; iy < g.ny; ++iy) s += std::pow(h[at(g.nx, g.nx - 1, iy)] - h[at(g.nx, 0, iy)], 2);
  for (int ix = 0; ix < g.nx; ++ix) s += std::pow(h[at(g.nx, ix, g.ny - 1)] - h[at(g.nx, ix, 0)], 2);
  return std::sqrt(s / (g.nx + g.ny));
}

// Fourier interpolation / truncation of a periodic field onto another grid of the same size.
RealField resample(const Grid& from, const RealField& h, const Grid& to) {
  const FFT f_from(from), f_to(to);
  SpecField src = f_from.spec_field();
  f_from.forward(h.data(), src.data());
  SpecField dst = f_to.spec_field();
  const double scale = static_cast<double>(to.size()) / static_cast<double>(from.size());
  for (int iky = 0; iky < to.ny; ++iky)
    for (int ikx = 0; ikx < to.nxh(); ++ikx) {
      const int kx = to.kx(ikx), ky = to.ky(iky);
      double factor = scale;
      // A mode on the target's Nyquist line when the target is coarser: dropped (it would
      // alias the +k and -k modes of the source into one real mode).
      if ((to.nx % 2 == 0 && kx == to.nx / 2 && to.nx < from.nx) ||
          (to.ny % 2 == 0 && std::abs(ky) == to.ny / 2 && to.ny < from.ny)) {
        dst[static_cast<std::size_t>(iky) * to.nxh() + ikx] = 0.0;
        continue;
      }
      if (kx > from.nx / 2 || std::abs(ky) > from.ny / 2) {
        dst[static_cast<std::size_t>(iky) * to.nxh() + ikx] = 0.0;
        continue;
      }
      // The source's Nyquist mode split between +k and -k when the target is finer.
      if (from.nx % 2 == 0 && kx == from.nx / 2 && to.nx > from.nx) factor *= 0.5;
      if (from.ny % 2 == 0 && std::abs(ky) == from.ny / 2 && to.ny > from.ny) factor *= 0.5;
      const int sky = ky >= 0 ? ky : ky + from.ny;
      dst[static_cast<std::size_t>(iky) * to.nxh() + ikx] =
          src[static_cast<std::size_t>(sky) * from.nxh() + kx] * factor;
    }
  RealField out(to.size());
  f_to.backward(dst.data(), out.data());
  return out;
}

// statistics() of a field held here: lent to a Topography and taken back, not copied.
TopographyStats stats_of(const Grid& g, RealField& h) {
  Topography t{g, std::move(h), "file"};
  const TopographyStats s = statistics(t);
  h = std::move(t.h);
  return s;
}

void check_choice(const char* name, const std::string& v, const std::vector<std::string>& allowed) {
  if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return;
  throw ParameterError(name, "must be \"" + allowed[0] + "\", \"" + allowed[1] + "\" or \"" + allowed[2] +
                                 "\" (got \"" + v + "\")");
}

}  // namespace

Topography load_height_map(const std::string& path, const MapOptions& o, MapReport* report) {
  check_choice("missing", o.missing, kMissingMethods);
  check_choice("detrend", o.detrend, kDetrendMethods);
  check_choice("periodize", o.periodize, kPeriodizeMethods);
  for (const auto& [key, u] : {std::pair{"unit", o.file_unit}, std::pair{"case_unit", o.case_unit}})
    if (!u.empty() && metres_per_unit(u) == 0.0)
      throw ParameterError(key, "unknown length unit \"" + u + "\" (m, mm, um, nm, pm or A)");

  HeightMap m = read_height_file(path);
  MapReport rep;
  rep.path = path;
  rep.format = m.format;
  rep.file_nx = m.nx;
  rep.file_ny = m.ny;

  // Units.
  if (!m.unit.empty()) {
    if (!o.file_unit.empty())
      throw ParameterError("unit", "the " + m.format +
                                       " file states its units; indenter.unit is only for files "
                                       "that state none (remove it)");
    rep.file_unit = "m";
    rep.case_unit = o.case_unit.empty() ? "m" : o.case_unit;
    rep.unit_factor = 1.0 / metres_per_unit(rep.case_unit);
  } else if (!o.file_unit.empty()) {
    rep.file_unit = o.file_unit;
    rep.case_unit = o.case_unit.empty() ? o.file_unit : o.case_unit;
    rep.unit_factor = metres_per_unit(o.file_unit) / metres_per_unit(rep.case_unit);
  } else if (!o.case_unit.empty()) {
    throw InputError(
        path, "the " + m.format + " file states no unit, and the case's lengths are in " + o.case_unit +
                  ": say what the file's numbers are with indenter.unit = \"um\" (or nm, m, ...)");
  }
  if (rep.unit_factor != 1.0) {
    for (double& v : m.h) v *= rep.unit_factor;
    m.lx *= rep.unit_factor;
    m.ly *= rep.unit_factor;
  }
  rep.file_lx = m.lx;
  rep.file_ly = m.ly;

  // Crop (in the file's points).
  Grid g{m.nx, m.ny, 0.0, 0.0};
  RealField h = std::move(m.h);
  rep.crop = o.crop;
  if (o.crop[2] > 0 || o.crop[3] > 0) {
    const auto [x0, y0, cx, cy] = o.crop;
    if (x0 < 0 || y0 < 0 || cx < 2 || cy < 2 || cx > m.nx || cy > m.ny || x0 > m.nx - cx || y0 > m.ny - cy)
      throw ParameterError("crop", "[ix0, iy0, nx, ny] = [" + std::to_string(x0) + ", " + std::to_string(y0) +
                                       ", " + std::to_string(cx) + ", " + std::to_string(cy) +
                                       "] does not lie inside the map of " + std::to_string(m.nx) + " x " +
                                       std::to_string(m.ny) + " points (nx, ny >= 2)");
    RealField c(static_cast<std::size_t>(cx * cy));
    for (long long iy = 0; iy < cy; ++iy)
      for (long long ix = 0; ix < cx; ++ix)
        c[static_cast<std::size_t>(iy * cx + ix)] =
            h[at(m.nx, static_cast<int>(x0 + ix), static_cast<int>(y0 + iy))];
    m.lx *= static_cast<double>(cx) / m.nx;
    m.ly *= static_cast<double>(cy) / m.ny;
    g.nx = static_cast<int>(cx);
    g.ny = static_cast<int>(cy);
    h = std::move(c);
  }
  // Size: the caller's wins, else the file's; one side known gives the other by square
  // pixels (ly = lx ny / nx).
  g.lx = o.lx > 0 ? o.lx : m.lx;
  g.ly = o.ly > 0 ? o.ly : m.ly;
  // A size given over the one the file states stretches the map: said, since the measured
  // slopes (and so the contact) change with it.
  for (const auto& [name, given, stated] : {std::tuple{"lx", o.lx, m.lx}, std::tuple{"ly", o.ly, m.ly}})
    if (given > 0 && stated > 0 && std::abs(given / stated - 1.0) > 1e-9) {
      std::ostringstream w;
      w.precision(6);
      w << "the case's grid." << name << " (" << given << " for the map) replaces the " << stated
        << " the file states: the map is stretched " << given / stated << " times along " << name[1]
        << ", and its slopes with it";
      rep.warnings.push_back(w.str());
    }
  if (!(g.ly > 0) && g.lx > 0) g.ly = g.lx * g.ny / g.nx;
  if (!(g.lx > 0) && g.ly > 0) g.lx = g.ly * g.nx / g.ny;
  for (const auto& [name, v] : {std::pair{"lx", g.lx}, std::pair{"ly", g.ly}})
    if (!(v > 0) || !std::isfinite(v))
      throw InputError(
          path, std::string("no physical size ") + name + ": the " + m.format + " file gives none" +
                    (m.format == "text" ? " (no '# lx = <value>' or '# ly = <value>' header line)" : "") +
                    "; give grid.lx (ly = lx ny/nx for square pixels unless given)");

  // Missing points and detrending, over the valid points.
  std::size_t missing = 0;
  std::string first = m.first_missing;
  if (o.crop[2] > 0 || o.crop[3] > 0) {  // the first missing point inside the crop, in the file's indices
    first.clear();
    for (std::size_t i = 0; i < h.size() && first.empty(); ++i)
      if (std::isnan(h[i]))
        first = "(iy, ix) = (" + std::to_string(o.crop[1] + static_cast<long long>(i) / g.nx) + ", " +
                std::to_string(o.crop[0] + static_cast<long long>(i) % g.nx) + ") of the file";
  }
  for (const double v : h) missing += std::isnan(v) ? 1 : 0;
  rep.missing = o.missing;
  rep.missing_points = missing;
  if (missing == h.size()) throw InputError(path, "every point of the map is missing");
  if (missing > 0 && o.missing == "error") throw InputError(path, missing_points_message(missing, first));
  rep.detrend = o.detrend;
  if (o.detrend != "none") {
    double a = 0, b = 0, c = 0;
    fit_plane(g, h, a, b, c);
    if (o.detrend == "mean") {
      double s = 0.0;
      for (const double v : h)
        if (!std::isnan(v)) s += v;
      a = s / static_cast<double>(h.size() - missing);
      b = c = 0.0;
    }
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) h[at(g.nx, ix, iy)] -= a + b * g.x(ix) + c * g.y(iy);
    rep.removed_mean = a;
    rep.removed_slope_x = b;
    rep.removed_slope_y = c;
  }
  if (missing > 0) {
    double s = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const double v : h)
      if (!std::isnan(v)) s += v, lo = std::min(lo, v), hi = std::max(hi, v);
    const double mean = s / static_cast<double>(h.size() - missing);
    if (o.missing == "mean") {
      for (double& v : h)
        if (std::isnan(v)) v = mean;
    } else {
      rep.fill_iterations = harmonic_fill(path, g, h, mean, hi - lo);
    }
  }

  // Periodicity.
  const TopographyStats before = stats_of(g, h);
  rep.edge_mismatch = before.rms_height > 0 ? edge_jump(g, h) / before.rms_height : 0.0;
  rep.periodize = o.periodize;
  if (o.periodize == "mirror" || o.periodize == "pad") {
    if (2LL * g.nx > 65536 || 2LL * g.ny > 65536)
      throw ParameterError("periodize", "the doubled map (" + std::to_string(2 * g.nx) + " x " +
                                            std::to_string(2 * g.ny) +
                                            ") exceeds 65536 points per side; crop the map first");
    Grid d{2 * g.nx, 2 * g.ny, 2 * g.lx, 2 * g.ly};
    RealField p(d.size());
    if (4LL * g.nx * g.ny > (1LL << 28))
      throw ParameterError("periodize", "the doubled map (" + std::to_string(2 * g.nx) + " x " +
                                            std::to_string(2 * g.ny) +
                                            ") exceeds 2^28 points; crop the map first");
    // Far below the map (ten height ranges): the run checks that it never touches.
    const double floor_value = before.min - 10.0 * (before.max - before.min);
    for (int iy = 0; iy < d.ny; ++iy)
      for (int ix = 0; ix < d.nx; ++ix) {
        const int sx = ix < g.nx ? ix : 2 * g.nx - 1 - ix, sy = iy < g.ny ? iy : 2 * g.ny - 1 - iy;
        const bool inside = ix < g.nx && iy < g.ny;
        p[at(d.nx, ix, iy)] = o.periodize == "mirror" || inside ? h[at(g.nx, sx, sy)] : floor_value;
      }
    if (o.periodize == "pad") rep.map_area_fraction = 0.25;
    g = d;
    h = std::move(p);
  } else if (rep.edge_mismatch > 0.5) {
    rep.warnings.push_back(
        "the map is not periodic: its opposite edges differ by " + num(rep.edge_mismatch) +
        " rms heights, and the solver repeats it periodically; consider indenter.periodize = "
        "\"mirror\" or \"pad\"");
  }
  rep.map_nx = g.nx;
  rep.map_ny = g.ny;

  // Resampling onto the solver's grid.
  const int nx = o.nx > 0 ? o.nx : g.nx, ny = o.ny > 0 ? o.ny : g.ny;
  if (nx != g.nx || ny != g.ny) {
    const Grid to{nx, ny, g.lx, g.ly};
    RealField r = resample(g, h, to);
    if (nx < g.nx || ny < g.ny) {
      const double g2 = std::pow(stats_of(g, h).rms_gradient, 2);
      const double r2 = std::pow(stats_of(to, r).rms_gradient, 2);
      rep.lost_gradient_fraction = g2 > 0 ? std::max(0.0, 1.0 - r2 / g2) : 0.0;
      if (rep.lost_gradient_fraction > 0.01)
        rep.warnings.push_back("resampling " + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                               " onto " + std::to_string(nx) + " x " + std::to_string(ny) +
                               " drops the wavelengths below " + num(2 * std::max(to.dx(), to.dy())) +
                               ", which carry " + num(100 * rep.lost_gradient_fraction) +
                               " % of the squared rms gradient");
    }
    g = to;
    h = std::move(r);
  }
  rep.grid_nx = g.nx;
  rep.grid_ny = g.ny;
  if (report) *report = rep;
  return Topography{g, std::move(h), "file"};
}

}  // namespace gfmd
