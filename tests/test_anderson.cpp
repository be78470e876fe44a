// Anderson acceleration of a fixed point split over several arrays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gfmd/anderson.hpp"

using namespace gfmd;

namespace {
// Steps to reach |G(x) - x|_inf < 1e-10 for the linear map G(x, y) = R (x, y) + b, a rotation
// by 1 rad scaled by 0.97 per pair of entries (a slow, rotating contraction like the slip
// feedback), or -1 if 2000 steps do not.
int steps_to_converge(int depth, double beta) {
  const std::size_t n = 50;
  std::vector<double> x(n, 0.0), y(n, 0.0), gx(n), gy(n);
  AndersonMixer mixer(depth, beta);
  const double c = 0.97 * std::cos(1.0), s = 0.97 * std::sin(1.0);
  for (int it = 0; it < 2000; ++it) {
    double res = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      gx[i] = c * x[i] - s * y[i] + 1.0 + 0.01 * static_cast<double>(i);
      gy[i] = s * x[i] + c * y[i] - 0.5;
      res = std::max({res, std::abs(gx[i] - x[i]), std::abs(gy[i] - y[i])});
    }
    if (res < 1e-10) return it;
    mixer.step({x.data(), y.data()}, {gx.data(), gy.data()}, n);
  }
  return -1;
}
}  // namespace

TEST(Anderson, AcceleratesARotatingContraction) {
  const int plain = steps_to_converge(0, 1.0);
  const int mixed = steps_to_converge(5, 1.0);
  std::printf("plain %d steps, Anderson(5) %d steps\n", plain, mixed);
  ASSERT_GT(plain, 0);
  ASSERT_GT(mixed, 0);
  EXPECT_LT(mixed * 5, plain);
  // After a reset the history is empty and the next step is plain relaxation.
  AndersonMixer m(3, 0.5);
  std::vector<double> x{1.0}, g{3.0};
  m.step({x.data()}, {g.data()}, 1);
  EXPECT_DOUBLE_EQ(x[0], 2.0);
  m.reset();
  EXPECT_EQ(m.history(), 0u);
}
