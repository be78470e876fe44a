// Coulomb's set-valued law (stick) on a viscoelastic body: tractive rolling of a cylinder in its
// relaxed and glassy limits against the elastic solves, the regularised law tending to the exact
// one, and the energy balance of rolling with stick over a layer at the loss peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gfmd/contact/observables.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/elastic/viscoelastic.hpp"
#include "gfmd/surface/topography.hpp"

using namespace gfmd;

namespace {

constexpr double kPi = std::numbers::pi;

ViscoelasticParams sls(double einf, double v) {
  ViscoelasticParams p;
  p.model = ViscoelasticParams::Model::StandardLinearSolid;
  p.high_frequency_modulus = einf;
  p.relaxation_time = 1.0;
  p.velocity = v;
  return p;
}

struct Rolled {
  ContactFields f;
  SolveInfo info;
  Observables o;
};

// Rolling at `creepage` with Coulomb's law (mu_c = 0.3), exact (eps = 0) or regularised.
Rolled roll(const Grid& g, const Topography& topo, const ElasticParams& ep, const ViscoelasticParams& ve,
            const LoadParams& load, double creepage, double eps = 0.0, double lateral = 0.0) {
  const ElasticBody body(g, ep, ve);
  SolverParams sp;
  sp.tolerance = 1e-10;
  FrictionParams fr;
  fr.coefficient = 0.3;
  fr.creepage = creepage;
  fr.lateral_creepage = lateral;
  fr.regularization = eps;
  InteractionParams hard;
  hard.hard_wall = true;
  ContactSolver solver(body, topo, hard, fr, sp);
  Rolled r;
  r.info = solver.solve(load, r.f);
  r.o = compute_observables(solver.fft(), topo, fr, r.f, r.info);
  return r;
}

double max_diff(const RealField& a, const RealField& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// A cylinder along y (every mode but the mean varies along the rolling direction x) rolling with
// a small creepage over a standard linear solid, nu = 0.3 (coupled): most of the contact sticks.
// At omega tau <= 1e-9 every mode is relaxed: the exact rolling solve of the elastic body with E0;
// at omega tau >= 1e9 every mode is glassy: the elastic solve with E_inf (pressure and tractions to
// 1e-6 of their largest value, the forces to 1e-6).
const Grid kStrip{128, 8, 1.0, 1.0 / 16};

TEST(ViscoelasticStick, RollingInTheRelaxedAndGlassyLimitsIsTheElasticRolling) {
  const Topography topo = make_cylinder(kStrip, 1.0, 'y');
  ElasticParams ep;
  ep.poisson = 0.3;
  const double einf = 5.0;
  for (const double v : {1e-9, 1e9}) {
    const double e = v > 1 ? einf : 1.0;
    const LoadParams load{LoadMode::Pressure, 0.01 * e};  // the same contact width at both ends
    const Rolled ve = roll(kStrip, topo, ep, sls(einf, v), load, 1e-4);
    ASSERT_TRUE(ve.info.converged) << ve.info.status;
    ElasticParams ref = ep;
    ref.contact_modulus = e;
    const Rolled el = roll(kStrip, topo, ref, ViscoelasticParams{}, load, 1e-4);
    ASSERT_TRUE(el.info.converged) << el.info.status;
    EXPECT_GT(el.o.stick_fraction, 0.2) << "v0 = " << v;
    EXPECT_LT(el.o.stick_fraction, 1.0) << "v0 = " << v;
    EXPECT_EQ(ve.o.stick_fraction, el.o.stick_fraction) << "v0 = " << v;
    const double pmax = el.o.max_pressure;
    EXPECT_LT(max_diff(ve.f.pressure, el.f.pressure) / pmax, 1e-6) << "v0 = " << v;
    EXPECT_LT(max_diff(ve.f.tx, el.f.tx) / (0.3 * pmax), 1e-6) << "v0 = " << v;
    EXPECT_NEAR(ve.o.tangential_force / el.o.tangential_force, 1.0, 1e-6) << "v0 = " << v;
    EXPECT_LT(std::abs(ve.o.hysteresis_friction), 1e-6) << "v0 = " << v;
  }
}

// Between the limits (omega tau = 0.1 .. 10 over the contact) the solution obeys Coulomb's law
// point by point, read from its own displacements (the body's response applied, the slip
// v = xi e_s + eta e_perp + (e_s.grad) u in the solve's upwind derivative; a lateral creepage eta
// too): where a point sticks |tau| <= mu_c p
// and its slip speed is below 1e-6 xi; where it slips (above 1e-2 xi: the stick zone's edge slips
// too slowly to resolve) |tau| = mu_c p and tau is along v, both to 1e-6.
TEST(ViscoelasticStick, BetweenTheLimitsTheSolutionObeysCoulombsLaw) {
  const Topography topo = make_cylinder(kStrip, 1.0, 'y');
  ElasticParams ep;
  ep.poisson = 0.3;
  const double xi = 0.01, eta = 0.004, mu = 0.3;
  const Rolled r = roll(kStrip, topo, ep, sls(10.0, 0.1), LoadParams{LoadMode::Pressure, 0.01}, xi, 0.0, eta);
  ASSERT_TRUE(r.info.converged) << r.info.status;
  EXPECT_GT(r.o.stick_fraction, 0.1);
  EXPECT_LT(r.o.stick_fraction, 0.9);
  EXPECT_GT(r.o.hysteresis_friction, 1e-4);
  const FFT fft(kStrip);
  FrictionParams fr;
  fr.coefficient = mu;
  fr.creepage = xi;
  fr.lateral_creepage = eta;
  RealField vx, vy;
  slip_velocity(fft, fr, r.f.ux, r.f.uy, vx, vy);
  double stuck_ratio = 0.0, stuck_speed = 0.0, slip_bound = 0.0, slip_angle = 0.0;
  int stuck = 0, slipping = 0;
  for (std::size_t i = 0; i < kStrip.size(); ++i) {
    const double p = r.f.pressure[i];
    if (!(p > 0)) continue;
    const double t = std::hypot(r.f.tx[i], r.f.ty[i]), v = std::hypot(vx[i], vy[i]);
    if (r.f.stick[i]) {
      ++stuck;
      stuck_ratio = std::max(stuck_ratio, t / (mu * p));
      stuck_speed = std::max(stuck_speed, v / xi);
    } else if (v > 1e-2 * xi) {
      ++slipping;
      slip_bound = std::max(slip_bound, std::abs(t / (mu * p) - 1.0));
      // The sine of the angle between tau and v, and tau.v > 0 (the same direction, not opposite).
      slip_angle = std::max(slip_angle, std::abs(r.f.tx[i] * vy[i] - r.f.ty[i] * vx[i]) / (t * v));
      if (!(r.f.tx[i] * vx[i] + r.f.ty[i] * vy[i] > 0)) slip_angle = 1.0;
    }
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipping, 0);
  EXPECT_LE(stuck_ratio, 1.0 + 1e-9);
  EXPECT_LT(stuck_speed, 1e-6);
  EXPECT_LT(slip_bound, 1e-6);
  EXPECT_LT(slip_angle, 1e-6);
}

// Rolling with stick over a nu = 0.3 layer (h = 0.3 L), a wave in full contact at the loss peak:
// the driving work per speed (xi sum tau.e_s + the downhill force of p) goes into the interface's
// slip (with the upwind derivative's own share) and the body's hysteresis, to 1e-6; the
// hysteresis from the fields and from the spectrum agree to 1e-9; part of the contact sticks.
TEST(ViscoelasticStick, RollingWithStickBalancesItsWork) {
  const double lx = 1.0, amp = 0.005, k = 2 * kPi / lx;
  const Grid g{64, 4, lx, lx / 16};
  Topography topo{g, RealField(g.size()), "array"};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      topo.h[static_cast<std::size_t>(iy) * g.nx + ix] = -amp * std::cos(k * lx * ix / g.nx);
  ElasticParams ep;
  ep.poisson = 0.3;
  ep.thickness = 0.3;
  const Rolled r = roll(g, topo, ep, sls(10.0, 1.0 / k), LoadParams{LoadMode::Pressure, 0.2}, 0.002);
  ASSERT_TRUE(r.info.converged) << r.info.status;
  ASSERT_EQ(r.o.relative_contact_area, 1.0);
  EXPECT_GT(r.o.stick_fraction, 0.05);
  EXPECT_LT(r.o.stick_fraction, 0.95);
  EXPECT_GT(r.o.hysteresis_friction, 0.0);
  EXPECT_LT(r.o.energy_balance_error_exact, 1e-6);
  EXPECT_LT(r.o.hysteresis_balance_error, 1e-9);
}

}  // namespace
