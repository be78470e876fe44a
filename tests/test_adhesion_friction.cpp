// Adhesion with sliding friction: the friction law reads the repulsive (compressive) part of the
// pressure; Menga, Carbone & Dini's claim that a uniform interfacial shear leaves the adhesive
// sphere unchanged where nothing couples it to the normal problem; what coupling does.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/surface/topography.hpp"
#include "maugis_reference.hpp"
#include "test_util.hpp"

using namespace gfmd;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kW = 1e-3;  // work of adhesion / (E* R)

// The Dugdale stress for the Maugis parameter lambda (R = 1, E* = 1, K = 4/3) and the radius unit
// (pi w R^2 / K)^(1/3).
double sigma0(double lambda) { return lambda / 2 * std::cbrt(kPi * kW * (16.0 / 9.0)); }
double radius_unit() { return std::cbrt(kPi * kW * 0.75); }

struct Point {
  double approach, force, area, tangential, traction, repulsive;
  bool converged;
  std::string status;
};

// An approach-controlled path of a sphere R = 1 sliding along x over a half-space of Poisson
// ratio nu, warm-started point to point, with the friction `fric` (coefficient 0: frictionless).
std::vector<Point> sliding_path(double lambda, double nu, int nx, double lx, const FrictionParams& fric,
                                const std::vector<double>& approaches) {
  const Grid grid{nx, nx, lx, lx};
  ElasticParams ep;
  ep.poisson = nu;
  const ElasticBody body(grid, ep);
  InteractionParams inter;
  inter.hard_wall = true;
  inter.work_of_adhesion = kW;
  inter.range = kW / sigma0(lambda);
  ContactSolver solver(body, make_hertz(grid, 1.0, 1.0), inter, fric, SolverParams{});
  ContactFields f;
  std::vector<Point> out;
  for (const double d : approaches) {
    const SolveInfo info = solver.solve(LoadParams{LoadMode::Approach, d}, f);
    Point pt{d, 0, 0, 0, 0, 0, info.converged, info.status};
    for (std::size_t i = 0; i < f.pressure.size(); ++i) {
      pt.force += f.pressure[i] * grid.cell_area();
      pt.area += f.in_contact(i) ? grid.cell_area() : 0.0;
      pt.tangential += f.tx[i] * grid.cell_area();
      pt.traction += std::hypot(f.tx[i], f.ty[i]) * grid.cell_area();
      pt.repulsive += f.repulsion(i) * grid.cell_area();
    }
    out.push_back(pt);
  }
  return out;
}

// A sphere R = 1 sliding on a nu = 0.3 half-space with adhesion (lambda = 1) and Coulomb friction.
const char* kSliding = R"(
[grid]
nx = 64
lx = 1.5
[elastic]
poisson = 0.3
[indenter]
type = "hertz"
radius = 1.0
[load]
approach = 0.0
[interaction]
model = "adhesive"
work_of_adhesion = 1e-3
range = 0.0113
[friction]
coefficient = 0.4
[output]
analysis = false
)";

FrictionParams tresca(double tau0) {
  // Coulomb's coefficient far above any tau0 / p: the shear strength tau0 wherever the repulsion
  // is not tiny, i.e. a uniform shear over the contact.
  FrictionParams fr;
  fr.coefficient = 1e3;
  fr.law.kind = FrictionLawKind::Tresca;
  fr.law.shear_strength = tau0;
  return fr;
}

}  // namespace

