// An elastic indenter after the solve: its own tractions and surface displacement (in its frame),
// the deformed surface the downhill force acts on, and its stresses. See src/case/run_detail.hpp.
#include <cstddef>

#include "gfmd/core/error.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"
#include "run_detail.hpp"

namespace gfmd::run_detail {

ContactFields indenter_fields(const FFT& fft, const ElasticParams& indenter, const ContactFields& f) {
  const Grid& g = fft.grid();
  const std::size_t n = g.local_size();
  const ElasticBody body(g, indenter);
  // In the indenter's frame (z' = -z, x and y kept) its traction is (-tx, -ty, -p): the reverse
  // of the body's (tx, ty, -p), with the normal pointing out of the indenter.
  SpecField P = fft.spec_field(), TX, TY;
  fft.forward(f.pressure.data(), P.data());
  const bool tangential = f.tx.size() == n && f.ty.size() == n;
  if (tangential) {
    TX = fft.spec_field();
    TY = fft.spec_field();
    fft.forward(f.tx.data(), TX.data());
    fft.forward(f.ty.data(), TY.data());
  }
  SpecField UX = fft.spec_field(), UY = fft.spec_field(), UZ = fft.spec_field();
  body.displacement(tangential ? TX.data() : nullptr, tangential ? TY.data() : nullptr, P.data(), UX.data(),
                    UY.data(), UZ.data(), -1.0, -1.0);
  ContactFields o;
  o.pressure = f.pressure;
  if (tangential) {
    o.tx.resize(n);
    o.ty.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      o.tx[i] = -f.tx[i];
      o.ty[i] = -f.ty[i];
    }
  }
  o.ux = fft.real_field();
  o.uy = fft.real_field();
  o.uz = fft.real_field();
  fft.backward(UX.data(), o.ux.data());
  fft.backward(UY.data(), o.uy.data());
  fft.backward(UZ.data(), o.uz.data());
  return o;
}

RealField deformed_indenter(const Topography& topo, const ContactFields& own) {
  // The indenter's face is at -h (h the heights, the gap g0 - delta - u_z with g0 = max h - h);
  // it moves by its lab displacement -u'_z: the face at -(h + u'_z).
  RealField face = topo.h;
  for (std::size_t i = 0; i < face.size(); ++i) face[i] += own.uz[i];
  return face;
}

void indenter_stresses(CaseResult& r, const FFT& fft, const ContactFields& own) {
  const Config& cfg = r.config;
  const Grid& g = fft.grid();
  const ElasticParams& el = *cfg.indenter.body;
  const double frac = cfg.stress.high_tension_fraction;
  r.indenter_stress_summary =
      summarize(g, principal(surface_stress(fft, el, own), PrincipalParts::SummaryOnly), frac);
  r.indenter_subsurface.clear();
  for (double d : cfg.stress.depths) {
    if (d > el.depth_of_base()) continue;  // below the indenter's own base
    const PrincipalField pf = principal(subsurface_stress(fft, el, own, d), PrincipalParts::SummaryOnly);
    r.indenter_subsurface.push_back({d, summarize(g, pf, frac), {}, {}});
  }
}

}  // namespace gfmd::run_detail
