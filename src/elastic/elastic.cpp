#include "gfmd/elastic/elastic.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <sstream>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/layered.hpp"

namespace gfmd {

void ElasticParams::validate() const {
  if (!(contact_modulus > 0.0) || !std::isfinite(contact_modulus))
    throw ParameterError("contact_modulus", "must be a positive finite number");
  if (!(poisson > -1.0 && poisson <= 0.5)) {
    std::ostringstream os;
    os << "Poisson's ratio " << poisson << " is outside (-1, 0.5]";
    throw ParameterError("poisson", os.str());
  }
  if (!(thickness > 0.0) || std::isnan(thickness))
    throw ParameterError("thickness", "must be \"inf\" or a positive number");
  if (poisson == 0.5 && !half_space() && !on_substrate())
    throw ParameterError("poisson",
                         "nu = 0.5 with a finite thickness is singular (an incompressible confined layer "
                         "cannot be compressed); use e.g. 0.49");
  if (!layered()) return;
  if (half_space())
    throw ParameterError("thickness", layers.empty()
                                          ? "must be finite on a substrate (the coating's thickness)"
                                          : "must be finite with layers beneath it");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const ElasticLayer& l = layers[i];
    const std::string key = "layers[" + std::to_string(i) + "].";
    if (!(l.contact_modulus > 0.0) || !std::isfinite(l.contact_modulus))
      throw ParameterError(key + "contact_modulus", "must be a positive finite number");
    if (!(l.poisson > -1.0 && l.poisson < 0.5))
      throw ParameterError(key + "poisson", "must be in (-1, 0.5) for a layer beneath the top one");
    if (!(l.thickness > 0.0) || !std::isfinite(l.thickness))
      throw ParameterError(key + "thickness", "must be a positive finite number");
  }
  if (on_substrate()) {
    if (!(substrate_contact_modulus > 0.0) || std::isnan(substrate_contact_modulus))
      throw ParameterError("substrate_contact_modulus", "must be a positive number (\"inf\": a rigid base)");
    if (!(substrate_poisson > -1.0 && substrate_poisson <= 0.5)) {
      std::ostringstream os;
      os << "Poisson's ratio " << substrate_poisson << " is outside (-1, 0.5]";
      throw ParameterError("substrate_poisson", os.str());
    }
  }
}

namespace {
// sinh(x)/x - 1 for |x| < 2 by its Taylor series (no cancellation).
double sinhc_m1(double x) {
  const double x2 = x * x;
  double term = 1.0, sum = 0.0;
  for (int k = 1; k < 40; ++k) {
    term *= x2 / ((2.0 * k) * (2.0 * k + 1.0));
    sum += term;
    if (term < 1e-18 * sum) break;
  }
  return sum;
}
}  // namespace

PhiRotated phi_rotated(double x, double nu) {
  const double a = 3.0 - 4.0 * nu;
  const double om = 1.0 - nu;
  PhiRotated r{};
  if (std::isinf(x)) {
    r.p11 = r.p33 = 2.0 * om * om / a;
    r.p22 = om / 2.0;
    r.p13 = om * (1.0 - 2.0 * nu) / a;
    return r;
  }
  if (x < 1.0) {
    // Write s^2 = x^2 (1 + t), sinh(2x) = 2x (1 + t2): every term below is a sum of
    // non-negative parts, so small qh loses no digits.
    const double t1 = sinhc_m1(x);
    const double t = t1 * (2.0 + t1);
    const double t2 = sinhc_m1(2.0 * x);
    const double dn = 8.0 * (1.0 - 2.0 * nu) * om + a * a * t;  // D / x^2
    r.p11 = om * om * 2.0 * (2.0 * (1.0 - 2.0 * nu) + a * t2) / (x * dn);
    r.p33 = om * om * 2.0 * (4.0 * om + a * t2) / (x * dn);
    r.p13 = om * (2.0 * om * (1.0 - 4.0 * nu) + a * (1.0 - 2.0 * nu) * t) / dn;
    r.p22 = om / (2.0 * std::tanh(x));
    return r;
  }
  // Divide numerators and D by sinh^2: only exp(-x) appears, no overflow.
  const double e = std::exp(-x);
  const double e2 = e * e;
  const double inv_s = 2.0 * e / (1.0 - e2);
  const double x_s = x * inv_s;
  const double coth = (1.0 + e2) / (1.0 - e2);
  const double dr = a * a - x_s * x_s;
  r.p11 = om * om * (2.0 * a * coth - 2.0 * x_s * inv_s) / dr;
  r.p33 = om * om * (2.0 * a * coth + 2.0 * x_s * inv_s) / dr;
  r.p13 = om * (a * (1.0 - 2.0 * nu) - x_s * x_s) / dr;
  r.p22 = om / 2.0 * coth;
  return r;
}

