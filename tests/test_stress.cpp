// Surface stresses against the Hertz and Hamilton closed forms, the post-analysis, and the
// principal-stress solver (the subsurface field: test_subsurface.cpp; the shared Hertz
// states: test_util.hpp).
//
// Hertz states: R = 1, E* = 1, F = 4 a^3 / 3 with a = 0.2 exactly, cell L = 3.2 = 16 a,
// hard-wall contact, nx = 512 (a/dx = 32) and, for the Hamilton extrapolation, nx = 1024
// (a/dx = 64). L = 16 a keeps the stress the periodic images add at the contact edge
// below about 2 % of (1-2nu)p0/3 (at L = 8 a it is about 8 %). The frictionless pressure
// on a half-space does not depend on nu, so one solve serves every nu.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"
#include "test_util.hpp"

using namespace gfmd;

using namespace gfmd::testing;

// ---- principal stresses ----------------------------------------------------------------

TEST(StressPrincipal, DiagonalTensorSortedWithAxes) {
  const double v[3] = {-2.0, 5.0, 1.5};
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    const Principal3 e = principal(v[p[0]], v[p[1]], v[p[2]], 0, 0, 0);
    EXPECT_NEAR(e.s1, 5.0, 1e-14);
    EXPECT_NEAR(e.s2, 1.5, 1e-14);
    EXPECT_NEAR(e.s3, -2.0, 1e-14);
    const int axis = static_cast<int>(std::find(p, p + 3, 1) - p);  // where 5.0 went
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.e1[k], k == axis ? 1.0 : 0.0, 1e-15);
  }
}

TEST(StressPrincipal, HydrostaticAndDegenerate) {
  const Principal3 h = principal(-3, -3, -3, 0, 0, 0);
  EXPECT_EQ(h.s1, -3.0);
  EXPECT_EQ(h.s3, -3.0);
  EXPECT_EQ(von_mises(-3, -3, -3, 0, 0, 0), 0.0);
  const Principal3 z = principal(0, 0, 0, 0, 0, 0);
  EXPECT_EQ(z.s1, 0.0);
  EXPECT_EQ(z.e1[0], 1.0);
  // s1 = s2 (eigenvector anywhere in the x-y plane) and s2 = s3 (unique e1 = z).
  const Principal3 a = principal(2, 2, -1, 0, 0, 0);
  EXPECT_NEAR(a.s1, 2.0, 1e-14);
  EXPECT_NEAR(a.s2, 2.0, 1e-14);
  EXPECT_NEAR(a.e1[2], 0.0, 1e-15);
  const Principal3 b = principal(1, 1, 4, 0, 0, 0);
  EXPECT_NEAR(b.s1, 4.0, 1e-14);
  EXPECT_NEAR(b.e1[2], 1.0, 1e-15);
}

