#include "gfmd/elastic/layered.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"

namespace gfmd {

namespace {

// The matrices below are written for a real material and, with a complex modulus (a viscoelastic
// top layer at one frequency: the correspondence principle), for a complex one; T is double or cplx.
template <class T>
using Mat4T = std::array<std::array<T, 4>, 4>;
template <class T>
using ColsT = std::array<std::array<T, 2>, 4>;  // a 4x2 matrix: two state vectors side by side
using Mat4 = Mat4T<double>;
using Cols = ColsT<double>;

template <class T>
Mat4T<T> mul(const Mat4T<T>& a, const Mat4T<T>& b) {
  Mat4T<T> c{};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 4; ++j) c[i][j] += a[i][k] * b[k][j];
  return c;
}

template <class T>
Mat4T<T> add_identity(Mat4T<T> m, double diag, double scale = 1.0) {  // scale m + diag I
  for (int i = 0; i < 4; ++i) {
    for (T& v : m[i]) v *= scale;
    m[i][i] += diag;
  }
  return m;
}

template <class T>
ColsT<T> times(const Mat4T<T>& a, const ColsT<T>& w) {
  ColsT<T> r{};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 2; ++j) r[i][j] += a[i][k] * w[k][j];
  return r;
}

// One layer's plane-strain system in x = q z with the state s = (U1, U3, S13/q, S33/q), where
// u1 = i U1, u3 = U3, sigma13 = i S13, sigma33 = S33 (real for a real mode):
//   dU1 = -U3 + s13/G,  dU3 = a U1 + b s33/G,  ds13 = 2G/(1-nu) U1 - a s33,  ds33 = s13,
// with a = nu/(1-nu), b = (1-2nu)/(2(1-nu)). M's eigenvalues are +1 and -1, each twice with
// one eigenvector: (M^2 - I)^2 = 0, so
//   exp(M x) = e^x P+ (I + x (M - I)) + e^-x P- (I + x (M + I)),
// P+ = (2I - M)(M + I)^2/4 and P- = (2I + M)(M - I)^2/4 the projectors (partial fractions
// of 1/((s-1)^2 (s+1)^2)). The antiplane system (U2, S23/q) has d = [[0, 1/G], [G, 0]].
// A complex G leaves the eigenvalues, and so the projector form, as they are.
template <class T>
struct MaterialT {
  Mat4T<T> grow, grow_n, decay, decay_n;  // P+, P+(M - I), P-, P-(M + I)
  T g = 0.0;                              // shear modulus
  double nu = 0.0;                        // Poisson ratio
  T es = 0.0;                             // E*
};
using Material = MaterialT<double>;

template <class T>
MaterialT<T> material(T contact_modulus, double nu) {
  const T g = contact_modulus * (1.0 - nu) / 2.0;
  const double a = nu / (1.0 - nu), b = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
  const T one(1.0), zero(0.0);
  const Mat4T<T> m = {{{zero, T(-1.0), 1.0 / g, zero},
                       {T(a), zero, zero, b / g},
                       {2.0 * g / (1.0 - nu), zero, zero, T(-a)},
                       {zero, zero, one, zero}}};
  const Mat4T<T> mp = add_identity(m, 1.0), mm = add_identity(m, -1.0);
  Mat4T<T> pp = mul(add_identity(m, 2.0, -1.0), mul(mp, mp));
  Mat4T<T> pm = mul(add_identity(m, 2.0), mul(mm, mm));
  for (Mat4T<T>* p : {&pp, &pm})
    for (auto& row : *p)
      for (T& v : row) v *= 0.25;
  return {pp, mul(pp, mm), pm, mul(pm, mp), g, nu, contact_modulus};
}

// The states of a half-space of this material (those that decay with depth, i.e. grow with
// z: the range of P+), spanned by P+ applied to unit surface displacements.
template <class T>
ColsT<T> half_space_states(const MaterialT<T>& mat) {
  ColsT<T> w{};
  for (int i = 0; i < 4; ++i) {
    w[i][0] = mat.grow[i][0];
    w[i][1] = mat.grow[i][1];
  }
  return w;
}

// Beyond this q h a layer hides what is below it to e^{-2 q h} < 1e-34.
constexpr double kOpaque = 40.0;

