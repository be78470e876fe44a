// Surface profiles of the rigid indenter (SPEC §3).
//
// Convention: h(r) is the height of the indenter surface measured TOWARDS the elastic
// body, i.e. a larger h protrudes further into the body (asperity peaks are maxima and
// touch first). The solver uses the initial gap g0(r) = max(h) - h(r).
// Fields are row-major with x fastest: h[iy * nx + ix] at x = ix*dx, y = iy*dy.
// Made on a slab grid (a distributed run, core/mpi.hpp) a topography holds the slab's rows
// only, and every process must make it (the self-affine surface and the statistics are
// collectives): the same heights as the rows of the whole map, bit for bit (the slabs'
// transforms have one process's bits, core/fft.hpp).
#pragma once

#include <cstdint>
#include <string>

#include "gfmd/core/fft.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd {

struct Topography {
  Grid grid;
  RealField h;       // grid.size() heights
  std::string kind;  // the indenter type that made it: "hertz", "flatpunch", ..., "file" or "array"
};

// Realised statistics. rms_height is about the mean. rms_gradient = sqrt(<|grad h|^2>) and
// rms_curvature = sqrt(<(lap h / 2)^2>) are computed spectrally from the FFT of h with
// the multipliers i*qx_deriv, i*qy_deriv of Grid (the Nyquist column/row derivative is
// dropped; the Laplacian is the divergence of that gradient, -(qx_deriv^2 + qy_deriv^2)).
struct TopographyStats {
  double mean = 0.0, rms_height = 0.0, rms_gradient = 0.0, rms_curvature = 0.0, min = 0.0, max = 0.0;
};

// Paraboloid (Hertz) with radii of curvature rx, ry > 0, apex on the node
// (nx/2, ny/2): h = -(x-xc)^2/(2 rx) - (y-yc)^2/(2 ry), xc = (nx/2)*dx, yc = (ny/2)*dy,
// computed from integer offsets so that h(xc+d) == h(xc-d) bit for bit. max(h) = 0.
// Throws ParameterError("radius_x"/"radius_y", ...) and ("grid", ...).
Topography make_hertz(const Grid& grid, double rx, double ry);

// Axisymmetric power law with elliptic contours, apex on the node (nx/2, ny/2) as make_hertz's:
// h = -r_e^n / (n R^(n-1)), r_e^2 = R ((x-xc)^2/rx + (y-yc)^2/ry), R = sqrt(rx ry): its slope is
// (r_e/R)^(n-1), so n = 2 is the paraboloid of make_hertz (to round-off) and R is where the slope
// reaches 1. Throws ParameterError("radius_x"/"radius_y", ...), ("exponent", ...) outside [1, 20].
Topography make_powerlaw(const Grid& grid, double rx, double ry, double exponent);

// A sphere of radius R, not its paraboloid: h = sqrt(R^2 - r^2) - R for r < R and -R outside
// (the equator's drop), apex on the node (nx/2, ny/2). Throws ParameterError("radius", ...).
Topography make_sphere(const Grid& grid, double radius);

// A cylinder of radius R lying along y (axis 'y') or x ('x') through the cell's centre line: the
// parabolic h = -(x-xc)^2/(2R) (a line contact, periodic along the axis). ParameterError("radius").
Topography make_cylinder(const Grid& grid, double radius, char axis);

// A straight step up and back down (a terrace): the strip |d| <= width/2 about the cell's centre
// node (d = x - xc for axis 'y', the strip lying along y; y - yc for 'x') has h = 0, the rest of
// the cell h = -depth. A periodic cell holds the two steps of the strip's edges; pressed onto a
// flat body, the strip is a periodic two-dimensional flat punch (Sadowsky's problem). Throws
// ParameterError("width", ...) when the strip or the lower terrace spans fewer than two grid
// spacings, ("depth", ...) for depth <= 0, ("axis", ...).
Topography make_step(const Grid& grid, double width, double depth, char axis);
// The checks of make_step on the parameters alone (the grid's size and spacing).
void check_step(const Grid& grid, double width, double depth, char axis);

// Adds a single-wavelength roughness a cos(2 pi d / lambda) to any surface, d = x - xc (axis 'x')
// or y - yc ('y') from the cell's centre node (so that a surface's apex there stays on a crest).
// lambda must divide the cell along the axis (relative tolerance 1e-9): ParameterError
// ("waviness_wavelength", ...); a > 0: ("waviness_amplitude", ...).
void add_waviness(Topography& t, double amplitude, double wavelength, char axis);

// Flat cylindrical punch of radius a, face on the node (nx/2, ny/2): h = 0 where
// (x-xc)^2 + (y-yc)^2 <= a^2 (offsets as make_hertz's), h = -depth elsewhere (the punch's
// side drops by depth, so the body meets only the face while its deflection outside stays
// below depth). max(h) = 0. Throws ParameterError("radius", ...) when a spans fewer than two
// grid spacings or the punch is wider than half the cell, ("depth", ...) for depth <= 0.
Topography make_flatpunch(const Grid& grid, double radius, double depth);
// The checks of make_flatpunch on the parameters alone (the grid's size and spacing).
void check_flatpunch(const Grid& grid, double radius, double depth);

