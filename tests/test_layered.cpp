// Layered bodies (a coating bonded to an elastic substrate, layers on a rigid base): the
// transfer-matrix compliance (layered.hpp) against its limits, against the closed form of a
// layer bonded to a half-space, and in full solves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/layered.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::difference;
using gfmd::testing::largest;
using gfmd::testing::solve;

namespace {
const double kInf = std::numeric_limits<double>::infinity();

// A homogeneous body's compliance from the closed form of SPEC §2 (elastic.cpp).
RotatedCompliance homogeneous(double q, double es, double nu, double h) {
  const PhiRotated p = phi_rotated(h == kInf ? kInf : q * h, nu);
  const double det = p.p11 * p.p33 - p.p13 * p.p13, f = q * es;
  return {p.p33 / (det * f), 1.0 / (p.p22 * f), p.p11 / (det * f), -p.p13 / (det * f)};
}

ElasticParams coating(double e1, double nu1, double h, double e2, double nu2) {
  ElasticParams el;
  el.contact_modulus = e1;
  el.poisson = nu1;
  el.thickness = h;
  el.substrate_contact_modulus = e2;
  el.substrate_poisson = nu2;
  return el;
}

// Each component within tol of the reference, relative to the largest of them (c13 can vanish).
void expect_close(const RotatedCompliance& a, const RotatedCompliance& b, double tol,
                  const std::string& what) {
  const double s = std::max({std::abs(b.c11), std::abs(b.c22), std::abs(b.c33)});
  EXPECT_NEAR(a.c11, b.c11, tol * s) << what;
  EXPECT_NEAR(a.c22, b.c22, tol * s) << what;
  EXPECT_NEAR(a.c33, b.c33, tol * s) << what;
  EXPECT_NEAR(a.c13, b.c13, tol * s) << what;
}

// The normal compliance of a layer (shear modulus G1, nu1, thickness t) bonded to a half-space
// (G2, nu2) under a pressure alone: u_z = 2 C(q t) p / (E1* q), with
//   C(x) = (1 + 4 b x e^-2x - a b e^-4x) / (1 - (a + b + 4 b x^2) e^-2x + a b e^-4x),
//   g = G1/G2, k_i = 3 - 4 nu_i, a = (g k2 - k1)/(1 + g k2), b = (g - 1)/(g + k1):
// Burmister's bonded-layer problem in the closed form with two bimaterial constants that the
// coated-contact literature uses (derived independently of the transfer matrices tested).
double bonded_layer_czz(double q, double e1, double nu1, double t, double e2, double nu2) {
  const double g1 = e1 * (1 - nu1) / 2, g2 = e2 * (1 - nu2) / 2, g = g1 / g2;
  const double k1 = 3 - 4 * nu1, k2 = 3 - 4 * nu2;
  const double a = (g * k2 - k1) / (1 + g * k2), b = (g - 1) / (g + k1);
  const double x = q * t, e = std::exp(-2 * x), e4 = e * e;
  const double c = (1 + 4 * b * x * e - a * b * e4) / (1 - (a + b + 4 * b * x * x) * e + a * b * e4);
  return 2 * c / (e1 * q);
}
}  // namespace

TEST(Layered, ACoatingOfTheSubstratesMaterialIsTheHalfSpace) {
  // Any thickness, through the transfer (q t < 40) and past it: the half-space to 1e-12.
  for (double nu : {-0.3, 0.0, 0.25, 0.49, 0.5})
    for (double qt : {1e-6, 1e-2, 0.5, 3.0, 39.0, 41.0, 200.0}) {
      const double q = 2.7;
      const RotatedCompliance c = layered_compliance(q, coating(1.7, nu, qt / q, 1.7, nu));
      expect_close(c, homogeneous(q, 1.7, nu, kInf), 1e-12,
                   "nu " + std::to_string(nu) + " qt " + std::to_string(qt));
    }
}

