// Green's tensor checks: SPEC §2 limits, stability, Hermitian symmetry, reciprocity sign.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/elastic/elastic.hpp"

using namespace gfmd;

namespace {
const double kInf = std::numeric_limits<double>::infinity();

// Direct evaluation of SPEC §2 in long double (reference for moderate qh).
PhiRotated phi_direct(long double x, long double nu) {
  const long double a = 3 - 4 * nu, s = std::sinh(x), d = a * a * s * s - x * x, om = 1 - nu;
  PhiRotated r{};
  r.p11 = static_cast<double>(om * om * (a * std::sinh(2 * x) - 2 * x) / d);
  r.p33 = static_cast<double>(om * om * (a * std::sinh(2 * x) + 2 * x) / d);
  r.p13 = static_cast<double>(om * (a * (1 - 2 * nu) * s * s - x * x) / d);
  r.p22 = static_cast<double>(om / (2 * std::tanh(x)));
  return r;
}
}  // namespace

TEST(Elastic, HalfSpaceLimits) {
  for (double nu : {-0.9, -0.3, 0.0, 0.25, 0.3, 0.49, 0.5}) {
    const PhiRotated p = phi_rotated(kInf, nu);
    EXPECT_DOUBLE_EQ(p.p11, 2 * (1 - nu) * (1 - nu) / (3 - 4 * nu));
    EXPECT_DOUBLE_EQ(p.p33, 2 * (1 - nu) * (1 - nu) / (3 - 4 * nu));
    EXPECT_DOUBLE_EQ(p.p22, (1 - nu) / 2);
    EXPECT_DOUBLE_EQ(p.p13, (1 - nu) * (1 - 2 * nu) / (3 - 4 * nu));
    // Finite but large qh converges to the same values, with no overflow up to 1e4.
    for (double x : {40.0, 349.0, 351.0, 710.0, 1e4}) {
      const PhiRotated q = phi_rotated(x, nu);
      EXPECT_NEAR(q.p11, p.p11, 1e-12) << "nu=" << nu << " qh=" << x;
      EXPECT_NEAR(q.p33, p.p33, 1e-12);
      EXPECT_NEAR(q.p22, p.p22, 1e-12);
      EXPECT_NEAR(q.p13, p.p13, 1e-12);
    }
  }
  const PhiRotated inc = phi_rotated(kInf, 0.5);
  EXPECT_DOUBLE_EQ(inc.p33, 0.5);
  EXPECT_DOUBLE_EQ(inc.p13, 0.0);
}

TEST(Elastic, ThinLayerLimits) {
  // q -> 0 at finite h: uniaxial strain and simple shear of a layer (SPEC §2).
  for (double nu : {-0.5, 0.0, 0.25, 0.49}) {
    for (double x : {1e-8, 1e-5}) {
      const PhiRotated p = phi_rotated(x, nu);
      EXPECT_NEAR(x * p.p33, (1 - nu) * (1 - nu) / (1 - 2 * nu), 1e-6) << nu;
      EXPECT_NEAR(x * p.p11, (1 - nu) / 2, 1e-6) << nu;
      EXPECT_NEAR(x * p.p22, (1 - nu) / 2, 1e-6) << nu;
      EXPECT_TRUE(std::isfinite(p.p13));
      EXPECT_NEAR(p.p13, (1 - nu) * (1 - 4 * nu) / (4 * (1 - 2 * nu)), 1e-6) << nu;
    }
  }
}

TEST(Elastic, StableFormMatchesDirectFormula) {
  for (double nu : {-0.5, 0.0, 0.25, 0.49}) {
    for (double x : {0.05, 0.3, 0.999999, 1.000001, 2.0, 5.0, 20.0}) {
      const PhiRotated a = phi_rotated(x, nu), b = phi_direct(x, nu);
      EXPECT_NEAR(a.p11, b.p11, 1e-11 * std::abs(b.p11)) << nu << " " << x;
      EXPECT_NEAR(a.p33, b.p33, 1e-11 * std::abs(b.p33)) << nu << " " << x;
      EXPECT_NEAR(a.p22, b.p22, 1e-11 * std::abs(b.p22)) << nu << " " << x;
      EXPECT_NEAR(a.p13, b.p13, 1e-10) << nu << " " << x;
    }
  }
}

