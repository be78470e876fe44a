// Stress module: surface stress against Hertz and Hamilton closed forms, the exact
// subsurface solution against the body's compliance, Navier/Hooke and the Hertz
// subsurface field, and the principal-stress solver.
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

using namespace gfmd;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kA = 0.2;                       // Hertz contact radius
constexpr double kF = 4.0 * kA * kA * kA / 3.0;  // load giving a = 0.2 for R = E* = 1
const double kP0 = 3.0 * kF / (2.0 * kPi * kA * kA);

// Runs the heavy tests on one thread (robust timing on a busy machine) and restores the
// library's thread count afterwards.
struct OneThread {
  int saved = threads();
  OneThread() { set_threads(1); }
  ~OneThread() { set_threads(saved); }
  OneThread(const OneThread&) = delete;
  OneThread& operator=(const OneThread&) = delete;
};

const CaseResult& hertz(int nx) {
  static std::map<int, CaseResult> cache;
  auto it = cache.find(nx);
  if (it != cache.end()) return it->second;
  char force[64];
  std::snprintf(force, sizeof force, "%.17g", kF);
  const std::string toml =
      "[grid]\nnx = " + std::to_string(nx) +
      "\nlx = 3.2\n[elastic]\npoisson = 0.3\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
      "[load]\nforce = " +
      force + "\n[interaction]\nmodel = \"hardwall\"\n[solver]\ntolerance = 1e-10\nthreads = 1\n";
  CaseResult r = run_case(parse_config(toml, "hertz.toml"));
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return cache.emplace(nx, std::move(r)).first->second;
}

// Hamilton (1983): max tension at the trailing edge of a sliding Hertz contact.
double hamilton(double nu, double mu) { return kP0 * ((1 - 2 * nu) / 3 + (4 + nu) * kPi * mu / 8); }

// Hertz on the axis at depth z (Johnson eqs. 3.46-3.47): sigma_r = sigma_theta, sigma_z.
double hertz_axis_von_mises(double z, double nu) {
  const double t = z / kA;
  const double sz = -1.0 / (1.0 + t * t);
  const double sr = -(1.0 + nu) * (1.0 - t * std::atan(1.0 / t)) + 0.5 / (1.0 + t * t);
  return kP0 * std::abs(sr - sz);
}

// Small deterministic generator (portable): uniform in [-1, 1).
struct Lcg {
  std::uint64_t s;
  double next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
  }
};

double max_abs(const RealField& f) {
  double m = 0;
  for (double v : f) m = std::max(m, std::abs(v));
  return m;
}

// Smooth band-limited random field: sum of a few Fourier modes with |k| <= kmax.
RealField smooth_field(const Grid& g, Lcg& rng, int kmax, double offset) {
  RealField f(g.size(), offset);
  for (int mx = -kmax; mx <= kmax; ++mx)
    for (int my = -kmax; my <= kmax; ++my) {
      const double a = rng.next(), b = rng.next();
      for (int iy = 0; iy < g.ny; ++iy)
        for (int ix = 0; ix < g.nx; ++ix) {
          const double ph = 2 * kPi * (double(mx) * ix / g.nx + double(my) * iy / g.ny);
          f[static_cast<std::size_t>(iy) * g.nx + ix] += 0.1 * (a * std::cos(ph) + b * std::sin(ph));
        }
    }
  return f;
}

// Spectral x / y derivative of a real field (Nyquist dropped).
RealField deriv(const FFT& fft, const RealField& f, bool along_x) {
  const Grid& g = fft.grid();
  SpecField s = fft.spec_field();
  fft.forward(f.data(), s.data());
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < g.nxh(); ++ikx)
      s[static_cast<std::size_t>(iky) * g.nxh() + ikx] *=
          cplx(0.0, along_x ? g.qx_deriv(ikx) : g.qy_deriv(iky));
  RealField out = fft.real_field();
  fft.backward(s.data(), out.data());
  return out;
}

}  // namespace

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

