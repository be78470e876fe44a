// Helpers shared by the test suites.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"

namespace gfmd::testing {

// Solves a case given as TOML text with overrides, expecting convergence.
inline CaseResult solve(const std::string& toml, const std::vector<std::string>& sets = {}) {
  const Config c = parse_config(toml, "test.toml", sets);
  CaseResult r = run_case(c);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return r;
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

}  // namespace gfmd::testing