namespace {
// A rotated compliance (real or complex entries) in lab axes, (c, s) = q/|q|. The uncoupled
// reference drops the cross-compliance (C'13 = i c13) and keeps the direct ones, so a frictionless
// solve is the same with and without coupling. On the Nyquist lines the odd parts (xy, xz, yz)
// have no consistent sign (q and -q are the same mode there), so they are dropped like derivatives.
template <class Mode, class Rotated>
Mode to_lab(const Rotated& r, double c, double s, bool nyq_x, bool nyq_y, bool coupling) {
  using T = decltype(r.c11);
  const T zero(0.0), c13 = coupling ? r.c13 : zero;
  return {c * c * r.c11 + s * s * r.c22,
          s * s * r.c11 + c * c * r.c22,
          (nyq_x || nyq_y) ? zero : c * s * (r.c11 - r.c22),
          r.c33,
          nyq_x ? zero : c * c13,
          nyq_y ? zero : s * c13};
}

// The pair's relative compliance u_body - u_indenter: the indenter's surface faces the other
// way (its z and its traction reversed), so its direct terms add and its coupling subtracts.
RotatedCompliance relative(const RotatedCompliance& body, const RotatedCompliance& indenter) {
  return {body.c11 + indenter.c11, body.c22 + indenter.c22, body.c33 + indenter.c33, body.c13 - indenter.c13};
}
}  // namespace

