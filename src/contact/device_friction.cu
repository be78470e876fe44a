// The CUDA contact solve (device_solve_class.cuh): the friction's normal displacement, the
// slip tractions and the tangential (stick-slip) solve, as friction.cpp on the host.

#include "device_solve_class.cuh"

namespace gfmd {

using namespace contact_detail;
using namespace cuda_kernels;
using namespace contact_device;
using namespace device_solve_detail;

void CudaSolve::friction_normal_displacement() {
  forward(tx_.get(), s2_.get());
  forward(ty_.get(), s3_.get());
  const ComplianceMode* md = modes_.get();
  const cufftDoubleComplex* a = s2_.get();
  const cufftDoubleComplex* b = s3_.get();
  cufftDoubleComplex* out = s1_.get();
  const double scale = 1.0 / static_cast<double>(n_);
  launch_each(ns_, [=] __device__(std::size_t k) {
    const ComplianceMode m = md[k];
    const cufftDoubleComplex x = cscale(scale, a[k]), y = cscale(scale, b[k]);
    const cufftDoubleComplex tx = times_i(m.cxz, x), ty = times_i(m.cyz, y);
    out[k] = {-tx.x - ty.x, -tx.y - ty.y};
  });
  backward(s1_.get(), w_.get());
}

std::array<double, 4> CudaSolve::slip_tractions() {
  // friction.cpp's slip_tractions: s2/s3 hold the spectra of tau_x/tau_y.
  const auto dir = direction();
  const double ex = dir.first, ey = dir.second;
  forward(p_.get(), s1_.get());
  {
    const ComplianceMode* md = modes_.get();
    const cufftDoubleComplex* dd = deriv_.get();
    cufftDoubleComplex* a = s1_.get();
    cufftDoubleComplex* b = s2_.get();
    cufftDoubleComplex* c = s3_.get();
    const double scale = 1.0 / static_cast<double>(n_);
    launch_each(ns_, [=] __device__(std::size_t k) {
      cufftDoubleComplex ux, uy;
      inplane(md[k], cscale(scale, b[k]), cscale(scale, c[k]), cscale(-scale, a[k]), ux, uy);
      a[k] = cmul(dd[k], ux);
      b[k] = cmul(dd[k], uy);
    });
  }
  backward(s1_.get(), cg_t_.get());
  backward(s2_.get(), cg_r_.get());
  const double mu = fric_.coefficient, eps = fric_.regularization;
  const FrictionLaw law = fric_.law;  // |tau| = mu_c p for Coulomb's law (friction_law.hpp)
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];
  const double* p = law_pressure();
  const double* r1 = cg_t_.get();
  const double* r2 = cg_r_.get();
  const double* fx = tx_.get();
  const double* fy = ty_.get();
  double* tx = ntx_.get();
  double* ty = nty_.get();
  const unsigned char* in_supp = in_supp_.get();
  constexpr double slow2 = kNearStickSpeed * kNearStickSpeed;
  return red_.run<4>(n_, [=] __device__(std::size_t i, double* acc) {
    const double pi = p[i];
    if (pi > 0) {
      const double vx = rx + r1[i], vy = ry + r2[i];
      const double v2 = vx * vx + vy * vy;
      if (v2 < slow2) acc[3] += 1.0;
      const double speed = sqrt(v2);
      const double norm = fmax(speed, eps);
      const double t = law.bound(mu, pi, speed);
      double x = 0.0, y = 0.0;
      if (norm > 0) {
        x = t * vx / norm;
        y = t * vy / norm;
      }
      tx[i] = x;
      ty[i] = y;
      add_change_dev(acc, in_supp[i], x, y, fx[i], fy[i]);
    } else if (in_supp[i]) {
      tx[i] = 0.0;
      ty[i] = 0.0;
      acc[0] += fabs(fx[i]) + fabs(fy[i]);
    }
  });
}