// Egg-crate h = h0 [cos(2 pi x / lambda) + cos(2 pi y / lambda)], peaks (h = 2 h0) at the
// origin. lambda must divide lx and ly (relative tolerance 1e-9) so that the surface is
// periodic: ParameterError("wavelength", ...); h0 > 0: ("amplitude", ...).
// SPEC §3: h0 = lambda/(2 pi)^2 gives a peak radius of curvature R = lambda.
Topography make_eggcrate(const Grid& grid, double wavelength, double amplitude);

// Self-affine random surface, see make_selfaffine below.
struct SelfAffineParams {
  double hurst = 0.8;         // 0 < H < 1
  double lambda_long = 0.0;   // long-wavelength cut-off (<= min(lx, ly))
  double lambda_short = 0.0;  // short-wavelength cut-off (>= 2 * max(dx, dy))
  double rms_height = 0.0;    // exactly one of rms_height / rms_gradient must be > 0
  double rms_gradient = 0.0;
  double lambda_rolloff = 0.0;  // 0: none; else > lambda_long and <= max(lx, ly)
  // Peklenik number gamma (anisotropy): the spectrum of q_e = sqrt(gamma qx^2 + qy^2/gamma), so
  // that wavelengths along x are sqrt(gamma) times, along y 1/sqrt(gamma) times the isotropic
  // ones: gamma > 1 stretches the asperities along x (ratio of correlation lengths gamma, of
  // rms slopes along x and y 1/gamma). 1: isotropic (the same surface as without the key).
  double peklenik = 1.0;
  std::uint64_t seed = 0;
  // "gfmd" (ours, below) or "contmech": the paper authors' code's surface for their seed
  // (surface/contmech.hpp; no roll-off, seed <= 2^31 - 1).
  std::string generator = "gfmd";
};

// Spectrum: |h~(q)|^2 = C q^(-2-2H) for q_l <= |q| <= q_s (|q| read as q_e with a Peklenik number) (q_l = 2
// pi/lambda_long, q_s = 2 pi/lambda_short); with a roll-off (lambda_rolloff > 0, q_r = 2 pi/lambda_rolloff)
// the modes with q_r <= |q| < q_l get the plateau value C q_l^(-2-2H); every other mode,
// q = 0 included, is zero. Band edges are inclusive with a relative tolerance of 1e-12
// (so that modes exactly on a cut-off are kept independently of rounding).
//
// Phases: h~(q) = A(q) exp(2 pi i U). One U = Rng(seed).uniform() is drawn for EVERY mode
// of the r2c half spectrum, in the order iky = 0..ny-1 (outer), ikx = 0..nx/2 (inner),
// whether or not the mode is in the band, so that the phase of a mode does not depend
// on the band parameters. Hermitian symmetry is then imposed on the kx = 0 and (nx even)
// kx = nx/2 columns: for ky < 0 the entry is the conjugate of the ky > 0 entry (those
// draws are unused), and self-conjugate modes (ky = 0 or ky = ny/2) are set to
// A * sign(cos(2 pi U)) (real, same magnitude). The field is synthesised with
// FFT::backward and rescaled once so that its realised rms height (about the mean, in
// real space) equals rms_height, or, if rms_gradient > 0 instead, so that its realised
// spectral rms gradient (as in statistics()) equals rms_gradient.
// The result does not depend on the number of threads. On a slab every process draws the
// whole phase sequence (time: the whole half spectrum) and keeps its rows' phases (memory:
// its rows only) plus the two symmetric columns'.
// Throws ParameterError naming hurst, lambda_long, lambda_short
// (also when 2 * grid spacing > lambda_short: the grid is too coarse),
// lambda_rolloff, rms_height (not exactly one of rms_height /
// rms_gradient > 0; a negative rms_gradient names rms_gradient), grid, generator (not one of
// gfmd, contmech), and for contmech lambda_rolloff (none) and seed (above 2^31 - 1).
// generator = "contmech" hands over to make_selfaffine_contmech (surface/contmech.hpp).
Topography make_selfaffine(const Grid& grid, const SelfAffineParams& params);
// The checks make_selfaffine makes of its parameters on a grid (ParameterError naming the
// parameter), without making the surface: case files are checked with them when read.
void check_selfaffine(const Grid& grid, const SelfAffineParams& params);

// Realised statistics (see TopographyStats). Throws std::invalid_argument if h does not
// match the grid.
TopographyStats statistics(const Topography& topo);

// Reads a height map file as a topography (kind "file"): see read_height_map in
// io/height_map.hpp for the formats, the size rules and the errors.
Topography read_topography(const std::string& path, double lx, double ly);

}  // namespace gfmd