ElasticBody::ElasticBody(const Grid& grid, const ElasticParams& params, const ViscoelasticParams& visco,
                         const ElasticParams* indenter)
    : grid_(grid), params_(params), modes_(grid.spectral_size()), visco_(visco) {
  // The kinds of body (body.hpp) supply the per-mode compliances; this turns them into lab-frame
  // tables. (make_body validates the parameters.)
  const std::unique_ptr<Body> body = make_body(params_);
  validate_viscoelastic_parts(params_, visco_);
  std::unique_ptr<Body> indenter_body;
  if (indenter) {
    indenter_body = make_body(*indenter);
    indenter_ = *indenter;
    own_.resize(modes_.size());
  }
  const int nxh = grid.nxh();
  // The rows of the half spectrum held here (all of them unless the grid is a slab).
  for_rows(grid.rows(), [&](int row) {
    const int iky = grid.y0 + row;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      const double qx = grid.qx(ikx), qy = grid.qy(iky);
      const double q = std::hypot(qx, qy);
      if (q == 0.0) {
        modes_[k] = ComplianceMode{0, 0, 0, 0, 0, 0};
        if (indenter) own_[k] = modes_[k];
        continue;
      }
      const double c = qx / q, s = qy / q;
      const bool nyq_x = grid.nx % 2 == 0 && ikx == grid.nx / 2,
                 nyq_y = grid.ny % 2 == 0 && iky == grid.ny / 2;
      const auto lab = [&](const RotatedCompliance& r) {
        return to_lab<ComplianceMode>(r, c, s, nyq_x, nyq_y, params_.coupling);
      };
      const RotatedCompliance own = body->compliance(q);
      if (indenter) {
        own_[k] = lab(own);
        modes_[k] = lab(relative(own, indenter_body->compliance(q)));
      } else {
        modes_[k] = lab(own);
      }
    }
  });
  const auto [own_zz, own_t] = body->mean_compliances();
  c0_zz_ = own_zz;
  c0_t_ = own_t;
  if (indenter) {
    const auto [ind_zz, ind_t] = indenter_body->mean_compliances();
    c0_zz_ += ind_zz;
    c0_t_ += ind_t;
  }
  if (grid.y0 == 0 && grid.rows() > 0) {  // the q = 0 mode
    modes_[0].czz = c0_zz_;
    modes_[0].cxx = modes_[0].cyy = c0_t_;
    if (indenter) {
      own_[0].czz = own_zz;
      own_[0].cxx = own_[0].cyy = own_t;
    }
  }
  if (visco_.enabled()) response_ = viscoelastic_factors(grid, visco_, relaxed_modulus(params_, visco_));
  if (visco_.enabled() && visco_.velocity != 0.0 && params_.layered() &&
      visco_.part != ViscoelasticParams::Part::All) {
    // Viscoelastic parts (the top layer, layers, the substrate) among elastic ones, or several of
    // different models: no common factor; each mode's compliance from the transfer matrices with
    // each part's E(omega) = E0_part / c_part. (Viscoelastic throughout, every modulus has the one
    // ratio: the factor path.)
    const ViscoelasticStack stack(grid, params_, visco_);
    layered_response_.resize(modes_.size());
    const std::vector<ComplianceMode>& own = own_.empty() ? modes_ : own_;
    for_rows(grid.rows(), [&](int row) {
      const int iky = grid.y0 + row;
      for (int ikx = 0; ikx < nxh; ++ikx) {
        const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
        const double qx = grid.qx(ikx), qy = grid.qy(iky), q = std::hypot(qx, qy);
        const ComplianceMode& o = own[k];
        if (q == 0.0) {  // steady: the elastic mean compliances
          layered_response_[k] = {o.cxx, o.cyy, o.cxy, o.czz, o.cxz, o.cyz};
          continue;
        }
        const ComplexRotatedCompliance r = body->compliance(q, stack.moduli(k));
        layered_response_[k] = to_lab<ResponseMode>(r, qx / q, qy / q, grid.nx % 2 == 0 && ikx == grid.nx / 2,
                                                    grid.ny % 2 == 0 && iky == grid.ny / 2, params_.coupling);
      }
    });
  }
}

namespace {
ResponseMode scaled(cplx c, const ComplianceMode& m) {
  return {c * m.cxx, c * m.cyy, c * m.cxy, c * m.czz, c * m.cxz, c * m.cyz};
}
}  // namespace

ResponseMode ElasticBody::own_response(std::size_t k) const {
  if (!layered_response_.empty()) return layered_response_[k];
  return scaled(response_[k], own_.empty() ? modes_[k] : own_[k]);
}

ResponseMode ElasticBody::response_mode(std::size_t k) const {
  const ComplianceMode& m = modes_[k];
  if (!moving()) return scaled(1.0, m);
  const ResponseMode r = own_response(k);
  if (own_.empty()) return r;
  // The body's own response; the indenter's part (the pair's less the body's) elastic.
  const ComplianceMode& o = own_[k];
  return {r.cxx + (m.cxx - o.cxx), r.cyy + (m.cyy - o.cyy), r.cxy + (m.cxy - o.cxy),
          r.czz + (m.czz - o.czz), r.cxz + (m.cxz - o.cxz), r.cyz + (m.cyz - o.cyz)};
}

ResponseMode ElasticBody::slip_response(std::size_t k) const {
  if (own_.empty() || roll_both_ || !moving()) return response_mode(k);
  return own_response(k);
}

cplx ElasticBody::normal_response(std::size_t k) const {
  if (!moving()) return modes_[k].czz;
  return response_mode(k).czz;
}

