// libFuzzer target: the whole `gfmd run` path on tiny grids. A case text is parsed, solved
// (frictionless or sliding, stresses, flow as configured) and its summary and fields.nc
// written (the maps are drawn by the front ends). Accepted behaviour: InputError for bad input, SolveError
// for a solve that fails; any other exception, crash, hang or sanitizer report is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const std::string dir =
      (std::filesystem::temp_directory_path() / ("gfmd_fuzz_run_" + std::to_string(::getpid()))).string();
  try {
    gfmd::Config c = gfmd::parse_config(text, "fuzz.toml");
    // Tiny and bounded: a few ms per input, so the fuzzer explores inputs, not iterations.
    if (c.grid.size() > 32 * 32 || c.indenter.type == "file" || c.sweep.active()) return 0;
    c.threads = 1;
    c.solver.max_iterations = std::min(c.solver.max_iterations, 300);
    c.solver.max_outer = std::min(c.solver.max_outer, 30);
    c.solver.max_tangential = std::min(c.solver.max_tangential, 300);
    const gfmd::CaseResult r = gfmd::run_case(c);
    if (r.info.converged) {
      const gfmd::DirectoryLock lock(dir);
      gfmd::clear_run_outputs(dir);
      gfmd::write_outputs(r, dir);
    } else {
      (void)gfmd::summary_json(r).dump();
    }
  } catch (const gfmd::InputError&) {
  } catch (const gfmd::SolveError&) {
  }
  return 0;
}
