// Tests of the algebraic multigrid (gfmd/amg.hpp): Galerkin hierarchy, symmetric
// preconditioner, convergence on Poisson problems with strongly varying coefficients,
// results independent of the thread count, bad input.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/flow/amg.hpp"

namespace {

using gfmd::AlgebraicMultigrid;
using gfmd::CsrMatrix;

// Compressed rows from a dense description: each row a list of (column, value), the
// diagonal first.
CsrMatrix from_rows(const std::vector<std::vector<std::pair<int, double>>>& rows) {
  CsrMatrix a;
  a.n = rows.size();
  a.ptr.push_back(0);
  for (const auto& r : rows) {
    for (const auto& [c, v] : r) {
      a.col.push_back(c);
      a.val.push_back(v);
    }
    a.ptr.push_back(a.col.size());
  }
  return a;
}

// Periodic-free 2D diffusion on nx x ny cells with face conductances k (random over
// `decades` decades when decades > 0, else 1), Dirichlet (a conductance of 1 to a fixed
// zero value) along the left edge: symmetric positive definite, an M-matrix.
CsrMatrix diffusion_2d(int nx, int ny, double decades, std::uint64_t seed) {
  gfmd::Rng rng(seed);
  std::vector<double> kx(static_cast<std::size_t>(nx * ny)), ky(kx.size());
  for (std::size_t i = 0; i < kx.size(); ++i) {
    kx[i] = decades > 0 ? std::pow(10.0, -decades * rng.uniform()) : 1.0;
    ky[i] = decades > 0 ? std::pow(10.0, -decades * rng.uniform()) : 1.0;
  }
  std::vector<std::vector<std::pair<int, double>>> rows(kx.size());
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const int i = iy * nx + ix;
      double d = ix == 0 ? 1.0 : 0.0;
      std::vector<std::pair<int, double>> off;
      auto link = [&](int j, double k) {
        d += k;
        off.emplace_back(j, -k);
      };
      if (ix > 0) link(i - 1, kx[static_cast<std::size_t>(i - 1)]);
      if (ix + 1 < nx) link(i + 1, kx[static_cast<std::size_t>(i)]);
      if (iy > 0) link(i - nx, ky[static_cast<std::size_t>(i - nx)]);
      if (iy + 1 < ny) link(i + nx, ky[static_cast<std::size_t>(i)]);
      rows[static_cast<std::size_t>(i)].emplace_back(i, d);
      for (const auto& e : off) rows[static_cast<std::size_t>(i)].push_back(e);
    }
  return from_rows(rows);
}