std::array<cplx, 9> ElasticBody::response_compliance(int ikx, int iky) const {
  const ResponseMode m = response_mode(static_cast<std::size_t>(iky - grid_.y0) * grid_.nxh() + ikx);
  const cplx i(0.0, 1.0);
  return {m.cxx, m.cxy, i * m.cxz, m.cxy, m.cyy, i * m.cyz, -i * m.cxz, -i * m.cyz, m.czz};
}

std::array<cplx, 9> ElasticBody::compliance(int ikx, int iky) const {
  const ComplianceMode& m = modes_[static_cast<std::size_t>(iky - grid_.y0) * grid_.nxh() + ikx];
  const cplx i(0.0, 1.0);
  return {cplx(m.cxx), cplx(m.cxy), i * m.cxz,  //
          cplx(m.cxy), cplx(m.cyy), i * m.cyz,  //
          -i * m.cxz,  -i * m.cyz,  cplx(m.czz)};
}

std::array<cplx, 9> ElasticBody::stiffness(int ikx, int iky) const {
  const double qx = grid_.qx(ikx), qy = grid_.qy(iky);
  const double q = std::hypot(qx, qy);
  std::array<cplx, 9> k{};
  if (q == 0.0) {
    if (c0_t_ > 0.0) {
      k[0] = k[4] = 1.0 / c0_t_;
      k[8] = 1.0 / c0_zz_;
    }
    return k;
  }
  PhiRotated p{};
  if (params_.layered() || indenter_) {  // the inverse of the (relative) compliance, in units of q E*
    RotatedCompliance r = make_body(params_)->compliance(q);
    if (indenter_) r = relative(r, make_body(*indenter_)->compliance(q));
    const double f = q * params_.contact_modulus, det = r.c11 * r.c33 - r.c13 * r.c13;
    p = PhiRotated{r.c33 / (det * f), 1.0 / (r.c22 * f), r.c11 / (det * f), -r.c13 / (det * f)};
  } else {
    p = phi_rotated(params_.half_space() ? std::numeric_limits<double>::infinity() : q * params_.thickness,
                    params_.poisson);
  }
  if (!params_.coupling) {
    // Inverse of the uncoupled compliance (direct terms of the coupled body kept).
    const double det = p.p11 * p.p33 - p.p13 * p.p13;
    p = PhiRotated{det / p.p33, p.p22, det / p.p11, 0.0};
  }
  const double c = qx / q, s = qy / q, f = q * params_.contact_modulus;
  const cplx i(0.0, 1.0);
  k[0] = f * (c * c * p.p11 + s * s * p.p22);
  k[4] = f * (s * s * p.p11 + c * c * p.p22);
  k[1] = k[3] = f * c * s * (p.p11 - p.p22);
  k[2] = f * i * c * p.p13;
  k[5] = f * i * s * p.p13;
  k[6] = std::conj(k[2]);
  k[7] = std::conj(k[5]);
  k[8] = f * p.p33;
  return k;
}

namespace {
// i c z for real c, without a general complex product (which also checks for NaN/inf).
inline cplx times_i(double c, cplx z) { return {-c * z.imag(), c * z.real()}; }
inline cplx times_i(cplx c, cplx z) { return cplx(0.0, 1.0) * c * z; }
// In-plane displacement (u_x, u_y) of one mode under the tractions (x, y, z).
template <class Mode>
inline std::array<cplx, 2> inplane(const Mode& m, cplx x, cplx y, cplx z) {
  return {m.cxx * x + m.cxy * y + times_i(m.cxz, z), m.cxy * x + m.cyy * y + times_i(m.cyz, z)};
}
}  // namespace

