// Anderson acceleration of a fixed-point map x <- G(x) (Walker & Ni 2011), with relaxation:
// the friction fixed point's accelerator, usable on any vector the caller can index.
//
// With f = G(x) - x and the differences dX, dF of the last `depth` iterates and residuals,
// gamma = argmin |f - dF gamma| and x <- x - dX gamma + omega (f - dF gamma); omega < 1
// damps rotating (imaginary-eigenvalue) modes. The history is kept in single precision
// (only the mixing uses it; convergence is judged on the unaccelerated map by the caller).
// The vector may grow between steps (new entries have zero history: their previous iterate,
// residual and differences are zero), which the friction solve uses to keep the state on the
// support of the traction only. Sums are deterministic (range_sums), so the iterates do not
// depend on the backend or the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/reduce.hpp"

namespace gfmd {

class AndersonMixer {
 public:
  // depth >= 1: the number of differences kept.
  explicit AndersonMixer(int depth);

  [[nodiscard]] int depth() const { return m_; }
  [[nodiscard]] std::size_t size() const { return xprev_.size(); }
  // Differences in the history now (0 after a restart and on the first two steps).
  [[nodiscard]] std::size_t history() const { return slots_.size(); }

  // Zero-extends the state to len entries (len >= size()), with 25 % headroom so that a
  // vector growing in small steps does not hold twice its memory.
  void resize(std::size_t len);
  // Drops the stored differences; the next step mixes from the last iterate on.
  void clear_history() { slots_.clear(); }
  // Drops everything: the next step only records x and f (and relaxes).
  void restart() {
    slots_.clear();
    have_prev_ = false;
  }

  // The state (a checkpoint's restart point): whether an iterate is recorded, the ring slots in
  // use (oldest first), the Gram matrix by slot (depth x depth), the last iterate and residual
  // and each slot's differences, by entry.
  [[nodiscard]] bool has_previous() const { return have_prev_; }
  [[nodiscard]] const std::vector<std::size_t>& slots() const { return slots_; }
  [[nodiscard]] const std::vector<double>& gram() const { return gram_; }
  [[nodiscard]] const std::vector<double>& previous_iterate() const { return xprev_; }
  [[nodiscard]] const std::vector<double>& previous_residual() const { return fprev_; }
  [[nodiscard]] const std::vector<float>& residual_differences(std::size_t slot) const { return df_[slot]; }
  [[nodiscard]] const std::vector<float>& iterate_differences(std::size_t slot) const { return dx_[slot]; }
  // Puts a saved state back on a mixer of the same depth and size: the slots in use, the Gram
  // matrix and whether an iterate is recorded; the per-entry vectors are then written through
  // the references below (size() entries each, the slots' in use too).
  void restore(bool have_prev, const std::vector<std::size_t>& slots, const std::vector<double>& gram);
  [[nodiscard]] std::vector<double>& previous_iterate() { return xprev_; }
  [[nodiscard]] std::vector<double>& previous_residual() { return fprev_; }
  [[nodiscard]] std::vector<float>& residual_differences(std::size_t slot) { return df_[slot]; }
  [[nodiscard]] std::vector<float>& iterate_differences(std::size_t slot) { return dx_[slot]; }

  // The plain relaxed step from the last recorded iterate, out(e, x + omega f) (what step()
  // writes with no history): the fallback when an extrapolated iterate is rejected.
  template <class Out>
  void plain_step(double omega, Out&& out) const {
    parallel_for(static_cast<std::ptrdiff_t>(xprev_.size()), [&](std::ptrdiff_t s) {
      const auto e = static_cast<std::size_t>(s);
      out(e, xprev_[e] + omega * fprev_[e]);
    });
  }

  // Sums over the entries by grid row (reduce.hpp, row_grouped_sums) instead of in blocks of
  // the list: the mixing then does not depend on how the grid is split over processes. The
  // arguments must outlive the steps that use them and list every entry; nullptr: blocks.
  void group_by_rows(const Grid* grid, const std::vector<std::uint32_t>* start,
                     const std::vector<std::uint32_t>* order) {
    grid_ = grid;
    start_ = start;
    order_ = order;
  }

