// Elastic response of an isotropic body of thickness h (h = inf: half-space; finite h:
// bonded to a rigid base) to surface tractions: the 3x3 Green's tensor of SPEC §2.
//
// Stiffness: t~_a(q) = q E* Phi_ab(q) u~_b(q) is the traction that must act on the
// surface to hold displacement u. Compliance: u~ = C(q) t~ with C = (q E* Phi)^-1.
// z points out of the body; a pressure p pushing on the body is t_z = -p.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "gfmd/core/fft.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/elastic/viscoelastic.hpp"

namespace gfmd {

// A layer bonded below the top one (a layered body, layered.hpp).
struct ElasticLayer {
  double contact_modulus = 1.0;  // E* of the layer
  double poisson = 0.25;
  double thickness = 1.0;
};

struct ElasticParams {
  double contact_modulus = 1.0;                                // E* = E/(1-nu^2)
  double poisson = 0.25;                                       // nu in (-1, 0.5]
  double thickness = std::numeric_limits<double>::infinity();  // h
  // false: the uncoupled reference. The cross-compliance (normal displacement from
  // tangential traction and in-plane displacement from pressure) is dropped; the direct
  // compliances stay those of the real body, so frictionless results do not change.
  bool coupling = true;
  // Beneath the top layer (finite thickness): further bonded layers, top to bottom, and what
  // the lowest one is bonded to: a rigid base (substrate_contact_modulus = inf, the default)
  // or an elastic half-space (a coating on a substrate).
  std::vector<ElasticLayer> layers;
  double substrate_contact_modulus = std::numeric_limits<double>::infinity();
  double substrate_poisson = 0.25;

  [[nodiscard]] bool half_space() const { return thickness == std::numeric_limits<double>::infinity(); }
  [[nodiscard]] bool on_substrate() const {
    return substrate_contact_modulus != std::numeric_limits<double>::infinity();
  }
  // More than one material, or a layer on an elastic substrate (layered.hpp).
  [[nodiscard]] bool layered() const { return on_substrate() || !layers.empty(); }
  // How deep the body reaches: the layers' total thickness above a rigid base, inf on a substrate
  // or for a half-space.
  [[nodiscard]] double depth_of_base() const {
    if (on_substrate()) return std::numeric_limits<double>::infinity();
    double d = thickness;
    for (const ElasticLayer& l : layers) d += l.thickness;
    return d;
  }
  [[nodiscard]] double shear_modulus() const { return contact_modulus * (1.0 - poisson) / 2.0; }
  // Throws ParameterError naming poisson / thickness / contact_modulus, the substrate's keys
  // or layers[i].<key>.
  void validate() const;
};

// A homogeneous body (a half-space or a layer on a rigid base) from its four numbers.
inline ElasticParams homogeneous_body(double contact_modulus, double poisson,
                                      double thickness = std::numeric_limits<double>::infinity(),
                                      bool coupling = true) {
  ElasticParams e;
  e.contact_modulus = contact_modulus;
  e.poisson = poisson;
  e.thickness = thickness;
  e.coupling = coupling;
  return e;
}

// The relaxed modulus E0 of the part of `e` that `v` makes viscoelastic (its top layer's, a
// layer's or its substrate's).
[[nodiscard]] inline double relaxed_modulus(const ElasticParams& e, const ViscoelasticParams& v) {
  if (v.part == ViscoelasticParams::Part::Substrate) return e.substrate_contact_modulus;
  if (v.part == ViscoelasticParams::Part::Layer && v.layer >= 0 &&
      static_cast<std::size_t>(v.layer) < e.layers.size())
    return e.layers[static_cast<std::size_t>(v.layer)].contact_modulus;
  return e.contact_modulus;
}

// Dimensionless Phi in the frame where q points along axis 1 (SPEC §2):
// Phi'11 = p11, Phi'22 = p22, Phi'33 = p33, Phi'13 = i*p13, Phi'31 = -i*p13.
struct PhiRotated {
  double p11, p22, p33, p13;
};

// qh = |q| h; qh = inf gives the half-space values. Stable for qh in [1e-8, inf).
PhiRotated phi_rotated(double qh, double nu);

// How (e.grad) is discretised in the slip velocity v = xi e + (e.grad) u of steady sliding
// and rolling (docs/solver.md, "The slip derivative"). Spectral: i e.q, exact for every
// resolved mode (the Nyquist modes dropped); it makes the slip operator skew-adjoint.
// Upwind: a one-sided difference against the material's motion, as rolling-contact codes
// use, written as band-limited shifts by h along e (theta = (e.q) h, h the cell size along
// e): first order (e^{i theta} - 1)/h, second order -(3 - 4 e^{i theta} + e^{2i theta})/(2h).
// Their real part is <= 0, so the slip operator gains a dissipative part that fixes the
// tractions of a stick zone, which the spectral derivative leaves nearly free.
enum class SlipDerivative { Spectral, Upwind, Upwind2 };
[[nodiscard]] const char* slip_derivative_name(SlipDerivative d);

// Per-mode compliance of the body on the r2c half spectrum, in lab axes.
// u~ = C t~ with C Hermitian: C_xx, C_yy, C_xy, C_zz real; C_xz = i*cxz, C_yz = i*cyz.
struct ComplianceMode {
  double cxx, cyy, cxy, czz, cxz, cyz;
};

// A mode's response when it is complex and not Hermitian (a viscoelastic body in steady
// sliding, alone or under an elastic indenter): the entries mean what ComplianceMode's do,
// u_x = cxx t_x + cxy t_y + i cxz t_z, u_z = -i cxz t_x - i cyz t_y + czz t_z, each complex.
struct ResponseMode {
  cplx cxx, cyy, cxy, czz, cxz, cyz;
};

// The symbol D(q) of (e.grad) at mode (ikx, iky) (iky global) of the r2c half spectrum. On
// the Nyquist lines of an even grid an upwind symbol is the mean over the aliases of the
// mode (+-q there are one mode), so that real fields stay real.
[[nodiscard]] cplx slip_derivative_symbol(const Grid& g, int ikx, int iky, double ex, double ey,
                                          SlipDerivative deriv);

class ElasticBody {
 public:
  // With `visco` enabled a viscoelastic body in steady sliding (viscoelastic.hpp):
  // params.contact_modulus is then its relaxed modulus E0. Throws ParameterError naming the
  // key (ElasticParams::validate, ViscoelasticParams::validate).
  //
  // With `indenter` the indenter is elastic too (two deformable bodies; either may be a layer
  // or layered). The gap sees the relative displacement u_body - u_indenter: modes(), the mean
  // compliances, compliance(), stiffness() and displacement()'s uz are the pair's, the two
  // bodies' compliances added with the indenter's coupling subtracted (its surface faces the
  // other way: Dundurs' beta is their difference). The slip of steady sliding is the body's own
  // surface velocity, since the indenter's material rests in the contact: displacement()'s
  // ux, uy, inplane_slope, slip_resolvent and slip_operator_norm are the body's own; in rolling
  // (roll_both) they are the pair's.
  ElasticBody(const Grid& grid, const ElasticParams& params, const ViscoelasticParams& visco = {},
              const ElasticParams* indenter = nullptr);