std::vector<double> random_vector(std::size_t n, std::uint64_t seed) {
  gfmd::Rng rng(seed);
  std::vector<double> v(n);
  for (double& x : v) x = rng.uniform() - 0.5;
  return v;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

TEST(Amg, CoarseOperatorsAreGalerkinProducts) {
  // A_c = P^T A P, with the columns of P taken from interpolate() of unit vectors.
  const CsrMatrix a = diffusion_2d(24, 20, 4.0, 3);
  AlgebraicMultigrid mg(a);
  ASSERT_GE(mg.levels(), 2);
  const std::size_t n = mg.level_size(0), nc = mg.level_size(1);
  ASSERT_LT(nc, n);
  std::vector<std::vector<double>> p(nc, std::vector<double>(n));
  std::vector<double> e(nc, 0.0);
  for (std::size_t j = 0; j < nc; ++j) {
    e[j] = 1.0;
    mg.interpolate(0, e.data(), p[j].data());
    e[j] = 0.0;
  }
  std::vector<std::vector<double>> ap(nc, std::vector<double>(n));
  for (std::size_t j = 0; j < nc; ++j) a.multiply(p[j].data(), ap[j].data());
  const CsrMatrix& ac = mg.level_matrix(1);
  double maxdiff = 0.0, maxval = 0.0;
  for (std::size_t i = 0; i < nc; ++i) {
    std::vector<double> row(nc, 0.0);
    for (std::size_t k = ac.ptr[i]; k < ac.ptr[i + 1]; ++k)
      row[static_cast<std::size_t>(ac.col[k])] += ac.val[k];
    EXPECT_EQ(ac.col[ac.ptr[i]], static_cast<std::int32_t>(i));  // diagonal first
    for (std::size_t j = 0; j < nc; ++j) {
      const double ref = dot(p[i], ap[j]);
      maxdiff = std::max(maxdiff, std::abs(row[j] - ref));
      maxval = std::max(maxval, std::abs(ref));
    }
  }
  EXPECT_LT(maxdiff, 1e-12 * maxval);
  // Coarse points are injected: every coarse unit vector interpolates to exactly one 1.
  for (std::size_t j = 0; j < nc; ++j) {
    int ones = 0;
    for (double v : p[j]) ones += v == 1.0 ? 1 : 0;
    EXPECT_GE(ones, 1);
  }
}

TEST(Amg, PreconditionerIsSymmetricPositiveDefinite) {
  const CsrMatrix a = diffusion_2d(60, 50, 6.0, 5);
  AlgebraicMultigrid mg(a);
  EXPECT_GE(mg.levels(), 3);
  const std::vector<double> u = random_vector(a.n, 1), v = random_vector(a.n, 2);
  std::vector<double> mu(a.n), mv(a.n);
  mg.precondition(u.data(), mu.data());
  mg.precondition(v.data(), mv.data());
  const double uv = dot(u, mv), vu = dot(v, mu);
  EXPECT_NEAR(uv, vu, 1e-12 * std::sqrt(dot(u, mu) * dot(v, mv)));
  EXPECT_GT(dot(u, mu), 0.0);
  EXPECT_GT(dot(v, mv), 0.0);
}

TEST(Amg, SolvesPoissonProblemsInFewIterations) {
  // Constant coefficients and coefficients spread over eight decades (cell by cell).
  for (double decades : {0.0, 8.0}) {
    const CsrMatrix a = diffusion_2d(200, 150, decades, 7);
    AlgebraicMultigrid mg(a);
    EXPECT_LT(mg.operator_complexity(), 3.0);
    const std::vector<double> x_true = random_vector(a.n, 9);
    std::vector<double> b(a.n), x(a.n);
    a.multiply(x_true.data(), b.data());
    const gfmd::CgOutcome cg = gfmd::amg_pcg(mg, b.data(), x.data(), 1e-10, 100);
    std::printf(
        "[ amg      ] 200x150, %g decades: %d levels, complexity %.2f, %d iterations, residual %.1e\n",
        decades, mg.levels(), mg.operator_complexity(), cg.iterations, cg.residual);
    EXPECT_TRUE(cg.converged);
    EXPECT_LE(cg.iterations, 25);
    EXPECT_LT(cg.residual, 2e-10);
    if (decades == 0.0) {
      double err = 0.0, ref = 0.0;
      for (std::size_t i = 0; i < a.n; ++i) {
        err = std::max(err, std::abs(x[i] - x_true[i]));
        ref = std::max(ref, std::abs(x_true[i]));
      }
      EXPECT_LT(err, 1e-6 * ref);
    }
  }
}

TEST(Amg, OneDimensionalProblemMatchesTheTridiagonalSolution) {
  // -u'' = 1 on (0, 1), u(0) = u(1) = 0, n interior points: the discrete solution is
  // exactly x (1 - x) / 2 at the nodes.
  const int n = 3000;
  const double h = 1.0 / (n + 1);
  std::vector<std::vector<std::pair<int, double>>> rows(n);
  for (int i = 0; i < n; ++i) {
    rows[static_cast<std::size_t>(i)].emplace_back(i, 2.0 / (h * h));
    if (i > 0) rows[static_cast<std::size_t>(i)].emplace_back(i - 1, -1.0 / (h * h));
    if (i + 1 < n) rows[static_cast<std::size_t>(i)].emplace_back(i + 1, -1.0 / (h * h));
  }
  AlgebraicMultigrid mg(from_rows(rows));
  std::vector<double> b(n, 1.0), x(n);
  const gfmd::CgOutcome cg = gfmd::amg_pcg(mg, b.data(), x.data(), 1e-12, 50);
  EXPECT_TRUE(cg.converged);
  EXPECT_LE(cg.iterations, 12);
  double err = 0.0;
  for (int i = 0; i < n; ++i) {
    const double xi = (i + 1) * h;
    err = std::max(err, std::abs(x[static_cast<std::size_t>(i)] - 0.5 * xi * (1 - xi)));
  }
  EXPECT_LT(err, 1e-9);
}

TEST(Amg, ResultsDoNotDependOnTheThreadCount) {
  const CsrMatrix a = diffusion_2d(260, 240, 5.0, 11);  // > 60 000 rows: parallel loops and blocks
  const std::vector<double> b = random_vector(a.n, 12);
  std::vector<std::vector<double>> xs;
  std::vector<int> its;
  const int saved = omp_get_max_threads();
  for (int t : {1, 2, 3}) {
    omp_set_num_threads(t);
    AlgebraicMultigrid mg(a);
    std::vector<double> x(a.n);
    its.push_back(gfmd::amg_pcg(mg, b.data(), x.data(), 1e-10, 100).iterations);
    xs.push_back(x);
  }
  omp_set_num_threads(saved);
  EXPECT_EQ(its[0], its[1]);
  EXPECT_EQ(its[0], its[2]);
  EXPECT_EQ(xs[0], xs[1]);
  EXPECT_EQ(xs[0], xs[2]);
}

// The 2D diffusion matrix plus `extra` random long-range links of conductance 1: rows
// couple to rows far away (other Gauss-Seidel blocks of the same colour, other blocks of
// the coarsening).
CsrMatrix with_long_links(int nx, int ny, int extra, std::uint64_t seed) {
  const CsrMatrix base = diffusion_2d(nx, ny, 3.0, seed);
  std::vector<std::vector<std::pair<int, double>>> rows(base.n);
  for (std::size_t i = 0; i < base.n; ++i)
    for (std::size_t k = base.ptr[i]; k < base.ptr[i + 1]; ++k)
      rows[i].emplace_back(base.col[k], base.val[k]);
  gfmd::Rng rng(seed + 1);
  for (int e = 0; e < extra; ++e) {
    const auto i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(base.n));
    const auto j = static_cast<std::size_t>(rng.uniform() * static_cast<double>(base.n));
    if (i == j) continue;
    rows[i][0].second += 1.0;
    rows[j][0].second += 1.0;
    rows[i].emplace_back(static_cast<int>(j), -1.0);
    rows[j].emplace_back(static_cast<int>(i), -1.0);
  }
  return from_rows(rows);
}