TEST(Layered, TheNormalComplianceIsTheBondedLayersClosedForm) {
  // Soft and stiff coatings, equal and unequal Poisson ratios, thin to thick: 1e-10.
  struct Pair {
    double nu1, nu2;
  };
  for (double ratio : {0.01, 0.1, 0.5, 2.0, 10.0, 100.0})
    for (Pair p : {Pair{0.25, 0.3}, Pair{0.49, 0.2}, Pair{0.0, 0.45}, Pair{0.3, 0.5}})
      for (double qt : {1e-3, 0.1, 1.0, 5.0, 20.0}) {
        const double q = 0.8, t = qt / q, e1 = 1.3, e2 = ratio * e1;
        const double ref = bonded_layer_czz(q, e1, p.nu1, t, e2, p.nu2);
        const RotatedCompliance c = layered_compliance(q, coating(e1, p.nu1, t, e2, p.nu2));
        EXPECT_NEAR(c.c33 / ref, 1.0, 1e-10)
            << "E2/E1 " << ratio << " nu " << p.nu1 << "/" << p.nu2 << " qt " << qt;
      }
}

TEST(Layered, LayersOfOneMaterialOnARigidBaseAreOneLayer) {
  // The top layer and two more of the same material on a rigid base: the single layer of their
  // total thickness (the closed form), to 1e-11; its mean compliances are the sums.
  for (double nu : {0.0, 0.3, 0.45})
    for (double q : {0.05, 1.0, 7.0, 60.0}) {
      ElasticParams el;
      el.contact_modulus = 2.0;
      el.poisson = nu;
      el.thickness = 0.1;
      el.layers = {ElasticLayer{2.0, nu, 0.25}, ElasticLayer{2.0, nu, 0.15}};
      expect_close(layered_compliance(q, el), homogeneous(q, 2.0, nu, 0.5), 1e-11,
                   "nu " + std::to_string(nu) + " q " + std::to_string(q));
      const double om = 1 - nu;
      EXPECT_NEAR(layered_mean_normal_compliance(el), 0.5 * (1 - 2 * nu) / (om * om * 2.0), 1e-15);
      EXPECT_NEAR(layered_mean_inplane_compliance(el), 0.5 / (2.0 * om / 2), 1e-15);
    }
}

TEST(Layered, CoatingLimits) {
  const double q = 1.3, e1 = 1.0, nu1 = 0.3, nu2 = 0.2;
  for (double e2 : {0.02, 50.0}) {
    // A thin coating is the substrate, to O(q t); a thick one the coating's half-space.
    expect_close(layered_compliance(q, coating(e1, nu1, 1e-9 / q, e2, nu2)), homogeneous(q, e2, nu2, kInf),
                 1e-7, "thin, E2 " + std::to_string(e2));
    expect_close(layered_compliance(q, coating(e1, nu1, 100.0 / q, e2, nu2)), homogeneous(q, e1, nu1, kInf),
                 1e-12, "thick, E2 " + std::to_string(e2));
  }
  // A substrate stiffer by 1e9: the layer on a rigid base, to the substrate's compliance share.
  for (double qh : {0.01, 0.3, 2.0, 10.0})
    expect_close(layered_compliance(q, coating(e1, nu1, qh / q, 1e9 * e1, nu2)),
                 homogeneous(q, e1, nu1, qh / q), 1e-7, "stiff substrate, qh " + std::to_string(qh));
  // The coating's direction of change: a soft substrate adds compliance, a stiff one removes it.
  const RotatedCompliance half = homogeneous(q, e1, nu1, kInf);
  EXPECT_GT(layered_compliance(q, coating(e1, nu1, 0.5 / q, 0.1, nu1)).c33, half.c33);
  EXPECT_LT(layered_compliance(q, coating(e1, nu1, 0.5 / q, 10.0, nu1)).c33, half.c33);
}

TEST(Layered, TheBodyIsPositiveAndItsStiffnessInvertsIt) {
  const Grid g{32, 32, 1.0, 1.0};
  ElasticParams el = coating(1.0, 0.3, 0.05, 0.2, 0.45);
  el.layers = {ElasticLayer{5.0, 0.2, 0.02}};
  const ElasticBody body(g, el);
  EXPECT_EQ(body.mean_normal_compliance(), 0.0);  // on a half-space substrate
  EXPECT_EQ(body.mean_inplane_compliance(), 0.0);
  for (int iky : {0, 1, 5, 16, 31})
    for (int ikx : {0, 1, 3, 16}) {
      if (ikx == 0 && iky == 0) continue;
      const auto c = body.compliance(ikx, iky), k = body.stiffness(ikx, iky);
      const bool nyq = ikx == 16 || iky == 16;  // odd parts dropped there
      for (int i = 0; i < 3; ++i) {
        EXPECT_GT(c[4 * i].real(), 0.0);
        for (int j = 0; j < 3; ++j) {
          EXPECT_NEAR(std::abs(c[3 * i + j] - std::conj(c[3 * j + i])), 0.0, 1e-14) << "Hermitian";
          if (nyq) continue;
          cplx s = 0.0;
          for (int m = 0; m < 3; ++m) s += k[3 * i + m] * c[3 * m + j];
          EXPECT_NEAR(std::abs(s - (i == j ? 1.0 : 0.0)), 0.0, 1e-10) << ikx << "," << iky;
        }
      }
    }
}