TEST(StressPrincipal, RandomAndNearlyDegenerateEigenpairs) {
  Lcg rng{12345};
  double worst = 0, worst_inv = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // Q diag(l) Q^T with a random rotation Q and eigenvalues that are random, nearly
    // repeated (gaps 1e-6 .. 1e-12) or exactly repeated.
    double l[3] = {rng.next(), rng.next(), rng.next()};
    if (trial % 4 == 1) l[1] = l[0] * (1 + std::pow(10.0, -6 - trial % 7));
    if (trial % 4 == 2) l[2] = l[1];
    if (trial % 4 == 3) l[0] = l[1] = l[2] * (1 - 1e-9);
    const double scale = std::pow(10.0, (trial % 9) - 4);
    double qv[4] = {rng.next(), rng.next(), rng.next(), rng.next()};
    const double qn = std::sqrt(qv[0] * qv[0] + qv[1] * qv[1] + qv[2] * qv[2] + qv[3] * qv[3]);
    const double w = qv[0] / qn, x = qv[1] / qn, y = qv[2] / qn, z = qv[3] / qn;
    const double Q[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    double A[3][3] = {};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) A[i][j] += Q[i][k] * l[k] * Q[j][k] * scale;
    const Principal3 e = principal(A[0][0], A[1][1], A[2][2], A[0][1], A[0][2], A[1][2]);
    std::sort(l, l + 3);
    const double ref = scale * std::max({std::abs(l[0]), std::abs(l[2])});
    ASSERT_GE(e.s1, e.s2);
    ASSERT_GE(e.s2, e.s3);
    worst_inv = std::max({worst_inv, std::abs(e.s1 - scale * l[2]) / ref, std::abs(e.s2 - scale * l[1]) / ref,
                          std::abs(e.s3 - scale * l[0]) / ref});
    // A v = s1 v, |v| = 1.
    double res = 0, nrm = 0;
    for (int i = 0; i < 3; ++i) {
      double av = 0;
      for (int j = 0; j < 3; ++j) av += A[i][j] * e.e1[j];
      res = std::max(res, std::abs(av - e.s1 * e.e1[i]));
      nrm += e.e1[i] * e.e1[i];
    }
    EXPECT_NEAR(nrm, 1.0, 1e-14);
    worst = std::max(worst, res / ref);
    // Von Mises from the components equals the principal form.
    const double vm = von_mises(A[0][0], A[1][1], A[2][2], A[0][1], A[0][2], A[1][2]);
    const double vp = std::sqrt(0.5 * ((e.s1 - e.s2) * (e.s1 - e.s2) + (e.s2 - e.s3) * (e.s2 - e.s3) +
                                       (e.s3 - e.s1) * (e.s3 - e.s1)));
    EXPECT_NEAR(vm, vp, 1e-12 * ref);
  }
  std::printf("principal: worst eigenvalue error %.2e, worst |A v - s1 v| %.2e (relative)\n", worst_inv,
              worst);
  EXPECT_LT(worst_inv, 1e-13);
  EXPECT_LT(worst, 1e-12);
}

TEST(StressPrincipal, FieldAndSummary) {
  const Grid g{4, 2, 4.0, 2.0};
  StressField s;
  for (RealField* f : {&s.xx, &s.yy, &s.zz, &s.xy, &s.xz, &s.yz}) f->assign(g.size(), 0.0);
  s.xx = {1.0, 0.95, 0.5, 0.0, -1.0, 0.91, 0.2, 0.3};
  s.zz[6] = -10.0;  // the largest von Mises
  const PrincipalField p = principal(s);
  const StressSummary m = summarize(g, p, 0.9);
  EXPECT_EQ(m.max_tensile_stress, 1.0);
  EXPECT_EQ(m.max_tensile_ix, 0);
  EXPECT_EQ(m.max_tensile_iy, 0);
  EXPECT_NEAR(m.max_von_mises, std::sqrt(0.5 * (0.04 + 100 + 10.2 * 10.2)), 1e-12);
  EXPECT_EQ(m.max_von_mises_ix, 2);
  EXPECT_EQ(m.max_von_mises_iy, 1);
  EXPECT_DOUBLE_EQ(m.high_tension_area_fraction, 3.0 / 8.0);  // 1.0, 0.95, 0.91
  EXPECT_EQ(m.high_tension_fraction_of, 0.9);
  EXPECT_EQ(p.e1x[0], 1.0);
  EXPECT_NEAR(p.s1[4], 0.0, 1e-15);  // (-1, 0, 0): s1 = 0
  EXPECT_NEAR(p.s3[4], -1.0, 1e-15);
}

// ---- surface stress --------------------------------------------------------------------

