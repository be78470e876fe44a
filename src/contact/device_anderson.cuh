// Anderson mixing on the device (the CUDA solve's part that AndersonMixer and GuardedAnderson
// are on the host): the mixed vectors' layouts (the friction traction on its support, the
// adhesive traction on every point), the single-precision history and the safeguard. Private
// to the CUDA solve (device_solve_class.cuh includes it).
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/core/cuda_kernels.cuh"

namespace gfmd::contact_device {

using namespace cuda_kernels;

inline constexpr int kMaxDepth = 50;  // solver.anderson's upper limit (case/config.cpp)

// Anderson mixing on the device (AndersonMixer's algorithm and its single-precision history;
// the small least-squares solve on the host), over a vector a target describes: x(e) the
// iterate's entry e, g(e) its image, set(e, v) writes the mixed iterate.
// The friction's target: entry 2j is tau_x at support point supp[j], 2j + 1 tau_y there; x is
// the iterate (ftx, fty), g its image (tx, ty).
struct MixTarget {
  double* ftx;
  double* fty;
  const double* tx;
  const double* ty;
  const std::uint32_t* supp;
  __device__ double x(std::size_t e) const { return (e % 2 == 0 ? ftx : fty)[supp[e / 2]]; }
  __device__ double g(std::size_t e) const { return (e % 2 == 0 ? tx : ty)[supp[e / 2]]; }
  __device__ void set(std::size_t e, double v) const { (e % 2 == 0 ? ftx : fty)[supp[e / 2]] = v; }
};
// A field over every point (adhesion's traction): the mixed iterate clipped to [lo, hi].
struct FieldTarget {
  double* xs;
  const double* gs;
  double lo, hi;
  __device__ double x(std::size_t e) const { return xs[e]; }
  __device__ double g(std::size_t e) const { return gs[e]; }
  __device__ void set(std::size_t e, double v) const { xs[e] = fmin(fmax(v, lo), hi); }
};

struct EightVectors {
  const float* v[8];
};

struct HistoryView {
  const float* dx[kMaxDepth];
  const float* df[kMaxDepth];
  double gamma[kMaxDepth];
  int h;
};

class DeviceAnderson {
 public:  // public throughout (extended lambdas in its members)
  DeviceAnderson(int depth, std::size_t entries, Tally* tally)
      : m_(depth), tally_(tally), min_cap_(entries / 8), df_(depth), dx_(depth) {
    gram_.assign(static_cast<std::size_t>(m_) * m_, 0.0);
  }
  // exact: a vector that does not grow (no headroom).
  void resize(std::size_t len, bool exact = false) {
    if (len > cap_) {
      // Doubling, from an eighth of the grid's entries: a few reallocations per solve (each
      // one waits for the device).
      const std::size_t cap = exact ? len : std::max(2 * len, min_cap_);
      xprev_.grow(cap, cap_, tally_, "the mixing history");
      fprev_.grow(cap, cap_, tally_, "the mixing history");
      for (int s = 0; s < m_; ++s) {
        df_[s].grow(cap, cap_, tally_, "the mixing history");
        dx_[s].grow(cap, cap_, tally_, "the mixing history");
      }
      cap_ = cap;
    }
    len_ = len;
  }
  void clear_history() { slots_.clear(); }
  [[nodiscard]] std::size_t history() const { return slots_.size(); }
  void restart() {
    slots_.clear();
    have_prev_ = false;
  }
  // One mixing step: the mixed iterate replaces the target's.
  template <class Target>
  void step(Reducer& red, double omega, Target t) {
    const std::size_t len = len_;
    double* xp = xprev_.get();
    double* fp = fprev_.get();
    std::vector<double> rhs;
    if (!have_prev_) {
      launch_each(len, [=] __device__(std::size_t e) {
        const double xi = t.x(e);
        xp[e] = xi;
        fp[e] = t.g(e) - xi;
      });
      have_prev_ = true;
    } else {
      const std::size_t slot = next_slot();
      float* dfs = df_[slot].get();
      float* dxs = dx_[slot].get();
      launch_each(len, [=] __device__(std::size_t e) {
        const double xi = t.x(e);
        const double fi = t.g(e) - xi;
        dfs[e] = static_cast<float>(fi - fp[e]);
        dxs[e] = static_cast<float>(xi - xp[e]);
        xp[e] = xi;
        fp[e] = fi;
      });
      const std::size_t h = slots_.size();
      std::vector<double> sums(2 * h);
      // <dF_r, dF_new> and <dF_r, f>, eight history vectors per pass.
      for (std::size_t r0 = 0; r0 < h; r0 += 8) {
        EightVectors hv{};
        const int cnt = static_cast<int>(std::min<std::size_t>(8, h - r0));
        for (int c = 0; c < cnt; ++c) hv.v[c] = df_[slots_[r0 + c]].get();
        const auto s = red.run<16>(len, [=] __device__(std::size_t e, double* acc) {
          const double dfi = static_cast<double>(dfs[e]), fi = fp[e];
          for (int c = 0; c < cnt; ++c) {
            const double hr = static_cast<double>(hv.v[c][e]);
            acc[c] += hr * dfi;
            acc[8 + c] += hr * fi;
          }
        });
        for (int c = 0; c < cnt; ++c) {
          sums[r0 + c] = s[c];
          sums[h + r0 + c] = s[8 + c];
        }
      }
      const auto mm = static_cast<std::size_t>(m_);
      for (std::size_t r = 0; r < h; ++r)
        gram_[slots_[r] * mm + slot] = gram_[slot * mm + slots_[r]] = sums[r];
      rhs.assign(sums.begin() + static_cast<std::ptrdiff_t>(h), sums.end());
    }
    const std::size_t h = rhs.size();
    HistoryView hv{};
    hv.h = static_cast<int>(h);
    if (h > 0) {
      const auto mm = static_cast<std::size_t>(m_);
      std::vector<double> M(h * h);
      for (std::size_t r = 0; r < h; ++r)
        for (std::size_t c = 0; c < h; ++c) M[r * h + c] = gram_[slots_[r] * mm + slots_[c]];
      const std::vector<double> gamma = anderson_solve_small(std::move(M), rhs);
      for (std::size_t r = 0; r < h; ++r) {
        hv.dx[r] = dx_[slots_[r]].get();
        hv.df[r] = df_[slots_[r]].get();
        hv.gamma[r] = gamma[r];
      }
    }
    launch_each(len, [=] __device__(std::size_t e) {
      double xe = xp[e], fe = fp[e];
      for (int r = 0; r < hv.h; ++r) {
        xe -= hv.gamma[r] * static_cast<double>(hv.dx[r][e]);
        fe -= hv.gamma[r] * static_cast<double>(hv.df[r][e]);
      }
      t.set(e, xe + omega * fe);
    });
  }