  [[nodiscard]] const Grid& grid() const { return grid_; }
  [[nodiscard]] const ElasticParams& params() const { return params_; }
  [[nodiscard]] bool elastic_indenter() const { return indenter_.has_value(); }
  // Two bodies rolling (friction.creepage): the material of both passes through the contact, so
  // the slip is their relative surface velocity, and displacement()'s ux, uy and the slip's
  // operators use the pair's compliance (the in-plane terms of both added; Kalker's combined
  // modulus) instead of the body's own. No effect under a rigid indenter. Call before a solver
  // is built on the body.
  void roll_both(bool both) { roll_both_ = both; }
  [[nodiscard]] const ComplianceMode& mode(std::size_t k) const { return modes_[k]; }
  [[nodiscard]] const std::vector<ComplianceMode>& modes() const { return modes_; }

  // Compliance of the q = 0 mode: zero for a half-space (the mean in-plane displacement
  // is pinned; the mean normal displacement is set by the load or the approach),
  // h(1-2nu)/((1-nu)^2 E*) normal and h/G in-plane for a layer.
  [[nodiscard]] double mean_normal_compliance() const { return c0_zz_; }
  [[nodiscard]] double mean_inplane_compliance() const { return c0_t_; }

  // Full 3x3 lab-frame stiffness q E* Phi at a mode (row-major, complex) for tests.
  [[nodiscard]] std::array<cplx, 9> stiffness(int ikx, int iky) const;
  [[nodiscard]] std::array<cplx, 9> compliance(int ikx, int iky) const;

  // A viscoelastic body's response per mode: the body's own compliance (made with the relaxed
  // modulus) times response(k) = E0/E(omega(q)) (a layered body, whose top layer is the
  // viscoelastic one: its transfer matrices with E(omega) there); under an elastic indenter the indenter's
  // part (elastic: its material rests in the contact) is added to that. displacement(), inplane_slope(),
  // slip_resolvent() and slip_operator_norm() include it: a caller sees one complex, non-Hermitian response
  // per mode. Stresses from given tractions do not depend on E with nu constant: the elastic calls give them.
  // An elastic body has no factors (viscoelastic() false); at rest (visco().velocity = 0) every factor is 1
  // and the elastic arithmetic is used.
  [[nodiscard]] bool viscoelastic() const { return !response_.empty(); }
  [[nodiscard]] const ViscoelasticParams& visco() const { return visco_; }
  [[nodiscard]] cplx response(std::size_t k) const { return response_.empty() ? cplx(1.0) : response_[k]; }
  // The mode's full response (the pair's under an elastic indenter) with the factors applied.
  [[nodiscard]] ResponseMode response_mode(std::size_t k) const;
  // Its normal part: the complex compliance u_z / t_z (czz on an elastic body or at rest).
  [[nodiscard]] cplx normal_response(std::size_t k) const;
  // response_mode as a full 3x3 lab-frame matrix (row-major), as compliance() gives the elastic one.
  [[nodiscard]] std::array<cplx, 9> response_compliance(int ikx, int iky) const;