// The states at the top of a layer of thickness x (in units of 1/q) whose bottom states are w,
// scaled to order one: with log_scale, exactly exp(M x) w = e^log_scale r (log_scale increased
// by x and the log of the scale); without, up to a factor (only their span matters), and a
// layer beyond kOpaque leaves the span of its own half-space.
template <class T>
ColsT<T> layer_step(const MaterialT<T>& mat, double x, const ColsT<T>& w, double* log_scale) {
  if (!log_scale && x > kOpaque) return half_space_states(mat);
  const double e2 = std::exp(-2.0 * x);  // exp(M x) = e^x (P+ (I + x (M - I)) + e^-2x P- (...))
  Mat4T<T> t{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      t[i][j] = mat.grow[i][j] + x * mat.grow_n[i][j] + e2 * (mat.decay[i][j] + x * mat.decay_n[i][j]);
  ColsT<T> r = times(t, w);
  double big = 0.0;
  for (const auto& row : r) big = std::max({big, std::abs(row[0]), std::abs(row[1])});
  if (big > 0.0)
    for (auto& row : r) {
      row[0] /= big;
      row[1] /= big;
    }
  if (log_scale) *log_scale += x + std::log(big);
  return r;
}

template <class T>
struct StackT {
  std::vector<MaterialT<T>> mats;  // top first
  std::vector<double> thick;       // top first
  bool substrate = false;
  MaterialT<T> base;  // the substrate's material when substrate
};
using Stack = StackT<double>;

// The stack of `el` with each material's E* given (T = cplx: complex moduli at one frequency) in
// the order top layer, layers top to bottom, substrate (ignored on a rigid base).
template <class T>
StackT<T> stack_of(const ElasticParams& el, const T* moduli) {
  StackT<T> s;
  s.mats.push_back(material(moduli[0], el.poisson));
  s.thick.push_back(el.thickness);
  for (std::size_t i = 0; i < el.layers.size(); ++i) {
    s.mats.push_back(material(moduli[i + 1], el.layers[i].poisson));
    s.thick.push_back(el.layers[i].thickness);
  }
  s.substrate = el.on_substrate();
  if (s.substrate) s.base = material(moduli[el.layers.size() + 1], el.substrate_poisson);
  return s;
}
// Each material's own E* of `el`, in stack order (top, layers, substrate).
template <class T>
std::vector<T> own_moduli(const ElasticParams& el) {
  std::vector<T> m{T(el.contact_modulus)};
  for (const ElasticLayer& l : el.layers) m.emplace_back(l.contact_modulus);
  m.emplace_back(el.substrate_contact_modulus);
  return m;
}
Stack stack_of(const ElasticParams& el) { return stack_of(el, own_moduli<double>(el).data()); }

}  // namespace