CudaSolve::Tangential CudaSolve::solve_tangential(double tol, int max_it) {
  // friction.cpp's Douglas-Rachford iteration; the image tau goes to (ntx, nty).
  const auto dir = direction();
  const double ex = dir.first, ey = dir.second;
  const std::array<double, 2> rigid = fric_.rigid_slip(ex, ey);
  const double rx = rigid[0], ry = rigid[1];
  const double mu = fric_.coefficient;
  const FrictionLaw law = fric_.law;
  const bool speed_law = law.speed_dependent();
  const double* p = law_pressure();  // the bound's; the coupling reads the net pressure p_
  // A bound that falls with the speed (the velocity law's static peak): the step stays above its
  // steepest fall at the largest pressure, raised with headroom, z afresh (friction.cpp).
  if (const double fall = law.steepest_fall(mu, 1.0); fall > 0) {
    const double need = fall * red_.run<1, true>(n_, [=] __device__(std::size_t i, double* acc) {
      acc[0] = fmax(acc[0], p[i]);
    })[0];
    if (kFallingStepMargin * need > gamma_) {
      gamma_ = kFallingStepHeadroom * need;
      have_z_ = false;
    }
  }
  const double gamma = gamma_;
  const double scale = 1.0 / static_cast<double>(n_);
  const ComplianceMode* md = modes_.get();
  const cufftDoubleComplex* dd = deriv_.get();
  cufftDoubleComplex* a = s1_.get();
  cufftDoubleComplex* b = s2_.get();
  cufftDoubleComplex* c = s3_.get();
  double* yx = cg_t_.get();
  double* yy = cg_r_.get();
  double* bx = bx_.get();
  double* by = by_.get();
  double* zx = zx_.get();
  double* zy = zy_.get();
  double* tx = ntx_.get();
  double* ty = nty_.get();
  forward(p_.get(), s1_.get());
  launch_each(ns_, [=] __device__(std::size_t k) {
    cufftDoubleComplex ux, uy;
    inplane(md[k], {0.0, 0.0}, {0.0, 0.0}, cscale(-scale * gamma, a[k]), ux, uy);
    b[k] = cmul(dd[k], ux);
    c[k] = cmul(dd[k], uy);
  });
  backward(s2_.get(), bx);
  backward(s3_.get(), by);
  if (!have_z_) {
    forward(tx, s2_.get());
    forward(ty, s3_.get());
    launch_each(ns_, [=] __device__(std::size_t k) {
      cufftDoubleComplex ux, uy;
      inplane(md[k], cscale(scale * gamma, b[k]), cscale(scale * gamma, c[k]), {0.0, 0.0}, ux, uy);
      b[k] = cmul(dd[k], ux);
      c[k] = cmul(dd[k], uy);
    });
    backward(s2_.get(), yx);
    backward(s3_.get(), yy);
    launch_each(n_, [=] __device__(std::size_t i) {
      zx[i] = tx[i] + gamma * rx + bx[i] + yx[i];
      zy[i] = ty[i] + gamma * ry + by[i] + yy[i];
    });
    have_z_ = true;
  }
  const auto project_pass = [&](bool rhs) {
    launch_each(n_, [=] __device__(std::size_t i) {
      // The projection onto the disc of radius bound(p, 0); for a law whose bound changes with
      // the slip speed, its resolvent (friction_law.hpp, as on the host).
      const double pi = p[i];
      const double r = law.bound(mu, pi, 0.0);
      double x = 0.0, y = 0.0;
      if (r > 0) {
        const double m2 = zx[i] * zx[i] + zy[i] * zy[i];
        if (m2 <= r * r) {
          x = zx[i];
          y = zy[i];
        } else {
          const double zm = sqrt(m2);
          const double f = (speed_law ? law.resolvent(mu, pi, zm, gamma) : r) / zm;
          x = f * zx[i];
          y = f * zy[i];
        }
      }
      tx[i] = x;
      ty[i] = y;
      if (rhs) {
        yx[i] = 2.0 * x - zx[i] + bx[i];
        yy[i] = 2.0 * y - zy[i] + by[i];
      }
    });
  };
  Tangential res{0, 1.0, false};
  const double cx = gamma * rx, cy = gamma * ry;
  const double beta = kTangentialRelaxation;
  for (int it = 0; it < max_it; ++it) {
    ++res.iterations;
    project_pass(true);
    forward(yx, s2_.get());
    forward(yy, s3_.get());
    launch_each(ns_, [=] __device__(std::size_t k) {
      const ComplianceMode m = md[k];
      const cufftDoubleComplex gd = cscale(gamma, dd[k]);
      const cufftDoubleComplex xa = cscale(scale, b[k]), xb = cscale(scale, c[k]);
      // The adjugate of M = I - gamma D C_tt and 1/det M (slip_resolvent).
      const cufftDoubleComplex m11 = {1.0 - gd.x * m.cyy, -gd.y * m.cyy};
      const cufftDoubleComplex m22 = {1.0 - gd.x * m.cxx, -gd.y * m.cxx};
      const cufftDoubleComplex m12 = cscale(m.cxy, gd);
      const cufftDoubleComplex det = {m11.x * m22.x - m11.y * m22.y - (m12.x * m12.x - m12.y * m12.y),
                                      m11.x * m22.y + m11.y * m22.x - 2.0 * m12.x * m12.y};
      const cufftDoubleComplex inv = cdiv1(det);
      b[k] = cmul(inv, cadd(cmul(m11, xa), cmul(m12, xb)));
      c[k] = cmul(inv, cadd(cmul(m12, xa), cmul(m22, xb)));
      if (k == 0) {
        b[0].x += cx;
        c[0].x += cy;
      }
    });
    backward(s2_.get(), yx);
    backward(s3_.get(), yy);
    const auto sums = red_.run<2>(n_, [=] __device__(std::size_t i, double* acc) {
      const double dx = yx[i] - tx[i], dy = yy[i] - ty[i];
      acc[0] += fabs(dx) + fabs(dy);
      acc[1] += fabs(tx[i]) + fabs(ty[i]);
      zx[i] += beta * dx;
      zy[i] += beta * dy;
    });
    res.error = sums[1] > 0 ? sums[0] / sums[1] : (sums[0] > 0 ? 1.0 : 0.0);
    require_finite(res.error, "the stick-slip traction", *total_);
    if (res.error < tol) {
      res.converged = true;
      break;
    }
    if (res.iterations % 64 == 0) poll(false);
  }
  project_pass(false);
  return res;
}

}  // namespace gfmd