TEST(Layered, BadLayersAreNamed) {
  const auto why = [](const ElasticParams& el) {
    try {
      el.validate();
    } catch (const ParameterError& e) {
      return e.where();
    }
    return std::string();
  };
  ElasticParams el = coating(1.0, 0.3, kInf, 2.0, 0.3);
  EXPECT_EQ(why(el), "thickness");
  el.thickness = 0.1;
  EXPECT_EQ(why(el), "");
  el.substrate_poisson = 0.7;
  EXPECT_EQ(why(el), "substrate_poisson");
  el.substrate_poisson = 0.3;
  el.substrate_contact_modulus = -1.0;
  EXPECT_EQ(why(el), "substrate_contact_modulus");
  el.substrate_contact_modulus = 2.0;
  el.layers = {ElasticLayer{1.0, 0.5, 0.1}};
  EXPECT_EQ(why(el), "layers[0].poisson");
  el.layers = {ElasticLayer{1.0, 0.3, 0.1}, ElasticLayer{0.0, 0.3, 0.1}};
  EXPECT_EQ(why(el), "layers[1].contact_modulus");
  // An incompressible coating is allowed on a substrate (it can still be pressed in).
  el.layers.clear();
  el.poisson = 0.5;
  EXPECT_EQ(why(el), "");
}

// In a case file, a layer's problem names its line (the element's key in the array of tables),
// in the body's layers and in an elastic indenter's alike.
TEST(Layered, ALayersProblemNamesItsLine) {
  const std::string head = "[grid]\nnx = 32\nlx = 1.5\n[elastic]\ncontact_modulus = 1.0\nthickness = 0.1\n";
  const std::string layers = "layers = [{thickness = -0.1, contact_modulus = 2.0, poisson = 0.3}]\n";
  const std::string tail = "[load]\nforce = 0.001\n";
  std::string e =
      gfmd::testing::config_problem(head + layers + "[indenter]\ntype = \"hertz\"\nradius = 1.0\n" + tail);
  EXPECT_NE(e.find("elastic.layers[0].thickness: must be a positive finite number [t.toml:7]"),
            std::string::npos)
      << e;
  e = gfmd::testing::config_problem(
      "[grid]\nnx = 32\nlx = 1.5\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
      "contact_modulus = 1.0\nthickness = 0.1\n" +
      layers + tail);
  EXPECT_NE(e.find("indenter.layers[0].thickness: must be a positive finite number [t.toml:9]"),
            std::string::npos)
      << e;
}

namespace {
const char* kSliding = R"(
[grid]
nx = 64
lx = 1.0
[elastic]
poisson = 0.3
[indenter]
type = "hertz"
radius = 2.0
[load]
pressure = 0.01
[friction]
coefficient = 0.5
reference = false
[solver]
tolerance = 1e-11
[output]
analysis = false
)";
}  // namespace