  // Displacement spectra from traction spectra, times `scale` (any of tx, ty, tz may be
  // null = zero; any of ux, uy, uz null = not wanted). Outputs may alias inputs (each mode
  // is read before it is written), e.g. ux = tx, uy = ty, uz = tz in place.
  void displacement(const cplx* tx, const cplx* ty, const cplx* tz, cplx* ux, cplx* uy, cplx* uz,
                    double scale = 1.0) const {
    displacement(tx, ty, tz, ux, uy, uz, scale, scale);
  }
  // The same with the normal traction scaled by scale_z instead: e.g. -scale turns the
  // spectrum of a pressure p into that of t_z = -p without a pass over the grid.
  void displacement(const cplx* tx, const cplx* ty, const cplx* tz, cplx* ux, cplx* uy, cplx* uz,
                    double scale, double scale_z) const;
  // The symbols D(q) of an upwind (e.grad) along (ex, ey) on every mode held here (r2c
  // half-spectrum order), for the calls below: their trigonometry otherwise costs more than
  // the rest of a spectral pass. 16 bytes per mode.
  [[nodiscard]] std::vector<cplx> slip_symbols(double ex, double ey, SlipDerivative deriv) const;
  // Spectra of the slopes (e.grad) u_x and (e.grad) u_y along the unit vector (ex, ey) of
  // the in-plane displacement caused by the tractions (scale tx, scale ty, scale_z tz), the
  // derivative discretised as `deriv` says (an upwind one's symbols from `symbols` =
  // slip_symbols(ex, ey, deriv) when given; the same numbers). Outputs may alias inputs.
  void inplane_slope(const cplx* tx, const cplx* ty, const cplx* tz, double ex, double ey, cplx* dux,
                     cplx* duy, double scale, double scale_z, SlipDerivative deriv = SlipDerivative::Spectral,
                     const cplx* symbols = nullptr) const;
  // Resolvent of the slip operator of steady sliding: A = (e.grad) C_tt maps a tangential
  // traction to the slip velocity it causes; with the spectral derivative A is skew-adjoint
  // (C_tt Hermitian, e.grad skew), with an upwind one A + A* <= 0; either way I - gamma A is
  // invertible for every gamma > 0. On a viscoelastic body A = (e.grad) c C_tt with its response
  // c = E0/E(omega) per mode, dissipative (A + A* <= 0) with either derivative. In place, per
  // mode: (x, y) <- (I - gamma A)^-1 scale (x, y); the q = 0 mode is scaled only.
  void slip_resolvent(cplx* x, cplx* y, double ex, double ey, double gamma, double scale,
                      SlipDerivative deriv = SlipDerivative::Spectral, const cplx* symbols = nullptr) const;
  // Spectral radius of A along (ex, ey): the largest |D(q)| times eigenvalue of C_tt(q) (times
  // |c| on a viscoelastic body).
  [[nodiscard]] double slip_operator_norm(double ex, double ey,
                                          SlipDerivative deriv = SlipDerivative::Spectral) const;

 private:
  Grid grid_;
  ElasticParams params_;
  // The compliance the slip sees: the body's own (own_) under a sliding elastic indenter.
  [[nodiscard]] const std::vector<ComplianceMode>& slip_modes() const {
    return own_.empty() || roll_both_ ? modes_ : own_;
  }
  bool roll_both_ = false;
  // A viscoelastic body in motion (factors other than 1): the complex paths below.
  [[nodiscard]] bool moving() const { return !response_.empty() && visco_.velocity != 0.0; }
  // The response the slip sees (response_mode, or the body's own under a sliding elastic indenter).
  [[nodiscard]] ResponseMode slip_response(std::size_t k) const;
  // The body's own response in motion: its elastic compliance times the factor, or for a layered
  // body (a viscoelastic top layer) the transfer matrices' at each mode's frequency.
  [[nodiscard]] ResponseMode own_response(std::size_t k) const;

  std::vector<ComplianceMode> modes_;
  std::vector<ComplianceMode> own_;  // the body's own modes under an elastic indenter; else empty
  std::optional<ElasticParams> indenter_;
  ViscoelasticParams visco_;
  std::vector<cplx> response_;  // E0/E(omega) per mode held here; empty: elastic
  // A layered viscoelastic body in motion: its own response per mode (96 bytes a mode); else empty.
  std::vector<ResponseMode> layered_response_;
  double c0_zz_ = 0.0, c0_t_ = 0.0;
};

}  // namespace gfmd
