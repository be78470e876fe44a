// The layered body: a top layer over further bonded layers, on a rigid base or on an elastic
// half-space (a coating on a substrate), by transfer matrices (layered.cpp, docs/solver.md
// "Layered bodies").
#include <stdexcept>
#include <string>

#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/layered.hpp"

namespace gfmd {

namespace {

class LayeredBody final : public Body {
 public:
  explicit LayeredBody(const ElasticParams& el) : el_(el) {}
  [[nodiscard]] RotatedCompliance compliance(double q) const override { return layered_compliance(q, el_); }
  [[nodiscard]] ComplexRotatedCompliance compliance(double q,
                                                    const std::vector<cplx>& moduli) const override {
    check(moduli);
    return layered_compliance(q, el_, moduli);
  }
  [[nodiscard]] std::pair<double, double> mean_compliances() const override {
    return {layered_mean_normal_compliance(el_), layered_mean_inplane_compliance(el_)};
  }
  [[nodiscard]] ModeResponse mode_response(double q, double depth) const override {
    return layered_mode_response(q, depth, el_);
  }
  [[nodiscard]] ModeResponse mode_response(double q, double depth,
                                           const std::vector<cplx>& moduli) const override {
    check(moduli);
    return layered_mode_response(q, depth, el_, moduli);
  }

 private:
  // One modulus per material: top, each layer, substrate (stack_moduli's order).
  void check(const std::vector<cplx>& moduli) const {
    if (moduli.size() != el_.layers.size() + 2)
      throw std::invalid_argument("layered body: " + std::to_string(moduli.size()) + " moduli for " +
                                  std::to_string(el_.layers.size() + 2) + " materials");
  }

  ElasticParams el_;
};

}  // namespace

const BodyType& layered_body_type() {
  static const BodyType t{
      .name = "layered",
      .purpose =
          "bonded layers (elastic.layers) on a rigid base, or a coating on an elastic substrate "
          "(substrate_contact_modulus): transfer matrices per mode",
      .describes = [](const ElasticParams& el) { return el.layered(); },
      .make = [](const ElasticParams& el) -> std::unique_ptr<Body> {
        return std::make_unique<LayeredBody>(el);
      }};
  return t;
}

}  // namespace gfmd