TEST(StressSurface, HookeCoefficientsFromAnalyticStrains) {
  // u_x = A sin(kx x) cos(ky y), u_y = B cos(kx x) sin(ky y), no traction: the in-plane
  // stress follows from the strains alone; nu = 0.5 must stay finite (2G/(1-nu) = E*).
  const Grid g{32, 16, 2.0, 1.0};
  FFT fft(g);
  const double kx = 2 * kPi * 3 / g.lx, ky = 2 * kPi * 2 / g.ly, A = 0.01, B = -0.02;
  ContactFields f;
  f.pressure = fft.real_field(0.3);  // uniform pressure: sigma_zz = -0.3 everywhere
  f.ux = fft.real_field();
  f.uy = fft.real_field();
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t k = static_cast<std::size_t>(iy) * g.nx + ix;
      f.ux[k] = A * std::sin(kx * g.x(ix)) * std::cos(ky * g.y(iy));
      f.uy[k] = B * std::cos(kx * g.x(ix)) * std::sin(ky * g.y(iy));
    }
  for (double nu : {0.25, 0.5, -0.3}) {
    ElasticParams el;
    el.contact_modulus = 2.5;
    el.poisson = nu;
    const StressField s = surface_stress(fft, el, f);
    const double G = el.contact_modulus * (1 - nu) / 2;
    double err = 0;
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        const std::size_t k = static_cast<std::size_t>(iy) * g.nx + ix;
        const double cc = std::cos(kx * g.x(ix)) * std::cos(ky * g.y(iy));
        const double ss = std::sin(kx * g.x(ix)) * std::sin(ky * g.y(iy));
        const double exx = A * kx * cc, eyy = B * ky * cc, exy = 0.5 * (-A * ky - B * kx) * ss;
        // Hooke's law itself: lambda, G, with eps_zz from sigma_zz = -0.3.
        const double lam = nu == 0.5 ? 0.0 : 2 * G * nu / (1 - 2 * nu);
        double sxx, syy;
        if (nu == 0.5) {  // incompressible: eps_zz = -(exx + eyy), pressure from sigma_zz
          const double ezz = -(exx + eyy), ph = -0.3 - 2 * G * ezz;
          sxx = ph + 2 * G * exx;
          syy = ph + 2 * G * eyy;
        } else {
          const double ezz = (-0.3 - lam * (exx + eyy)) / (lam + 2 * G);
          sxx = lam * (exx + eyy + ezz) + 2 * G * exx;
          syy = lam * (exx + eyy + ezz) + 2 * G * eyy;
        }
        err =
            std::max({err, std::abs(s.xx[k] - sxx), std::abs(s.yy[k] - syy), std::abs(s.xy[k] - 2 * G * exy),
                      std::abs(s.zz[k] + 0.3), std::abs(s.xz[k]), std::abs(s.yz[k])});
      }
    EXPECT_LT(err, 1e-13) << "nu = " << nu;
  }
}

TEST(StressSurface, HertzFrictionlessEdgeAndCentre) {
  const OneThread one_thread;
  const CaseResult& r = hertz(512);
  const Grid& g = r.config.grid;
  FFT fft(g);
  const std::size_t c = static_cast<std::size_t>(g.ny / 2) * g.nx + g.nx / 2;
  for (double nu : {0.25, 0.3}) {
    ElasticParams el = r.config.elastic;
    el.poisson = nu;
    // u recomputed for this nu (the frictionless pressure does not depend on it).
    const ElasticBody body(g, el);
    const StressField s = post_analysis_stress(fft, body, r.fields.pressure, 0.0, 0.0);
    const StressSummary m = summarize(g, principal(s));
    const double edge = (1 - 2 * nu) / 3 * kP0, centre = -(1 + 2 * nu) / 2 * kP0;
    const double r_max =
        std::hypot((m.max_tensile_ix - g.nx / 2) * g.dx(), (m.max_tensile_iy - g.ny / 2) * g.dy());
    const double e_edge = m.max_tensile_stress / edge - 1, e_xx = s.xx[c] / centre - 1,
                 e_yy = s.yy[c] / centre - 1, e_zz = s.zz[c] / -kP0 - 1;
    std::printf("Hertz nu=%.2f: edge tension %+.4f at r/a=%.3f, centre xx %+.4f yy %+.4f zz %+.4f\n", nu,
                e_edge, r_max / kA, e_xx, e_yy, e_zz);
    EXPECT_LT(std::abs(e_edge), 0.03);
    EXPECT_NEAR(r_max / kA, 1.0, 2 * g.dx() / kA);
    EXPECT_LT(std::abs(e_xx), 0.03);
    EXPECT_LT(std::abs(e_yy), 0.03);
    EXPECT_LT(std::abs(e_zz), 0.03);
    // The stress from the solver's own displacements (nu = 0.3 solve) is the same state.
    if (nu == 0.3) {
      const StressField s2 = surface_stress(fft, el, r.fields);
      double d = 0;
      for (std::size_t k = 0; k < g.size(); ++k) d = std::max(d, std::abs(s2.xx[k] - s.xx[k]));
      EXPECT_LT(d, 1e-9 * kP0);
    }
  }
}

// ---- post-analysis (Hamilton) ------------------------------------------------------------

