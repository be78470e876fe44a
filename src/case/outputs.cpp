// The output stage: summary.json, fields.nc and tables of a solved case (the PNG maps are
// drawn from them by the front ends, scripts/plot_maps.py).
// See include/gfmd/case/outputs.hpp.
#include "gfmd/case/outputs.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include "gfmd/case/run_dir.hpp"
#include "gfmd/contact/patches.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
namespace gfmd {

namespace fs = std::filesystem;

void publish_outputs(const CaseResult& r, const std::string& dir, const std::function<void()>& extra) {
  try {
    write_outputs(r, dir);
    if (extra) extra();
    write_status(dir, "converged");
  } catch (const std::exception& e) {
    clear_run_outputs(dir);
    try {
      write_status(dir, "failed", std::string("writing the outputs: ") + e.what());
    } catch (const std::exception&) {
      // The status cannot be written either (disk full): the error itself still goes up.
    }
    throw;
  }
}

namespace {

// What the lengths of the outputs are measured in, for summary.json and fields.nc.
std::string lengths_in(const Config& c) {
  return c.length_unit.empty() ? std::string("lengths in the unit of grid.lx")
                               : "lengths in " + c.length_unit;
}
// profiles.csv: a comment naming the centre, then s and the columns (10 significant digits).
std::string profiles_csv(const LineProfiles& pr) {
  std::ostringstream os;
  os.precision(10);
  os << "# profiles through the pressure maximum at (" << pr.centre_x << ", " << pr.centre_y
     << "); s = distance along the line; longitudinal = along the sliding direction, transverse = across\n";
  os << "s";
  for (const std::string& c : pr.columns) os << "," << c;
  os << "\n";
  for (std::size_t k = 0; k < pr.s.size(); ++k) {
    os << pr.s[k];
    for (const std::vector<double>& v : pr.values) os << "," << v[k];
    os << "\n";
  }
  return os.str();
}
nlohmann::json observables_json(const Observables& o) {
  nlohmann::json j = {{"relative_contact_area", o.relative_contact_area},
                      {"normal_force", o.normal_force},
                      {"mean_pressure", o.mean_pressure},
                      {"max_pressure", o.max_pressure},
                      {"mean_gap", o.mean_gap},
                      {"approach", o.approach}};
  if (o.plastic) {
    j["plastic_area_fraction"] = o.plastic_area_fraction;
    j["max_plastic_displacement"] = o.max_plastic_displacement;
    j["mean_plastic_displacement"] = o.mean_plastic_displacement;
  }
  if (o.adhesive) {
    j["adhesive_force"] = o.adhesive_force;
    j["repulsive_force"] = o.repulsive_force;
    j["attraction_area_fraction"] = o.attraction_area_fraction;
    j["cohesive_zone_fraction"] = o.cohesive_zone_fraction;
    j["min_pressure"] = o.min_pressure;
    j["cohesive_zone_cells"] = o.cohesive_zone_cells;
  }
  if (o.friction) {
    j["friction_force"] = o.friction_force;
    j["friction_force_slip"] = o.friction_force_slip;
    j["friction_force_downhill"] = o.friction_force_downhill;
    j["downhill_force"] = o.downhill_force;
    j["downhill_friction"] = o.downhill_friction;
    j["friction_coefficient"] = o.friction_coefficient;
    j["friction_coefficient_downhill"] = o.friction_coefficient_downhill;
    j["energy_balance_error"] = o.energy_balance_error;
    j["friction_force_drive"] = o.friction_force_drive;
    j["energy_balance_error_exact"] = o.energy_balance_error_exact;
    j["numerical_dissipation"] = o.numerical_dissipation;
    j["numerical_dissipation_fraction"] = o.numerical_dissipation_fraction;
    j["max_slip_velocity"] = o.max_slip_velocity;
    j["min_slip_velocity"] = o.min_slip_velocity;
    j["near_stick_fraction"] = o.near_stick_fraction;
    j["stick_fraction"] = o.stick_fraction;
    j["tangential_force"] = o.tangential_force;
    j["tangential_force_x"] = o.tangential_force_x;
    j["tangential_force_y"] = o.tangential_force_y;
    j["traction_coefficient"] = o.traction_coefficient;
  }
  if (o.viscoelastic) {
    j["hysteresis_force"] = o.hysteresis_force;
    j["hysteresis_friction"] = o.hysteresis_friction;
    j["hysteresis_dissipation"] = o.hysteresis_dissipation;
    j["hysteresis_balance_error"] = o.hysteresis_balance_error;
    if (o.friction) j["total_friction_coefficient"] = o.total_friction_coefficient;
  }
  j["centroid_shift"] = o.centroid_shift;
  j["centroid_shift_transverse"] = o.centroid_shift_transverse;
  j["pressure_max_shift"] = o.pressure_max_shift;
  j["contact_extent_longitudinal"] = o.contact_extent_longitudinal;
  j["contact_extent_transverse"] = o.contact_extent_transverse;
  return j;
}

}  // namespace

nlohmann::json topography_stats_json(const TopographyStats& s) {
  return {{"mean", s.mean},
          {"rms_height", s.rms_height},
          {"rms_gradient", s.rms_gradient},
          {"rms_curvature", s.rms_curvature},
          {"min", s.min},
          {"max", s.max}};
}

nlohmann::json map_report_json(const MapReport& m) {
  nlohmann::json j = {{"path", m.path},
                      {"format", m.format},
                      {"file_points", {m.file_nx, m.file_ny}},
                      {"file_unit", m.file_unit},
                      {"case_unit", m.case_unit},
                      {"unit_factor", m.unit_factor},
                      {"missing", {{"method", m.missing}, {"points", m.missing_points}}},
                      {"detrend", {{"method", m.detrend}}},
                      {"periodize", {{"method", m.periodize}, {"edge_mismatch", m.edge_mismatch}}},
                      {"map_points", {m.map_nx, m.map_ny}},
                      {"map_area_fraction", m.map_area_fraction},
                      {"grid_points", {m.grid_nx, m.grid_ny}},
                      {"resampled", m.map_nx != m.grid_nx || m.map_ny != m.grid_ny},
                      {"lost_gradient_fraction", m.lost_gradient_fraction},
                      {"warnings", m.warnings}};
  if (m.file_lx > 0) j["file_size"] = {m.file_lx, m.file_ly};
  if (m.crop[2] > 0) j["crop"] = m.crop;
  if (m.missing == "interpolate" && m.missing_points > 0) j["missing"]["sweeps"] = m.fill_iterations;
  if (m.detrend == "plane" || m.detrend == "mean") {
    j["detrend"]["removed_mean"] = m.removed_mean;
    j["detrend"]["removed_slope_x"] = m.removed_slope_x;
    j["detrend"]["removed_slope_y"] = m.removed_slope_y;
  }
  return j;
}

nlohmann::json summary_json(const CaseResult& r) {
  nlohmann::json j = observables_json(r.observables);
  j["iterations"] = r.info.iterations;
  j["outer_iterations"] = r.info.outer_iterations;
  if (r.config.interaction.adhesive()) {
    j["adhesion_steps"] = r.info.adhesion_steps;
    j["elastic_energy"] = r.info.elastic_energy;
    j["adhesive_energy"] = r.info.adhesive_energy;
    j["energy"] = r.info.energy;
  }
  if (r.config.visco.enabled()) {
    j["viscoelastic_steps"] = r.info.viscoelastic_steps;
    // The power the body dissipates, F_h v0 (length x force per time unit of the relaxation time).
    j["hysteresis_power"] = r.observables.hysteresis_force * r.config.visco.velocity;
  }
  if (r.config.friction.coefficient > 0) {
    j["tangential_iterations"] = r.info.tangential_iterations;
    const FrictionLawType& law = friction_law_type(r.config.friction.law.kind);
    if (law.kind == FrictionLawKind::Coulomb) {
      const bool reg = r.config.friction.regularized();
      j["friction_law"] = reg ? "regularized" : "coulomb";
      j["friction_law_traction"] = reg ? "mu_c p v/max(|v|, eps)" : law.traction;
    } else {
      j["friction_law"] = law.name;
      j["friction_law_traction"] = law.traction;
    }
    j["slip_derivative"] = slip_derivative_name(r.info.slip_derivative);  // the one the solution used
    // The friction loop's mixing history at its end (solver.anderson, deeper after a stall).
    j["anderson_depth"] = r.info.history_depth;
  }
  j["converged"] = r.info.converged;
  j["status"] = r.info.status;
  j["residual"] = r.info.residual;
  j["residual_bound"] = r.info.residual_bound;
  if (r.resumed.iterations > 0 || r.resumed.wall_time_s > 0) {
    j["resumed"] = {{"iterations_before", r.resumed.iterations},
                    {"wall_time_s_before", r.resumed.wall_time_s}};
    // iterations_before counts every solve of the earlier sessions; the frictionless reference's
    // share is reported apart (it is not in `iterations`, which may be smaller).
    if (r.resumed.reference_iterations > 0)
      j["resumed"]["frictionless_iterations_before"] = r.resumed.reference_iterations;
  }
  j["pressure_change"] = r.info.pk_error;
  if (r.config.friction.coefficient > 0) j["friction_change"] = r.info.friction_error;
  j["wall_time_s"] = r.info.wall_time_s;
  const Grid& g = r.config.grid;
  const auto stress_json = [&g](const StressSummary& s) {
    return nlohmann::json{{"max_tensile_stress", s.max_tensile_stress},
                          {"max_tensile_stress_location", {g.x(s.max_tensile_ix), g.y(s.max_tensile_iy)}},
                          {"max_von_mises", s.max_von_mises},
                          {"max_von_mises_location", {g.x(s.max_von_mises_ix), g.y(s.max_von_mises_iy)}},
                          {"high_tension_area_fraction", s.high_tension_area_fraction},
                          {"high_tension_fraction_of", s.high_tension_fraction_of}};
  };
  if (r.stress_summary) j.update(stress_json(*r.stress_summary));
  if (!r.post_analyses.empty()) {
    // The first kind as "post_analysis" (its keys as before, plus kind, the area above half
    // the maximum and the full/post ratios), every kind as "post_analysis_<kind>".
    const auto pa_json = [&](const CaseResult::PostAnalysis& pa) {
      nlohmann::json e = stress_json(pa.summary);
      e["kind"] = pa.kind;
      e["area_fraction_above_half_max"] = pa.area_above_half_max;
      const auto value = [](const std::optional<double>& v) {
        return v ? nlohmann::json(*v) : nlohmann::json();
      };
      e["ratio_max_tensile_stress"] = value(pa.ratio_max_tensile_stress);
      e["ratio_max_von_mises"] = value(pa.ratio_max_von_mises);
      e["ratio_area_above_half_max"] = value(pa.ratio_area_above_half_max);
      return e;
    };
    j["post_analysis"] = pa_json(r.post_analyses.front());
    for (const auto& pa : r.post_analyses) j["post_analysis_" + pa.kind] = pa_json(pa);
    j["area_fraction_above_half_max"] = r.area_above_half_max;
  }
  if (r.leakage) j["flow"] = r.leakage->json;
  if (!r.post_analyses.empty() && r.post_analyses.front().ratio_max_tensile_stress)
    j["tensile_stress_ratio_to_post_analysis"] = *r.post_analyses.front().ratio_max_tensile_stress;
  const Comparisons& cmp = r.comparisons;
  if (!r.subsurface.empty()) {
    j["subsurface"] = nlohmann::json::array();
    for (const auto& ss : r.subsurface) {
      nlohmann::json e = stress_json(ss.summary);
      e["depth"] = ss.depth;
      j["subsurface"].push_back(e);
    }
  }
  if (r.indenter_stress_summary) {  // an elastic indenter's own stresses
    j["indenter_stress"] = stress_json(*r.indenter_stress_summary);
    j["indenter_stress"]["subsurface"] = nlohmann::json::array();
    for (const auto& ss : r.indenter_subsurface) {
      nlohmann::json e = stress_json(ss.summary);
      e["depth"] = ss.depth;
      j["indenter_stress"]["subsurface"].push_back(e);
    }
  }
  if (cmp.delta_mu_over_mu_c) j["delta_mu_over_mu_c"] = *cmp.delta_mu_over_mu_c;
  if (cmp.delta_mu_over_mu_c_downhill) j["delta_mu_over_mu_c_downhill"] = *cmp.delta_mu_over_mu_c_downhill;
  if (r.reference) {
    j["frictionless"] = observables_json(r.reference->observables);
    j["frictionless"]["iterations"] = r.reference->info.iterations;
  }
  if (cmp.delta_area_over_area) j["delta_area_over_area"] = *cmp.delta_area_over_area;
  j["time_per_iteration_s"] = r.info.iterations > 0 ? r.info.wall_time_s / r.info.iterations : 0.0;
  j["fft_count"] = r.info.transforms;
  j["fft_time_s"] = r.info.fft_seconds;  // time inside the transforms (part of wall_time_s)
  j["interaction_stiffness"] =
      std::isinf(r.info.stiffness) ? nlohmann::json("inf") : nlohmann::json(r.info.stiffness);
  j["threads"] = threads();
  j["omp_wait"] = omp_wait_setting();
  j["backend"] = r.config.backend;
  if (r.info.device_bytes > 0) j["device_memory_bytes"] = r.info.device_bytes;  // the CUDA solve's peak
  if (r.stress_summary) j["stress_time_s"] = r.stress_time_s;
  // Where the stresses were evaluated ("host" if any of them ran there).
  if (r.config.backend == "cuda" && r.stress_summary)
    j["stress_backend"] = r.stress_on_device ? "cuda" : "host";
  j["mpi_ranks"] = r.mpi_ranks;
  if (const auto& u = r.mpi_usage) {
    nlohmann::json per_rank = nlohmann::json::array();
    for (double b : u->solve_peak_bytes) per_rank.push_back(b / 1048576.0);
    j["mpi"] = {
        {"ranks", r.mpi_ranks},
        {"solve_peak_memory_mib", per_rank},
        {"rank0_peak_memory_mib", u->peak_bytes / 1048576.0},
        {"reduction_time_s", u->reduction_seconds},
        {"decomposition",
         "slabs of rows (FFTW-MPI); observables, stresses and flow on the slabs; the analysis on rank 0"}};
  }
  const auto& s = r.topography_stats;
  j["topography"] = topography_stats_json(s);
  j["topography"]["kind"] = r.topography.kind;
  if (r.map_report) j["topography"]["preprocessing"] = map_report_json(*r.map_report);
  // Every warning of the run, as gfmd run prints them: the map's preparation, then plausibility.
  j["warnings"] = nlohmann::json::array();
  if (r.map_report)
    for (const std::string& w : r.map_report->warnings)
      j["warnings"].push_back(r.map_report->path + ": " + w);
  for (const std::string& w :
       plausibility_warnings(r.config, r.topography_stats, r.map_report ? &*r.map_report : nullptr))
    j["warnings"].push_back(w);
  for (const std::string& w : solution_warnings(r.observables)) j["warnings"].push_back(w);
  if (r.analysis) j["analysis"] = analysis_json(*r.analysis);
  j["input"] = r.config.to_json();
  j["units"] = lengths_in(r.config) +
               "; pressures, stresses and E* in the unit of elastic.contact_modulus; "
               "forces = pressure x length^2";
  j["conventions"] = {
      {"topography", "indenter height towards the body (peaks are maxima); initial gap g0 = max(h) - h"},
      {"z", "out of the body towards the indenter; uz < 0 is a depression"},
      {"approach",
       "indenter displacement towards the body from first touch; for h = inf relative to the mean "
       "surface (mean uz pinned to 0)"}};
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  return j;
}

std::vector<std::string> solution_warnings(const Observables& o) {
  std::vector<std::string> w;
  if (o.adhesive && o.cohesive_zone_fraction > 0 && o.cohesive_zone_cells < kMinCohesiveZoneCells) {
    char buf[400];
    std::snprintf(
        buf, sizeof buf,
        "the cohesive zone is %.2g cells wide: below about %.0f cells its edge is trapped by the grid "
        "and the adhesive force and pull-off come out too large (refine the grid: more cells per "
        "contact radius)",
        o.cohesive_zone_cells, kMinCohesiveZoneCells);
    w.emplace_back(buf);
  }
  return w;
}

void write_fields_file(const CaseResult& r, const std::string& path, bool maps_only) {
  const Grid& g = r.config.grid;
  const FieldSet set = result_fields(r, maps_only);
  write_fields_netcdf(
      path, g, set.fields,
      {{"gfmd_version", kVersion},
       {"git_commit", kGitCommit},
       {"input_toml", r.config.to_toml()},
       {"normalisation", lengths_in(r.config) + ", pressures in units of E* (contact_modulus)"}},
      length_units(r.config.length_unit));
}

std::vector<std::string> plot_maps_arguments(const std::vector<std::string>& dirs,
                                             const std::vector<std::string>& options) {
  std::vector<std::string> args = options;
  if (dirs.size() == 1) {
    const fs::path staging = fs::path(dirs.front()) / kMapsStagingFile;
    std::error_code ec;
    if (fs::is_regular_file(staging, ec)) {
      args.emplace_back("--fields");
      args.push_back(staging.string());
    }
  }
  args.emplace_back("--");
  args.insert(args.end(), dirs.begin(), dirs.end());
  return args;
}

namespace {
bool is_file_in(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  return fs::is_regular_file(dir / name, ec);
}
}  // namespace

// The run directories below dir (point_NNN of a sweep, seed_N of an ensemble) whose maps
// are still to be drawn: a staging file of the maps, or output.png on, fields.nc there and
// no pressure.png (points finished earlier whose maps were not drawn are caught up too).
std::vector<std::string> runs_needing_maps(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_directory(ec) || !is_file_in(e.path(), "summary.json")) continue;
    bool need = is_file_in(e.path(), kMapsStagingFile);
    if (!need && is_file_in(e.path(), "fields.nc") && !is_file_in(e.path(), "pressure.png")) {
      try {
        const auto j = nlohmann::json::parse(
            read_regular_file((e.path() / "summary.json").string(), 64u << 20, "summary file"));
        need = j.at("input").at("output").at("png").get<bool>();
      } catch (const std::exception&) {
        need = false;
      }
    }
    if (need) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void write_outputs(const CaseResult& r, const std::string& dir) {
  fs::create_directories(dir);
  const Grid& g = r.config.grid;
  if (r.config.output.fields)
    write_fields_file(r, (fs::path(dir) / "fields.nc").string());
  else if (r.config.output.png)
    write_fields_file(r, (fs::path(dir) / kMapsStagingFile).string(), true);
  if (r.config.stress.profiles && r.profiles)
    write_text_atomic((fs::path(dir) / "profiles.csv").string(), profiles_csv(*r.profiles));
  if (r.leakage)
    write_leakage(g, *r.leakage, dir, {{"relative_contact_area", r.observables.relative_contact_area}},
                  r.config.length_unit);
  if (r.analysis) {
    write_text_atomic((fs::path(dir) / "patches.csv").string(), patches_csv(*r.analysis));
    write_text_atomic((fs::path(dir) / "distributions.csv").string(), distributions_csv(*r.analysis));
    write_text_atomic((fs::path(dir) / "spectrum.csv").string(), spectrum_csv(*r.analysis));
    write_text_atomic((fs::path(dir) / "bands.csv").string(), bands_csv(*r.analysis));
  }
  // summary.json last: its presence marks a complete run directory.
  write_text_atomic((fs::path(dir) / "summary.json").string(), summary_json(r).dump(2) + "\n");
}

std::vector<std::pair<std::string, nlohmann::json>> summary_row(const nlohmann::json& summary) {
  std::vector<std::pair<std::string, nlohmann::json>> row;
  for (const auto& [k, v] : summary.items()) {
    if (k == "input" || k == "units" || k == "conventions") continue;
    if (v.is_object()) {
      for (const auto& [k2, v2] : v.items())
        if (v2.is_primitive()) row.emplace_back(k + "." + k2, v2);
    } else if (v.is_primitive()) {
      row.emplace_back(k, v);
    }
  }
  return row;
}

}  // namespace gfmd