TEST(Elastic, HermitianAndInverse) {
  const Grid g{16, 12, 1.0, 0.8};
  for (double h : {kInf, 0.05}) {
    for (bool coupling : {true, false}) {
      ElasticBody body(g, homogeneous_body(2.0, 0.3, h, coupling));
      for (int iky = 0; iky < g.ny; ++iky)
        for (int ikx = 0; ikx < g.nxh(); ++ikx) {
          if ((ikx == 0 && iky == 0) || ikx == g.nx / 2 || iky == g.ny / 2) continue;
          const auto k = body.stiffness(ikx, iky);
          const auto c = body.compliance(ikx, iky);
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
              EXPECT_NEAR(std::abs(k[3 * a + b] - std::conj(k[3 * b + a])), 0.0, 1e-12);
              cplx prod = 0;
              for (int m = 0; m < 3; ++m) prod += c[3 * a + m] * k[3 * m + b];
              EXPECT_NEAR(std::abs(prod - cplx(a == b ? 1.0 : 0.0)), 0.0, 1e-10);
            }
          // Positive definite: real parts of the diagonal and the 2x2 x-z determinant.
          EXPECT_GT(k[0].real(), 0);
          EXPECT_GT(k[8].real(), 0);
        }
    }
  }
}

TEST(Elastic, HalfSpaceNormalComplianceIsTwoOverQEstar) {
  // Frictionless normal contact of a half-space depends on E* only, for any nu.
  const Grid g{8, 8, 1.0, 1.0};
  for (double nu : {-0.5, 0.25, 0.49, 0.5}) {
    ElasticBody body(g, homogeneous_body(3.0, nu, kInf, true));
    const double q = 2 * M_PI * std::hypot(1.0, 2.0);
    EXPECT_NEAR(body.compliance(1, 2)[8].real(), 2.0 / (q * 3.0), 1e-14);
  }
}

TEST(Elastic, UncoupledKeepsDirectCompliance) {
  const Grid g{8, 8, 1.0, 1.0};
  ElasticBody c(g, homogeneous_body(1.0, 0.25, 0.3, true)), u(g, homogeneous_body(1.0, 0.25, 0.3, false));
  for (std::size_t k = 0; k < c.modes().size(); ++k) {
    EXPECT_DOUBLE_EQ(c.mode(k).czz, u.mode(k).czz);
    EXPECT_DOUBLE_EQ(c.mode(k).cxx, u.mode(k).cxx);
    EXPECT_EQ(u.mode(k).cxz, 0.0);
    EXPECT_EQ(u.mode(k).cyz, 0.0);
  }
  EXPECT_NE(c.mode(1).cxz, 0.0);
}

TEST(Elastic, ReciprocitySignTangentialLineLoad) {
  // A tangential line load in +x on a compressible half-space depresses the surface
  // ahead of it (x > x0) and raises it behind (Johnson, Contact Mechanics §2.3;
  // Betti's theorem with Boussinesq's inward radial displacement).
  const Grid g{256, 4, 1.0, 1.0 / 64};
  FFT fft(g);
  ElasticBody body(g, homogeneous_body(1.0, 0.25, kInf, true));
  RealField tx = fft.real_field(), uz = fft.real_field(), ux = fft.real_field();
  const int x0 = 128;
  for (int iy = 0; iy < g.ny; ++iy) tx[iy * g.nx + x0] = 1.0;
  SpecField tq = fft.spec_field(), uq = fft.spec_field(), uxq = fft.spec_field();
  fft.forward(tx.data(), tq.data());
  body.displacement(tq.data(), nullptr, nullptr, uxq.data(), nullptr, uq.data());
  fft.backward(uq.data(), uz.data());
  fft.backward(uxq.data(), ux.data());
  for (int d = 2; d < 40; ++d) {
    EXPECT_LT(uz[x0 + d], 0.0) << "ahead, d=" << d;
    EXPECT_GT(uz[x0 - d], 0.0) << "behind, d=" << d;
  }
  EXPECT_GT(ux[x0], 0.0);  // the surface moves with the load
  // Betti: a pressure at x0 (t_z = -1) pulls surface points towards it.
  RealField tz = fft.real_field();
  for (int iy = 0; iy < g.ny; ++iy) tz[iy * g.nx + x0] = -1.0;
  fft.forward(tz.data(), tq.data());
  body.displacement(nullptr, nullptr, tq.data(), uxq.data(), nullptr, nullptr);
  fft.backward(uxq.data(), ux.data());
  EXPECT_GT(ux[x0 - 10], 0.0);
  EXPECT_LT(ux[x0 + 10], 0.0);
  // The uncoupled reference has no normal displacement from tangential load.
  ElasticBody unc(g, homogeneous_body(1.0, 0.25, kInf, false));
  fft.forward(tx.data(), tq.data());
  unc.displacement(tq.data(), nullptr, nullptr, nullptr, nullptr, uq.data());
  fft.backward(uq.data(), uz.data());
  for (double v : uz) EXPECT_NEAR(v, 0.0, 1e-14);
}