namespace {

// Where a depth lies: in layer `layer` (mats.size(): the substrate), below_top beneath its top.
// A depth on an interface belongs to the layer above it.
struct Place {
  std::size_t layer;
  double below_top;
};

template <class T>
Place place_of(const StackT<T>& s, double depth) {
  double top = 0.0;
  for (std::size_t i = 0; i < s.mats.size(); ++i) {
    if (depth <= top + s.thick[i] || (i + 1 == s.mats.size() && !s.substrate))
      return {i, std::min(depth - top, s.thick[i])};
    top += s.thick[i];
  }
  return {s.mats.size(), depth - top};
}

const Material& material_at(const Stack& s, std::size_t layer) {
  return layer < s.mats.size() ? s.mats[layer] : s.base;
}

// The plane-strain states at a place that the body below it admits (their span), from the base up.
template <class T>
ColsT<T> states_at(const StackT<T>& s, double q, Place p) {
  if (p.layer == s.mats.size()) return half_space_states(s.base);  // any depth of the substrate
  ColsT<T> w{};
  if (s.substrate) {
    w = half_space_states(s.base);
  } else {  // a rigid base: no displacement, any traction
    w[2][0] = 1.0;
    w[3][1] = 1.0;
  }
  for (std::size_t i = s.mats.size(); i-- > p.layer + 1;)
    w = layer_step(s.mats[i], q * s.thick[i], w, nullptr);
  const double h = s.thick[p.layer];
  if (h == std::numeric_limits<double>::infinity()) return half_space_states(s.mats[p.layer]);
  return layer_step(s.mats[p.layer], q * (h - p.below_top), w, nullptr);
}

// Antiplane states (U2, S23/q): d/dx = [[0, 1/G], [G, 0]], exp = [[ch, sh/G], [G sh, ch]].
template <class T>
using PairT = std::array<T, 2>;
using Pair = PairT<double>;

template <class T>
PairT<T> anti_step(T g, double x, PairT<T> w, double* log_scale) {
  if (!log_scale && x > kOpaque) return {T(1.0), g};  // the span only: a half-space of this material
  const double e2 = std::exp(-2.0 * x), ch = 0.5 * (1.0 + e2), sh = 0.5 * (1.0 - e2);  // e^-x cosh, sinh
  const PairT<T> r = {ch * w[0] + sh * w[1] / g, g * sh * w[0] + ch * w[1]};
  const double big = std::max(std::abs(r[0]), std::abs(r[1]));
  if (log_scale) *log_scale += x + std::log(big);
  return {r[0] / big, r[1] / big};
}

template <class T>
PairT<T> anti_states_at(const StackT<T>& s, double q, Place p) {
  if (p.layer == s.mats.size()) return {T(1.0), s.base.g};
  PairT<T> w = s.substrate ? PairT<T>{T(1.0), s.base.g} : PairT<T>{T(0.0), T(1.0)};
  for (std::size_t i = s.mats.size(); i-- > p.layer + 1;)
    w = anti_step(s.mats[i].g, q * s.thick[i], w, nullptr);
  const double h = s.thick[p.layer];
  if (h == std::numeric_limits<double>::infinity()) return {T(1.0), s.mats[p.layer].g};
  return anti_step(s.mats[p.layer].g, q * (h - p.below_top), w, nullptr);
}

}  // namespace

namespace {
// C = X Y^-1 / q from the surface states (X their displacement rows, Y their traction rows S/q),
// c22 = U2 / (q s23) from the antiplane ones.
template <class T>
std::array<T, 4> surface_compliance(double q, const StackT<T>& s) {
  const ColsT<T> w = states_at(s, q, {0, 0.0});
  const T det = w[2][0] * w[3][1] - w[2][1] * w[3][0];
  const T y00 = w[3][1] / det, y01 = -w[2][1] / det, y10 = -w[3][0] / det, y11 = w[2][0] / det;
  const PairT<T> a = anti_states_at(s, q, {0, 0.0});
  return {(w[0][0] * y00 + w[0][1] * y10) / q,   // c11
          a[0] / (a[1] * q),                     // c22
          (w[1][0] * y01 + w[1][1] * y11) / q,   // c33
          (w[0][0] * y01 + w[0][1] * y11) / q};  // c13 = (X Y^-1)_{10}: the matrix is symmetric
}
}  // namespace

RotatedCompliance layered_compliance(double q, const ElasticParams& el) {
  const std::array<double, 4> c = surface_compliance(q, stack_of(el));
  return {c[0], c[1], c[2], c[3]};
}

ComplexRotatedCompliance layered_compliance(double q, const ElasticParams& el,
                                            const std::vector<cplx>& moduli) {
  const std::array<cplx, 4> c = surface_compliance(q, stack_of(el, moduli.data()));
  return {c[0], c[1], c[2], c[3]};
}

