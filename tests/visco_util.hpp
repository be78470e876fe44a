// Helpers shared by the viscoelastic test files: a standard linear solid, a wave along x, and a
// hard-wall solve with its observables.
#pragma once

#include <cmath>
#include <numbers>
#include <string>

#include "gfmd/contact/observables.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/elastic/viscoelastic.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd::testing::visco {

constexpr double kPi = std::numbers::pi;

// A sphere on a standard linear solid (E_inf = 10 E0, tau = 1) sliding at v0 = 0.1, 32^2: the
// case the input checks start from (other models and bodies by without_keys and --set values).
inline const std::string kSlsSphere = R"(
[grid]
nx = 32
lx = 2.0
[elastic]
viscoelastic = "sls"
high_frequency_modulus = 10.0
relaxation_time = 1.0
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
[friction]
velocity = 0.1
)";

inline ViscoelasticParams sls(double einf, double tau, double v) {
  ViscoelasticParams p;
  p.model = ViscoelasticParams::Model::StandardLinearSolid;
  p.high_frequency_modulus = einf;
  p.relaxation_time = tau;
  p.velocity = v;
  return p;
}

// A sinusoid along x, uniform along y: h = -amp cos(2 pi x / lx) (every mode but the mean has
// q_x != 0).
inline Topography wave(const Grid& g, double amp) {
  Topography t{g, RealField(g.size()), "array"};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      t.h[static_cast<std::size_t>(iy) * g.nx + ix] = -amp * std::cos(2 * kPi * ix / g.nx);
  return t;
}

struct Solved {
  ContactFields f;
  SolveInfo info;
  Observables o;
};
inline Solved solve_with(const Grid& g, const Topography& topo, const ElasticParams& ep,
                         const ViscoelasticParams& ve, const LoadParams& load, double mu = 0.0) {
  const ElasticBody body(g, ep, ve);
  SolverParams sp;
  sp.tolerance = 1e-10;
  FrictionParams fr;
  fr.direction_deg = ve.direction_deg;
  fr.coefficient = mu;
  fr.regularization = mu > 0 ? 0.01 : 0.0;
  InteractionParams hard;
  hard.hard_wall = true;
  ContactSolver solver(body, topo, hard, fr, sp);
  Solved s;
  s.info = solver.solve(load, s.f);
  const FFT& fft = solver.fft();
  s.o = compute_observables(fft, topo, fr, s.f, s.info);
  return s;
}

}  // namespace gfmd::testing::visco
