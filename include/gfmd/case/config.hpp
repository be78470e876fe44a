// Case files (TOML): one file per case, every key checked, defaults filled in.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/surface/measured.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd {

// Limits checked while reading a case, before anything is allocated (docs in README).
inline constexpr long long kMaxThreads = 1024;                  // solver.threads
inline constexpr long long kMaxSweepPoints = 10000;             // [sweep] points or values; any TOML array
inline constexpr std::size_t kMaxStressDepths = 64;             // stress.depths
inline constexpr std::size_t kMaxLayers = 64;                   // elastic.layers
inline constexpr int kMaxTomlNesting = 64;                      // arrays, inline tables and dotted keys
inline constexpr std::size_t kMaxCaseFileBytes = 1u << 20;      // and arrays of <= kMaxSweepPoints
inline constexpr double kMinLength = 1e-30, kMaxLength = 1e30;  // grid.lx, grid.ly
// The thinnest layer, relative to the larger cell side (elastic.thickness).
inline constexpr double kMinThicknessRatio = 1e-12;
// The largest mean pressure / E* a load may ask for (force / (E* lx ly) likewise).
inline constexpr double kMaxPressureOverModulus = 1e3;

struct IndenterConfig {
  // One of the registered types (src/case/indenter_types.cpp; indenter_types() below):
  // hertz | flatpunch | powerlaw | sphere | cylinder | step | eggcrate | selfaffine | file, and
  // array for a program's heights.
  std::string type = "hertz";
  double radius = 0.0, radius_x = 0.0, radius_y = 0.0;  // hertz; flatpunch: radius
  double depth = 0.0;                                   // flatpunch, step: the drop of its side
  double width = 0.0;                                   // step: the raised strip's width
  double exponent = 2.0;                                // powerlaw: n
  char axis = 'y';                                      // cylinder, step: the direction it lies along
  // Any type: a single-wavelength roughness a cos(2 pi x/lambda) (along x or y) added to the
  // heights (amplitude 0: none).
  double waviness_amplitude = 0.0, waviness_wavelength = 0.0;
  char waviness_axis = 'x';
  double wavelength = 0.0, amplitude = 0.0;
  SelfAffineParams selfaffine;
  std::string path;  // file: resolved against the case file's folder
  // file: preparation of a measured map (surface/measured.hpp, MapOptions)
  std::string unit;                           // the file's length unit when it states none
  std::string missing = "error";              // error | mean | interpolate
  std::string detrend = "none";               // none | mean | plane
  std::string periodize = "none";             // none | mirror | pad
  std::array<long long, 4> crop{0, 0, 0, 0};  // ix0, iy0, nx, ny (nx = 0: no crop)
  // An elastic indenter (indenter.contact_modulus, poisson, thickness; two deformable bodies,
  // ElasticBody's `indenter`): its body. Rigid when absent (contact_modulus not given or "inf").
  std::optional<ElasticParams> body;
};

struct OutputConfig {
  bool fields = true;    // fields.nc
  bool png = true;       // PNG maps
  bool analysis = true;  // patches, distributions, spectrum (analysis.hpp): summary + CSV (+ analysis.png)
};

struct SweepConfig {
  std::string parameter;                      // "section.key", e.g. "load.force"
  std::vector<double> values;                 // the values, in order
  std::string plot = "friction_coefficient";  // summary key drawn against the parameter
  [[nodiscard]] bool active() const { return !parameter.empty(); }
};

struct StressConfig {
  // Post-analysis references of the frictional stress (paper Fig. 3a,c), in order:
  // "paper" (the frictionless solution as it is plus sigma_az = mu p e_s, no strain from the
  // friction: what the paper computed) and/or "consistent" (the strain of mu p e_s included).
  std::vector<std::string> post_analysis;
  double high_tension_fraction = 0.9;  // "zone of high tension": s1 >= fraction * max s1
  std::vector<double> depths;          // planes below the surface for subsurface stresses
  bool profiles = true;                // profiles.csv (+ png) through the pressure maximum
};

struct FlowConfig {
  bool enabled = false;                   // [flow] present: flow right after the contact solve
  std::vector<double> angles{0.0, 90.0};  // directions of the mean pressure gradient (deg from +x)
  double tolerance = 1e-10;               // relative residual of the linear solve
  FlowSolver solver = FlowSolver::Auto;   // key flow.solver: "auto", "amg" or "boomeramg"
};

// Flow directions from "x", "y", "both" or an angle in degrees; empty if the text is none
// of these.
std::vector<double> parse_flow_directions(const std::string& text);

struct Config {
  Grid grid;
  std::string length_unit;  // grid.unit: the unit of every length of the case ("" = none named)
  ElasticParams elastic;
  // elastic.viscoelastic and its keys, friction.velocity (and direction): a viscoelastic body
  // in steady sliding; disabled: elastic.
  ViscoelasticParams visco;
  IndenterConfig indenter;
  LoadParams load;
  FrictionParams friction;
  InteractionParams interaction;
  SolverParams solver;
  int threads = 0;
  std::string backend = "threads";  // solver.backend: where passes and FFTs run (core/backend.hpp)
  OutputConfig output;
  bool friction_reference = true;  // with friction: also solve frictionless at the same load
  bool velocity_given = false;     // friction.velocity was given (a viscoelastic body without it warns)
  StressConfig stress;
  FlowConfig flow;
  SweepConfig sweep;
  std::string source;  // the case file's path ("" for a string)
  // The text it was read from and the folder its relative paths are taken from (not recorded in
  // summary.json): a study's points are made from this text (reparse_config), not from the file
  // as it is when each point starts.
  std::string source_text, source_dir;

