// The stage of run_case after the solve (src/case/run.cpp): observables, derived fields, the
// plastic figures, stresses, the padded map's check, the leakage and the comparisons with the
// references, where the fields are; the analysis, which needs the whole cell.
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

#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/contact/device.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/elastic/device_stress.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
#include "run_detail.hpp"

namespace gfmd::run_detail {

namespace {
// The solution's figures over its references' (summary.json; Comparisons), from the
// observables and the stress summaries that every process holds.
void compare_with_references(const Config& cfg, CaseResult& r) {
  Comparisons& c = r.comparisons;
  if (cfg.friction.coefficient > 0) {
    const double mu = cfg.friction.coefficient;
    c.delta_mu_over_mu_c = (r.observables.friction_coefficient - mu) / mu;
    c.delta_mu_over_mu_c_downhill = (r.observables.friction_coefficient_downhill - mu) / mu;
  }
  if (r.reference)
    c.delta_area_over_area =
        r.observables.relative_contact_area / r.reference->observables.relative_contact_area - 1.0;
  if (!r.stress_summary) return;
  const auto ratio = [](double a, double b) { return b > 0 ? std::optional<double>(a / b) : std::nullopt; };
  for (CaseResult::PostAnalysis& pa : r.post_analyses) {
    pa.ratio_max_tensile_stress = ratio(r.stress_summary->max_tensile_stress, pa.summary.max_tensile_stress);
    pa.ratio_max_von_mises = ratio(r.stress_summary->max_von_mises, pa.summary.max_von_mises);
    pa.ratio_area_above_half_max = ratio(r.area_above_half_max, pa.area_above_half_max);
  }
}

// Plastic saturation's figures (interaction.hardness): where the repulsive pressure (with adhesion
// the net pressure plus the adhesive traction) is at the cap, the
// indenter overlaps the undeformed surface by delta + u_z - g0 (g0 = max h - h), of which p/k
// is elastic (harmonic interaction; none for the hard wall). A collective on a slab.
void plastic_saturation(const Config& cfg, const Grid& grid, const Topography& topo, CaseResult& r) {
  const double H = cfg.interaction.hardness;
  const double hmax = grid_max(
      grid, [&](std::size_t i) { return topo.h[i]; }, -std::numeric_limits<double>::infinity());
  const double elastic =
      H / cfg.interaction.stiffness_on(cfg.elastic.contact_modulus, cfg.grid.dx());  // 0: hard wall
  RealField& pd = r.derived.plastic_displacement;
  pd.assign(grid.local_size(), 0.0);
  const double delta = r.info.approach;
  const auto s = grid_sums<2>(grid, [&](std::size_t i, std::array<double, 2>& acc) {
    if (!(r.fields.repulsion(i) >= H)) return;  // the repulsion is capped (with adhesion p + a)
    const double g0 = hmax - topo.h[i];
    pd[i] = std::max(0.0, delta + r.fields.uz[i] - g0 - elastic);
    acc[0] += 1.0;
    acc[1] += pd[i];
  });
  Observables& o = r.observables;
  o.plastic = true;
  o.plastic_area_fraction = s[0] / static_cast<double>(grid.size());
  o.max_plastic_displacement = grid_max(
      grid, [&](std::size_t i) { return pd[i]; }, 0.0);
  o.mean_plastic_displacement = s[0] > 0 ? s[1] / s[0] : 0.0;
}

}  // namespace

// Everything after the solve that works on the fields where they are -- the whole cell in
// one process, this process's slab in a distributed run, where every process calls it (its
// passes, transforms and reductions are collectives): observables, derived fields, stresses
// with their summaries and profiles, the check of a padded map. grid: the fields' grid.
void after_solve_here(const Config& cfg, const RunOptions& opts, const Grid& grid, const Topography& topo,
                      CaseResult& r) {
  const FFT fft(grid, cfg.solver.fft_planner);
  // The slip velocity with the derivative the solution was computed with (an automatic one
  // turns to upwind2 where the solve met stick).
  FrictionParams fric = cfg.friction;
  fric.slip_derivative = r.info.slip_derivative;
  // An elastic indenter: in sliding the downhill force acts on its deformed face (its material
  // rests in the contact, the face is a fixed shape); in rolling its material passes through the
  // contact too, and the work on its own deformation cancels over its surface (elastic, steady),
  // so the pressure drives against its undeformed profile (the energy balance of elastic pairs
  // rolling: 4e-3 on the deformed face, 7e-13 on the profile; TwoBodies.RollingPairsBalanceTheirWork).
  std::optional<ContactFields> own;
  RealField face;
  if (cfg.indenter.body) {
    own = indenter_fields(fft, *cfg.indenter.body, r.fields);
    face = deformed_indenter(topo, *own);
  }
  r.observables = compute_observables(fft, topo, fric, r.fields, r.info,
                                      own && !fric.rolling() ? &face : nullptr, own ? &*own : nullptr);
  if (fric.coefficient > 0) r.derived = derived_fields(fft, fric, r.fields);
  if (cfg.interaction.plastic()) plastic_saturation(cfg, grid, topo, r);
  if (r.info.converged) {
    const auto t0 = std::chrono::steady_clock::now();
    compute_stresses(r, fft, topo, opts.keep_stress_fields);
    if (own) indenter_stresses(r, fft, *own);
    r.stress_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const bool padded = cfg.indenter.type == "file" && cfg.indenter.periodize == "pad";
  if (r.info.converged && padded) {
    // The padding (every cell outside the map's corner quarter) must carry no load.
    const auto s = grid_sums<2>(grid, [&](std::size_t i, std::array<double, 2>& acc) {
      const double p = r.fields.repulsion(i);  // the pressure itself without adhesion
      const int ix = static_cast<int>(i % grid.nx), iy = grid.y0 + static_cast<int>(i / grid.nx);
      acc[0] += p;
      if (ix >= grid.nx / 2 || iy >= grid.ny / 2) acc[1] += p;
    });
    if (s[1] > 0.0)
      throw InputError(
          "indenter.periodize",
          "\"pad\": the padding around the map came into contact (" + format_number(100.0 * s[1] / s[0]) +
              " % of the load): the body's deformation at this load exceeds the pad's depth; use "
              "periodize = \"mirror\"");
  }
  // The leakage: on a slab the Reynolds system is solved over all processes (HYPRE).
  if (r.info.converged && cfg.flow.enabled)
    r.leakage = compute_leakage(grid, r.fields.gap.data(), cfg.flow.angles, cfg.flow.tolerance,
                                cfg.flow.solver, opts.stop_request);
  compare_with_references(cfg, r);
}

// What needs the whole cell at once, in one process (rank 0 of a distributed run): the run's
// analysis (patches, distributions, spectrum).
void after_solve_whole(const Config& cfg, CaseResult& r) {
  if (r.info.converged && cfg.output.analysis) {
    r.analysis = analyse_run(r.topography, r.fields);
    // A padded cell's spectrum is the pad's step, not the surface's: no Hurst fit.
    if (cfg.indenter.type == "file" && cfg.indenter.periodize == "pad") r.analysis->rough = false;
  }
}

}  // namespace gfmd::run_detail
