// Anderson mixing of the friction fixed point on the device (the CUDA solve's part that
// AndersonMixer is on the host): the mixed vector's layout on the traction's support and the
// single-precision history. Private to src/contact/device_solve.cu, which includes it.
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/core/cuda_kernels.cuh"

namespace gfmd::contact_device {

using namespace cuda_kernels;

inline constexpr int kMaxDepth = 50;  // solver.anderson's upper limit (case/config.cpp)

// Anderson mixing of the friction fixed point on the device (AndersonMixer's algorithm and
// its single-precision history; the small least-squares solve on the host).
// The mixed vector: entry 2j is tau_x at support point supp[j], 2j + 1 tau_y there; x is
// the iterate (ftx, fty), g its image (tx, ty).
struct MixTarget {
  double* ftx;
  double* fty;
  const double* tx;
  const double* ty;
  const std::uint32_t* supp;
};
__device__ inline double mix_x(const MixTarget& t, std::size_t e) {
  return (e % 2 == 0 ? t.ftx : t.fty)[t.supp[e / 2]];
}
__device__ inline double mix_g(const MixTarget& t, std::size_t e) {
  return (e % 2 == 0 ? t.tx : t.ty)[t.supp[e / 2]];
}

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
  void resize(std::size_t len) {
    if (len > cap_) {
      // Doubling, from an eighth of the grid's entries: a few reallocations per solve (each
      // one waits for the device).
      const std::size_t cap = std::max(2 * len, min_cap_);
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
  void restart() {
    slots_.clear();
    have_prev_ = false;
  }
  // One mixing step: the mixed iterate replaces (ftx, fty) on the support.
  void step(Reducer& red, double omega, MixTarget t) {
    const std::size_t len = len_;
    double* xp = xprev_.get();
    double* fp = fprev_.get();
    std::vector<double> rhs;
    if (!have_prev_) {
      launch_each(len, [=] __device__(std::size_t e) {
        const double xi = mix_x(t, e);
        xp[e] = xi;
        fp[e] = mix_g(t, e) - xi;
      });
      have_prev_ = true;
    } else {
      const std::size_t slot = next_slot();
      float* dfs = df_[slot].get();
      float* dxs = dx_[slot].get();
      launch_each(len, [=] __device__(std::size_t e) {
        const double xi = mix_x(t, e);
        const double fi = mix_g(t, e) - xi;
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
      (e % 2 == 0 ? t.ftx : t.fty)[t.supp[e / 2]] = xe + omega * fe;
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

using Clock = std::chrono::steady_clock;

}  // namespace gfmd::contact_device