  // The full input with defaults filled in (recorded in summary.json).
  [[nodiscard]] nlohmann::json to_json() const;
  // TOML text that reproduces this configuration. Heights given by the calling program
  // (indenter.type = "array") are read from the file `heights` (.npy, beside the case file),
  // which the caller writes (Python's Result.save_case): a comment says so.
  [[nodiscard]] std::string to_toml(const std::string& heights = "heights.npy") const;
};

// Parses a case file and applies "section.key=value" overrides (values in TOML syntax;
// a bare word is taken as a string). Throws InputError listing every problem found,
// each with the key and, where known, file:line.
Config load_config(const std::string& path, const std::vector<std::string>& overrides = {});
Config parse_config(const std::string& toml_text, const std::string& name,
                    const std::vector<std::string>& overrides = {}, const std::string& base_dir = ".");
// The configuration `base` was read from (its source_text, parse_config's), with other
// overrides: a sweep's, a curve's or an ensemble's points. A case file edited while a study runs
// changes none of its points. Throws InputError if `base` was not read from text.
Config reparse_config(const Config& base, const std::vector<std::string>& overrides);
// The same for a case held as tables instead of text (a JSON object of sections, each an object
// of keys, as summary.json's "input" holds them): read by the same rules, each problem naming
// its key (no file or line). Integers stay integers; NaN is refused naming its key. The Python
// library passes its cases this way (python/_core.cpp, CaseSolver).
Config config_from_tables(const nlohmann::json& tables, const std::string& name,
                          const std::vector<std::string>& overrides = {}, const std::string& base_dir = ".");

// The case's load (c.load) against the limits a case file's [load] is held to: the key
// ("force", "pressure", "approach") and why, or two empty strings; check_load throws it as
// InputError("load.<key>", why). For programs that set a parsed case's load themselves.
std::pair<std::string, std::string> load_problem(const Config& c);
void check_load(const Config& c);

// Builds the indenter's topography of a configuration (through its type's part).
Topography make_topography(const Config& cfg, MapReport* report = nullptr);

// The indenter types a case file may give (indenter.type), each with its one-line purpose
// and keys, in the order the docs list them.
struct IndenterTypeInfo {
  std::string name, purpose;
  std::vector<std::string> keys;
};
std::vector<IndenterTypeInfo> indenter_types();
// The topography of an indenter type on `grid` from its keys (a JSON object of numbers,
// strings, booleans and lists, as in summary.json's "input"), read and checked as the case
// file's [indenter] would be; a relative path is taken from base_dir. Throws InputError
// naming "indenter.<key>".
Topography make_indenter(const std::string& type, const Grid& grid, const nlohmann::json& keys,
                         const std::string& base_dir = ".");
// Whether a distributed run makes each process's rows of the surface alone: analytic and
// self-affine surfaces (on any grid: the slabs' transforms have one process's bits, core/fft.hpp).
// A height map is read and prepared whole on rank 0, which hands out the rows (docs/mpi.md).
bool surface_made_on_slabs(const Config& cfg);
// The options of a file indenter's map for the case's grid.
MapOptions map_options(const Config& cfg);

// Runs f; a ParameterError from the library becomes InputError("<section>.<parameter>"):
// how physics errors come to name config keys, here in the case layer only.
template <class F>
decltype(auto) in_section(const std::string& section, F&& f) {
  try {
    return f();
  } catch (const ParameterError& e) {
    throw InputError(section + "." + e.where(), e.why());
  }
}

// Estimated peak memory of a solve in bytes.
// Per process when the run is split over `processes` (mpirun); whole_surface: the whole map is
// made here (a height map on rank 0; docs/mpi.md).
// active_set: a sliding viscoelastic body's active set may run (its Krylov basis).
double estimated_memory_bytes(const Grid& grid, int processes = 1, bool whole_surface = true,
                              bool active_set = false);

// The memory a solve may use here: the smallest of 80% of the physical memory, MemAvailable,
// 80% of a cgroup limit and 80% of RLIMIT_AS / RLIMIT_DATA (bytes 0: none known), and which.
struct MemoryLimit {
  double bytes = 0.0;
  std::string source;
};
MemoryLimit memory_limit();
// Why `bytes` do not fit memory_limit(): "<what> needs about X GB, more than the Y GB allowed
// here (<its source>)"; "" when they fit or no limit is known.
std::string memory_shortfall(double bytes, const std::string& what);

// An rms gradient above this is legal but most likely heights and lateral lengths in different
// units (issue 41): the run warns.
inline constexpr double kMaxPlausibleRmsGradient = 5.0;
// Warnings on a case, each naming the keys to check (empty: none): a surface's rms gradient
// above kMaxPlausibleRmsGradient (map: how a file indenter's map was prepared, its units); a
// viscoelastic body without friction.velocity (at rest).
std::vector<std::string> plausibility_warnings(const Config& cfg, const TopographyStats& stats,
                                               const MapReport* map = nullptr);

}  // namespace gfmd
