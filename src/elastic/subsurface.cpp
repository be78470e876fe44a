// Subsurface stresses and displacements of a layer or half-space under surface tractions
// (SPEC §5): per-mode plane-strain responses (propagator or anchored layer solution), then
// rotated to the lab frame and synthesised. See include/gfmd/elastic/stress.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/body.hpp"
#include "gfmd/elastic/layered.hpp"
#include "gfmd/elastic/stress.hpp"
#include "stress_detail.hpp"
#include "subsurface_mode.hpp"

namespace gfmd {

using namespace stress_detail;
using namespace subsurface_detail;

namespace {

// Lab-frame stress (xx, yy, zz, xy, xz, yz) and displacement of one mode with direction
// (c, s) for lab tractions (tx, ty, tz).
void to_lab(const ModeResponse& r, double c, double s, cplx tx, cplx ty, cplx tz, cplx* sig, cplx* u) {
  const cplx t[3] = {c * tx + s * ty, -s * tx + c * ty, tz};
  cplx sp[6], up[3];
  for (int k = 0; k < 6; ++k) sp[k] = r.stress[k][0] * t[0] + r.stress[k][1] * t[1] + r.stress[k][2] * t[2];
  for (int k = 0; k < 3; ++k) up[k] = r.disp[k][0] * t[0] + r.disp[k][1] * t[1] + r.disp[k][2] * t[2];
  if (sig) {
    const cplx s11 = sp[0], s22 = sp[1], s33 = sp[2], s12 = sp[3], s13 = sp[4], s23 = sp[5];
    sig[0] = c * c * s11 + s * s * s22 - 2.0 * c * s * s12;
    sig[1] = s * s * s11 + c * c * s22 + 2.0 * c * s * s12;
    sig[2] = s33;
    sig[3] = c * s * (s11 - s22) + (c * c - s * s) * s12;
    sig[4] = c * s13 - s * s23;
    sig[5] = s * s13 + c * s23;
  }
  if (u) {
    u[0] = c * up[0] - s * up[1];
    u[1] = s * up[0] + c * up[1];
    u[2] = up[2];
  }
}

// Spectral evaluation of the response on the whole grid; sig (6 spectra) and/or u (3).
// stack: a layered body's viscoelastic parts in motion and their per-mode factors (null: elastic).
void subsurface_spectra(const FFT& fft, const ElasticParams& el, const ContactFields& f, double depth,
                        std::array<SpecField, 6>* sig, std::array<SpecField, 3>* u,
                        const ViscoelasticStack* stack = nullptr) {
  const std::unique_ptr<Body> body = make_body(el);  // validates el
  check_depth(el, depth);
  const Grid& g = fft.grid();
  const std::size_t n = g.local_size();
  require_size(f.pressure, n, "pressure");
  const bool has_tx = present(f.tx, g, "tx"), has_ty = present(f.ty, g, "ty");
  RealField tz(n);
  for (std::size_t i = 0; i < n; ++i) tz[i] = -f.pressure[i];
  SpecField TZ = fft.spec_field(), TX, TY;
  fft.forward(tz.data(), TZ.data());
  if (has_tx) {
    TX = fft.spec_field();
    fft.forward(f.tx.data(), TX.data());
  }
  if (has_ty) {
    TY = fft.spec_field();
    fft.forward(f.ty.data(), TY.data());
  }
  if (sig)
    for (auto& s : *sig) s = fft.spec_field();
  if (u)
    for (auto& s : *u) s = fft.spec_field();
  const int nxh = g.nxh();
  const bool evenx = g.nx % 2 == 0, eveny = g.ny % 2 == 0;
  for_rows(g.rows(), [&](int row) {
    const int iky = g.y0 + row;
    for (int ikx = 0; ikx < nxh; ++ikx) {
      const std::size_t k = static_cast<std::size_t>(row) * nxh + ikx;
      const double qx = g.qx(ikx), qy = g.qy(iky), q = std::hypot(qx, qy);
      const ModeResponse r =
          stack ? body->mode_response(q, depth, stack->moduli(k)) : body->mode_response(q, depth);
      const double c = q > 0 ? qx / q : 1.0, s = q > 0 ? qy / q : 0.0;
      const cplx tx = has_tx ? TX[k] : cplx(0.0), ty = has_ty ? TY[k] : cplx(0.0), tzk = TZ[k];
      // On a Nyquist line the mode q and its mirror are the same mode: keep the part of
      // the response that is even in that component (as ElasticBody does).
      const bool nyx = evenx && ikx == g.nx / 2, nyy = eveny && iky == g.ny / 2;
      cplx sacc[6] = {}, uacc[3] = {};
      int count = 0;
      for (int fx = 0; fx < (nyx ? 2 : 1); ++fx)
        for (int fy = 0; fy < (nyy ? 2 : 1); ++fy) {
          cplx sg[6], ug[3];
          to_lab(r, fx ? -c : c, fy ? -s : s, tx, ty, tzk, sig ? sg : nullptr, u ? ug : nullptr);
          if (sig)
            for (int m = 0; m < 6; ++m) sacc[m] += sg[m];
          if (u)
            for (int m = 0; m < 3; ++m) uacc[m] += ug[m];
          ++count;
        }
      if (sig)
        for (int m = 0; m < 6; ++m) (*sig)[m][k] = sacc[m] / static_cast<double>(count);
      if (u)
        for (int m = 0; m < 3; ++m) (*u)[m][k] = uacc[m] / static_cast<double>(count);
    }
  });
}
}  // namespace

ModeResponse mode_response(double q, double depth, const ElasticParams& el) {
  return make_body(el)->mode_response(q, depth);
}

StressField subsurface_stress(const FFT& fft, const ElasticParams& el, const ContactFields& f, double depth,
                              const ViscoelasticParams& visco) {
  std::array<SpecField, 6> sig;
  using Part = ViscoelasticParams::Part;
  if (visco.enabled() && visco.velocity != 0.0 && el.layered() && visco.part != Part::All) {
    // A layered viscoelastic body in motion: each viscoelastic part's E(omega) = E0 / c per mode.
    // (Viscoelastic throughout, every modulus has one ratio: the stresses from tractions are the
    // elastic ones.)
    const ViscoelasticStack stack(fft.grid(), el, visco);
    subsurface_spectra(fft, el, f, depth, &sig, nullptr, &stack);
  } else {
    subsurface_spectra(fft, el, f, depth, &sig, nullptr);
  }
  StressField s = make_stress(fft.grid().local_size());
  RealField* out[6] = {&s.xx, &s.yy, &s.zz, &s.xy, &s.xz, &s.yz};
  for (int m = 0; m < 6; ++m) fft.backward(sig[m].data(), out[m]->data());
  return s;
}

DisplacementField subsurface_displacement(const FFT& fft, const ElasticParams& el, const ContactFields& f,
                                          double depth) {
  std::array<SpecField, 3> u;
  subsurface_spectra(fft, el, f, depth, nullptr, &u);
  DisplacementField d;
  RealField* out[3] = {&d.ux, &d.uy, &d.uz};
  for (int m = 0; m < 3; ++m) {
    out[m]->assign(fft.grid().local_size(), 0.0);
    fft.backward(u[m].data(), out[m]->data());
  }
  return d;
}

}  // namespace gfmd
