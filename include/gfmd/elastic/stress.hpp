// Stresses in the elastic body (SPEC §5): the full tensor at the surface from a solved
// state, its principal stresses and von Mises stress, the post-analysis reference of
// the paper (frictionless pressure plus mu p of uniform slip), and the exact stress and
// displacement on a plane below the surface (half-space or layer on a rigid base).
//
// Conventions (SPEC §1): z points out of the body towards the indenter; tensile stress
// is positive; the surface traction on the body is t = (tx, ty, -p), i.e.
// sigma_xz = tx, sigma_yz = ty, sigma_zz = -p at the surface. Fourier modes exp(+i q.r).
#pragma once

#include <array>

#include "gfmd/core/fft.hpp"
#include "gfmd/core/fields.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/elastic/elastic.hpp"

namespace gfmd {

// The six independent components of the symmetric stress tensor on the grid.
struct StressField {
  RealField xx, yy, zz, xy, xz, yz;
};

// Principal stresses s1 >= s2 >= s3 (s1 = sigma_I, the most tensile), the unit
// eigenvector of s1 (sign fixed so that its largest-magnitude component is positive; for
// a tensor with s1 = s2 = s3 it is (1, 0, 0)) and the von Mises stress
// sqrt(((s1-s2)^2 + (s2-s3)^2 + (s3-s1)^2)/2).
struct PrincipalField {
  RealField s1, s2, s3;
  RealField e1x, e1y, e1z;
  RealField von_mises;
};

// Displacements on a plane inside the body.
struct DisplacementField {
  RealField ux, uy, uz;
};

// Surface stress of a solved state. sigma_xz, sigma_yz, sigma_zz are the tractions; the
// in-plane components follow from the surface strains eps_ab = (d_a u_b + d_b u_a)/2
// (spectral derivatives of f.ux, f.uy, Nyquist derivative dropped as Grid::qx_deriv)
// through Hooke's law with sigma_zz known:
//   sigma_xx = E* (eps_xx + nu eps_yy) + nu/(1-nu) sigma_zz,  (E* = 2G/(1-nu))
//   sigma_yy = E* (eps_yy + nu eps_xx) + nu/(1-nu) sigma_zz,   sigma_xy = 2 G eps_xy.
// f.tx / f.ty may be empty (frictionless). The q = 0 in-plane strain is zero (periodic
// displacements), so the mean in-plane stress is nu/(1-nu) times the mean sigma_zz.
StressField surface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f);

// The surface stress the tractions of f (tx, ty may be empty; -pressure) cause on the body `el`
// describes, through its own elastic displacement recomputed from them (f's displacements are
// not read): for states whose displacement is not the body's own elastic one, a viscoelastic body
// in motion (each mode's E(omega) times its displacement is E0 times the elastic one, nu
// constant) and a body rolling under an elastic indenter (f's in-plane displacement is the pair's).
// A layered viscoelastic body in motion (`visco`, its top layer the viscoelastic one): its own
// displacement from the tractions through its complex response, and the strains of each mode
// times E(omega)/E0 of the top layer in Hooke's law.
StressField traction_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                            const ViscoelasticParams& visco = {});

// The tractions of uniform slip on a frictionless solution: its pressure p and mu p e_s in-plane,
// e_s = (cos a, sin a) (a = angle_deg): what both post-analyses add to it.
ContactFields uniform_slip_tractions(const RealField& pressure, double mu, double angle_deg);

// Consistent post-analysis reference ("consistent"): the given (frictionless) pressure p plus the
// traction mu p e_s of uniform slip on the body, e_s = (cos a, sin a) the sliding
// direction of the indenter (a = angle_deg); the displacements are recomputed from
// (mu p e_s, -p) with the body's compliance (its coupling setting included), then the
// stress is surface_stress of that state.
StressField post_analysis_stress(const FFT& fft, const ElasticBody& body, const RealField& pressure,
                                 double mu, double angle_deg);