TEST(Layered, ACoatedSlidingSolveLimits) {
  // A coating of the substrate's material is the half-space in a full sliding solve (coupled,
  // friction 0.5); a soft substrate under a thin coating widens the contact.
  const std::string planes = "stress.depths=[0.02, 0.05, 0.1]";  // in, on and below the coating
  const CaseResult half = solve(kSliding, {planes});
  const CaseResult same =
      solve(kSliding, {planes, "elastic.thickness=0.05", "elastic.substrate_contact_modulus=1",
                       "elastic.substrate_poisson=0.3"});
  ASSERT_TRUE(half.info.converged && same.info.converged);
  double d = 0.0, pmax = 0.0;
  for (std::size_t i = 0; i < half.fields.pressure.size(); ++i) {
    d = std::max(d, std::abs(half.fields.pressure[i] - same.fields.pressure[i]));
    pmax = std::max(pmax, half.fields.pressure[i]);
  }
  EXPECT_LT(d, 1e-9 * pmax);
  EXPECT_NEAR(same.observables.friction_coefficient, half.observables.friction_coefficient, 1e-10);
  const nlohmann::json hs = summary_json(half)["subsurface"], ss = summary_json(same)["subsurface"];
  ASSERT_EQ(hs.size(), 3u);
  ASSERT_EQ(ss.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    for (const char* key : {"max_von_mises", "max_tensile_stress"})
      EXPECT_NEAR(ss[i][key].get<double>(), hs[i][key].get<double>(),
                  1e-9 * hs[i]["max_von_mises"].get<double>())
          << key << " at depth " << hs[i]["depth"];
  const CaseResult soft =
      solve(kSliding, {"elastic.thickness=0.05", "elastic.substrate_contact_modulus=0.1"});
  ASSERT_TRUE(soft.info.converged);
  EXPECT_GT(soft.observables.relative_contact_area, 1.2 * half.observables.relative_contact_area);
  // The written case carries the substrate (and reads back to the same body).
  const auto j = soft.config.to_json();
  EXPECT_EQ(j["elastic"]["substrate_contact_modulus"], 0.1);
  EXPECT_EQ(j["elastic"]["substrate_poisson"], 0.25);
}

TEST(Layered, CaseKeysAreChecked) {
  const auto problem = [](const std::vector<std::string>& sets) {
    return gfmd::testing::config_problem(kSliding, sets);
  };
  EXPECT_NE(problem({"elastic.substrate_contact_modulus=2"}).find("elastic.thickness"), std::string::npos);
  EXPECT_NE(problem({"elastic.substrate_poisson=0.3"}).find("elastic.substrate_poisson"), std::string::npos);
  EXPECT_NE(problem({"elastic.thickness=0.1", "elastic.layers=[{contact_modulus=1, thikness=0.1}]"})
                .find("did you mean"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.thickness=0.1", "elastic.layers=[{contact_modulus=1}]"}).find("layers[0]"),
            std::string::npos);
  // Planes: anywhere above a rigid base, at any depth on a substrate.
  EXPECT_NE(problem({"elastic.thickness=0.1", "elastic.layers=[{contact_modulus=2, thickness=0.1}]",
                     "stress.depths=[0.25]"})
                .find("stress.depths"),
            std::string::npos);
  EXPECT_EQ(problem({"elastic.thickness=0.1", "elastic.layers=[{contact_modulus=2, thickness=0.1}]",
                     "stress.depths=[0.2]"}),
            "");
  EXPECT_EQ(problem({"elastic.thickness=0.1", "elastic.substrate_contact_modulus=2", "stress.depths=[5]"}),
            "");
  EXPECT_EQ(
      problem({"elastic.thickness=0.1", "elastic.substrate_contact_modulus=2", "elastic.viscoelastic=\"sls\"",
               "elastic.high_frequency_modulus=10", "elastic.relaxation_time=1"}),
      "")
      << "a viscoelastic coating (tests/test_viscoelastic_coating.cpp)";
  EXPECT_EQ(
      problem({"elastic.thickness=0.1", "elastic.layers=[{contact_modulus=3, poisson=0.2, thickness=0.1}]",
               "elastic.substrate_contact_modulus=0.5"}),
      "");
}

TEST(Layered, PlanesBelowOneMaterialAreTheHomogeneousBodys) {
  // The stress and displacement of each mode at depth (above, on and below the interface, and
  // deep): a coating on a substrate of its own material is the half-space, layers of one
  // material on a rigid base are one layer (its closed-form planes, subsurface.cpp), to 1e-10.
  const double t = 0.1;
  for (double q : {0.0, 0.5, 3.0, 30.0, 300.0})
    for (double d : {0.0, 0.3 * t, t, 2.5 * t, 9.0 * t}) {
      const ModeResponse a = layered_mode_response(q, d, coating(1.0, 0.3, t, 1.0, 0.3));
      const ModeResponse b = mode_response(q, d, homogeneous_body(1.0, 0.3));
      EXPECT_LE(difference(a, b), 1e-10 * largest(b)) << "substrate, q " << q << " d " << d;
      ElasticParams el = homogeneous_body(1.0, 0.3, 0.4 * t);
      el.layers = {ElasticLayer{1.0, 0.3, 0.6 * t}, ElasticLayer{1.0, 0.3, 9.0 * t}};
      const ModeResponse c = layered_mode_response(q, d, el);
      const ModeResponse e = mode_response(q, d, homogeneous_body(1.0, 0.3, 10.0 * t));
      EXPECT_LE(difference(c, e), 1e-10 * largest(e)) << "rigid base, q " << q << " d " << d;
    }
}

TEST(Layered, PlanesMeetTractionsInterfacesAndEquilibrium) {
  // A hard coating on a soft substrate with other Poisson ratios (and the reverse):
  const double t = 0.1;
  for (double e2 : {0.1, 10.0}) {
    const ElasticParams el = coating(1.0, 0.25, t, e2, 0.4);
    for (double q : {0.7, 8.0, 60.0}) {
      // the surface: the tractions themselves and the body's compliance;
      const ModeResponse s = layered_mode_response(q, 0.0, el);
      const RotatedCompliance c = layered_compliance(q, el);
      EXPECT_NEAR(std::abs(s.stress[2][2] - 1.0), 0.0, 1e-12);
      EXPECT_NEAR(std::abs(s.stress[4][0] - 1.0), 0.0, 1e-12);
      EXPECT_NEAR(std::abs(s.stress[5][1] - 1.0), 0.0, 1e-12);
      EXPECT_NEAR(std::abs(s.stress[2][0]) + std::abs(s.stress[4][2]), 0.0, 1e-12);
      EXPECT_NEAR(s.disp[0][0].real(), c.c11, 1e-12 * c.c11);
      EXPECT_NEAR(s.disp[0][2].imag(), c.c13, 1e-12 * c.c11);
      EXPECT_NEAR(s.disp[2][2].real(), c.c33, 1e-12 * c.c33);
      EXPECT_NEAR(s.disp[1][1].real(), c.c22, 1e-12 * c.c22);
      // the interface: tractions (s33, s13, s23) and displacements continuous, s11 not;
      const ModeResponse up = layered_mode_response(q, t * (1 - 1e-10), el),
                         down = layered_mode_response(q, t * (1 + 1e-10), el);
      const double scale = largest(up);
      for (int row : {2, 4, 5})
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(std::abs(up.stress[row][k] - down.stress[row][k]), 0.0, 1e-7 * scale);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(up.disp[i][k] - down.disp[i][k]), 0.0, 1e-7 * scale);
      EXPECT_GT(std::abs(up.stress[0][2] - down.stress[0][2]), 1e-3 * std::abs(up.stress[0][2]));
      // equilibrium inside each material: d_1 s1j + d_3 s3j = 0 with d_1 = i q, d_3 = -d/d(depth).
      for (double d : {0.5 * t, 3.0 * t}) {
        const double h = 1e-6 / q;
        const ModeResponse a = layered_mode_response(q, d + h, el), b = layered_mode_response(q, d - h, el),
                           m = layered_mode_response(q, d, el);
        const double sc = largest(m);
        const cplx iq(0.0, q);
        for (int k = 0; k < 3; ++k) {
          const auto dd = [&](int row) { return (a.stress[row][k] - b.stress[row][k]) / (2 * h); };
          EXPECT_NEAR(std::abs(iq * m.stress[0][k] - dd(4)), 0.0, 1e-6 * q * sc)
              << "x, q " << q << " d " << d;
          EXPECT_NEAR(std::abs(iq * m.stress[4][k] - dd(2)), 0.0, 1e-6 * q * sc)
              << "z, q " << q << " d " << d;
          EXPECT_NEAR(std::abs(iq * m.stress[3][k] - dd(5)), 0.0, 1e-6 * q * sc)
              << "y, q " << q << " d " << d;
        }
      }
    }
  }
  // Far below a short wave nothing is left, and nothing overflows.
  const ModeResponse deep = layered_mode_response(500.0, 5.0, coating(1.0, 0.25, t, 0.1, 0.4));
  EXPECT_LT(largest(deep), 1e-100);
}