TEST(StressPostAnalysis, HamiltonTrailingEdge) {
  const OneThread one_thread;
  // The exact field has a square-root cusp at the trailing edge (sigma_xx drops like
  // sqrt(-x-a) just outside), so the grid maximum converges like sqrt(dx): the raw error
  // is about -8 % at a/dx = 32 and -6 % at a/dx = 64. The Richardson extrapolation in
  // sqrt(dx) of the two must match Hamilton's closed form within 3 %.
  const CaseResult& c1 = hertz(512);
  const CaseResult& c2 = hertz(1024);
  for (double nu : {0.25, 0.3})
    for (double mu : {0.3, 0.5}) {
      double v[2];
      int k = 0;
      for (const CaseResult* r : {&c1, &c2}) {
        const Grid& g = r->config.grid;
        FFT fft(g);
        ElasticParams el = r->config.elastic;
        el.poisson = nu;
        const ElasticBody body(g, el);
        const StressField s = post_analysis_stress(fft, body, r->fields.pressure, mu, 0.0);
        const StressSummary m = summarize(g, principal(s));
        v[k++] = m.max_tensile_stress;
        const double x = (m.max_tensile_ix - g.nx / 2) * g.dx(), y = (m.max_tensile_iy - g.ny / 2) * g.dy();
        // At the trailing edge x = -a (on the contact circle, within a few cells of the axis).
        EXPECT_NEAR(std::hypot(x, y), kA, 1.5 * g.dx());
        EXPECT_LT(x, -0.95 * kA);
        if (g.nx == 512) {
          // Inside the contact the friction part of sigma_xx on the axis is linear,
          // -(4+nu) pi mu p0 x / (8 a) (Hamilton): a smooth region, tight check.
          const StressField s0 = post_analysis_stress(fft, body, r->fields.pressure, 0.0, 0.0);
          double err = 0;
          for (int ix = g.nx / 2 - 24; ix <= g.nx / 2 + 24; ++ix) {
            const std::size_t i = static_cast<std::size_t>(g.ny / 2) * g.nx + ix;
            const double xa = (ix - g.nx / 2) * g.dx() / kA;
            err = std::max(err, std::abs(s.xx[i] - s0.xx[i] + (4 + nu) * kPi * mu / 8 * kP0 * xa));
          }
          std::printf("  interior friction stress |x| <= 0.75a: max error %.4f of the edge value\n",
                      err / ((4 + nu) * kPi * mu / 8 * kP0));
          EXPECT_LT(err, 0.01 * (4 + nu) * kPi * mu / 8 * kP0);
        }
      }
      const double ex = hamilton(nu, mu);
      const double extrap = (std::sqrt(2.0) * v[1] - v[0]) / (std::sqrt(2.0) - 1.0);
      std::printf("Hamilton nu=%.2f mu=%.1f: a/dx=32 %+.4f, a/dx=64 %+.4f, extrapolated %+.4f\n", nu, mu,
                  v[0] / ex - 1, v[1] / ex - 1, extrap / ex - 1);
      EXPECT_LT(std::abs(extrap / ex - 1), 0.03);
      EXPECT_LT(std::abs(v[1] / ex - 1), std::abs(v[0] / ex - 1));  // converging
      EXPECT_LT(std::abs(v[1] / ex - 1), 0.08);
    }
}