TEST(Amg, LongRangeCouplingsKeepTheCycleSymmetricAndThreadIndependent) {
  const CsrMatrix a = with_long_links(300, 250, 2000, 21);
  const std::vector<double> b = random_vector(a.n, 22);
  std::vector<std::vector<double>> xs;
  std::vector<int> its;
  const int saved = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    AlgebraicMultigrid mg(a);
    std::vector<double> x(a.n);
    const gfmd::CgOutcome cg = gfmd::amg_pcg(mg, b.data(), x.data(), 1e-10, 100);
    EXPECT_TRUE(cg.converged);
    EXPECT_LE(cg.iterations, 30);
    its.push_back(cg.iterations);
    xs.push_back(x);
    const std::vector<double> u = random_vector(a.n, 23), v = random_vector(a.n, 24);
    std::vector<double> mu(a.n), mv(a.n);
    mg.precondition(u.data(), mu.data());
    mg.precondition(v.data(), mv.data());
    EXPECT_NEAR(dot(u, mv), dot(v, mu), 1e-12 * std::sqrt(dot(u, mu) * dot(v, mv)));
  }
  omp_set_num_threads(saved);
  EXPECT_EQ(its[0], its[1]);
  EXPECT_EQ(xs[0], xs[1]);
}

TEST(Amg, UncoupledRowsAreSolvedOnTheFinestLevel) {
  // No couplings at all: nothing to coarsen, the finest level is the coarsest, too large for
  // the dense factorisation (relaxed by Gauss-Seidel instead, exact here).
  const int n = 5000;
  std::vector<std::vector<std::pair<int, double>>> rows(n);
  for (int i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)].emplace_back(i, 1.0 + i % 7);
  AlgebraicMultigrid mg(from_rows(rows));
  EXPECT_EQ(mg.levels(), 1);
  const std::vector<double> b = random_vector(static_cast<std::size_t>(n), 31);
  std::vector<double> x(static_cast<std::size_t>(n));
  const gfmd::CgOutcome cg = gfmd::amg_pcg(mg, b.data(), x.data(), 1e-12, 20);
  EXPECT_TRUE(cg.converged);
  EXPECT_LE(cg.iterations, 2);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(x[static_cast<std::size_t>(i)], b[static_cast<std::size_t>(i)] / (1.0 + i % 7), 1e-12);
}

TEST(Amg, BadMatricesAreRejected) {
  EXPECT_THROW(AlgebraicMultigrid(CsrMatrix{}), gfmd::InputError);
  // Diagonal not first.
  EXPECT_THROW(AlgebraicMultigrid(from_rows({{{1, -1.0}, {0, 2.0}}, {{1, 2.0}, {0, -1.0}}})),
               gfmd::InputError);
  // Column out of range.
  EXPECT_THROW(AlgebraicMultigrid(from_rows({{{0, 2.0}, {5, -1.0}}, {{1, 2.0}}})), gfmd::InputError);
  // Non-positive diagonal, non-finite entry.
  EXPECT_THROW(AlgebraicMultigrid(from_rows({{{0, 0.0}}, {{1, 1.0}}})), gfmd::SolveError);
  EXPECT_THROW(AlgebraicMultigrid(from_rows({{{0, 2.0}, {1, std::nan("")}}, {{1, 2.0}, {0, -1.0}}})),
               gfmd::SolveError);
  // A zero right-hand side gives zero at once.
  AlgebraicMultigrid mg(from_rows({{{0, 2.0}, {1, -1.0}}, {{1, 2.0}, {0, -1.0}}}));
  std::vector<double> b(2, 0.0), x(2, 5.0);
  const gfmd::CgOutcome cg = gfmd::amg_pcg(mg, b.data(), x.data(), 1e-10, 10);
  EXPECT_TRUE(cg.converged);
  EXPECT_EQ(cg.iterations, 0);
  EXPECT_EQ(x, std::vector<double>(2, 0.0));
}

}  // namespace
