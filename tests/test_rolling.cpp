// Tractive rolling: Kalker's creep coefficients, the upwind slip derivative, lateral creepage.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

using gfmd::testing::solve;

// A Hertz sphere R = 1 on a half-space, F = 4 E* a^3/(3R) for a = L/8, mu_c = 0.3. With
// creepages of 1e-4 the traction stays far inside the friction disc except at the trailing
// edge: almost the whole contact sticks, Kalker's linear theory.
const char* kSphere = R"(
[grid]
nx = 128
lx = 1.0
[elastic]
poisson = 0.5
coupling = false
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.0026041666666666665
[friction]
coefficient = 0.3
creepage = 1e-4
reference = false
[output]
fields = false
png = false
analysis = false
[stress]
profiles = false
)";

// Kalker's creep coefficient from a solve: F = G' c^2 C xi with Kalker's combined shear
// modulus 1/G' = (1/G1 + 1/G2)/2, so G' = 2G for a rigid indenter on a body of shear modulus
// G, and c the radius of the contact (of the area of the contact cells).
struct Creep {
  double coefficient, stick_fraction;
};
Creep creep_coefficient(int nx, double nu, bool lateral) {
  std::vector<std::string> sets = {"grid.nx=" + std::to_string(nx), "elastic.poisson=" + std::to_string(nu)};
  if (lateral) {
    sets.emplace_back("friction.creepage=1e-8");
    sets.emplace_back("friction.lateral_creepage=1e-4");
  }
  const auto r = solve(kSphere, sets);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  const auto& o = r.observables;
  const double c2 = o.relative_contact_area * r.config.grid.area() / std::numbers::pi;
  const double g2 = 2.0 * r.config.elastic.shear_modulus();
  const double f = lateral ? o.tangential_force_y : o.tangential_force_x;
  return {std::abs(f) / (g2 * c2 * 1e-4), o.stick_fraction};
}

}  // namespace

// Kalker (1967), linear theory of rolling with small creepage: for a circular contact
// C11 = 5.20, C22 = 3.98 at nu = 0.5 and C11 = 4.12, C22 = 3.67 at nu = 0.25 (as tabulated in
// K. L. Johnson, Contact Mechanics, 1985, Table 8.1). Within 3 % at c = 16 cells; at nu = 0.25
// the error shrinks from 128^2 to 256^2 (measured: C11 -0.7 % -> -0.1 %, C22 -1.0 % -> -0.4 %).
TEST(Rolling, KalkerCreepCoefficientsOfACircle) {
  struct Case {
    double nu;
    bool lateral;
    double kalker;
  };
  for (const Case& k :
       {Case{0.5, false, 5.20}, Case{0.5, true, 3.98}, Case{0.25, false, 4.12}, Case{0.25, true, 3.67}}) {
    const Creep c = creep_coefficient(128, k.nu, k.lateral);
    std::printf("Kalker nu = %.2f %s: C = %.4f (table %.2f, %+.2f %%), stick %.4f\n", k.nu,
                k.lateral ? "C22" : "C11", c.coefficient, k.kalker, 100.0 * (c.coefficient / k.kalker - 1.0),
                c.stick_fraction);
    EXPECT_NEAR(c.coefficient / k.kalker, 1.0, 0.03);
    EXPECT_GT(c.stick_fraction, 0.99);  // Kalker's limit: (nearly) all of the contact sticks
    if (k.nu == 0.25) {
      const Creep fine = creep_coefficient(256, k.nu, k.lateral);
      std::printf("  256^2: C = %.4f (%+.2f %%)\n", fine.coefficient,
                  100.0 * (fine.coefficient / k.kalker - 1.0));
      EXPECT_LT(std::abs(fine.coefficient / k.kalker - 1.0), std::abs(c.coefficient / k.kalker - 1.0));
    }
  }
}