  // One step over entries 0..len-1 (len == size()): x(e) is the current iterate, g(e) its
  // image G(x), out(e, v) receives the mixed iterate. Entries may be updated in parallel.
  template <class X, class G, class Out>
  void step(double omega, X&& x, G&& g, Out&& out);

 private:
  // The ring slot for the newest difference (the oldest one's once the ring is full).
  std::size_t next_slot();
  // Least-squares coefficients from the Gram matrix of the slots in use and dF^T f.
  [[nodiscard]] std::vector<double> coefficients(const std::vector<double>& rhs) const;
  static void grow(auto& v, std::size_t len) {
    if (v.capacity() < len) v.reserve(len + len / 4);
    v.resize(len, 0);
  }

  int m_;
  std::vector<double> xprev_, fprev_;
  std::vector<std::vector<float>> df_, dx_;  // ring buffers of the differences
  std::vector<double> gram_;                 // <dF_a, dF_b> by slot
  std::vector<std::size_t> slots_;           // ring slots in use, oldest first
  bool have_prev_ = false;
  const Grid* grid_ = nullptr;
  const std::vector<std::uint32_t>* start_ = nullptr;
  const std::vector<std::uint32_t>* order_ = nullptr;
};

// The safeguard's decisions (GuardedAnderson's, and the CUDA solve's DeviceGuarded alike): for
// each step, from its relative change, whether to take the plain image, to reject the last
// extrapolation (back to the kept image, the history dropped, plain steps for 5, 10, 20, ...
// steps) or to mix.
class AndersonGuard {
 public:
  enum class Step { Plain, Reject, Mix };
  // The next step for an iterate whose step changed by `change`; mixing: a mixer exists.
  Step next(double change, bool mixing) {
    if (!mixing || plain_left_ > 0) {
      if (plain_left_ > 0 && --plain_left_ == 0) kept_change_ = std::numeric_limits<double>::infinity();
      return Step::Plain;
    }
    if (mixed_ && !(change < kept_change_)) {
      mixed_ = false;
      plain_left_ = kPlainSteps << std::min(rejected_, 10);
      ++rejected_;
      return Step::Reject;
    }
    kept_change_ = change;
    return Step::Mix;
  }
  // After a Mix step: whether the new iterate is an extrapolation (the mixer had a history).
  void mixed(bool extrapolated) { mixed_ = extrapolated; }
  void restart() { *this = AndersonGuard{}; }
  // The decisions' state (a checkpoint's restart point) and back.
  struct State {
    double kept_change = std::numeric_limits<double>::infinity();
    bool mixed = false;
    std::int32_t rejected = 0, plain_left = 0;
  };
  [[nodiscard]] State state() const { return {kept_change_, mixed_, rejected_, plain_left_}; }
  void restore(const State& s) {
    kept_change_ = s.kept_change;
    mixed_ = s.mixed;
    rejected_ = s.rejected;
    plain_left_ = s.plain_left;
  }

 private:
  static constexpr int kPlainSteps = 5;
  double kept_change_ = std::numeric_limits<double>::infinity();
  bool mixed_ = false;  // the current iterate is an extrapolation
  int rejected_ = 0, plain_left_ = 0;
};

// A fixed point x <- G(x) over every point of the grid held here (adhesion's traction, a
// viscoelastic body's pressure), Anderson-mixed with a safeguard (AndersonGuard): an extrapolated iterate is
// kept only where its step's change is below the last kept one's; otherwise the plain image of
// the last kept iterate is taken and the history dropped, and plain steps take over for a
// while, longer after each rejection (5, 10, 20, ... steps) before mixing starts afresh. Near
// an instability (adhesion's jump-off) an unguarded extrapolation throws the state over the
// barrier; where the map is not smooth (contact edges flipping) it keeps failing. Sums by grid
// row: the same iterates on any process count.
class GuardedAnderson {
 public:
  // depth 0: plain steps only.
  GuardedAnderson(int depth, const Grid& grid);
  // Forgets the history and the rejections (a new solve).
  void restart();
  // x: the iterate, image: G(x), change: the step's relative change (the caller's measure of
  // |G(x) - x|). Writes the next iterate into x, clipped to [lo, hi].
  void advance(RealField& x, const RealField& image, double change, double lo, double hi);
  // The state between steps (a checkpoint's restart point): the mixer (null at depth 0), the
  // image of the last iterate kept and the safeguard's decisions; restored through the same.
  [[nodiscard]] AndersonMixer* mixer() const { return mixer_.get(); }
  [[nodiscard]] RealField& kept() { return kept_; }
  [[nodiscard]] const RealField& kept() const { return kept_; }
  [[nodiscard]] AndersonGuard& guard() { return guard_; }
  [[nodiscard]] const AndersonGuard& guard() const { return guard_; }