void ElasticBody::displacement(const cplx* tx, const cplx* ty, const cplx* tz, cplx* ux, cplx* uy, cplx* uz,
                               double scale, double scale_z) const {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(modes_.size());
  const std::vector<ComplianceMode>& slip = slip_modes();
  const bool moving = this->moving();
  parallel_for(n, [&](std::ptrdiff_t k) {
    const ComplianceMode& m = modes_[k];
    const cplx x = tx ? scale * tx[k] : cplx(0.0), y = ty ? scale * ty[k] : cplx(0.0),
               z = tz ? scale_z * tz[k] : cplx(0.0);
    if (moving) {  // the complex response of a viscoelastic body in motion
      const auto kk = static_cast<std::size_t>(k);
      const ResponseMode r = response_mode(kk);
      if (ux || uy) {
        // The slip's response is this one but under a sliding elastic indenter (slip_response).
        const auto u = inplane(own_.empty() || roll_both_ ? r : own_response(kk), x, y, z);
        if (ux) ux[k] = u[0];
        if (uy) uy[k] = u[1];
      }
      if (uz) uz[k] = r.czz * z - times_i(r.cxz, x) - times_i(r.cyz, y);
      return;
    }
    if (ux || uy) {
      const auto u = inplane(slip[k], x, y, z);
      if (ux) ux[k] = u[0];
      if (uy) uy[k] = u[1];
    }
    if (uz) uz[k] = m.czz * z - times_i(m.cxz, x) - times_i(m.cyz, y);
  });
}

namespace {
// f(row, k, m, d) for every mode of the half spectrum held here, rows in parallel: row its
// local row, k its index, m its compliance, d = e.q the wavenumber of the derivative along
// (ex, ey) (Nyquist modes: 0).
template <class F>
void for_each_slope_mode(const Grid& g, const std::vector<ComplianceMode>& modes, double ex, double ey,
                         F&& f) {
  const int nxh = g.nxh();
  for_rows(g.rows(), [&](int row) {
    const double dy = ey * g.qy_deriv(g.y0 + row);
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      f(row, k, modes[k], ex * g.qx_deriv(ikx) + dy);
    }
  });
}
}  // namespace

const char* slip_derivative_name(SlipDerivative d) {
  switch (d) {
    case SlipDerivative::Upwind:
      return "upwind";
    case SlipDerivative::Upwind2:
      return "upwind2";
    case SlipDerivative::Spectral:
      break;
  }
  return "spectral";
}

namespace {
// The upwind symbol at the wave vector (qx, qy): theta = (e.q) h.
cplx upwind_symbol(double qx, double qy, double ex, double ey, double h, SlipDerivative deriv) {
  const double th = (ex * qx + ey * qy) * h;
  const cplx e1(std::cos(th), std::sin(th));
  if (deriv == SlipDerivative::Upwind) return (e1 - 1.0) / h;
  const cplx e2(std::cos(2.0 * th), std::sin(2.0 * th));
  return -(3.0 - 4.0 * e1 + e2) / (2.0 * h);
}
}  // namespace

cplx slip_derivative_symbol(const Grid& g, int ikx, int iky, double ex, double ey, SlipDerivative deriv) {
  if (deriv == SlipDerivative::Spectral) return {0.0, ex * g.qx_deriv(ikx) + ey * g.qy_deriv(iky)};
  // The cell size along e: the shift h e is one cell for e along an axis.
  const double h = std::hypot(ex * g.dx(), ey * g.dy());
  const double qx = g.qx(ikx), qy = g.qy(iky);
  const bool nyq_x = g.nx % 2 == 0 && ikx == g.nx / 2, nyq_y = g.ny % 2 == 0 && iky == g.ny / 2;
  cplx d = upwind_symbol(qx, qy, ex, ey, h, deriv);
  int count = 1;
  if (nyq_x) {
    d += upwind_symbol(-qx, qy, ex, ey, h, deriv);
    ++count;
  }
  if (nyq_y) {
    d += upwind_symbol(qx, -qy, ex, ey, h, deriv);
    ++count;
  }
  if (nyq_x && nyq_y) {
    d += upwind_symbol(-qx, -qy, ex, ey, h, deriv);
    ++count;
  }
  return d / static_cast<double>(count);
}

