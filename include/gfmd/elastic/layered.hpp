// A layered body: the top layer (ElasticParams' contact_modulus, poisson, thickness) over
// further bonded layers, all on a rigid base or on an elastic half-space (a coating on a
// substrate). Its surface compliance per mode by transfer matrices (docs/solver.md,
// "Layered bodies"): the state (u1, u3, sigma13, sigma33) of a mode exp(i q x1) obeys
// d/dz s = q M s with M constant in each layer; exp(M x) is written with the projectors on
// the eigenvalues +1 and -1 of M (each twice, a Jordan block), so no matrix function and no
// overflow is needed for any q h.
#pragma once

#include <vector>

#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd {

// The compliance at |q| = q of the body `el` describes (layered or not), exact for every q.
// For a homogeneous body it equals the closed form's (tests compare them); the layered body kind
// (body_layered.cpp) uses it, so a homogeneous body keeps its closed form's bits.
[[nodiscard]] RotatedCompliance layered_compliance(double q, const ElasticParams& el);

// The response at a depth below the surface of a layered body to one surface-traction mode
// (stress.hpp's ModeResponse, the same frame and meaning; the real coupled body whatever
// el.coupling says): the states the body below the depth admits, lifted to the surface, fixed by
// the traction there. A depth on an interface is taken in the layer above it (its side of the
// in-plane stresses, which jump there). At depth 0 the displacement is layered_compliance.
[[nodiscard]] ModeResponse layered_mode_response(double q, double depth, const ElasticParams& el);

// The same with each material's E* complex (a viscoelastic part at one frequency, E(omega) by the
// correspondence principle, nu constant), `moduli` in the order top layer, layers top to bottom,
// substrate (its entry ignored on a rigid base; stack_moduli gives them):
// u1 = c11 t1 + i c13 t3, u2 = c22 t2, u3 = -i c13 t1 + c33 t3 with complex entries.
[[nodiscard]] ComplexRotatedCompliance layered_compliance(double q, const ElasticParams& el,
                                                          const std::vector<cplx>& moduli);

// layered_mode_response with each material's E* complex (as layered_compliance's overload); at
// q = 0 the elastic one.
[[nodiscard]] ModeResponse layered_mode_response(double q, double depth, const ElasticParams& el,
                                                 const std::vector<cplx>& moduli);

// A body's viscoelastic parts (v.parts(): elastic.viscoelastic's and each of
// elastic.viscoelastic_parts') with each one's response factor c = E0_part/E_part(omega) per mode
// of the spectral rows held here (viscoelastic_factors).
class ViscoelasticStack {
 public:
  ViscoelasticStack(const Grid& grid, const ElasticParams& el, const ViscoelasticParams& v);
  // Each material's E* (top, layers, substrate: layered_compliance's order) at spectral mode k:
  // a viscoelastic part's E0_part / c_part, every material's own E* over c for "all", the
  // elastic ones their own.
  [[nodiscard]] std::vector<cplx> moduli(std::size_t k) const;
  // Whether the top layer is viscoelastic (a part "top" or "all"), and its factor at k (1 if not).
  [[nodiscard]] bool top_viscoelastic() const { return top_ >= 0; }
  [[nodiscard]] cplx top_factor(std::size_t k) const {
    return top_ < 0 ? cplx(1.0) : factors_[static_cast<std::size_t>(top_)][k];
  }

 private:
  ElasticParams el_;
  std::vector<ViscoelasticParams> parts_;
  std::vector<std::vector<cplx>> factors_;  // [part][mode]
  int top_ = -1;                            // the part that is the top layer, if any
};

// Throws ParameterError naming the key when a part of `v` is not in `el` (a substrate part
// without a substrate, a layer the body does not have), two parts are one, "all" has company,
// or a part's model is bad for its relaxed modulus (ViscoelasticParams::validate). A further
// part's keys are named "viscoelastic_parts[i].<key>".
void validate_viscoelastic_parts(const ElasticParams& el, const ViscoelasticParams& v);

// The q = 0 compliances of a layered body: zero on a half-space substrate (its mean
// displacement is pinned as a half-space's is), else the sums over the layers of
// h (1-2nu)/((1-nu)^2 E*) (normal) and h/G (in-plane).
[[nodiscard]] double layered_mean_normal_compliance(const ElasticParams& el);
[[nodiscard]] double layered_mean_inplane_compliance(const ElasticParams& el);

}  // namespace gfmd