TEST(StressSubsurface, SurfaceDisplacementIsTheBodyCompliance) {
  // Mode level: the exact elastic solution at depth 0 against phi_rotated (SPEC §2), both
  // layer branches (qh < 1 propagator, qh >= 1 anchored amplitudes) and the half-space.
  double worst = 0;
  for (double nu : {-0.5, 0.0, 0.25, 0.49, 0.5})
    for (double qh : {1e-7, 1e-3, 0.2, 0.999999, 1.0, 1.5, 7.0, 40.0, 800.0, 1e6, HUGE_VAL}) {
      if (nu == 0.5 && qh != HUGE_VAL) continue;
      ElasticParams el;
      el.contact_modulus = 1.7;
      el.poisson = nu;
      const double q = 3.0;
      el.thickness = qh == HUGE_VAL ? HUGE_VAL : qh / q;
      const ModeResponse r = mode_response(q, 0.0, el);
      const PhiRotated p = phi_rotated(qh, nu);
      const double det = p.p11 * p.p33 - p.p13 * p.p13, f = q * el.contact_modulus;
      const double c11 = p.p33 / (det * f), c33 = p.p11 / (det * f), c13 = -p.p13 / (det * f),
                   c22 = 1 / (p.p22 * f);
      const cplx i(0, 1);
      const cplx expect[3][3] = {{c11, 0, i * c13}, {0, c22, 0}, {-i * c13, 0, c33}};
      const double scale = std::max({c11, c22, c33});
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) worst = std::max(worst, std::abs(r.disp[a][b] - expect[a][b]) / scale);
      // And the tractions are reproduced: sigma'_13 = t1, sigma'_23 = t2, sigma'_33 = t3.
      EXPECT_NEAR(std::abs(r.stress[4][0] - 1.0) + std::abs(r.stress[4][2]) + std::abs(r.stress[5][1] - 1.0) +
                      std::abs(r.stress[2][2] - 1.0) + std::abs(r.stress[2][0]),
                  0.0, 1e-12);
    }
  std::printf("surface compliance of the subsurface solution: worst relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
  // Sign (SPEC §2): +x shear on a compressible half-space, u_z~ = -i c13 t_x~ with c13 < 0
  // (the surface ahead of the load goes down).
  ElasticParams el;
  el.poisson = 0.25;
  EXPECT_GT(mode_response(1.0, 0.0, el).disp[2][0].imag(), 0.0);
}