namespace {
// The response of a mode q > 0 at the place p of the stack s (layered_mode_response).
template <class T>
ModeResponse plane_response(const StackT<T>& s, double q, Place p) {
  const MaterialT<T>& mat = p.layer < s.mats.size() ? s.mats[p.layer] : s.base;
  const double nu = mat.nu;
  const T g = mat.g;
  ModeResponse r;
  // Plane strain: the states at the depth (span w) lifted to the surface (v = exp(..) w up to
  // e^log_scale); the surface traction fixes the combination, s(d) = w (v_S)^-1 S_top.
  const ColsT<T> w = states_at(s, q, p);
  double log_scale = 0.0;
  ColsT<T> v = layer_step(mat, q * p.below_top, w, &log_scale);
  for (std::size_t i = std::min(p.layer, s.mats.size()); i-- > 0;)
    v = layer_step(s.mats[i], q * s.thick[i], v, &log_scale);
  const T det = v[2][0] * v[3][1] - v[2][1] * v[3][0];
  const double f = std::exp(-log_scale);
  const T i00 = v[3][1] / det, i01 = -v[2][1] / det, i10 = -v[3][0] / det, i11 = v[2][0] / det;
  T R[4][2];  // s(d) = R (S_top / q)
  for (int i = 0; i < 4; ++i) {
    R[i][0] = f * (w[i][0] * i00 + w[i][1] * i10);
    R[i][1] = f * (w[i][0] * i01 + w[i][1] * i11);
  }
  const cplx I(0.0, 1.0);
  const T kk = 2.0 * g / (1.0 - nu);
  const double nn = nu / (1.0 - nu);
  // t1 = 1 (S13 = -i): u1 = R00/q, u3 = -i R10/q, sigma13 = R20, sigma33 = -i R30,
  // sigma11 = i (kk R00 - nn R30); t3 = 1 (S33 = 1): u1 = i R01/q, u3 = R11/q,
  // sigma13 = i R21, sigma33 = R31, sigma11 = -kk R01 + nn R31. Plane strain: s22 = nu (s11 + s33).
  const cplx s11[2] = {I * (kk * R[0][0] - nn * R[3][0]), -kk * R[0][1] + nn * R[3][1]};
  const cplx s33[2] = {-I * R[3][0], R[3][1]};
  for (int k = 0; k < 2; ++k) {
    const int col = k == 0 ? 0 : 2;
    r.stress[0][col] = s11[k];
    r.stress[2][col] = s33[k];
    r.stress[1][col] = nu * (s11[k] + s33[k]);
  }
  r.stress[4][0] = R[2][0];
  r.stress[4][2] = I * R[2][1];
  r.disp[0][0] = R[0][0] / q;
  r.disp[0][2] = I * R[0][1] / q;
  r.disp[2][0] = -I * R[1][0] / q;
  r.disp[2][2] = R[1][1] / q;
  // Antiplane (t2 = 1): u2 = U2, sigma23 = S23, sigma12 = i q G u2.
  const PairT<T> a = anti_states_at(s, q, p);
  double alog = 0.0;
  PairT<T> b = anti_step(mat.g, q * p.below_top, a, &alog);
  for (std::size_t i = std::min(p.layer, s.mats.size()); i-- > 0;)
    b = anti_step(s.mats[i].g, q * s.thick[i], b, &alog);
  const T fa = std::exp(-alog) / b[1];  // s(d) = a (S23_top/q) / b[1] up to e^-alog
  r.disp[1][1] = fa * a[0] / q;
  r.stress[5][1] = fa * a[1];
  r.stress[3][1] = I * g * fa * a[0];
  return r;
}

}  // namespace

ModeResponse layered_mode_response(double q, double depth, const ElasticParams& el) {
  const Stack s = stack_of(el);
  const Place p = place_of(s, depth);
  const Material& mat = material_at(s, p.layer);
  const double nu = mat.nu;
  ModeResponse r;
  if (q == 0.0) {
    // Uniform traction: uniform sigma_13, sigma_23, sigma_33 and uniaxial strain in each layer
    // (sigma_11 = sigma_22 = nu/(1-nu) sigma_33 with its own nu). The displacement is zero at
    // the surface on a substrate (as ElasticBody pins it) and on the base of a rigid one: the
    // strain integrated from there, t/G in-plane and (1-2nu)/((1-nu)^2 E*) t3 normal per length.
    r.stress[0][2] = r.stress[1][2] = nu / (1.0 - nu);
    r.stress[2][2] = 1.0;
    r.stress[4][0] = 1.0;
    r.stress[5][1] = 1.0;
    double t_per = 0.0, n_per = 0.0, top = 0.0;
    const auto add = [&](const Material& m, double len, double sign) {
      t_per += sign * len / m.g;
      n_per += sign * len * (1.0 - 2.0 * m.nu) / ((1.0 - m.nu) * (1.0 - m.nu) * m.es);
    };
    for (std::size_t i = 0; i < s.mats.size(); ++i) {
      const double h = s.thick[i];
      if (s.substrate)  // -(the part of the layer above the depth)
        add(s.mats[i], std::clamp(depth - top, 0.0, h), -1.0);
      else  // the part of the layer below the depth
        add(s.mats[i], std::clamp(top + h - depth, 0.0, h), 1.0);
      top += h;
    }
    if (s.substrate && depth > top) add(s.base, depth - top, -1.0);
    r.disp[0][0] = r.disp[1][1] = t_per;
    r.disp[2][2] = n_per;
    return r;
  }
  return plane_response(s, q, p);
}