namespace {
// f(row, k, m, D) for every mode held here with an upwind symbol D (complex): from `table`
// (ElasticBody::slip_symbols) when given, else computed.
template <class F>
void for_each_upwind_mode(const Grid& g, const std::vector<ComplianceMode>& modes, double ex, double ey,
                          SlipDerivative deriv, const cplx* table, F&& f) {
  const int nxh = g.nxh();
  for_rows(g.rows(), [&](int row) {
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      f(row, k, modes[k], table ? table[k] : slip_derivative_symbol(g, ikx, g.y0 + row, ex, ey, deriv));
    }
  });
}
}  // namespace

std::vector<cplx> ElasticBody::slip_symbols(double ex, double ey, SlipDerivative deriv) const {
  std::vector<cplx> d(modes_.size());
  const int nxh = grid_.nxh();
  for_rows(grid_.rows(), [&](int row) {
    for (int ikx = 0; ikx < nxh; ++ikx)
      d[static_cast<std::size_t>(row) * nxh + ikx] =
          slip_derivative_symbol(grid_, ikx, grid_.y0 + row, ex, ey, deriv);
  });
  return d;
}

void ElasticBody::inplane_slope(const cplx* tx, const cplx* ty, const cplx* tz, double ex, double ey,
                                cplx* dux, cplx* duy, double scale, double scale_z, SlipDerivative deriv,
                                const cplx* symbols) const {
  const bool moving = this->moving();
  const auto load = [&](std::size_t k, const ComplianceMode& m) {
    const cplx x = tx ? scale * tx[k] : cplx(0.0), y = ty ? scale * ty[k] : cplx(0.0),
               z = tz ? scale_z * tz[k] : cplx(0.0);
    return moving ? inplane(slip_response(k), x, y, z) : inplane(m, x, y, z);
  };
  if (deriv == SlipDerivative::Spectral) {
    for_each_slope_mode(grid_, slip_modes(), ex, ey,
                        [&](int, std::size_t k, const ComplianceMode& m, double d) {
                          const auto u = load(k, m);
                          dux[k] = times_i(d, u[0]);
                          duy[k] = times_i(d, u[1]);
                        });
    return;
  }
  for_each_upwind_mode(grid_, slip_modes(), ex, ey, deriv, symbols,
                       [&](int, std::size_t k, const ComplianceMode& m, cplx d) {
                         const auto u = load(k, m);
                         dux[k] = d * u[0];
                         duy[k] = d * u[1];
                       });
}

double ElasticBody::slip_operator_norm(double ex, double ey, SlipDerivative deriv) const {
  // max over modes of |D| times the largest eigenvalue of C_tt (real symmetric 2x2).
  std::vector<double> rows(static_cast<std::size_t>(grid_.rows()), 0.0);
  // A viscoelastic body in motion: |D| times the largest singular value of its complex C_tt
  // (|c| times the elastic one's on a body alone).
  const bool moving = this->moving();
  const auto take = [&](int row, std::size_t k, const ComplianceMode& m, double absd) {
    double& r = rows[static_cast<std::size_t>(row)];
    if (moving) {
      const ResponseMode c = slip_response(k);
      // sigma_max^2 = (|C|_F^2 + sqrt(|C|_F^4 - 4 |det C|^2)) / 2 for a 2x2 matrix.
      const double f2 = std::norm(c.cxx) + std::norm(c.cyy) + 2.0 * std::norm(c.cxy);
      const double det = std::abs(c.cxx * c.cyy - c.cxy * c.cxy);
      const double s2 = 0.5 * (f2 + std::sqrt(std::max(0.0, f2 * f2 - 4.0 * det * det)));
      r = std::max(r, absd * std::sqrt(s2));
      return;
    }
    const double tr = 0.5 * (m.cxx + m.cyy), df = 0.5 * (m.cxx - m.cyy);
    r = std::max(r, absd * (tr + std::sqrt(df * df + m.cxy * m.cxy)));
  };
  if (deriv == SlipDerivative::Spectral)
    for_each_slope_mode(
        grid_, slip_modes(), ex, ey,
        [&](int row, std::size_t k, const ComplianceMode& m, double d) { take(row, k, m, std::abs(d)); });
  else
    for_each_upwind_mode(
        grid_, slip_modes(), ex, ey, deriv, nullptr,
        [&](int row, std::size_t k, const ComplianceMode& m, cplx d) { take(row, k, m, std::abs(d)); });
  const double mine = rows.empty() ? 0.0 : *std::max_element(rows.begin(), rows.end());
  return mpi::max_all(grid_, mine);
}

