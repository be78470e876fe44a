// Anderson acceleration (contact/anderson.hpp) on maps whose fixed point is known.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/core/backend.hpp"

using namespace gfmd;

namespace {

// G(x) = A x + b with A = Q diag(rho_k) Q^T, Q a product of plane rotations: a contraction
// with spectral radius max rho_k, fixed point x* = (I - A)^{-1} b, which we choose first.
struct LinearMap {
  std::size_t n;
  std::vector<double> a, xstar, b;
  explicit LinearMap(std::size_t n_, double rho_max) : n(n_), a(n_ * n_, 0.0), xstar(n_), b(n_) {
    std::vector<double> q(n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) q[i * n + i] = 1.0;
    for (std::size_t i = 0; i + 1 < n; ++i) {  // rotate rows i, i+1 by 0.7 rad
      const double c = std::cos(0.7), s = std::sin(0.7);
      for (std::size_t k = 0; k < n; ++k) {
        const double u = q[i * n + k], v = q[(i + 1) * n + k];
        q[i * n + k] = c * u - s * v;
        q[(i + 1) * n + k] = s * u + c * v;
      }
    }
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t c = 0; c < n; ++c)
        for (std::size_t k = 0; k < n; ++k) {
          const double rho = rho_max * (0.2 + 0.8 * static_cast<double>(k) / static_cast<double>(n - 1));
          a[r * n + c] += q[k * n + r] * rho * q[k * n + c];
        }
    for (std::size_t i = 0; i < n; ++i) xstar[i] = std::sin(1.0 + static_cast<double>(i));
    for (std::size_t r = 0; r < n; ++r) {
      double ax = 0;
      for (std::size_t c = 0; c < n; ++c) ax += a[r * n + c] * xstar[c];
      b[r] = xstar[r] - ax;
    }
  }
  [[nodiscard]] std::vector<double> apply(const std::vector<double>& x) const {
    std::vector<double> g(n);
    for (std::size_t r = 0; r < n; ++r) {
      double v = b[r];
      for (std::size_t c = 0; c < n; ++c) v += a[r * n + c] * x[c];
      g[r] = v;
    }
    return g;
  }
  [[nodiscard]] double error(const std::vector<double>& x) const {
    double e = 0;
    for (std::size_t i = 0; i < n; ++i) e = std::max(e, std::abs(x[i] - xstar[i]));
    return e;
  }
};

// Error after `steps` Anderson steps (depth m) from x = 0.
double anderson_error(const LinearMap& map, int m, int steps, double omega,
                      std::vector<double>* out = nullptr) {
  AndersonMixer mix(m);
  mix.resize(map.n);
  std::vector<double> x(map.n, 0.0);
  for (int k = 0; k < steps; ++k) {
    const std::vector<double> g = map.apply(x);
    mix.step(
        omega, [&](std::size_t e) { return x[e]; }, [&](std::size_t e) { return g[e]; },
        [&](std::size_t e, double v) { x[e] = v; });
  }
  if (out) *out = x;
  return map.error(x);
}

}  // namespace

TEST(Anderson, SolvesALinearContractionInAboutDimensionSteps) {
  // On a linear map Anderson(m >= n) is equivalent to GMRES: the fixed point after about n+1
  // steps, up to the single precision of the stored differences. Plain iteration with
  // spectral radius 0.95 still has 0.95^12 ~ 0.5 of its error after 12 steps.
  const LinearMap map(6, 0.95);
  const double plain = [&] {
    std::vector<double> x(map.n, 0.0);
    for (int k = 0; k < 12; ++k) x = map.apply(x);
    return map.error(x);
  }();
  EXPECT_GT(plain, 0.1);
  EXPECT_LT(anderson_error(map, 8, 12, 1.0), 1e-5);
  // Damped mixing (omega = 0.5) converges too, a little later.
  EXPECT_LT(anderson_error(map, 8, 20, 0.5), 1e-5);
}

TEST(Anderson, ShortHistoryStillAccelerates) {
  const LinearMap map(40, 0.95);
  const double start = map.error(std::vector<double>(map.n, 0.0));
  EXPECT_LT(anderson_error(map, 5, 60, 1.0), 1e-4 * start);
}

TEST(Anderson, RestartAndClearHistoryKeepConvergence) {
  const LinearMap map(6, 0.9);
  AndersonMixer mix(4);
  mix.resize(map.n);
  std::vector<double> x(map.n, 0.0);
  for (int k = 0; k < 40; ++k) {
    if (k == 5) mix.clear_history();
    if (k == 12) mix.restart();
    if (k == 6) {
      EXPECT_EQ(mix.history(), 1U);
    }
    if (k == 13) {
      EXPECT_EQ(mix.history(), 0U);
    }
    const std::vector<double> g = map.apply(x);
    mix.step(
        1.0, [&](std::size_t e) { return x[e]; }, [&](std::size_t e) { return g[e]; },
        [&](std::size_t e, double v) { x[e] = v; });
  }
  EXPECT_LT(map.error(x), 1e-5);
}

TEST(Anderson, GrowingVectorStartsNewEntriesWithZeroHistory) {
  // The first 3 components are iterated alone, then the vector grows to 6 (the friction
  // solve's support growing): the mixer must go on to the fixed point of the whole map.
  const LinearMap map(6, 0.9);
  AndersonMixer mix(8);
  mix.resize(3);
  std::vector<double> x(map.n, 0.0);
  for (int k = 0; k < 30; ++k) {
    if (k == 4) mix.resize(6);
    const std::vector<double> g = map.apply(x);
    mix.step(
        1.0, [&](std::size_t e) { return x[e]; }, [&](std::size_t e) { return g[e]; },
        [&](std::size_t e, double v) { x[e] = v; });
  }
  EXPECT_EQ(mix.size(), 6U);
  EXPECT_LT(map.error(x), 1e-5);
}

TEST(Anderson, SameIteratesOnEveryBackend) {
  const LinearMap map(50, 0.97);
  std::vector<double> a, b;
  {
    const BackendScope s(serial_backend());
    anderson_error(map, 6, 15, 0.7, &a);
  }
  {
    const BackendScope s(threads_backend());
    anderson_error(map, 6, 15, 0.7, &b);
  }
  EXPECT_EQ(a, b);
}

TEST(Anderson, SmallSolveAndBadDepth) {
  // A small SPD system, checked by substitution (the 1e-10 trace shift is within 1e-8).
  const std::vector<double> M{4, 1, 0, 1, 3, 1, 0, 1, 2}, rhs{1, 2, 3};
  const auto x = anderson_solve_small(M, rhs);
  for (std::size_t r = 0; r < 3; ++r) {
    double v = 0;
    for (std::size_t c = 0; c < 3; ++c) v += M[r * 3 + c] * x[c];
    EXPECT_NEAR(v, rhs[r], 1e-8);
  }
  EXPECT_THROW(AndersonMixer(0), std::invalid_argument);
}
