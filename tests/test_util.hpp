// Helpers shared by the test suites.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gfmd/config.hpp"
#include "gfmd/run.hpp"

namespace gfmd::testing {

// Solves a case given as TOML text with overrides, expecting convergence.
inline CaseResult solve(const std::string& toml, const std::vector<std::string>& sets = {}) {
  const Config c = parse_config(toml, "test.toml", sets);
  CaseResult r = run_case(c);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return r;
}

}  // namespace gfmd::testing