// The upwind derivative's own dissipation closes the energy balance: dissipation in the
// slipping points + numerical dissipation = work of the driving force, to round-off; with
// full stick the numerical part is nearly all of it.
TEST(Rolling, UpwindEnergyBalanceCountsTheNumericalDissipation) {
  for (const char* d : {"upwind", "upwind2"}) {
    const auto r = solve(kSphere, {"grid.nx=64", std::string("friction.slip_derivative=\"") + d + "\""});
    ASSERT_TRUE(r.info.converged) << r.info.status;
    const auto& o = r.observables;
    EXPECT_LT(o.energy_balance_error_exact, 1e-6) << d;
    // The loose check is the exact one in rolling (read as sliding's it was of order 1e4).
    EXPECT_EQ(o.energy_balance_error, o.energy_balance_error_exact) << d;
    EXPECT_GT(o.numerical_dissipation_fraction, 0.9) << d;
    EXPECT_LE(o.numerical_dissipation_fraction, 1.0 + 1e-6) << d;
  }
}

// auto picks the spectral derivative for sliding where every point slips (the results of
// earlier versions, bit for bit) and upwind2 for rolling (sliding with stick: test_sliding.cpp).
TEST(Rolling, AutomaticDerivativeIsSpectralForSlidingUpwindForRolling) {
  const auto same = [](const CaseResult& a, const CaseResult& b) {
    return a.observables.tangential_force_x == b.observables.tangential_force_x &&
           a.observables.friction_force == b.observables.friction_force &&
           a.info.tangential_iterations == b.info.tangential_iterations;
  };
  const std::vector<std::string> slide = {"grid.nx=32", "friction.creepage=1"};
  auto with = [](std::vector<std::string> v, const std::string& s) {
    v.push_back(s);
    return v;
  };
  const auto s_auto = solve(kSphere, slide);
  const auto s_spec = solve(kSphere, with(slide, "friction.slip_derivative=\"spectral\""));
  const auto s_up = solve(kSphere, with(slide, "friction.slip_derivative=\"upwind2\""));
  EXPECT_TRUE(same(s_auto, s_spec));
  EXPECT_FALSE(same(s_auto, s_up));
  EXPECT_EQ(s_up.observables.stick_fraction, 0.0);  // sliding: every point slips either way
  EXPECT_EQ(s_auto.observables.numerical_dissipation, 0.0);
  const std::vector<std::string> roll = {"grid.nx=32"};
  const auto r_auto = solve(kSphere, roll);
  const auto r_up2 = solve(kSphere, with(roll, "friction.slip_derivative=\"upwind2\""));
  const auto r_up1 = solve(kSphere, with(roll, "friction.slip_derivative=\"upwind\""));
  EXPECT_TRUE(same(r_auto, r_up2));
  EXPECT_FALSE(same(r_auto, r_up1));
}

// The symbols: the upwind ones dissipate (Re D <= 0), approach i e.q for resolved modes (first
// and second order), and are Hermitian on the Nyquist lines so that real fields stay real.
TEST(Elastic, UpwindSlipSymbols) {
  Grid g;
  g.nx = 16;
  g.ny = 12;
  g.lx = 2.0;
  g.ly = 1.5;
  const double th = 0.3, ex = std::cos(th), ey = std::sin(th);
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < g.nxh(); ++ikx)
      for (SlipDerivative d : {SlipDerivative::Upwind, SlipDerivative::Upwind2}) {
        const cplx s = slip_derivative_symbol(g, ikx, iky, ex, ey, d);
        EXPECT_LE(s.real(), 1e-12);
        if (ikx == g.nx / 2) {
          const cplx partner = slip_derivative_symbol(g, ikx, (g.ny - iky) % g.ny, ex, ey, d);
          EXPECT_NEAR(std::abs(s - std::conj(partner)), 0.0, 1e-12) << ikx << " " << iky;
        }
      }
  // Order of accuracy on the first mode along x: the error falls 2x / 4x per halving of dx.
  const auto err = [&](int n, SlipDerivative d) {
    Grid h = g;
    h.nx = n;
    h.ny = n;
    const cplx s = slip_derivative_symbol(h, 1, 0, 1.0, 0.0, d);
    return std::abs(s - cplx(0.0, h.qx(1)));
  };
  EXPECT_NEAR(err(64, SlipDerivative::Upwind) / err(128, SlipDerivative::Upwind), 2.0, 0.05);
  EXPECT_NEAR(err(64, SlipDerivative::Upwind2) / err(128, SlipDerivative::Upwind2), 4.0, 0.1);
  EXPECT_EQ(slip_derivative_symbol(g, 3, 2, ex, ey, SlipDerivative::Spectral),
            cplx(0.0, ex * g.qx(3) + ey * g.qy(2)));
}

