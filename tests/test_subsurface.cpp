// Subsurface stresses (elastic/subsurface.cpp): the exact solution at depth against the
// body's compliance at the surface, Navier's equilibrium and Hooke's law inside, the
// conditions at the base of a layer, and the Hertz field on the axis (Johnson 1985, 3.4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"
#include "test_util.hpp"

using namespace gfmd;
using namespace gfmd::testing;

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