ModeResponse layered_mode_response(double q, double depth, const ElasticParams& el,
                                   const std::vector<cplx>& moduli) {
  if (q == 0.0) return layered_mode_response(q, depth, el);  // steady: elastic
  const StackT<cplx> s = stack_of(el, moduli.data());
  return plane_response(s, q, place_of(s, depth));
}

namespace {
// The index of the material (stack order) a part names; "all" has none (-1).
int material_of(const ViscoelasticParams& p, const ElasticParams& el) {
  using Part = ViscoelasticParams::Part;
  switch (p.part) {
    case Part::All:
      return -1;
    case Part::Substrate:
      return static_cast<int>(el.layers.size()) + 1;
    case Part::Layer:
      return p.layer + 1;
    case Part::Top:
      break;
  }
  return 0;
}
}  // namespace

ViscoelasticStack::ViscoelasticStack(const Grid& grid, const ElasticParams& el, const ViscoelasticParams& v)
    : el_(el), parts_(v.parts()) {
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    factors_.push_back(viscoelastic_factors(grid, parts_[i], relaxed_modulus(el, parts_[i])));
    if (material_of(parts_[i], el) <= 0) top_ = static_cast<int>(i);
  }
}

std::vector<cplx> ViscoelasticStack::moduli(std::size_t k) const {
  std::vector<cplx> m = own_moduli<cplx>(el_);
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    const cplx c = factors_[i][k];
    if (const int j = material_of(parts_[i], el_); j < 0)
      for (cplx& e : m) e /= c;
    else
      m[static_cast<std::size_t>(j)] /= c;
  }
  return m;
}

void validate_viscoelastic_parts(const ElasticParams& el, const ViscoelasticParams& v) {
  using Part = ViscoelasticParams::Part;
  const std::vector<ViscoelasticParams> parts = v.parts();
  std::vector<int> seen;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const ViscoelasticParams& p = parts[i];
    const std::string prefix = i == 0 ? "" : "viscoelastic_parts[" + std::to_string(i - 1) + "].";
    const std::string key = prefix + "viscoelastic_part";
    if (p.part == Part::Substrate && !el.on_substrate())
      throw ParameterError(key, "\"substrate\" needs an elastic substrate (substrate_contact_modulus)");
    if (p.part == Part::Layer && !(p.layer >= 0 && static_cast<std::size_t>(p.layer) < el.layers.size()))
      throw ParameterError(key, "names layers[" + std::to_string(p.layer) + "], but elastic.layers has " +
                                    std::to_string(el.layers.size()));
    if (p.part == Part::All && parts.size() > 1)
      throw ParameterError(key,
                           "\"all\" makes every part viscoelastic with one model: it cannot be "
                           "combined with elastic.viscoelastic_parts");
    const int m = material_of(p, el);
    if (std::find(seen.begin(), seen.end(), m) != seen.end())
      throw ParameterError(key, "names \"" + p.part_name() +
                                    "\", which another viscoelastic part already names (one model per part)");
    seen.push_back(m);
    try {
      p.validate(relaxed_modulus(el, p));
    } catch (const InputError& e) {
      throw ParameterError(prefix + e.where(), e.why());
    }
  }
}

double layered_mean_normal_compliance(const ElasticParams& el) {
  if (el.on_substrate()) return 0.0;
  const auto one = [](double es, double nu, double h) {
    return h * (1.0 - 2.0 * nu) / ((1.0 - nu) * (1.0 - nu) * es);
  };
  double c = one(el.contact_modulus, el.poisson, el.thickness);
  for (const ElasticLayer& l : el.layers) c += one(l.contact_modulus, l.poisson, l.thickness);
  return c;
}

double layered_mean_inplane_compliance(const ElasticParams& el) {
  if (el.on_substrate()) return 0.0;
  const auto one = [](double es, double nu, double h) { return 2.0 * h / (es * (1.0 - nu)); };
  double c = one(el.contact_modulus, el.poisson, el.thickness);
  for (const ElasticLayer& l : el.layers) c += one(l.contact_modulus, l.poisson, l.thickness);
  return c;
}

}  // namespace gfmd