  std::size_t next_slot() {
    std::size_t slot = 0;
    if (slots_.size() == static_cast<std::size_t>(m_)) {
      slot = slots_.front();
      slots_.erase(slots_.begin());
    } else {
      std::vector<bool> used(static_cast<std::size_t>(m_), false);
      for (std::size_t sl : slots_) used[sl] = true;
      while (used[slot]) ++slot;
    }
    slots_.push_back(slot);
    return slot;
  }

  int m_;
  Tally* tally_;
  std::size_t min_cap_;
  std::size_t len_ = 0, cap_ = 0;
  DevArray<double> xprev_, fprev_;
  std::vector<DevArray<float>> df_, dx_;
  std::vector<double> gram_;
  std::vector<std::size_t> slots_;
  bool have_prev_ = false;
};

// GuardedAnderson on the device: a fixed point over every point of the grid (adhesion's
// traction), Anderson-mixed with the host's safeguard (the same AndersonGuard decides).
class DeviceGuarded {
 public:
  DeviceGuarded(int depth, std::size_t n, Tally* tally) : n_(n) {
    if (depth <= 0) return;
    mixer_.emplace(depth, n, tally);
    mixer_->resize(n, true);
    kept_.allocate(n, tally, "the mixing history");
  }
  void restart() {
    if (mixer_) mixer_->restart();
    guard_.restart();
  }
  // x: the iterate, image: G(x), change: the step's relative change. The next iterate into x.
  void advance(Reducer& red, double* x, const double* image, double change, double lo, double hi) {
    const std::size_t bytes = n_ * sizeof(double);
    switch (guard_.next(change, mixer_.has_value())) {
      case AndersonGuard::Step::Plain:
        cuda_check(cudaMemcpy(x, image, bytes, cudaMemcpyDeviceToDevice), "a plain step");
        return;
      case AndersonGuard::Step::Reject:
        cuda_check(cudaMemcpy(x, kept_.get(), bytes, cudaMemcpyDeviceToDevice), "a rejected step");
        mixer_->restart();
        return;
      case AndersonGuard::Step::Mix:
        break;
    }
    cuda_check(cudaMemcpy(kept_.get(), image, bytes, cudaMemcpyDeviceToDevice), "keeping an image");
    mixer_->step(red, 1.0, FieldTarget{x, image, lo, hi});
    guard_.mixed(mixer_->history() > 0);
  }

 private:
  std::size_t n_;
  std::optional<DeviceAnderson> mixer_;
  DevArray<double> kept_;
  AndersonGuard guard_;
};

using Clock = std::chrono::steady_clock;

}  // namespace gfmd::contact_device
