// The homogeneous body: one isotropic material, a half-space (thickness = inf) or a layer of
// thickness h bonded to a rigid base; closed forms (SPEC §2, the compliance; SPEC §5 and
// subsurface.cpp's header comment, the response at a depth).
#include <algorithm>
#include <cmath>
#include <limits>

#include "gfmd/elastic/body.hpp"
#include "subsurface_mode.hpp"

namespace gfmd {

namespace {

class HomogeneousBody final : public Body {
 public:
  explicit HomogeneousBody(const ElasticParams& el) : el_(el) {}

  [[nodiscard]] RotatedCompliance compliance(double q) const override {
    const double es = el_.contact_modulus;
    const PhiRotated f = phi_rotated(
        el_.half_space() ? std::numeric_limits<double>::infinity() : q * el_.thickness, el_.poisson);
    const double det = f.p11 * f.p33 - f.p13 * f.p13;
    return {f.p33 / (det * q * es), 1.0 / (f.p22 * q * es), f.p11 / (det * q * es), -f.p13 / (det * q * es)};
  }

  // One material: every compliance scales as 1/E* (nu constant), so E*(omega) scales the
  // elastic one by E* / E*(omega).
  [[nodiscard]] ComplexRotatedCompliance compliance(double q,
                                                    const std::vector<cplx>& moduli) const override {
    const RotatedCompliance r = compliance(q);
    const cplx f = el_.contact_modulus / moduli.at(0);
    return {f * r.c11, f * r.c22, f * r.c33, f * r.c13};
  }

  [[nodiscard]] std::pair<double, double> mean_compliances() const override {
    if (el_.half_space()) return {0.0, 0.0};
    const double nu = el_.poisson, om = 1.0 - nu;
    return {el_.thickness * (1.0 - 2.0 * nu) / (om * om * el_.contact_modulus),
            el_.thickness / el_.shear_modulus()};
  }

  [[nodiscard]] ModeResponse mode_response(double q, double depth) const override;

  // The stresses a traction causes do not depend on E* (nu constant); the displacements scale.
  [[nodiscard]] ModeResponse mode_response(double q, double depth,
                                           const std::vector<cplx>& moduli) const override {
    ModeResponse r = mode_response(q, depth);
    if (q == 0.0) return r;
    const cplx f = el_.contact_modulus / moduli.at(0);
    for (auto& row : r.disp)
      for (cplx& v : row) v *= f;
    return r;
  }

 private:
  ElasticParams el_;
};

ModeResponse HomogeneousBody::mode_response(double q, double depth) const {
  using namespace subsurface_detail;
  const double nu = el_.poisson, es = el_.contact_modulus, om = 1.0 - nu;
  const double G = el_.shear_modulus();
  const bool half = el_.half_space();
  const double h = el_.thickness;
  const cplx i(0.0, 1.0);
  ModeResponse r;
  if (q == 0.0) {
    // Uniform traction: uniform stress, uniaxial strain (no mean in-plane strain).
    r.stress[0][2] = r.stress[1][2] = nu / om;
    r.stress[2][2] = 1.0;
    r.stress[4][0] = 1.0;
    r.stress[5][1] = 1.0;
    // Uniform strain eps_xz = t1/(2G), eps_zz = t3/(lambda+2G); displacement pinned at the
    // rigid base (layer) or, as in ElasticBody, zero at the surface (half-space).
    const double z = half ? -depth : std::max(0.0, h - depth);
    r.disp[0][0] = r.disp[1][1] = z / G;
    r.disp[2][2] = z * (1.0 - 2.0 * nu) / (om * om * es);
    return r;
  }
  // antiplane: sigma_23 = tau t2, sigma_12 = i rho t2, u2 = rho t2 / (G q)
  const Mode m = mode_plane(q, depth, nu, half, h);
  const Plane& p = m.p;
  const double tau = m.tau, rho = m.rho;
  // Plane strain inputs S0 = -i t1, N0 = t3.
  r.stress[0][0] = -i * p.X[0];
  r.stress[0][2] = p.X[1];
  r.stress[1][0] = -i * p.Y[0];
  r.stress[1][2] = p.Y[1];
  r.stress[2][0] = -i * p.N[0];
  r.stress[2][2] = p.N[1];
  r.stress[4][0] = p.S[0];  // sigma_13 = i S = S_S t1 + i S_N t3
  r.stress[4][2] = i * p.S[1];
  r.stress[3][1] = i * rho;                   // sigma_12
  r.stress[5][1] = tau;                       // sigma_23
  const double u_unit = 1.0 / (2.0 * G * q);  // U, W are 2 G q times the displacement
  r.disp[0][0] = p.U[0] * u_unit;             // u1 = i U
  r.disp[0][2] = i * p.U[1] * u_unit;
  r.disp[2][0] = -i * p.W[0] * u_unit;  // u3 = W
  r.disp[2][2] = p.W[1] * u_unit;
  r.disp[1][1] = rho / (G * q);
  return r;
}

}  // namespace

const BodyType& homogeneous_body_type() {
  static const BodyType t{
      .name = "homogeneous",
      .purpose =
          "one isotropic material: a half-space (thickness = inf) or a layer bonded to a rigid base; "
          "closed forms",
      .keys = {},  // only the keys every body has
      .describes = [](const ElasticParams& el) { return !el.layered(); },
      .make = [](const ElasticParams& el) -> std::unique_ptr<Body> {
        return std::make_unique<HomogeneousBody>(el);
      }};
  return t;
}

}  // namespace gfmd