// The paper's post-analysis ([stress] post_analysis = "paper") against an independent
// recomputation: the frictionless solution (a separate mu = 0 solve of the same case) is
// differentiated by a plain O(N^2) DFT (Nyquist derivative dropped), Hooke's law of SPEC §5
// gives the in-plane stresses, sigma_az = mu p e_s and sigma_zz = -p are written in, and
// sigma_I follows per point. The run's field must agree to 1e-10 of the largest stress. The
// consistent kind of the same run differs (it includes the strain of mu p).
TEST(StressPostAnalysis, PaperKindEqualsIndependentRecomputation) {
  const OneThread one_thread;
  const std::string base = R"([grid]
nx = 32
ny = 24
lx = 1.0
ly = 0.75
[elastic]
poisson = 0.3
thickness = 0.3
[indenter]
type = "selfaffine"
lambda_long = 0.5
lambda_short = 0.125
rms_gradient = 0.2
seed = 3
[load]
pressure = 0.05
[friction]
direction = 30.0
[solver]
tolerance = 1e-11
threads = 1
[stress]
post_analysis = ["paper", "consistent"]
)";
  const double mu = 0.6, a = 30.0 * kPi / 180.0, nu = 0.3;
  const CaseResult r = run_case(parse_config(base, "t.toml", {"friction.coefficient=0.6"}));
  ASSERT_TRUE(r.info.converged) << r.info.status;
  ASSERT_EQ(r.post_analyses.size(), 2u);
  ASSERT_EQ(r.post_analyses[0].kind, "paper");
  ASSERT_EQ(r.post_analyses[1].kind, "consistent");
  const CaseResult f0 = run_case(parse_config(base, "t.toml", {"friction.coefficient=0"}));
  ASSERT_TRUE(f0.info.converged);
  const Grid& g = r.config.grid;
  const int nx = g.nx, ny = g.ny;
  // d/dx and d/dy of a real field by the DFT sum, Nyquist wave numbers dropped.
  const auto derivative = [&](const RealField& u, int axis) {
    std::vector<std::complex<double>> U(g.size());
    for (int ky = 0; ky < ny; ++ky)
      for (int kx = 0; kx < nx; ++kx) {
        std::complex<double> sum = 0;
        for (int iy = 0; iy < ny; ++iy)
          for (int ix = 0; ix < nx; ++ix)
            sum +=
                u[static_cast<std::size_t>(iy) * nx + ix] *
                std::polar(
                    1.0, -2 * kPi * (static_cast<double>(kx) * ix / nx + static_cast<double>(ky) * iy / ny));
        U[static_cast<std::size_t>(ky) * nx + kx] = sum / static_cast<double>(g.size());
      }
    RealField d(g.size());
    for (int iy = 0; iy < ny; ++iy)
      for (int ix = 0; ix < nx; ++ix) {
        std::complex<double> sum = 0;
        for (int ky = 0; ky < ny; ++ky)
          for (int kx = 0; kx < nx; ++kx) {
            const int mx = kx <= nx / 2 ? kx : kx - nx, my = ky <= ny / 2 ? ky : ky - ny;
            if ((axis == 0 && 2 * kx == nx) || (axis == 1 && 2 * ky == ny)) continue;
            const double q = axis == 0 ? 2 * kPi * mx / g.lx : 2 * kPi * my / g.ly;
            sum +=
                std::complex<double>(0, q) * U[static_cast<std::size_t>(ky) * nx + kx] *
                std::polar(1.0,
                           2 * kPi * (static_cast<double>(kx) * ix / nx + static_cast<double>(ky) * iy / ny));
          }
        d[static_cast<std::size_t>(iy) * nx + ix] = sum.real();
      }
    return d;
  };
  const RealField uxx = derivative(f0.fields.ux, 0), uxy = derivative(f0.fields.ux, 1),
                  uyx = derivative(f0.fields.uy, 0), uyy = derivative(f0.fields.uy, 1);
  const double es = r.config.elastic.contact_modulus, gmod = es * (1 - nu) / 2;
  double err = 0, scale = 0, differs = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    const double p = f0.fields.pressure[k], zz = -p;
    const double xx = es * (uxx[k] + nu * uyy[k]) + nu / (1 - nu) * zz;
    const double yy = es * (uyy[k] + nu * uxx[k]) + nu / (1 - nu) * zz;
    const double xy = gmod * (uxy[k] + uyx[k]);
    const Principal3 pr = principal(xx, yy, zz, xy, mu * p * std::cos(a), mu * p * std::sin(a));
    err = std::max(err, std::abs(pr.s1 - r.post_analyses[0].s1[k]));
    scale = std::max({scale, std::abs(xx), std::abs(yy), std::abs(zz)});
    differs = std::max(differs, std::abs(r.post_analyses[1].s1[k] - r.post_analyses[0].s1[k]));
  }
  std::printf("paper post-analysis: max |sigma_I - independent| = %.2e of max |sigma| %.3e\n", err / scale,
              scale);
  EXPECT_LT(err, 1e-10 * scale);
  EXPECT_GT(differs, 1e-3 * scale);  // the consistent kind includes the friction's strain
  // Summary: both kinds with their ratios; the first is also "post_analysis".
  const nlohmann::json j = summary_json(r);
  EXPECT_EQ(j["post_analysis"]["kind"], "paper");
  EXPECT_EQ(j["post_analysis_consistent"]["kind"], "consistent");
  EXPECT_DOUBLE_EQ(j["post_analysis_paper"]["ratio_max_tensile_stress"].get<double>(),
                   r.stress_summary->max_tensile_stress / r.post_analyses[0].summary.max_tensile_stress);
  EXPECT_GT(j["post_analysis_paper"]["area_fraction_above_half_max"].get<double>(), 0.0);
}

