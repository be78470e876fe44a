// The result of one case: plain typed values (fields, solve info, observables, stresses,
// leakage), filled by run_case and serialised by the output stage (case/outputs.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gfmd/case/analysis.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/contact/observables.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd {

// Where a run's solves stood at a checkpoint, besides the pressure and traction (a warm start
// alone): the converged frictionless reference (friction.reference), so that a resumed run
// need not solve it again, and the friction solve's restart point (ContactSolver::
// restart_point; the host solve only), so that it goes on where it stopped. Fields on the
// whole grid as read from a checkpoint (run_case hands every process its rows).
struct SolveResume {
  struct Reference {
    RealField pressure;  // tx = ty = 0
    SolveInfo info;      // its counts, approach and times (the residual is checked again)
    RealField adhesion;  // with adhesion: its adhesive traction
  };
  std::optional<Reference> reference;
  std::optional<FrictionRestart> friction;
  // Adhesion (interaction.model = "adhesive"): the adhesive traction that goes with the fields'
  // net pressure (the warm start of the adhesive steps), and the reference's.
  bool adhesive = false;
  RealField adhesion;
  // A frictionless adhesive solve stopped inside its adhesive steps: where they stood.
  std::optional<AdhesiveRestart> adhesive_restart;
};

// Work done before a checkpoint: a resumed run reports cumulative counts.
struct CheckpointProgress {
  std::int64_t iterations = 0;
  // Of those, the finished frictionless reference's (set on the result, summary.json's
  // resumed.frictionless_iterations_before; the sliding solve's own are the rest).
  std::int64_t reference_iterations = 0;
  double wall_time_s = 0.0;
  // Where the solves stood (null: nothing beyond the fields, e.g. an interruption on the
  // device); shared, so that copies of the progress stay cheap.
  std::shared_ptr<const SolveResume> state;
};

// Line profiles through the pressure maximum along and across the sliding direction
// (profiles.csv): values[c][k] is column c at distance s[k] from the maximum.
struct LineProfiles {
  double centre_x = 0, centre_y = 0;  // the pressure maximum
  std::vector<double> s;
  std::vector<std::string> columns;  // e.g. "pressure_longitudinal", "sigma_1_transverse"
  std::vector<std::vector<double>> values;
};

// The solution's figures against its references (summary.json): set where the reference
// exists and the ratio is defined. The stress ratios are PostAnalysis::ratio_*.
struct Comparisons {
  std::optional<double> delta_mu_over_mu_c;           // (mu - mu_c) / mu_c, with friction
  std::optional<double> delta_mu_over_mu_c_downhill;  // the same for the downhill estimate
  std::optional<double> delta_area_over_area;         // A / A_frictionless - 1
};

struct CaseResult {
  Config config;
  Topography topography;
  TopographyStats topography_stats;
  std::optional<MapReport> map_report;  // a file indenter: how its map was prepared
  ContactFields fields;
  SolveInfo info;
  Observables observables;
  DerivedFields derived;  // slip and dissipation fields (with friction; empty otherwise)
  // The converged frictionless solve at the same load (with friction and friction_reference).
  struct Reference {
    Observables observables;
    SolveInfo info;
    // Its pressure and in-plane displacements, kept for the stress post-analysis only
    // (empty otherwise; moved out by it).
    RealField pressure, ux, uy;
  };
  std::optional<Reference> reference;
  // Stresses (SPEC §5): the summary after a converged solve; the fields only if
  // RunOptions::keep_stress_fields.
  std::optional<StressSummary> stress_summary;
  std::optional<LineProfiles> profiles;  // profiles.csv (stress.profiles)
  StressField stress;
  PrincipalField principal;
  bool stress_on_device = false;  // every stress evaluated on the CUDA device
  double stress_time_s = 0.0;     // wall time of the stresses (surface, post-analyses, subsurface)
  // Post-analysis references, one per kind of [stress] post_analysis, in its order (empty:
  // none asked for); the outputs show the first also under the names of earlier versions.
  struct PostAnalysis {
    std::string kind;  // "paper" or "consistent"
    StressSummary summary;
    double area_above_half_max = 0;  // fraction of cells with s1 >= 0.5 max s1 of this field
    RealField s1;                    // sigma_I
    // The full solution's figure over this reference's (unset where the reference's is 0).
    std::optional<double> ratio_max_tensile_stress, ratio_max_von_mises, ratio_area_above_half_max;
  };
  std::vector<PostAnalysis> post_analyses;
  double area_above_half_max = 0;  // the full solution's, as PostAnalysis::area_above_half_max
  struct Subsurface {
    double depth;
    StressSummary summary;
    RealField von_mises, s1;
  };
  std::vector<Subsurface> subsurface;
  // An elastic indenter's stresses (indenter.contact_modulus): its surface's summary and the
  // planes of stress.depths inside it (summaries only).
  std::optional<StressSummary> indenter_stress_summary;
  std::vector<Subsurface> indenter_subsurface;
  std::optional<LeakageResult> leakage;  // [flow], after a converged solve
  // Processes the solve ran on (mpirun; core/mpi.hpp). In a distributed run only rank 0 holds
  // whole fields (run_case says which); every rank holds `info`, the observables, the stress
  // summaries and the leakage's figures.
  int mpi_ranks = 1;
  // Under mpirun (any number of processes; summary.json "mpi"): per rank, the peak resident
  // memory at the end of the solves (bytes) and the time in the reductions' collectives; rank
  // 0's peak at the end of the run.
  struct MpiUsage {
    std::vector<double> solve_peak_bytes, reduction_seconds;
    double peak_bytes = 0.0;
  };
  std::optional<MpiUsage> mpi_usage;
  Comparisons comparisons;
  std::optional<RunAnalysis> analysis;  // output.analysis, after a converged solve
  CheckpointProgress resumed;           // earlier sessions' work, included in info (RunOptions::resumed)
};

}  // namespace gfmd