TEST(StressSubsurface, FieldDisplacementAndStressAtDepthZero) {
  // Random smooth-ish tractions on a grid; at depth 0 the displacement equals
  // ElasticBody::displacement (Nyquist lines included) and the stress equals
  // surface_stress of that state except on the Nyquist lines, which carry no energy here.
  const Grid g{64, 48, 1.0, 0.75};
  FFT fft(g);
  Lcg rng{7};
  ContactFields f;
  f.pressure = smooth_field(g, rng, 4, 0.5);
  f.tx = smooth_field(g, rng, 4, 0.1);
  f.ty = smooth_field(g, rng, 4, -0.05);
  // Add white noise to test the Nyquist handling of the displacement.
  for (RealField* fld : {&f.pressure, &f.tx, &f.ty})
    for (double& v : *fld) v += 0.01 * rng.next();
  for (double h : {HUGE_VAL, 0.05, 0.5}) {
    ElasticParams el;
    el.poisson = 0.3;
    el.thickness = h;
    const ElasticBody body(g, el);
    SpecField TX = fft.spec_field(), TY = fft.spec_field(), TZ = fft.spec_field();
    RealField tz = fft.real_field();
    for (std::size_t k = 0; k < g.size(); ++k) tz[k] = -f.pressure[k];
    fft.forward(f.tx.data(), TX.data());
    fft.forward(f.ty.data(), TY.data());
    fft.forward(tz.data(), TZ.data());
    SpecField UX = fft.spec_field(), UY = fft.spec_field(), UZ = fft.spec_field();
    body.displacement(TX.data(), TY.data(), TZ.data(), UX.data(), UY.data(), UZ.data());
    ContactFields s = f;
    s.ux = fft.real_field();
    s.uy = fft.real_field();
    s.uz = fft.real_field();
    fft.backward(UX.data(), s.ux.data());
    fft.backward(UY.data(), s.uy.data());
    fft.backward(UZ.data(), s.uz.data());
    const DisplacementField d = subsurface_displacement(fft, el, f, 0.0);
    double du = 0;
    for (std::size_t k = 0; k < g.size(); ++k)
      du = std::max(
          {du, std::abs(d.ux[k] - s.ux[k]), std::abs(d.uy[k] - s.uy[k]), std::abs(d.uz[k] - s.uz[k])});
    const double uscale = std::max({max_abs(s.ux), max_abs(s.uy), max_abs(s.uz)});
    EXPECT_LT(du, 1e-12 * uscale) << "h = " << h;
    // Stress: remove the noise so that the Nyquist lines are empty, then compare.
    ContactFields smooth = f;
    Lcg rng2{7};
    smooth.pressure = smooth_field(g, rng2, 4, 0.5);
    smooth.tx = smooth_field(g, rng2, 4, 0.1);
    smooth.ty = smooth_field(g, rng2, 4, -0.05);
    const DisplacementField u0 = subsurface_displacement(fft, el, smooth, 0.0);
    smooth.ux = u0.ux;
    smooth.uy = u0.uy;
    smooth.uz = u0.uz;
    const StressField a = surface_stress(fft, el, smooth), b = subsurface_stress(fft, el, smooth, 0.0);
    double ds = 0;
    for (std::size_t k = 0; k < g.size(); ++k)
      ds =
          std::max({ds, std::abs(a.xx[k] - b.xx[k]), std::abs(a.yy[k] - b.yy[k]), std::abs(a.zz[k] - b.zz[k]),
                    std::abs(a.xy[k] - b.xy[k]), std::abs(a.xz[k] - b.xz[k]), std::abs(a.yz[k] - b.yz[k])});
    EXPECT_LT(ds, 1e-12 * max_abs(a.zz)) << "h = " << h;
  }
}

TEST(StressSubsurface, DepthZeroMatchesSurfaceStressOfSolvedSlidingState) {
  const OneThread one_thread;
  // A solved frictional state (coupled; nu = 0.25 half-space and a nu = 0.3 layer
  // h = 0.3 R): the d = 0 plane equals surface_stress of the solver's own fields. They
  // differ only on the Nyquist lines (derivative dropped there vs odd response dropped):
  // with those modes removed from the difference it vanishes to rounding.
  for (const char* sets : {"elastic.poisson=0.25", "elastic.thickness=0.3"}) {
    const std::string toml =
        "[grid]\nnx = 128\nlx = 1.6\n[elastic]\npoisson = 0.3\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
        "[load]\nforce = 0.01\n[friction]\ncoefficient = 0.5\nreference = false\n[solver]\ntolerance = "
        "1e-10\nthreads = 1\n";
    const CaseResult r = run_case(parse_config(toml, "t.toml", {sets}));
    ASSERT_TRUE(r.info.converged) << r.info.status;
    const Grid& g = r.config.grid;
    FFT fft(g);
    const StressField a = surface_stress(fft, r.config.elastic, r.fields);
    const StressField b = subsurface_stress(fft, r.config.elastic, r.fields, 0.0);
    const double pmax = max_abs(r.fields.pressure);
    const RealField* fa[6] = {&a.xx, &a.yy, &a.zz, &a.xy, &a.xz, &a.yz};
    const RealField* fb[6] = {&b.xx, &b.yy, &b.zz, &b.xy, &b.xz, &b.yz};
    double raw = 0, off_nyquist = 0;
    for (int c = 0; c < 6; ++c) {
      RealField d = fft.real_field();
      for (std::size_t k = 0; k < g.size(); ++k) d[k] = (*fa[c])[k] - (*fb[c])[k];
      raw = std::max(raw, max_abs(d));
      SpecField sd = fft.spec_field();
      fft.forward(d.data(), sd.data());
      for (int iky = 0; iky < g.ny; ++iky)
        for (int ikx = 0; ikx < g.nxh(); ++ikx)
          if (ikx == g.nx / 2 || iky == g.ny / 2) sd[static_cast<std::size_t>(iky) * g.nxh() + ikx] = 0.0;
      fft.backward(sd.data(), d.data());
      off_nyquist = std::max(off_nyquist, max_abs(d));
    }
    std::printf("%s: depth 0 vs surface stress: %.2e of p_max, %.2e without the Nyquist lines\n", sets,
                raw / pmax, off_nyquist / pmax);
    EXPECT_LT(off_nyquist, 1e-12 * pmax);
    EXPECT_LT(raw, 5e-3 * pmax);
  }
}