// The paper's post-analysis (Fig. 3a,c; "paper" in [stress] post_analysis): the frictionless
// solution as it is -- its pressure p and in-plane displacements ux, uy -- with the
// friction only written into the shear tractions, sigma_az = mu p e_s (sigma_zz = -p); the
// in-plane stresses are those of the frictionless strains (Hooke's law as surface_stress).
// No in-plane strain is caused by the added friction. `frictionless` needs pressure, ux, uy.
StressField paper_post_analysis_stress(const FFT& fft, const ElasticParams& el,
                                       const ContactFields& frictionless, double mu, double angle_deg);

// Eigen-decomposition of one symmetric 3x3 tensor in closed form: the best-separated
// eigenvalue by the trigonometric formula and its eigenvector from cross products of the
// rows of A - lambda I, the other two from the exact 2x2 problem orthogonal to it (robust
// for repeated and nearly repeated eigenvalues; errors ~ eps * max|A_ij|).
struct Principal3 {
  double s1, s2, s3;         // s1 >= s2 >= s3
  std::array<double, 3> e1;  // unit eigenvector of s1 (sign as in PrincipalField)
};
Principal3 principal(double xx, double yy, double zz, double xy, double xz, double yz);
double von_mises(double xx, double yy, double zz, double xy, double xz, double yz);

// All: every member of PrincipalField. SummaryOnly: s1 and von_mises only (what
// summarize reads), the other members left empty.
enum class PrincipalParts { All, SummaryOnly };
PrincipalField principal(const StressField& s, PrincipalParts parts = PrincipalParts::All);

struct StressSummary {
  double max_tensile_stress = 0;  // max of s1 over the grid
  int max_tensile_ix = 0, max_tensile_iy = 0;
  double max_von_mises = 0;
  int max_von_mises_ix = 0, max_von_mises_iy = 0;
  // Fraction of all cells with s1 >= high_tension_fraction_of * max_tensile_stress
  // (0 when max_tensile_stress <= 0, i.e. no tension anywhere).
  double high_tension_area_fraction = 0;
  double high_tension_fraction_of = 0;  // the threshold fraction used
};
StressSummary summarize(const Grid& g, const PrincipalField& p, double high_tension_fraction = 0.9);

// ---- Below the surface -----------------------------------------------------------------
//
// Response at depth d of one surface-traction mode exp(i q x1) with wave number q >= 0,
// in the frame where q points along axis 1 (1: along q, 2: across, 3 = z), for the body
// of `el` (half-space, or layer of thickness h bonded to a rigid base; the real coupled
// body whatever el.coupling says):
//   sigma'_c(d) = sum_k stress[c][k] t'_k,  c = 11, 22, 33, 12, 13, 23 (order of StressField),
//   u'_i(d)     = sum_k disp[i][k] t'_k,   i, k = 1, 2, 3.
// At d = 0, disp is the body's compliance (SPEC §2, including the coupling sign); q = 0 is
// the uniform state (sigma_11 = sigma_22 = nu/(1-nu) t3, uniaxial strain) with displacement
// z t/G in-plane and z (1-2nu)/((1-nu)^2 E*) t3 normal, z = h - d for a layer (zero on the
// base) and z = -d for the half-space (zero at the surface, as ElasticBody pins it).
struct ModeResponse {
  std::array<std::array<cplx, 3>, 6> stress{};
  std::array<std::array<cplx, 3>, 3> disp{};
};
ModeResponse mode_response(double q, double depth, const ElasticParams& el);

// Full stress tensor / displacement on the plane at depth `depth` >= 0 below the surface
// (depth <= h for a layer) caused by the surface tractions (f.tx, f.ty, -f.pressure);
// f.tx / f.ty may be empty. At depth 0 the stress equals surface_stress except on the
// Nyquist lines (there the odd parts of the response are dropped, as in ElasticBody,
// instead of the derivative), and the displacement equals ElasticBody::displacement.
// Throws ParameterError("depth") for a depth outside the body.
// With `visco` moving a layered body (its top layer viscoelastic) each mode's response is the
// transfer matrices' at that mode's E(omega); a homogeneous body's stresses from tractions do not
// depend on E (nu constant), so there `visco` changes nothing.
StressField subsurface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f, double depth,
                              const ViscoelasticParams& visco = {});
DisplacementField subsurface_displacement(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                                          double depth);

}  // namespace gfmd
