// Error types. Every user-facing error names what is wrong (config key, file) and why.
#pragma once

#include <stdexcept>
#include <string>

namespace gfmd {

// Bad user input: a config key, a command-line value or an input file.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& why)
      : std::runtime_error(where + ": " + why), where_(where), why_(why) {}
  [[nodiscard]] const std::string& where() const { return where_; }
  [[nodiscard]] const std::string& why() const { return why_; }

 private:
  std::string where_, why_;
};

// A solve that failed numerically (NaN, divergence, no convergence when required).
class SolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A solve stopped on request (SIGINT/SIGTERM); the state reached is kept for a resume.
class Interrupted : public SolveError {
 public:
  using SolveError::SolveError;
};

}  // namespace gfmd