TEST(StressSubsurface, NavierEquilibriumHookeAndBaseConditions) {
  // At depth d: div sigma = 0 (z-derivative by central differences), in-plane Hooke's
  // law with the strains of the displacement at that depth, sigma_xz = G (du_x/dz +
  // du_z/dx), and u = 0 on the rigid base. Layer h = 0.05 L spans both branches
  // (q h from 0.31 to 10).
  const Grid g{64, 64, 1.0, 1.0};
  FFT fft(g);
  Lcg rng{99};
  ContactFields f;
  f.pressure = smooth_field(g, rng, 6, 0.4);
  f.tx = smooth_field(g, rng, 6, 0.05);
  f.ty = smooth_field(g, rng, 6, 0.0);
  for (double h : {0.05, HUGE_VAL}) {
    ElasticParams el;
    el.poisson = 0.3;
    el.contact_modulus = 2.0;
    el.thickness = h;
    const double G = el.shear_modulus(), nu = el.poisson, es = el.contact_modulus;
    for (double d : {0.01, 0.03}) {
      const double e = 1e-5;
      const StressField s = subsurface_stress(fft, el, f, d);
      const StressField sp = subsurface_stress(fft, el, f, d - e), sm = subsurface_stress(fft, el, f, d + e);
      const DisplacementField u = subsurface_displacement(fft, el, f, d);
      const DisplacementField up = subsurface_displacement(fft, el, f, d - e),
                              um = subsurface_displacement(fft, el, f, d + e);
      // z = -d: d/dz = -d/dd, so d/dz ~ (F(d - e) - F(d + e)) / (2e).
      const RealField dxx = deriv(fft, s.xx, true), dxy_y = deriv(fft, s.xy, false),
                      dxy_x = deriv(fft, s.xy, true), dyy = deriv(fft, s.yy, false),
                      dxz = deriv(fft, s.xz, true), dyz = deriv(fft, s.yz, false);
      const RealField exx = deriv(fft, u.ux, true), eyy = deriv(fft, u.uy, false),
                      uxy = deriv(fft, u.ux, false), uyx = deriv(fft, u.uy, true),
                      uzx = deriv(fft, u.uz, true), uzy = deriv(fft, u.uz, false);
      const double scale = max_abs(s.zz) + max_abs(s.xx);
      double eq = 0, hk = 0;
      for (std::size_t k = 0; k < g.size(); ++k) {
        const double dz_xz = (sp.xz[k] - sm.xz[k]) / (2 * e), dz_yz = (sp.yz[k] - sm.yz[k]) / (2 * e),
                     dz_zz = (sp.zz[k] - sm.zz[k]) / (2 * e);
        eq = std::max({eq, std::abs(dxx[k] + dxy_y[k] + dz_xz), std::abs(dxy_x[k] + dyy[k] + dz_yz),
                       std::abs(dxz[k] + dyz[k] + dz_zz)});
        const double dz_ux = (up.ux[k] - um.ux[k]) / (2 * e), dz_uy = (up.uy[k] - um.uy[k]) / (2 * e),
                     dz_uz = (up.uz[k] - um.uz[k]) / (2 * e);
        const double lam = 2 * G * nu / (1 - 2 * nu);
        const double tr = exx[k] + eyy[k] + dz_uz;
        hk = std::max({hk, std::abs(s.xx[k] - es * (exx[k] + nu * eyy[k]) - nu / (1 - nu) * s.zz[k]),
                       std::abs(s.yy[k] - es * (eyy[k] + nu * exx[k]) - nu / (1 - nu) * s.zz[k]),
                       std::abs(s.xy[k] - G * (uxy[k] + uyx[k])), std::abs(s.xz[k] - G * (dz_ux + uzx[k])),
                       std::abs(s.yz[k] - G * (dz_uy + uzy[k])),
                       std::abs(s.zz[k] - lam * tr - 2 * G * dz_uz)});
      }
      std::printf("h=%g d=%g: equilibrium residual %.2e /L, Hooke residual %.2e (of the stress scale)\n", h,
                  d, eq / scale * g.lx, hk / scale);
      EXPECT_LT(eq * g.lx, 1e-5 * scale);
      EXPECT_LT(hk, 1e-5 * scale);
    }
    if (h != HUGE_VAL) {
      const DisplacementField base = subsurface_displacement(fft, el, f, h);
      const DisplacementField top = subsurface_displacement(fft, el, f, 0.0);
      const double us = max_abs(top.uz);
      EXPECT_LT(std::max({max_abs(base.ux), max_abs(base.uy), max_abs(base.uz)}), 1e-13 * us);
    }
  }
}

