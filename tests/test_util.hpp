// Helpers shared by the test suites.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd::testing {

// Solves a case given as TOML text with overrides, expecting convergence.
inline CaseResult solve(const std::string& toml, const std::vector<std::string>& sets = {}) {
  const Config c = parse_config(toml, "test.toml", sets);
  CaseResult r = run_case(c);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return r;
}

// What is wrong with a case given as TOML text with overrides: InputError's message, or "".
inline std::string config_problem(const std::string& toml, const std::vector<std::string>& sets = {},
                                  const std::string& base_dir = ".") {
  try {
    (void)parse_config(toml, "t.toml", sets, base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A fresh, empty scratch directory <tmp>/gfmd_<suite>_<pid>/<name>.
inline std::filesystem::path scratch_dir(const std::string& suite, const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("gfmd_" + suite + "_" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) { std::ofstream(p) << text; }

// The gfmd program (GFMD_EXE) run with args (run_gfmd_env: after environment assignments
// "NAME=value "); its exit code and its stdout + stderr.
struct Outcome {
  int code;
  std::string output;
};
inline Outcome run_gfmd_env(const std::string& env, const std::string& args) {
  const std::string cmd = std::string("OMP_WAIT_POLICY=PASSIVE ") + env + GFMD_EXE + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (pipe && fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pipe ? pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
inline Outcome run_gfmd(const std::string& args) { return run_gfmd_env("", args); }

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A small frictionless Hertz case (R = 1, F = 0.01 E*R^2, 64^2 cells on L = 4R) that the
// command-line tests run and edit.
inline const std::string kSmallHertz = R"([grid]
nx = 64
lx = 4.0
[elastic]
poisson = 0.25
[indenter]
type = "hertz"
radius = 1.0
[load]
force = 0.01
)";

// ---------------------------------------------------------------------------------------
// Stress fixtures (test_stress.cpp, test_subsurface.cpp). Hertz states: R = 1, E* = 1,
// F = 4 a^3 / 3 with a = 0.2 exactly, cell L = 3.2 = 16 a, hard-wall contact; L = 16 a keeps
// the stress the periodic images add at the contact edge below about 2 % of (1-2nu)p0/3.
// The frictionless pressure on a half-space does not depend on nu: one solve serves every nu.

constexpr double kPi = std::numbers::pi;
constexpr double kA = 0.2;                       // Hertz contact radius
constexpr double kF = 4.0 * kA * kA * kA / 3.0;  // load giving a = 0.2 for R = E* = 1
inline const double kP0 = 3.0 * kF / (2.0 * kPi * kA * kA);

// Runs the heavy tests on one thread (robust timing on a busy machine) and restores the
// library's thread count afterwards.
struct OneThread {
  int saved = threads();
  OneThread() { set_threads(1); }
  ~OneThread() { set_threads(saved); }
  OneThread(const OneThread&) = delete;
  OneThread& operator=(const OneThread&) = delete;
};

inline const CaseResult& hertz(int nx) {
  static std::map<int, CaseResult> cache;
  auto it = cache.find(nx);
  if (it != cache.end()) return it->second;
  char force[64];
  std::snprintf(force, sizeof force, "%.17g", kF);
  const std::string toml =
      "[grid]\nnx = " + std::to_string(nx) +
      "\nlx = 3.2\n[elastic]\npoisson = 0.3\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n"
      "[load]\nforce = " +
      force + "\n[interaction]\nmodel = \"hardwall\"\n[solver]\ntolerance = 1e-10\nthreads = 1\n";
  CaseResult r = run_case(parse_config(toml, "hertz.toml"));
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return cache.emplace(nx, std::move(r)).first->second;
}

// Hamilton (1983): max tension at the trailing edge of a sliding Hertz contact.
inline double hamilton(double nu, double mu) { return kP0 * ((1 - 2 * nu) / 3 + (4 + nu) * kPi * mu / 8); }

// Hertz on the axis at depth z (Johnson eqs. 3.46-3.47): sigma_r = sigma_theta, sigma_z.
inline double hertz_axis_von_mises(double z, double nu) {
  const double t = z / kA;
  const double sz = -1.0 / (1.0 + t * t);
  const double sr = -(1.0 + nu) * (1.0 - t * std::atan(1.0 / t)) + 0.5 / (1.0 + t * t);
  return kP0 * std::abs(sr - sz);
}

// Small deterministic generator (portable): uniform in [-1, 1).
struct Lcg {
  std::uint64_t s;
  double next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
  }
};

// The largest entry of one mode's response at depth (stresses and displacements per traction),
// and the largest difference of two.
inline double largest(const ModeResponse& r) {
  double m = 0.0;
  for (const auto& row : r.stress)
    for (cplx v : row) m = std::max(m, std::abs(v));
  for (const auto& row : r.disp)
    for (cplx v : row) m = std::max(m, std::abs(v));
  return m;
}
inline double difference(const ModeResponse& a, const ModeResponse& b) {
  double m = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) m = std::max(m, std::abs(a.stress[i][k] - b.stress[i][k]));
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m = std::max(m, std::abs(a.disp[i][k] - b.disp[i][k]));
  return m;
}

inline double max_abs(const RealField& f) {
  double m = 0;
  for (double v : f) m = std::max(m, std::abs(v));
  return m;
}

inline double max_abs_diff(const RealField& a, const RealField& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// Two stress planes: the largest difference of their xx, yy, zz and xz components over the
// largest of the second's.
inline double stress_difference(const StressField& a, const StressField& b) {
  double top = 0.0, d = 0.0;
  for (const auto& [x, y] :
       {std::pair{&a.xx, &b.xx}, std::pair{&a.yy, &b.yy}, std::pair{&a.zz, &b.zz}, std::pair{&a.xz, &b.xz}}) {
    top = std::max(top, max_abs(*y));
    d = std::max(d, max_abs_diff(*x, *y));
  }
  return d / top;
}

// TOML text with the lines that set `keys` ("key = ..." at a line's start) taken out.
inline std::string without_keys(const std::string& toml, const std::vector<std::string>& keys) {
  std::string out;
  for (std::size_t at = 0; at < toml.size();) {
    const std::size_t end = std::min(toml.find('\n', at), toml.size());
    const std::string line = toml.substr(at, end - at);
    at = end + 1;
    bool drop = false;
    for (const std::string& k : keys) drop = drop || line.rfind(k + " =", 0) == 0;
    if (!drop) out += line + "\n";
  }
  return out;
}

// An egg-crate (h0 = 0.005 L on a cell of side L = 1, 64^2) pressed into full contact at 0.2 E*,
// the hard wall, Coulomb's set-valued law with mu_c = 0.3, tolerance 1e-10: a periodic surface in
// full contact, whose slopes are exact, so a work balance closes to the solver's tolerance.
// `elastic`, `indenter` and `friction` are further lines of those sections.
inline std::string eggcrate_in_full_contact(const std::string& elastic, const std::string& indenter = "",
                                            const std::string& friction = "") {
  return "[grid]\nnx = 64\nlx = 1.0\n[elastic]\n" + elastic +
         "[indenter]\ntype = \"eggcrate\"\namplitude = 0.005\n" + indenter +
         "[load]\npressure = 0.2\n[interaction]\nmodel = \"hardwall\"\n[friction]\ncoefficient = 0.3\n" +
         "reference = false\n" + friction + "[solver]\ntolerance = 1e-10\n[output]\nanalysis = false\n";
}

// Solves `toml` sliding (friction.creepage = 1) and rolling (0.002: part of the contact sticks),
// with `sets`: in full contact the driving work balances the dissipation to 1e-6 and a
// viscoelastic body's hysteresis from the fields and from the spectrum agree to 1e-9 (and is not
// zero). Returns the two results.
inline std::array<CaseResult, 2> expect_work_balances(const std::string& toml,
                                                      std::vector<std::string> sets = {}) {
  std::array<CaseResult, 2> out;
  int i = 0;
  for (const char* creepage : {"friction.creepage=1", "friction.creepage=0.002"}) {
    std::vector<std::string> s = sets;
    s.push_back(creepage);
    CaseResult& r = out[static_cast<std::size_t>(i++)];
    r = solve(toml, s);
    const Observables& o = r.observables;
    std::printf("%s: mu_total %.6g, mu_h %.6g, stick %.3f, balance %.1e (exact), %.1e (hysteresis)\n",
                creepage, o.total_friction_coefficient, o.hysteresis_friction, o.stick_fraction,
                o.energy_balance_error_exact, o.hysteresis_balance_error);
    EXPECT_EQ(o.relative_contact_area, 1.0) << creepage;
    EXPECT_LT(o.energy_balance_error_exact, 1e-6) << creepage;
    if (o.viscoelastic) {
      EXPECT_GT(o.hysteresis_friction, 1e-5) << creepage;
      EXPECT_LT(o.hysteresis_balance_error, 1e-9) << creepage;
    }
  }
  EXPECT_LT(out[0].observables.stick_fraction, 0.05) << "sliding";
  EXPECT_GT(out[1].observables.stick_fraction, 0.05) << "rolling";
  EXPECT_LT(out[1].observables.stick_fraction, 0.95) << "rolling";
  return out;
}

// A solved case's surface sigma_xx (r.stress) against the plane at depth 0 computed from its
// tractions (subsurface_stress, another code path), and Hooke's law on its solved displacement
// (surface_stress of r.fields) against that plane: both as the largest difference over the
// plane's largest |sigma_xx|. At depth 0 the two paths differ on the Nyquist lines only.
struct AgainstPlane {
  double output, hooke_on_solved;
};
inline AgainstPlane surface_stress_against_plane(const CaseResult& r) {
  const FFT fft(r.config.grid);
  const StressField below = subsurface_stress(fft, r.config.elastic, r.fields, 0.0, r.config.visco);
  const StressField hooke = surface_stress(fft, r.config.elastic, r.fields);
  const double top = max_abs(below.xx);
  const AgainstPlane a{max_abs_diff(below.xx, r.stress.xx) / top, max_abs_diff(below.xx, hooke.xx) / top};
  std::printf(
      "surface sigma_xx against the tractions' plane at depth 0: %.2e (Hooke's law on the solved "
      "displacement: %.2e)\n",
      a.output, a.hooke_on_solved);
  return a;
}

// Smooth band-limited random field: sum of a few Fourier modes with |k| <= kmax.
inline RealField smooth_field(const Grid& g, Lcg& rng, int kmax, double offset) {
  RealField f(g.size(), offset);
  for (int mx = -kmax; mx <= kmax; ++mx)
    for (int my = -kmax; my <= kmax; ++my) {
      const double a = rng.next(), b = rng.next();
      for (int iy = 0; iy < g.ny; ++iy)
        for (int ix = 0; ix < g.nx; ++ix) {
          const double ph = 2 * kPi * (double(mx) * ix / g.nx + double(my) * iy / g.ny);
          f[static_cast<std::size_t>(iy) * g.nx + ix] += 0.1 * (a * std::cos(ph) + b * std::sin(ph));
        }
    }
  return f;
}

// Spectral x / y derivative of a real field (Nyquist dropped).
inline RealField deriv(const FFT& fft, const RealField& f, bool along_x) {
  const Grid& g = fft.grid();
  SpecField s = fft.spec_field();
  fft.forward(f.data(), s.data());
  for (int iky = 0; iky < g.ny; ++iky)
    for (int ikx = 0; ikx < g.nxh(); ++ikx)
      s[static_cast<std::size_t>(iky) * g.nxh() + ikx] *=
          cplx(0.0, along_x ? g.qx_deriv(ikx) : g.qy_deriv(iky));
  RealField out = fft.real_field();
  fft.backward(s.data(), out.data());
  return out;
}

}  // namespace gfmd::testing
