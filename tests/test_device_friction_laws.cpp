// The friction laws on the CUDA backend: each law's bound, its stick disc and (for a law that
// changes with the slip speed) its resolvent are FrictionLaw's GFMD_HD functions, one text for
// host and device; these cases solve on both and compare fields and observables to 1e-9
// (against solves to 1e-10 and tighter), where a CUDA device is usable (skipped with the reason
// elsewhere: CI has no GPU).
#include "device_helpers.hpp"

using namespace gfmd;
using namespace gfmd::testing;

// Tractive rolling with a static peak (the velocity law with stick: the step is raised above the
// law's steepest fall, the resolvent's Newton solve per slipping point).
TEST(Device, VelocityLawRollingWithAStaticPeakMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("rolling_static_peak"), {}, 1e-9);
}

// The regularised velocity law (mu_s = 1.3 falling to mu_k = 1) in full sliding on a layer.
TEST(Device, RegularisedVelocityLawSlidingMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("hertz_sliding"),
                    {"grid.nx=128", "friction.law=\"velocity\"", "friction.static_coefficient=1.3",
                     "friction.velocity_scale=0.1", "friction.regularization=0.01", "solver.tolerance=1e-11"},
                    1e-9);
}

// Rate strengthening, mu = mu_c + a ln(1 + |v|/v_c), in full sliding.
TEST(Device, RateLawSlidingMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("hertz_sliding"),
                    {"grid.nx=128", "friction.law=\"rate\"", "friction.rate_coefficient=0.05",
                     "friction.velocity_scale=0.1", "solver.tolerance=1e-11"},
                    1e-9);
}

// Coulomb capped at a shear strength (tresca) in rolling with stick on a compressible body: the
// cap (0.01 E*) acts where mu_c p exceeds it (p up to 0.077 E*).
TEST(Device, TrescaRollingWithStickMatchesTheHost) {
  REQUIRE_CUDA_DEVICE();
  compare_with_host(example("rolling_sphere"),
                    {"grid.nx=64", "elastic.poisson=0.3", "friction.creepage=0.002",
                     "friction.law=\"tresca\"", "friction.shear_strength=0.01", "solver.tolerance=1e-11"},
                    1e-9);
}