 private:
  std::unique_ptr<AndersonMixer> mixer_;
  std::vector<std::uint32_t> start_, order_;
  RealField kept_;  // the image of the last iterate kept
  AndersonGuard guard_;
};

// Solves the small (regularised) normal equations M x = rhs of the least-squares problem
// (M symmetric positive semi-definite, h x h, row-major); exposed for tests.
std::vector<double> anderson_solve_small(std::vector<double> M, std::vector<double> rhs);

template <class X, class G, class Out>
void AndersonMixer::step(double omega, X&& x, G&& g, Out&& out) {
  const std::size_t len = xprev_.size();
  std::vector<double> rhs;
  if (!have_prev_) {
    parallel_for(static_cast<std::ptrdiff_t>(len), [&](std::ptrdiff_t s) {
      const auto e = static_cast<std::size_t>(s);
      const double xi = x(e);
      xprev_[e] = xi;
      fprev_[e] = g(e) - xi;
    });
    have_prev_ = true;
  } else {
    const std::size_t slot = next_slot();
    auto& dfs = df_[slot];
    auto& dxs = dx_[slot];
    grow(dfs, len);
    grow(dxs, len);
    const std::size_t h = slots_.size();
    std::vector<const float*> hist(h);
    for (std::size_t r = 0; r < h; ++r) hist[r] = df_[slots_[r]].data();
    // One pass stores the new differences and forms the new Gram row, acc[0..h-1] =
    // <dF_r, dF_new>, and dF^T f, acc[h..2h-1] = <dF_r, f>.
    const auto entry = [&](std::size_t e, double* acc) {
      const double xi = x(e);
      const double fi = g(e) - xi;
      const float dfi = static_cast<float>(fi - fprev_[e]);
      dfs[e] = dfi;
      dxs[e] = static_cast<float>(xi - xprev_[e]);
      xprev_[e] = xi;
      fprev_[e] = fi;
      for (std::size_t r = 0; r < h; ++r) {
        const double hr = hist[r][e];
        acc[r] += hr * static_cast<double>(dfi);
        acc[h + r] += hr * fi;
      }
    };
    const auto sums =
        grid_ ? row_grouped_sums(*grid_, *start_, *order_, 2 * h, entry) : range_sums(len, 2 * h, entry);
    const auto mm = static_cast<std::size_t>(m_);
    for (std::size_t r = 0; r < h; ++r) gram_[slots_[r] * mm + slot] = gram_[slot * mm + slots_[r]] = sums[r];
    rhs.assign(sums.begin() + static_cast<std::ptrdiff_t>(h), sums.end());
  }
  const std::size_t h = rhs.size();
  const std::vector<double> gamma = coefficients(rhs);
  std::vector<const float*> hf(h), hx(h);
  for (std::size_t r = 0; r < h; ++r) {
    hf[r] = df_[slots_[r]].data();
    hx[r] = dx_[slots_[r]].data();
  }
  parallel_for(static_cast<std::ptrdiff_t>(len), [&](std::ptrdiff_t s) {
    const auto e = static_cast<std::size_t>(s);
    double xe = xprev_[e], fe = fprev_[e];
    for (std::size_t r = 0; r < h; ++r) {
      xe -= gamma[r] * hx[r][e];
      fe -= gamma[r] * hf[r][e];
    }
    out(e, xe + omega * fe);
  });
}

}  // namespace gfmd
