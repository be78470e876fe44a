// Error types. Every user-facing error names what is wrong (config key, file) and why.
#pragma once

#include <charconv>
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

// A bad argument of a library function, named by the function's parameter ("radius_x",
// "poisson", "depth"), never by a config key: physics does not know the case file. The case
// layer, which does, turns it into an InputError naming the key (gfmd::in_section in
// case/config.hpp). An InputError itself, so callers catching InputError see it too.
class ParameterError : public InputError {
 public:
  using InputError::InputError;
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

// A process of a distributed run that stops because rank 0 failed after the solve: rank 0
// reports why, this process only exits, with the code rank 0's error gives.
class StoppedWithRoot : public std::runtime_error {
 public:
  explicit StoppedWithRoot(int code) : std::runtime_error("stopped with rank 0"), code_(code) {}
  [[nodiscard]] int code() const { return code_; }

 private:
  int code_;
};

// The shortest text that reads back as exactly v (std::to_chars): for messages and for
// values passed on as text (sweep points), where six fixed decimals would lose 1e-7.
inline std::string format_number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace gfmd
