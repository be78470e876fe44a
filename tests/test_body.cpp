// The body kinds (elastic/body.hpp): the registry picks exactly one kind for each [elastic], and
// the kinds agree where they describe the same material column, elastic and with complex moduli
// (a viscoelastic body at one frequency).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <set>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/layered.hpp"
#include "test_util.hpp"

namespace {

using namespace gfmd;
using gfmd::testing::difference;
using gfmd::testing::largest;

ElasticParams layer(double h) {
  ElasticParams el;
  el.contact_modulus = 1.0;
  el.poisson = 0.3;
  el.thickness = h;
  return el;
}

// The same layer of thickness 0.5 as three bonded layers of its material on the rigid base.
ElasticParams as_stack() {
  ElasticParams el = layer(0.2);
  el.layers = {ElasticLayer{1.0, 0.3, 0.1}, ElasticLayer{1.0, 0.3, 0.2}};
  return el;
}

double largest(const ComplexRotatedCompliance& c) {
  return std::max({std::abs(c.c11), std::abs(c.c22), std::abs(c.c33), std::abs(c.c13)});
}
double difference(const ComplexRotatedCompliance& a, const ComplexRotatedCompliance& b) {
  return std::max(
      {std::abs(a.c11 - b.c11), std::abs(a.c22 - b.c22), std::abs(a.c33 - b.c33), std::abs(a.c13 - b.c13)});
}
TEST(Body, EachElasticSectionIsExactlyOneRegisteredKind) {
  std::set<std::string> names;
  for (const BodyType* t : body_types()) {
    EXPECT_TRUE(names.insert(t->name).second) << t->name << " registered twice";
    EXPECT_FALSE(t->purpose.empty()) << t->name;
  }
  ElasticParams coated = layer(0.1);
  coated.substrate_contact_modulus = 10.0;
  const std::vector<std::pair<ElasticParams, std::string>> cases = {{ElasticParams{}, "homogeneous"},
                                                                    {layer(0.5), "homogeneous"},
                                                                    {as_stack(), "layered"},
                                                                    {coated, "layered"}};
  for (const auto& [el, kind] : cases) {
    int describing = 0;
    for (const BodyType* t : body_types()) describing += t->describes(el) ? 1 : 0;
    EXPECT_EQ(describing, 1) << kind;
    EXPECT_EQ(body_type_of(el).name, kind);
  }
  ElasticParams bad = layer(0.5);
  bad.poisson = 0.7;
  EXPECT_THROW((void)make_body(bad), ParameterError);
}

TEST(Body, TheKindsAgreeOnOneMaterialElasticAndViscoelastic) {
  // A layer of thickness 0.5 on a rigid base, once homogeneous (closed forms), once as three
  // bonded layers of its material (transfer matrices): the same surface compliance and the
  // same response at depth (in each sublayer and on the interfaces), to 1e-10 of the largest
  // entry; and with every modulus the complex E*(omega) of a standard linear solid near its loss
  // peak (E0 = 1, E_inf = 10, omega tau = 0.3), where the homogeneous body scales its elastic
  // response by E0/E*(omega) and the stack runs its transfer matrices in complex arithmetic.
  const auto homogeneous = make_body(layer(0.5));
  const auto stack = make_body(as_stack());
  const cplx e = 1.0 + 9.0 * cplx(0.0, 0.3) / (1.0 + cplx(0.0, 0.3));
  const std::vector<cplx> moduli(4,
                                 e);  // top, two layers, substrate (as stack_moduli; unused on a rigid base)
  for (double q : {0.5, 4.0, 40.0, 400.0}) {
    const RotatedCompliance a = homogeneous->compliance(q), b = stack->compliance(q);
    const ComplexRotatedCompliance ar{a.c11, a.c22, a.c33, a.c13}, br{b.c11, b.c22, b.c33, b.c13};
    EXPECT_LE(difference(ar, br), 1e-10 * largest(ar)) << "q " << q;
    const ComplexRotatedCompliance ac = homogeneous->compliance(q, moduli), bc = stack->compliance(q, moduli);
    EXPECT_LE(difference(ac, bc), 1e-10 * largest(ac)) << "complex, q " << q;
    EXPECT_GT(std::abs(ac.c33.imag()), 1e-3 * std::abs(ac.c33)) << "a lossy modulus gives a lossy compliance";
    for (double d : {0.0, 0.1, 0.2, 0.33, 0.5}) {
      const ModeResponse r = homogeneous->mode_response(q, d), s = stack->mode_response(q, d);
      EXPECT_LE(difference(r, s), 1e-10 * largest(r)) << "q " << q << " d " << d;
      const ModeResponse rc = homogeneous->mode_response(q, d, moduli),
                         sc = stack->mode_response(q, d, moduli);
      EXPECT_LE(difference(rc, sc), 1e-10 * largest(rc)) << "complex, q " << q << " d " << d;
    }
  }
  const auto [hz, ht] = homogeneous->mean_compliances();
  const auto [sz, st] = stack->mean_compliances();
  EXPECT_NEAR(hz, sz, 1e-14 * hz);
  EXPECT_NEAR(ht, st, 1e-14 * ht);
  EXPECT_GT(hz, 0.0);
}

}  // namespace
