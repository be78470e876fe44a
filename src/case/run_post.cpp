// The post-processing of a solved case: line profiles and stresses. See src/case/run_detail.hpp.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "gfmd/elastic/stress.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
#include "run_detail.hpp"

namespace gfmd::run_detail {

// Line profiles through the pressure maximum along and across the sliding direction
// (nearest grid point on the line), as in the paper's SM Fig. 2. Needs the surface stress
// tensor; the principal values are evaluated at the line points only. The fields are those
// held here (the whole cell, or a slab: the line points' values are picked from the
// processes that hold them, and every process makes the same table).
LineProfiles line_profiles(const Grid& g, const CaseResult& r) {
  const std::size_t imax = grid_argmax(g, [&](std::size_t i) { return r.fields.pressure[i]; }).first;
  const int cx = static_cast<int>(imax % g.nx), cy = static_cast<int>(imax / g.nx);
  const double th = r.config.friction.direction_deg * std::numbers::pi / 180.0;
  const double ex = std::cos(th), ey = std::sin(th);
  const DerivedFields& d = r.derived;
  std::vector<std::pair<std::string, const RealField*>> cols = {
      {"ux", &r.fields.ux}, {"uy", &r.fields.uy}, {"uz", &r.fields.uz}, {"pressure", &r.fields.pressure}};
  if (r.config.friction.coefficient > 0) {
    cols.push_back({"dissipation", &d.dissipation});
    cols.push_back({"slip_longitudinal", &d.slip_longitudinal});
    cols.push_back({"slip_transverse", &d.slip_transverse});
  }
  const StressField& st = r.stress;
  const std::size_t stress_from = cols.size();
  for (const auto& c : std::vector<std::pair<std::string, const RealField*>>{{"sigma_xx", &st.xx},
                                                                             {"sigma_yy", &st.yy},
                                                                             {"sigma_zz", &st.zz},
                                                                             {"sigma_xy", &st.xy},
                                                                             {"sigma_xz", &st.xz},
                                                                             {"sigma_yz", &st.yz}})
    cols.push_back(c);
  static const char* const kPrincipal[] = {"sigma_1", "von_mises", "e1_x", "e1_y", "e1_z"};
  // The line points: for each distance, the point along and the point across, at the finer
  // spacing, over the cell's longer side (each line wraps around the periodic cell: a line
  // contact's thin cell gives the whole profile along the long side, the short one repeating),
  // at most max(nx, ny) of them (cells far from square: the finer spacing's stretch).
  const double ds = std::min(g.dx(), g.dy());
  const double along = std::min(std::max(g.lx, g.ly) / ds, static_cast<double>(std::max(g.nx, g.ny)));
  const int half = static_cast<int>(std::lround(along)) / 2;
  const auto at = [&](double sx, double sy) {
    const int ix = ((cx + static_cast<int>(std::lround(sx / g.dx()))) % g.nx + g.nx) % g.nx;
    const int iy = ((cy + static_cast<int>(std::lround(sy / g.dy()))) % g.ny + g.ny) % g.ny;
    return static_cast<std::size_t>(iy) * g.nx + ix;
  };
  std::vector<std::size_t> points;
  for (int k = -half; k < half; ++k) {
    const double sdist = k * ds;
    points.push_back(at(sdist * ex, sdist * ey));
    points.push_back(at(-sdist * ey, sdist * ex));
  }
  std::vector<std::vector<double>> values;
  for (const auto& c : cols) values.push_back(mpi::pick(g, *c.second, points));
  LineProfiles out;
  out.centre_x = g.x(cx);
  out.centre_y = g.y(cy);
  for (int k = -half; k < half; ++k) out.s.push_back(k * ds);
  const std::size_t rows = out.s.size();
  for (int line = 0; line < 2; ++line) {
    const std::string dir_name = line == 0 ? "longitudinal" : "transverse";
    for (std::size_t c = 0; c < cols.size(); ++c) {
      out.columns.push_back(cols[c].first + "_" + dir_name);
      std::vector<double>& v = out.values.emplace_back(rows);
      for (std::size_t row = 0; row < rows; ++row) v[row] = values[c][2 * row + line];
    }
    const std::size_t first = out.values.size();  // the principal columns of this line
    for (const char* c : kPrincipal) {
      out.columns.push_back(c + ("_" + dir_name));
      out.values.emplace_back(rows);
    }
    for (std::size_t row = 0; row < rows; ++row) {
      const auto sv = [&](std::size_t c) { return values[stress_from + c][2 * row + line]; };
      const Principal3 e = principal(sv(0), sv(1), sv(2), sv(3), sv(4), sv(5));
      const double pv[] = {e.s1, von_mises(sv(0), sv(1), sv(2), sv(3), sv(4), sv(5)), e.e1[0], e.e1[1],
                           e.e1[2]};
      for (std::size_t c = 0; c < std::size(pv); ++c) out.values[first + c][row] = pv[c];
    }
  }
  return out;
}

// Stresses, their summaries and the profiles table, on the fields held here (fft's grid).
// With keep_fields false only the summaries and the table stay (the full fields are what
// fields.nc and the PNG maps show).
void compute_stresses(CaseResult& r, const FFT& fft, const Topography& topo, bool keep_fields) {
  const Config& cfg = r.config;
  const Grid& g = fft.grid();
  // Fraction of the cells with s1 >= half its maximum (the full solution's here, while its
  // field is still there; each post-analysis's below).
  const auto above_half = [&g](const RealField& s1, double max) {
    if (!(max > 0)) return 0.0;
    return grid_sum(g, [&](std::size_t i) { return s1[i] >= 0.5 * max ? 1.0 : 0.0; }) /
           static_cast<double>(g.size());
  };
  // The CUDA backend evaluates the stresses (surface, both post-analyses, subsurface planes)
  // on the device where they fit its memory (docs/gpu.md).
  // The solved displacement is not the body's own elastic one for a viscoelastic body in motion
  // (times E0/E(omega) per mode) or, in rolling under an elastic indenter, in-plane (the pair's):
  // then the stress comes from the tractions through the body's own elastic response
  // (traction_stress), which with nu constant is the viscoelastic body's too.
  const bool own_displacement =
      !(cfg.visco.enabled() && cfg.visco.velocity != 0.0) && !(cfg.indenter.body && cfg.friction.rolling());
  const bool on_device = backend().name() == "cuda" && own_displacement;
  DeviceStressRequest ask;
  ask.high_tension_fraction = cfg.stress.high_tension_fraction;
  std::optional<DeviceStressResult> dev;
  if (on_device) {
    ask.tensor = keep_fields || cfg.stress.profiles;
    ask.parts = keep_fields ? PrincipalParts::All : PrincipalParts::SummaryOnly;
    dev = device_surface_stress(g, cfg.elastic, r.fields, ask);
  }
  r.stress_on_device = dev.has_value();
  // The post-analyses and planes below bring back their summary and sigma_I's map, as on the host.
  DeviceStressRequest summary_s1;
  summary_s1.high_tension_fraction = cfg.stress.high_tension_fraction;
  summary_s1.s1 = true;
  if (dev) {
    r.stress = std::move(dev->tensor);
    r.principal = std::move(dev->principal);
    r.stress_summary = dev->summary;
    if (!cfg.stress.post_analysis.empty()) r.area_above_half_max = dev->above_half;
  } else {
    r.stress = own_displacement ? surface_stress(fft, cfg.elastic, r.fields)
                                : traction_stress(fft, cfg.elastic, r.fields, cfg.visco);
    r.principal = principal(r.stress, keep_fields ? PrincipalParts::All : PrincipalParts::SummaryOnly);
    r.stress_summary = summarize(g, r.principal, cfg.stress.high_tension_fraction);
    if (!cfg.stress.post_analysis.empty())
      r.area_above_half_max = above_half(r.principal.s1, r.stress_summary->max_tensile_stress);
  }
  if (cfg.stress.profiles) r.profiles = line_profiles(g, r);
  if (!keep_fields) {
    r.stress = StressField{};
    r.principal = PrincipalField{};
  }
  if (!cfg.stress.post_analysis.empty()) {
    // The frictionless solution: the reference solve (kept for this alone), or the solution
    // itself without friction, or (no reference kept) a frictionless solve now.
    ContactFields rf;
    if (r.reference) {  // run_case kept its pressure and displacements for this
      rf.pressure = std::move(r.reference->pressure);
      rf.ux = std::move(r.reference->ux);
      rf.uy = std::move(r.reference->uy);
    } else if (cfg.friction.coefficient == 0) {
      rf.pressure = r.fields.pressure;
      rf.ux = r.fields.ux;
      rf.uy = r.fields.uy;
    }
    const ElasticBody body(g, cfg.elastic, {}, cfg.indenter.body ? &*cfg.indenter.body : nullptr);
    if (!r.reference && cfg.friction.coefficient > 0) {
      FrictionParams none = cfg.friction;
      none.coefficient = 0.0;
      // The body as solved (a viscoelastic one in motion too); `body` serves the stresses.
      const ElasticBody solved(g, cfg.elastic, cfg.visco, cfg.indenter.body ? &*cfg.indenter.body : nullptr);
      ContactSolver ref(solved, topo, cfg.interaction, none, cfg.solver);
      const SolveInfo info = ref.solve(cfg.load, rf);
      if (!info.converged) throw SolveError("post-analysis reference: " + info.status);
    }
    const double mu = cfg.friction.coefficient, angle = cfg.friction.direction_deg;
    for (const std::string& kind : cfg.stress.post_analysis) {
      if (on_device) {
        std::optional<DeviceStressResult> d =
            kind == "paper" ? device_paper_post_analysis_stress(g, cfg.elastic, rf, mu, angle, summary_s1)
                            : device_post_analysis_stress(body, rf.pressure, mu, angle, summary_s1);
        if (d) {
          CaseResult::PostAnalysis& pa = r.post_analyses.emplace_back();
          pa.kind = kind;
          pa.summary = d->summary;
          pa.area_above_half_max = d->above_half;
          pa.s1 = std::move(d->principal.s1);
          continue;
        }
        r.stress_on_device = false;
      }
      PrincipalField pp;
      {
        StressField ps;
        if (own_displacement) {
          ps = kind == "paper" ? paper_post_analysis_stress(fft, cfg.elastic, rf, mu, angle)
                               : post_analysis_stress(fft, body, rf.pressure, mu, angle);
        } else {
          // The solved displacement is not the body's own elastic one: both kinds from tractions,
          // the paper's with the friction written into the shear tractions only.
          ContactFields st = uniform_slip_tractions(rf.pressure, mu, angle);
          RealField tx, ty;
          if (kind == "paper") {
            tx = std::exchange(st.tx, RealField());
            ty = std::exchange(st.ty, RealField());
          }
          ps = traction_stress(fft, cfg.elastic, st, cfg.visco);
          if (kind == "paper") {
            ps.xz = std::move(tx);
            ps.yz = std::move(ty);
          }
        }
        pp = principal(ps, PrincipalParts::SummaryOnly);
      }
      CaseResult::PostAnalysis pa;
      pa.kind = kind;
      pa.summary = summarize(g, pp, cfg.stress.high_tension_fraction);
      pa.area_above_half_max = above_half(pp.s1, pa.summary.max_tensile_stress);
      pa.s1 = std::move(pp.s1);
      r.post_analyses.push_back(std::move(pa));
    }
  }
  for (double d : cfg.stress.depths) {
    PrincipalField pf;
    try {
      if (on_device) {
        DeviceStressRequest q = summary_s1;
        q.von_mises = true;
        if (std::optional<DeviceStressResult> dv = device_subsurface_stress(g, cfg.elastic, r.fields, d, q)) {
          r.subsurface.push_back(
              {d, dv->summary, std::move(dv->principal.von_mises), std::move(dv->principal.s1)});
          continue;
        }
        r.stress_on_device = false;
      }
      pf =
          principal(subsurface_stress(fft, cfg.elastic, r.fields, d, cfg.visco), PrincipalParts::SummaryOnly);
    } catch (const ParameterError& e) {
      throw InputError("stress.depths", e.why() + " (depth " + format_number(d) + ")");
    }
    r.subsurface.push_back({d, summarize(g, pf, cfg.stress.high_tension_fraction), pf.von_mises, pf.s1});
  }
}

}  // namespace gfmd::run_detail