TEST(AdhesionFriction, UniformShearLeavesTheIncompressibleSphereOnMaugisCurve) {
  // Menga, Carbone & Dini (JMPS 2018, corrigendum 2019; arXiv 1710.06506): a uniform tangential
  // stress over the contact leaves the adhesive solution (contact radius, pull-off) as without
  // shear. On an incompressible half-space nothing couples the shear to the normal problem, so
  // the sliding path is the frictionless one to the solver's tolerance (1e-8: forces within 1e-6
  // relative), on Maugis's curve (lambda = 1, 128^2 on 1.5 R: the pull-off within 3 %, measured
  // 0.6 %; the radius within 3 %), with the tangential force tau0 times the contact area (minus
  // the edge cells where mu_c p_rep < tau0: within 5 %).
  const double lambda = 1.0, tau0 = 0.02;
  std::vector<double> ds = {0.01, 0.005, 0.0};
  for (int k = 0; k <= 6; ++k) ds.push_back(-0.002 - 0.001 * k);
  const auto slid = sliding_path(lambda, 0.5, 128, 1.5, tresca(tau0), ds);
  const auto still = sliding_path(lambda, 0.5, 128, 1.5, FrictionParams{}, ds);
  double least = 0.0;
  for (std::size_t k = 0; k < ds.size(); ++k) {
    ASSERT_TRUE(slid[k].converged) << "approach " << ds[k] << ": " << slid[k].status;
    ASSERT_TRUE(still[k].converged) << still[k].status;
    EXPECT_NEAR(slid[k].force, still[k].force, 1e-6 * std::abs(still[k].force) + 1e-12)
        << "approach " << ds[k];
    EXPECT_EQ(slid[k].area, still[k].area) << "approach " << ds[k];
    if (slid[k].area > 0) {
      EXPECT_NEAR(slid[k].tangential / (tau0 * slid[k].area), 1.0, 0.05) << "approach " << ds[k];
      const double P = slid[k].force / (kPi * kW);
      if (k <= 1) {  // away from the pull-off, where the force fixes the radius
        const double A = std::sqrt(slid[k].area / kPi) / radius_unit();
        EXPECT_NEAR(A / gfmd::testing::maugis_radius(lambda, P), 1.0, 0.03) << "force " << P;
      }
    }
    least = std::min(least, slid[k].force);
  }
  EXPECT_NEAR(least / (kPi * kW) / gfmd::testing::maugis_pull_off(lambda), 1.0, 0.03);
}

TEST(AdhesionFriction, CoulombReadsTheRepulsiveSideOfThePressure) {
  // Coulomb's law with adhesion bounds the traction by mu_c times the repulsion p + a (the
  // compressive part of the pressure, Derjaguin's two-term friction: F_t = mu_c (F_z + F_adh)),
  // so where every contact point slips the sum of |tau| is mu_c times the repulsive force,
  // not mu_c times the net force (which is tensile near the pull-off). On a compressible
  // half-space (nu = 0.3) the coupling also moves the normal solution: the force at the same
  // approach differs from the frictionless one, the friction converges, and the net force stays
  // tensile at a negative approach.
  FrictionParams fr;
  fr.coefficient = 0.3;
  const std::vector<double> ds = {0.01, 0.0, -0.004};
  const auto slid = sliding_path(1.0, 0.3, 64, 1.5, fr, ds);
  const auto still = sliding_path(1.0, 0.3, 64, 1.5, FrictionParams{}, ds);
  for (std::size_t k = 0; k < ds.size(); ++k) {
    ASSERT_TRUE(slid[k].converged) << "approach " << ds[k] << ": " << slid[k].status;
    ASSERT_GT(slid[k].area, 0.0);
    EXPECT_NEAR(slid[k].traction / (fr.coefficient * slid[k].repulsive), 1.0, 1e-9) << "approach " << ds[k];
    EXPECT_GT(std::abs(slid[k].force - still[k].force), 1e-4 * std::abs(still[k].force))
        << "approach " << ds[k];
  }
  EXPECT_LT(slid.back().force, 0.0);
  EXPECT_GT(slid.back().tangential, 0.0);
}