TEST(StressSubsurface, LayerBaseUnderUniformPressure) {
  const Grid g{16, 16, 1.0, 1.0};
  FFT fft(g);
  ContactFields f;
  f.pressure = fft.real_field(0.7);
  for (double nu : {0.0, 0.3, 0.45}) {
    ElasticParams el;
    el.poisson = nu;
    el.thickness = 0.2;
    for (double d : {0.0, 0.1, 0.2}) {
      const StressField s = subsurface_stress(fft, el, f, d);
      const DisplacementField u = subsurface_displacement(fft, el, f, d);
      for (std::size_t k = 0; k < g.size(); ++k) {
        EXPECT_NEAR(s.zz[k], -0.7, 1e-14);
        EXPECT_NEAR(s.xx[k], -0.7 * nu / (1 - nu), 1e-14);
        EXPECT_NEAR(s.yy[k], -0.7 * nu / (1 - nu), 1e-14);
        EXPECT_NEAR(std::abs(s.xy[k]) + std::abs(s.xz[k]) + std::abs(s.yz[k]), 0.0, 1e-14);
        // SPEC §7: u_z = -p (h - d)(1-2nu)/((1-nu)^2 E*).
        EXPECT_NEAR(u.uz[k], -0.7 * (0.2 - d) * (1 - 2 * nu) / ((1 - nu) * (1 - nu)), 1e-14);
      }
    }
  }
}