TEST(Elastic, UniformPressureOnBondedLayer) {
  // SPEC §7: uz = -p h (1-2nu)/((1-nu)^2 E*), from the q = 0 mode.
  const Grid g{8, 8, 1.0, 1.0};
  const double p = 0.01, h = 0.2, nu = 0.3, es = 2.0;
  FFT fft(g);
  ElasticBody body(g, homogeneous_body(es, nu, h, true));
  RealField tz = fft.real_field(-p), uz = fft.real_field();
  SpecField tq = fft.spec_field(), uq = fft.spec_field();
  fft.forward(tz.data(), tq.data());
  body.displacement(nullptr, nullptr, tq.data(), nullptr, nullptr, uq.data());
  fft.backward(uq.data(), uz.data());
  const double expect = -p * h * (1 - 2 * nu) / ((1 - nu) * (1 - nu) * es);
  for (double v : uz) EXPECT_NEAR(v, expect, 1e-15);
}

TEST(Elastic, RejectsBadParameters) {
  auto msg = [](std::array<double, 3> v) {
    const ElasticParams p = homogeneous_body(v[0], v[1], v[2]);
    try {
      p.validate();
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // The library names its parameters; the config layer adds the section (elastic.poisson).
  EXPECT_NE(msg({1.0, 0.6, kInf}).find("poisson: "), std::string::npos);
  EXPECT_NE(msg({1.0, -1.0, kInf}).find("poisson: "), std::string::npos);
  EXPECT_NE(msg({1.0, 0.3, -1.0}).find("thickness: "), std::string::npos);
  EXPECT_NE(msg({1.0, 0.3, 0.0}).find("thickness: "), std::string::npos);
  EXPECT_NE(msg({1.0, 0.5, 1.0}).find("singular"), std::string::npos);
  EXPECT_NE(msg({-1.0, 0.3, kInf}).find("contact_modulus"), std::string::npos);
  EXPECT_EQ(msg({1.0, 0.5, kInf}), "");
}

// The measuring planner gives the same transforms as the estimating one to round-off,
// and keeps its plans as wisdom in the file named by GFMD_FFTW_WISDOM (written
// atomically: no temporary file is left behind).
TEST(FFTPlanner, MeasureMatchesEstimateAndCachesWisdom) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("gfmd_wisdom_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path file = dir / "sub" / "wisdom";
  ::setenv("GFMD_FFTW_WISDOM", file.c_str(), 1);
  const gfmd::Grid g{48, 40, 1.0, 1.0};
  gfmd::FFT est(g), meas(g, gfmd::Planner::Measure);
  RealField x = est.real_field();
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * static_cast<double>(i)) + 0.1 * (i % 7);
  SpecField a = est.spec_field(), b = est.spec_field();
  est.forward(x.data(), a.data());
  meas.forward(x.data(), b.data());
  double scale = 0.0, diff = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    scale = std::max(scale, std::abs(a[k]));
    diff = std::max(diff, std::abs(a[k] - b[k]));
  }
  EXPECT_GT(scale, 1.0);
  EXPECT_LT(diff, 1e-12 * scale);
  RealField y = est.real_field();
  meas.backward(b.data(), y.data());
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(y[i], x[i], 1e-12);
  ASSERT_TRUE(fs::exists(file));
  EXPECT_GT(fs::file_size(file), 0u);
  for (const auto& e : fs::directory_iterator(file.parent_path()))
    EXPECT_EQ(e.path().filename(), "wisdom") << "left behind: " << e.path();
  ::unsetenv("GFMD_FFTW_WISDOM");
  fs::remove_all(dir);
}

TEST(Elastic, DisplacementInPlaceAndScaledEqualsOutOfPlace) {
  // The solver writes displacement spectra over the traction spectra and folds 1/N into
  // the product: both must give what the out-of-place product gives.
  const Grid g{32, 16, 1.0, 0.5};
  ElasticBody body(g, homogeneous_body(1.0, 0.3, 0.2, true));
  const std::size_t ns = g.spectral_size();
  SpecField tx(ns), ty(ns), tz(ns);
  for (std::size_t k = 0; k < ns; ++k) {
    const double a = static_cast<double>(k);
    tx[k] = cplx(std::sin(a), std::cos(1.3 * a));
    ty[k] = cplx(std::cos(0.7 * a), std::sin(2.1 * a));
    tz[k] = cplx(std::sin(0.3 * a + 1), -std::cos(a));
  }
  SpecField ux(ns), uy(ns), uz(ns);
  body.displacement(tx.data(), ty.data(), tz.data(), ux.data(), uy.data(), uz.data());
  const double scale = 0.125;
  SpecField a = tx, b = ty, c = tz;
  body.displacement(a.data(), b.data(), c.data(), a.data(), b.data(), c.data(), scale);
  double err = 0, mag = 0;
  for (std::size_t k = 0; k < ns; ++k) {
    err = std::max({err, std::abs(a[k] - scale * ux[k]), std::abs(b[k] - scale * uy[k]),
                    std::abs(c[k] - scale * uz[k])});
    mag = std::max({mag, std::abs(ux[k]), std::abs(uy[k]), std::abs(uz[k])});
  }
  EXPECT_GT(mag, 0.0);
  EXPECT_LT(err, 1e-15 * mag);
}

