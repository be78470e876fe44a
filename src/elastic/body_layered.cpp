// The layered body: a top layer over further bonded layers, on a rigid base or on an elastic
// half-space (a coating on a substrate), by transfer matrices (layered.cpp, docs/solver.md
// "Layered bodies").
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

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
      .keys =
          {
              {.name = "substrate_contact_modulus",
               .kind = BodyKey::Kind::NumberOrInf,
               .member = &ElasticParams::substrate_contact_modulus,
               .default_value = std::numeric_limits<double>::infinity(),
               .doc = "E* of an elastic half-space beneath the layers (a coating on a substrate); inf: a "
                      "rigid base",
               .needs = "",
               .written = [](const ElasticParams& el) { return el.on_substrate(); },
               .fields = {},
               .set_rows = nullptr,
               .rows = nullptr},
              {.name = "substrate_poisson",
               .kind = BodyKey::Kind::Number,
               .member = &ElasticParams::substrate_poisson,
               .default_value = 0.25,
               .doc = "the substrate's Poisson ratio",
               .needs = "substrate_contact_modulus",
               .written = [](const ElasticParams& el) { return el.on_substrate(); },
               .fields = {},
               .set_rows = nullptr,
               .rows = nullptr},
              {.name = "layers",
               .kind = BodyKey::Kind::Tables,
               .member = nullptr,
               .default_value = 0.0,
               .doc =
                   "bonded layers beneath the top one, top to bottom: {contact_modulus, poisson, thickness}",
               .needs = "",
               .written = nullptr,
               .fields = {{.name = "contact_modulus", .required = true, .default_value = 0.0},
                          {.name = "poisson", .required = false, .default_value = ElasticLayer{}.poisson},
                          {.name = "thickness", .required = true, .default_value = 0.0}},
               .set_rows =
                   [](ElasticParams& el, const std::vector<std::vector<double>>& rows) {
                     el.layers.clear();
                     for (const auto& r : rows)
                       el.layers.push_back(
                           ElasticLayer{.contact_modulus = r[0], .poisson = r[1], .thickness = r[2]});
                   },
               .rows =
                   [](const ElasticParams& el) {
                     std::vector<std::vector<double>> out;
                     for (const ElasticLayer& l : el.layers)
                       out.push_back({l.contact_modulus, l.poisson, l.thickness});
                     return out;
                   }},
          },
      .describes = [](const ElasticParams& el) { return el.layered(); },
      .make = [](const ElasticParams& el) -> std::unique_ptr<Body> {
        return std::make_unique<LayeredBody>(el);
      }};
  return t;
}

}  // namespace gfmd
