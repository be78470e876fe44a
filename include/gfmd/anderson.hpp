// Anderson acceleration of a fixed point x = G(x) over vectors stored as several arrays
// (e.g. the two components of a tangential field), with the history in single precision.
//
// Type II Anderson mixing (Walker & Ni 2011): with f = G(x) - x and the differences dF, dX of
// the last `depth` residuals and iterates, gamma = argmin |f - dF gamma|_2 and
// x <- x - dX gamma + beta (f - dF gamma). The sums run in fixed blocks, so the result does
// not depend on the number of threads.
#pragma once

#include <cstddef>
#include <vector>

namespace gfmd {

// Solves the small (regularised) normal equations M x = rhs of the Anderson least-squares
// problem (M symmetric positive semi-definite, h x h row-major).
std::vector<double> solve_small_spd(std::vector<double> M, std::vector<double> rhs);

class AndersonMixer {
 public:
  // depth 0: plain relaxation x <- x + beta f.
  AndersonMixer(int depth, double beta) : depth_(depth), beta_(beta) {}

  // Forgets the history (e.g. after the problem changed under the iteration).
  void reset() {
    slots_.clear();
    have_prev_ = false;
  }
  [[nodiscard]] int depth() const { return depth_; }
  [[nodiscard]] std::size_t history() const { return slots_.size(); }

  // x[a][0..len): the current iterate, split into arrays; g[a]: its image G(x). x is replaced
  // by the next iterate. Every call must pass the same number of arrays of the same length.
  void step(const std::vector<double*>& x, const std::vector<const double*>& g, std::size_t len);

 private:
  int depth_;
  double beta_;
  bool have_prev_ = false;
  std::vector<double> xprev_, fprev_;
  std::vector<std::vector<float>> df_, dx_;  // ring of differences
  std::vector<int> slots_;                   // ring slots in use, oldest first
  std::vector<double> gram_;                 // <dF_a, dF_b> by slot
};

}  // namespace gfmd
