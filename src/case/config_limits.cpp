// Limits of the machine and of case text: memory available to a run, its estimate, and
// the checks of case text run before parsing (UTF-8, nesting depth).
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <toml.hpp>

#include "config_detail.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/flow/flow.hpp"
#include "indenter_types.hpp"

namespace gfmd {

namespace {
// A number from a one-line file such as cgroup's memory.max ("max": no limit, 0).
double read_limit_file(const char* path) {
  std::ifstream f(path);
  std::string w;
  if (!(f >> w) || w == "max") return 0;
  char* end = nullptr;
  const double v = std::strtod(w.c_str(), &end);
  return (end != w.c_str() && v > 0 && v < 1e18) ? v : 0;
}
}  // namespace

MemoryLimit memory_limit() {
  MemoryLimit best;
  const auto consider = [&best](double bytes, const std::string& what) {
    if (bytes > 0 && (best.bytes <= 0 || bytes < best.bytes)) best = {bytes, what};
  };
  const double phys =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  consider(0.8 * phys, "80% of the physical memory");
  {
    std::ifstream mi("/proc/meminfo");
    std::string key, unit;
    double kb = 0;
    while (mi >> key >> kb) {
      std::getline(mi, unit);
      if (key == "MemAvailable:") consider(kb * 1024.0, "the memory available now (MemAvailable)");
    }
  }
  consider(0.8 * read_limit_file("/sys/fs/cgroup/memory.max"), "80% of the cgroup limit memory.max");
  consider(0.8 * read_limit_file("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
           "80% of the cgroup limit memory.limit_in_bytes");
  for (const auto& [res, name] :
       {std::pair{RLIMIT_AS, "RLIMIT_AS (ulimit -v)"}, std::pair{RLIMIT_DATA, "RLIMIT_DATA (ulimit -d)"}}) {
    rlimit rl{};
    if (getrlimit(res, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
      consider(0.8 * static_cast<double>(rl.rlim_cur), std::string("80% of ") + name);
  }
  return best;
}

std::string memory_shortfall(double bytes, const std::string& what) {
  const MemoryLimit lim = memory_limit();
  if (!(lim.bytes > 0) || !(bytes > lim.bytes)) return "";
  std::ostringstream os;
  os.precision(3);
  os << what << " needs about " << bytes / 1e9 << " GB, more than the " << lim.bytes / 1e9
     << " GB allowed here (" << lim.source << ")";
  return os.str();
}

std::vector<std::string> plausibility_warnings(const Config& cfg, const TopographyStats& s,
                                               const MapReport* map) {
  std::vector<std::string> warnings;
  using config_detail::g3;
  if (const double slope = config_detail::plausibility_gradient(cfg, s.rms_gradient);
      slope > kMaxPlausibleRmsGradient) {
    const auto [what, check] = config_detail::implausible_surface_text(cfg, map);
    warnings.push_back(
        what + " rms gradient is " + g3(slope) + ", above " + g3(kMaxPlausibleRmsGradient) +
        " (slopes steeper than 79 degrees): heights and lateral lengths are likely in different "
        "units; check " +
        check);
  }
  // A friction law of its own chosen without a coefficient, whose traction then vanishes
  // (tresca's min(mu_c p, tau_0); a law that does not vanish is refused by the config).
  if (cfg.friction.law.kind != FrictionLawKind::Coulomb && !(cfg.friction.coefficient > 0)) {
    const FrictionLawType& law = friction_law_type(cfg.friction.law.kind);
    warnings.push_back("friction.law = \"" + law.name +
                       "\" with friction.coefficient = 0 is frictionless: its traction, " + law.traction +
                       ", vanishes with mu_c = 0; give friction.coefficient" +
                       (cfg.friction.law.kind == FrictionLawKind::Tresca ? " (e.g. 3 with tresca)" : ""));
  }
  // The planes of stress.depths below an elastic indenter's base are left out of its stresses
  // (the body's own are checked against its thickness).
  if (cfg.indenter.body) {
    std::vector<std::string> deep;
    for (const double d : cfg.stress.depths)
      if (d > cfg.indenter.body->depth_of_base()) deep.push_back(g3(d));
    if (!deep.empty()) {
      warnings.push_back("stress.depths " + config_detail::comma_list(deep) +
                         " lie below the elastic indenter's base (indenter.thickness " +
                         g3(cfg.indenter.body->depth_of_base()) +
                         "): indenter_stress.subsurface leaves them out; the body's planes are all there");
    }
  }
  // A viscoelastic body without a speed is at rest: every mode relaxed (E0), no hysteresis.
  // Valid (the slow limit; friction.velocity = 0 says so), but more often a forgotten key.
  if (cfg.visco.enabled() && !cfg.velocity_given)
    warnings.push_back(
        "elastic.viscoelastic is set but friction.velocity is not: the body is at rest and responds "
        "with its relaxed modulus alone, without hysteresis; give friction.velocity (length per time unit "
        "of the body's relaxation times) for steady sliding");
  return warnings;
}

double estimated_memory_bytes(const Grid& grid, int processes, bool whole_surface, bool active_set) {
  // Peak of a sliding solve (BENCHMARKS.md, memory budget): topography, pressure and two
  // tractions, g0, w, the traction image, three CG fields (11 real fields), three complex
  // half-spectra, the compliance tables (56 B/mode) and the Anderson history on the
  // traction's support (196 B per support point; allowance: half the grid in contact).
  const double n = static_cast<double>(grid.size());
  const double ns = static_cast<double>(grid.spectral_size());
  // A sliding viscoelastic body's active set adds its Krylov basis (solver.hpp).
  const double solve = n * (8.0 * 11.0 + 0.5 * 196.0 + (active_set ? kActiveSetBytesPerPoint : 0.0)) +
                       ns * (3.0 * 16.0 + 56.0);
  if (processes <= 1) return solve;
  // Distributed: each process holds its share of the solve and one gathered field (rank 0's
  // checkpoints and outputs, 8 B per point of the cell) or, while a whole topography is made,
  // the whole map with its spectrum and phases (32 B per point; docs/mpi.md).
  return solve / processes + (whole_surface ? 32.0 : 8.0) * n;
}

// TOML is UTF-8 text. Checking it first also keeps malformed bytes away from toml11
// (3.7 reads past the end of some invalid sequences; found by fuzz/fuzz_config).
void config_detail::require_utf8(const std::string& s, const std::string& name) {
  std::size_t i = 0, line = 1;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = 0;
    if (c == '\n') ++line;
    if (c < 0x80) {
      len = 1;
      if (c == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c == 0x7f)
        throw InputError(name + ":" + std::to_string(line), "control character in the case file");
    } else if ((c & 0xe0) == 0xc0 && c >= 0xc2) {
      len = 2;
    } else if ((c & 0xf0) == 0xe0) {
      len = 3;
    } else if ((c & 0xf8) == 0xf0 && c <= 0xf4) {
      len = 4;
    } else {
      throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    }
    if (i + len > s.size()) throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    // The second byte's range (RFC 3629): no overlong forms, no surrogates, nothing above
    // U+10FFFF. toml11 checks strings the same way, and its report of a bad one in a
    // multi-line string reads past its buffer (toml11 3.7.1), so none may reach it.
    if (len > 1) {
      const auto c1 = static_cast<unsigned char>(s[i + 1]);
      const unsigned char lo = c == 0xe0 ? 0xa0 : c == 0xf0 ? 0x90 : 0x80;
      const unsigned char hi = c == 0xed ? 0x9f : c == 0xf4 ? 0x8f : 0xbf;
      if (c1 < lo || c1 > hi) throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    }
    for (std::size_t k = 1; k < len; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80)
        throw InputError(name + ":" + std::to_string(line), "not valid UTF-8 text");
    i += len;
  }
}

// toml11 parses arrays, inline tables and dotted keys recursively: a file nested thousands
// deep overflows the stack. This scan (strings and comments skipped) refuses such files first.
void config_detail::require_shallow_nesting(const std::string& s, const std::string& name) {
  int dots = 0, line = 1;
  std::vector<long> elements;  // per open array / inline table (the nesting depth): its commas
  bool in_key = true;          // at a position where a key (and so dotted-key nesting) may be written
  const auto fail = [&](const std::string& what) {
    throw InputError(name + ":" + std::to_string(line),
                     what + " nested deeper than " + std::to_string(kMaxTomlNesting) + " levels");
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\n') {
      ++line;
      if (elements.empty()) {
        in_key = true;
        dots = 0;
      }
      continue;
    }
    if (c == '#') {
      while (i + 1 < s.size() && s[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '"' || c == '\'') {
      const bool multi = s.compare(i, 3, std::string(3, c)) == 0;
      i += multi ? 3 : 1;
      while (i < s.size()) {
        if (s[i] == '\n') ++line;
        if (c == '"' && s[i] == '\\') {
          i += 2;
          continue;
        }
        if (multi ? s.compare(i, 3, std::string(3, c)) == 0 : s[i] == c) break;
        ++i;
      }
      if (multi) i += 2;
      continue;
    }
    if (c == '[' || c == '{') {
      elements.push_back(0);
      if (static_cast<int>(elements.size()) > kMaxTomlNesting) fail("arrays or inline tables");
      if (c == '{') {
        in_key = true;
        dots = 0;
      }
    } else if (c == ']' || c == '}') {
      if (!elements.empty()) elements.pop_back();
    } else if (c == '=') {
      in_key = false;
    } else if (c == ',') {
      // toml11's arrays grow quadratically (200 000 numbers: 50 s): bounded like sweeps.
      if (!elements.empty() && ++elements.back() >= kMaxSweepPoints)
        throw InputError(
            name + ":" + std::to_string(line),
            "an array or inline table with more than " + std::to_string(kMaxSweepPoints) + " elements");
      in_key = true;
      dots = 0;
    } else if (c == '.' && in_key) {
      if (++dots > kMaxTomlNesting) fail("dotted keys");
    }
  }
}

}  // namespace gfmd