TEST(StressSubsurface, StableForLargeQhAndRejectsBadDepth) {
  const Grid g{64, 64, 1.0, 1.0};
  FFT fft(g);
  Lcg rng{3};
  ContactFields f;
  f.pressure = smooth_field(g, rng, 12, 0.5);
  ElasticParams half;
  half.poisson = 0.25;
  ElasticParams thick = half;
  thick.thickness = 1e5;  // q h up to 2e7: the layer is a half-space
  for (double d : {0.0, 0.02, 0.3}) {
    const StressField a = subsurface_stress(fft, half, f, d), b = subsurface_stress(fft, thick, f, d);
    double diff = 0;
    for (std::size_t k = 0; k < g.size(); ++k) {
      ASSERT_TRUE(std::isfinite(b.xx[k]) && std::isfinite(b.zz[k]) && std::isfinite(b.xz[k]));
      diff = std::max(
          {diff, std::abs(a.xx[k] - b.xx[k]), std::abs(a.zz[k] - b.zz[k]), std::abs(a.xz[k] - b.xz[k])});
    }
    EXPECT_LT(diff, 1e-12 * max_abs(f.pressure)) << "d = " << d;
  }
  // Near the base of a thick layer (the base terms matter there, the others underflow).
  ElasticParams lay = half;
  lay.thickness = 30.0;
  const StressField nb = subsurface_stress(fft, lay, f, 30.0);
  for (std::size_t k = 0; k < g.size(); ++k) ASSERT_TRUE(std::isfinite(nb.xx[k]) && std::isfinite(nb.zz[k]));
  EXPECT_THROW(subsurface_stress(fft, half, f, -0.1), InputError);
  EXPECT_THROW(subsurface_stress(fft, lay, f, 30.5), InputError);
  EXPECT_THROW(subsurface_stress(fft, half, f, std::nan("")), InputError);
}

TEST(StressSubsurface, HertzMaximumVonMisesOnAxis) {
  const OneThread one_thread;
  // nu = 0.3: max von Mises on the axis ~ 0.62 p0 at depth ~ 0.48 a (Johnson §4.2).
  const CaseResult& r = hertz(512);
  const Grid& g = r.config.grid;
  FFT fft(g);
  const ElasticParams el = r.config.elastic;  // nu = 0.3
  const std::size_t c = static_cast<std::size_t>(g.ny / 2) * g.nx + g.nx / 2;
  auto vm_at = [&](double z) {
    const StressField s = subsurface_stress(fft, el, r.fields, z);
    return von_mises(s.xx[c], s.yy[c], s.zz[c], s.xy[c], s.xz[c], s.yz[c]);
  };
  // Coarse scan, then a parabola through the best three points.
  const int n = 9;
  double z[n], v[n];
  int best = 0;
  for (int k = 0; k < n; ++k) {
    z[k] = kA * (0.3 + 0.05 * k);
    v[k] = vm_at(z[k]);
    if (v[k] > v[best]) best = k;
  }
  ASSERT_GT(best, 0);
  ASSERT_LT(best, n - 1);
  const double h = z[1] - z[0], y0 = v[best - 1], y1 = v[best], y2 = v[best + 1];
  const double off = 0.5 * h * (y0 - y2) / (y0 - 2 * y1 + y2);
  const double z_max = z[best] + off, v_max = vm_at(z_max);
  // Closed form, maximised by a fine scan.
  double ref = 0, z_ref = 0;
  for (int k = 1; k <= 20000; ++k) {
    const double zz = kA * k * 1e-4, vv = hertz_axis_von_mises(zz, 0.3);
    if (vv > ref) {
      ref = vv;
      z_ref = zz;
    }
  }
  std::printf(
      "Hertz subsurface: max von Mises %.4f p0 at %.4f a (closed form %.4f p0 at %.4f a): %+.4f, %+.4f\n",
      v_max / kP0, z_max / kA, ref / kP0, z_ref / kA, v_max / ref - 1, z_max / z_ref - 1);
  EXPECT_NEAR(ref / kP0, 0.62, 0.005);
  EXPECT_NEAR(z_ref / kA, 0.48, 0.005);
  EXPECT_LT(std::abs(v_max / ref - 1), 0.03);
  EXPECT_LT(std::abs(z_max / z_ref - 1), 0.03);
  // The on-axis profile itself, above and below the maximum.
  for (double zz : {0.25 * kA, kA, 2 * kA})
    EXPECT_LT(std::abs(vm_at(zz) / hertz_axis_von_mises(zz, 0.3) - 1), 0.03);
}