TEST(StressPostAnalysis, KindsParsedAndRecorded) {
  const std::string base =
      "[grid]\nnx = 16\nlx = 1\n[indenter]\ntype = \"eggcrate\"\n[load]\npressure = 0.01\n";
  const auto kinds = [&](const std::string& v) {
    return parse_config(base + "[stress]\npost_analysis = " + v + "\n", "t.toml").stress.post_analysis;
  };
  EXPECT_TRUE(kinds("false").empty());
  EXPECT_EQ(kinds("true"), std::vector<std::string>{"consistent"});  // the earlier meaning
  EXPECT_EQ(kinds("\"paper\""), std::vector<std::string>{"paper"});
  EXPECT_EQ(kinds("[\"consistent\", \"paper\"]"), (std::vector<std::string>{"consistent", "paper"}));
  EXPECT_THROW((void)kinds("\"hamilton\""), InputError);
  EXPECT_THROW((void)kinds("[\"paper\", 3]"), InputError);
  // Recorded in the input, read back the same.
  const Config c = parse_config(base + "[stress]\npost_analysis = [\"paper\", \"consistent\"]\n", "t.toml");
  EXPECT_EQ(parse_config(c.to_toml(), "again.toml").stress.post_analysis, c.stress.post_analysis);
  EXPECT_EQ(c.to_json()["stress"]["post_analysis"], nlohmann::json({"paper", "consistent"}));
}

TEST(StressPostAnalysis, RotatingSlidingDirectionWithIndenterRotatesField) {
  const OneThread one_thread;
  // Isotropic Hertz centred on a node of a square grid: sliding along +y is sliding
  // along +x rotated by 90 degrees, (x, y) -> (-y, x).
  const CaseResult& r = hertz(512);
  const Grid& g = r.config.grid;
  FFT fft(g);
  const ElasticBody body(g, r.config.elastic);
  const PrincipalField p0 = principal(post_analysis_stress(fft, body, r.fields.pressure, 0.5, 0.0));
  const PrincipalField p90 = principal(post_analysis_stress(fft, body, r.fields.pressure, 0.5, 90.0));
  const StressSummary m0 = summarize(g, p0), m90 = summarize(g, p90);
  EXPECT_NEAR(m90.max_tensile_stress / m0.max_tensile_stress, 1.0, 1e-6);
  EXPECT_NEAR(m90.max_von_mises / m0.max_von_mises, 1.0, 1e-6);
  const int cx = g.nx / 2, cy = g.ny / 2;
  double d = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const int jx = ((cx - (iy - cy)) % g.nx + g.nx) % g.nx, jy = ((cy + (ix - cx)) % g.ny + g.ny) % g.ny;
      const std::size_t i = static_cast<std::size_t>(iy) * g.nx + ix,
                        j = static_cast<std::size_t>(jy) * g.nx + jx;
      d = std::max({d, std::abs(p90.s1[j] - p0.s1[i]), std::abs(p90.von_mises[j] - p0.von_mises[i])});
      // e1 rotates with the field (up to sign).
      const double ex = -p0.e1y[i], ey = p0.e1x[i], ez = p0.e1z[i];
      if (p0.s1[i] - p0.s2[i] > 1e-3 * kP0)
        d = std::max(d, kP0 * (1.0 - std::abs(ex * p90.e1x[j] + ey * p90.e1y[j] + ez * p90.e1z[j])));
    }
  EXPECT_LT(d, 1e-6 * m0.max_tensile_stress);
  // The trailing edge moved from x = -a to y = -a.
  EXPECT_LT((m90.max_tensile_iy - cy) * g.dy(), -0.95 * kA);
}

// ---- below the surface ------------------------------------------------------------------