TEST(Elastic, InplaneSlopeIsTheDerivativeOfTheDisplacement) {
  // The friction step takes the slopes (e.grad) u_x, (e.grad) u_y of the in-plane
  // displacement of (tx, ty, -tz) in one spectral pass: it must equal the displacement
  // product (normal traction scaled by -1 via scale_z) times i (e.q), Nyquist modes dropped.
  const Grid g{32, 16, 1.0, 0.5};
  ElasticBody body(g, homogeneous_body(1.0, 0.3, 0.2, true));
  const std::size_t ns = g.spectral_size();
  SpecField tx(ns), ty(ns), tz(ns), mz(ns);
  for (std::size_t k = 0; k < ns; ++k) {
    const double a = static_cast<double>(k);
    tx[k] = cplx(std::sin(a), std::cos(1.3 * a));
    ty[k] = cplx(std::cos(0.7 * a), std::sin(2.1 * a));
    tz[k] = cplx(std::sin(0.3 * a + 1), -std::cos(a));
    mz[k] = -tz[k];
  }
  const double scale = 0.25, th = 0.6, ex = std::cos(th), ey = std::sin(th);
  SpecField ux(ns), uy(ns), vx(ns), vy(ns);
  body.displacement(tx.data(), ty.data(), mz.data(), ux.data(), uy.data(), nullptr);
  body.displacement(tx.data(), ty.data(), tz.data(), vx.data(), vy.data(), nullptr, scale, -scale);
  SpecField a = tx, b = ty, c = tz;
  body.inplane_slope(a.data(), b.data(), c.data(), ex, ey, a.data(), b.data(), scale, -scale);
  double err = 0, err_z = 0, mag = 0;
  const int nxh = g.nxh();
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(iky) * nxh + ikx;
      const cplx d(0.0, ex * g.qx_deriv(ikx) + ey * g.qy_deriv(iky));
      err = std::max({err, std::abs(a[k] - scale * d * ux[k]), std::abs(b[k] - scale * d * uy[k])});
      err_z = std::max({err_z, std::abs(vx[k] - scale * ux[k]), std::abs(vy[k] - scale * uy[k])});
      mag = std::max({mag, std::abs(scale * d * ux[k]), std::abs(scale * d * uy[k])});
    }
  EXPECT_GT(mag, 0.0);
  EXPECT_LT(err, 1e-14 * mag);
  EXPECT_LT(err_z, 1e-14 * mag);
}

TEST(Elastic, SlipResolventInvertsOneMinusGammaA) {
  // (I - gamma A) applied to the resolvent's output gives back its input on every mode, with
  // A = (e.grad) C_tt from inplane_slope; for a layer and a half-space, with coupling.
  const Grid g{16, 12, 1.0, 0.8};
  for (const double h : {std::numeric_limits<double>::infinity(), 0.05}) {
    const ElasticBody body(g, homogeneous_body(1.0, 0.3, h, true));
    const std::size_t ns = g.spectral_size();
    std::vector<cplx> x(ns), y(ns), ax(ns), ay(ns), rx(ns), ry(ns);
    for (std::size_t k = 0; k < ns; ++k) {
      x[k] = cplx(std::sin(1.0 + k), std::cos(2.0 * k));
      y[k] = cplx(std::cos(3.0 + k), std::sin(0.5 * k));
    }
    const double ex = std::cos(0.4), ey = std::sin(0.4), gamma = 0.7;
    rx = x;
    ry = y;
    body.slip_resolvent(rx.data(), ry.data(), ex, ey, gamma, 1.0);
    body.inplane_slope(rx.data(), ry.data(), nullptr, ex, ey, ax.data(), ay.data(), 1.0, 0.0);
    double err = 0.0;
    for (std::size_t k = 0; k < ns; ++k)
      err = std::max({err, std::abs(rx[k] - gamma * ax[k] - x[k]), std::abs(ry[k] - gamma * ay[k] - y[k])});
    EXPECT_LT(err, 1e-12) << "h = " << h;
  }
}