TEST(AdhesionFriction, SlidingAdhesiveContactBalancesItsEnergy) {
  // Through the case pipeline: the work of the driving force (the tangential force plus the
  // downhill force of the net pressure on the tilted indenter) against the dissipation by slip
  // (summary.json's energy_balance_error_exact). Not to round-off: the net pressure jumps by
  // sigma0 at the cohesive zone's outer edge and the cell law is conservative only at a fixed
  // spread; the error falls with refinement (measured 9.7e-4, 5.2e-4, 1.2e-5 at 64, 128, 256^2;
  // without adhesion 2.9e-5 at 128^2). The summary carries the adhesive figures beside the
  // friction ones.
  const CaseResult coarse = gfmd::testing::solve(kSliding, {});
  const CaseResult fine = gfmd::testing::solve(kSliding, {"grid.nx=256"});
  for (const CaseResult* r : {&coarse, &fine}) {
    ASSERT_TRUE(r->info.converged) << r->info.status;
    const Observables& o = r->observables;
    EXPECT_TRUE(o.adhesive);
    EXPECT_TRUE(o.friction);
    EXPECT_GT(o.adhesive_force, o.repulsive_force);  // tensile at approach 0
    // sum |tau| dA (friction_force_downhill less the downhill force) = mu_c times the repulsion.
    EXPECT_NEAR((o.friction_force_downhill - o.downhill_force) / (0.4 * o.repulsive_force), 1.0, 1e-9);
    // The elastic energy with the tractions' share, 1/2 sum (tau.u_t - p u_z) dA: positive.
    EXPECT_GT(r->info.elastic_energy, 0.0);
  }
  EXPECT_LT(coarse.observables.energy_balance_error_exact, 2e-3);
  EXPECT_LT(fine.observables.energy_balance_error_exact, 1e-4);
  EXPECT_LT(fine.observables.energy_balance_error_exact, 0.1 * coarse.observables.energy_balance_error_exact);
}

TEST(AdhesionFriction, ASteepTrescaCapUnderCouplingSaysWhatToChange) {
  // With mu_c -> inf the tresca law switches tau0 on and off at the contact's edge, and on a
  // compressible half-space the shear moves the edge: the fixed point may not settle (measured
  // through the pipeline, tau0 = 0.02, 0.05, 0.06 E* at approach 0.01 and 0.008 R, lambda = 1,
  // nu = 0.25, 128^2: mu_c = 3 and 5 settle in all six, 10 in five, 30 and 100 in four, 300 in
  // two, 1000 in three; at 256^2 mu_c = 5 fails where 3 settles: the example's mu_c is 3). The failure says
  // what to change, and the change works.
  const std::string text =
      gfmd::testing::read_file(std::string(GFMD_SOURCE_DIR) + "/examples/adhesive_sliding_sphere.toml");
  const std::vector<std::string> sets = {"friction.shear_strength=0.05", "load.approach=0.01"};
  std::vector<std::string> steep_sets = sets;
  steep_sets.push_back("friction.coefficient=1000");
  const CaseResult steep = run_case(parse_config(text, "adhesive_sliding_sphere.toml", steep_sets));
  ASSERT_FALSE(steep.info.converged);
  EXPECT_NE(steep.info.status.find("lower friction.coefficient"), std::string::npos) << steep.info.status;
  const CaseResult gentle = gfmd::testing::solve(text, sets);
  EXPECT_TRUE(gentle.info.converged) << gentle.info.status;
}

TEST(AdhesionFriction, TwoEqualBodiesSlideWithTheFrictionlessAdhesiveContact) {
  // Two elastic bodies of the same material (nu = 0.3, E* = 2 each: the pair's E* = 1) have
  // Dundurs' beta = 0: the friction does not reach the normal problem, so the sliding adhesive
  // contact is the frictionless one (forces within 1e-6, the same contact cells), and the driving
  // work balances the slip's dissipation to round-off (measured 2e-15; the bodies' normal
  // displacements from the shear cancel).
  const std::vector<std::string> pair = {"elastic.contact_modulus=2.0", "indenter.contact_modulus=2.0",
                                         "indenter.poisson=0.3"};
  std::vector<std::string> frictionless = pair;
  frictionless.push_back("friction.coefficient=0");
  const CaseResult slid = gfmd::testing::solve(kSliding, pair);
  const CaseResult still = gfmd::testing::solve(kSliding, frictionless);
  const Observables &a = slid.observables, &b = still.observables;
  EXPECT_NEAR(a.normal_force, b.normal_force, 1e-6 * std::abs(b.normal_force));
  EXPECT_EQ(a.relative_contact_area, b.relative_contact_area);
  EXPECT_LT(a.normal_force, 0.0);
  EXPECT_LT(a.energy_balance_error_exact, 1e-10);
  EXPECT_NEAR((a.friction_force_downhill - a.downhill_force) / (0.4 * a.repulsive_force), 1.0, 1e-9);
}