// The solver's table of upwind symbols (computed once per solve) gives the slope and the
// resolvent the numbers they compute without it, to the bit.
TEST(Elastic, SlipSymbolTableGivesTheSameNumbers) {
  const Grid g{24, 18, 2.0, 1.5};
  const ElasticBody body(g, homogeneous_body(1.0, 0.3, 0.2, true));
  const double th = 0.4, ex = std::cos(th), ey = std::sin(th);
  std::vector<cplx> a(g.spectral_size()), b(a.size()), c(a.size());
  Rng rng(3);
  for (std::size_t k = 0; k < a.size(); ++k) {
    a[k] = {rng.uniform() - 0.5, rng.uniform() - 0.5};
    b[k] = {rng.uniform() - 0.5, rng.uniform() - 0.5};
    c[k] = {rng.uniform() - 0.5, rng.uniform() - 0.5};
  }
  for (SlipDerivative d : {SlipDerivative::Upwind, SlipDerivative::Upwind2}) {
    const std::vector<cplx> table = body.slip_symbols(ex, ey, d);
    std::vector<cplx> u1(a.size()), v1(a.size()), u2(a.size()), v2(a.size());
    body.inplane_slope(a.data(), b.data(), c.data(), ex, ey, u1.data(), v1.data(), 0.7, -0.7, d);
    body.inplane_slope(a.data(), b.data(), c.data(), ex, ey, u2.data(), v2.data(), 0.7, -0.7, d,
                       table.data());
    EXPECT_EQ(u1, u2);
    EXPECT_EQ(v1, v2);
    std::vector<cplx> x1 = a, y1 = b, x2 = a, y2 = b;
    body.slip_resolvent(x1.data(), y1.data(), ex, ey, 0.3, 0.5, d);
    body.slip_resolvent(x2.data(), y2.data(), ex, ey, 0.3, 0.5, d, table.data());
    EXPECT_EQ(x1, x2);
    EXPECT_EQ(y1, y2);
    EXPECT_NE(x1, a);  // the resolvent did something
  }
}

TEST(Rolling, LateralCreepageAndDerivativeAreChecked) {
  for (const auto& [set, key] : std::vector<std::pair<std::string, std::string>>{
           {"friction.slip_derivative=\"central\"", "friction.slip_derivative"},
           {"friction.slip_derivative=1", "friction.slip_derivative"},
           {"friction.lateral_creepage=nan", "friction.lateral_creepage"},
           {"friction.lateral_creepage=1e7", "friction.lateral_creepage"}}) {
    try {
      (void)parse_config(kSphere, "test.toml", {set});
      ADD_FAILURE() << set << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  try {
    (void)parse_config(kSphere, "test.toml",
                       {"friction.coefficient=0", "friction.creepage=1", "friction.lateral_creepage=0.01"});
    ADD_FAILURE() << "lateral creepage without friction was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("friction.lateral_creepage"), std::string::npos) << e.what();
  }
}

// The shipped example runs as its comment says (at a quarter of its cells here).
TEST(Rolling, ExampleRollingSphereSticksAndPullsForward) {
  std::ifstream in(std::string(GFMD_SOURCE_DIR) + "/examples/rolling_sphere.toml");
  ASSERT_TRUE(in) << "examples/rolling_sphere.toml";
  std::stringstream text;
  text << in.rdbuf();
  const auto r = solve(text.str(), {"grid.nx=64", "output.png=false"});
  ASSERT_TRUE(r.info.converged) << r.info.status;
  EXPECT_GT(r.observables.stick_fraction, 0.95);
  EXPECT_GT(r.observables.tangential_force_x, 0.0);
  EXPECT_LT(r.observables.energy_balance_error_exact, 1e-6);
}