void ElasticBody::slip_resolvent(cplx* x, cplx* y, double ex, double ey, double gamma, double scale,
                                 SlipDerivative deriv, const cplx* symbols) const {
  // M = I - g D C with Re D <= 0: M's Hermitian part I - g Re(D) C >= I, so det M != 0. On a
  // viscoelastic body in motion C is its complex C_tt: c C_tt(E0) with c = E0/E(omega) per mode,
  // and Re(D c) <= 0 too (omega = -(q.e_s) v0, so Im c has the sign of q.e_s, as Im D has);
  // under an elastic indenter in rolling the indenter's elastic C_tt is added, which keeps
  // M's Hermitian part >= I.
  const auto general = [&](std::size_t k, const auto& m, cplx gd) {
    const cplx a = scale * x[k], b = scale * y[k];
    const cplx m11 = 1.0 - gd * m.cyy, m22 = 1.0 - gd * m.cxx, m12 = gd * m.cxy;  // adjugate of M
    const cplx inv = 1.0 / (m11 * m22 - m12 * m12);
    x[k] = inv * (m11 * a + m12 * b);
    y[k] = inv * (m12 * a + m22 * b);
  };
  if (moving()) {  // at rest c = 1: the elastic branch below
    if (deriv == SlipDerivative::Spectral)
      for_each_slope_mode(grid_, slip_modes(), ex, ey,
                          [&](int, std::size_t k, const ComplianceMode&, double d) {
                            general(k, slip_response(k), gamma * cplx(0.0, d));
                          });
    else
      for_each_upwind_mode(grid_, slip_modes(), ex, ey, deriv, symbols,
                           [&](int, std::size_t k, const ComplianceMode&, cplx d) {
                             general(k, slip_response(k), gamma * d);
                           });
    return;
  }
  if (deriv == SlipDerivative::Spectral) {
    // M = I - i g d C with C = [[cxx, cxy], [cxy, cyy]] real symmetric and g d real: M is
    // complex symmetric, det M = 1 - i g d (cxx + cyy) - (g d)^2 (cxx cyy - cxy^2), never 0.
    for_each_slope_mode(
        grid_, slip_modes(), ex, ey, [&](int, std::size_t k, const ComplianceMode& m, double d) {
          const double gd = gamma * d;
          const cplx a = scale * x[k], b = scale * y[k];
          if (gd == 0.0) {
            x[k] = a;
            y[k] = b;
            return;
          }
          const cplx det(1.0 - gd * gd * (m.cxx * m.cyy - m.cxy * m.cxy), -gd * (m.cxx + m.cyy));
          const cplx inv = 1.0 / det;
          // M^-1 = [[1 - i gd cyy, i gd cxy], [i gd cxy, 1 - i gd cxx]] / det
          const cplx m11(1.0, -gd * m.cyy), m22(1.0, -gd * m.cxx), m12(0.0, gd * m.cxy);
          x[k] = inv * (m11 * a + m12 * b);
          y[k] = inv * (m12 * a + m22 * b);
        });
    return;
  }
  for_each_upwind_mode(
      grid_, slip_modes(), ex, ey, deriv, symbols,
      [&](int, std::size_t k, const ComplianceMode& m, cplx d) { general(k, m, gamma * d); });
}

}  // namespace gfmd
