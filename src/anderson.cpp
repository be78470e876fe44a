#include "gfmd/anderson.hpp"

#include <cmath>
#include <utility>

#include "gfmd/reduce.hpp"

namespace gfmd {

// Solves the small (regularised) normal equations of the Anderson least-squares problem.
std::vector<double> solve_small_spd(std::vector<double> M, std::vector<double> rhs) {
  const std::size_t h = rhs.size();
  double trace = 0;
  for (std::size_t a = 0; a < h; ++a) trace += M[a * h + a];
  for (std::size_t a = 0; a < h; ++a) M[a * h + a] += 1e-10 * trace + 1e-300;
  for (std::size_t c = 0; c < h; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < h; ++r)
      if (std::abs(M[r * h + c]) > std::abs(M[piv * h + c])) piv = r;
    if (piv != c) {
      for (std::size_t k = 0; k < h; ++k) std::swap(M[c * h + k], M[piv * h + k]);
      std::swap(rhs[c], rhs[piv]);
    }
    for (std::size_t r = c + 1; r < h; ++r) {
      const double fct = M[r * h + c] / M[c * h + c];
      for (std::size_t k = c; k < h; ++k) M[r * h + k] -= fct * M[c * h + k];
      rhs[r] -= fct * rhs[c];
    }
  }
  std::vector<double> x(h);
  for (std::size_t c = h; c-- > 0;) {
    double v = rhs[c];
    for (std::size_t k = c + 1; k < h; ++k) v -= M[c * h + k] * x[k];
    x[c] = v / M[c * h + c];
  }
  return x;
}

void AndersonMixer::step(const std::vector<double*>& x, const std::vector<const double*>& g,
                         std::size_t len) {
  const std::size_t na = x.size();
  const std::size_t total = na * len;
  const auto at = [len](std::size_t e) { return std::pair<std::size_t, std::size_t>{e / len, e % len}; };
  if (depth_ == 0) {
#pragma omp parallel for schedule(static)
    for (std::size_t e = 0; e < total; ++e) {
      const auto [a, i] = at(e);
      x[a][i] += beta_ * (g[a][i] - x[a][i]);
    }
    return;
  }
  const std::size_t m = static_cast<std::size_t>(depth_);
  if (df_.size() != m) {
    df_.assign(m, {});
    dx_.assign(m, {});
    gram_.assign(m * m, 0.0);
  }
  if (!have_prev_) {
    xprev_.resize(total);
    fprev_.resize(total);
#pragma omp parallel for schedule(static)
    for (std::size_t e = 0; e < total; ++e) {
      const auto [a, i] = at(e);
      xprev_[e] = x[a][i];
      fprev_[e] = g[a][i] - x[a][i];
      x[a][i] += beta_ * fprev_[e];
    }
    have_prev_ = true;
    return;
  }
  // New ring slot (the oldest is dropped when the ring is full).
  int slot = 0;
  if (slots_.size() == m) {
    slot = slots_.front();
    slots_.erase(slots_.begin());
  } else {
    std::vector<bool> used(m, false);
    for (int sl : slots_) used[static_cast<std::size_t>(sl)] = true;
    while (used[static_cast<std::size_t>(slot)]) ++slot;
  }
  slots_.push_back(slot);
  auto& dfs = df_[static_cast<std::size_t>(slot)];
  auto& dxs = dx_[static_cast<std::size_t>(slot)];
  dfs.resize(total);
  dxs.resize(total);
  const std::size_t h = slots_.size();
  std::vector<const float*> hf(h), hx(h);
  for (std::size_t r = 0; r < h; ++r) {
    hf[r] = df_[static_cast<std::size_t>(slots_[r])].data();
    hx[r] = dx_[static_cast<std::size_t>(slots_[r])].data();
  }
  // One pass: the new differences, the new Gram row <dF_r, dF_new> and <dF_r, f>.
  const auto sums = range_sums(total, 2 * h, [&](std::size_t e, double* acc) {
    const auto [a, i] = at(e);
    const double xi = x[a][i], fi = g[a][i] - xi;
    const float dfi = static_cast<float>(fi - fprev_[e]);
    dfs[e] = dfi;
    dxs[e] = static_cast<float>(xi - xprev_[e]);
    xprev_[e] = xi;
    fprev_[e] = fi;
    for (std::size_t r = 0; r < h; ++r) {
      const double hr = hf[r][e];
      acc[r] += hr * static_cast<double>(dfi);
      acc[h + r] += hr * fi;
    }
  });
  for (std::size_t r = 0; r < h; ++r) {
    const auto a = static_cast<std::size_t>(slots_[r]), b = static_cast<std::size_t>(slot);
    gram_[a * m + b] = gram_[b * m + a] = sums[r];
  }
  std::vector<double> M(h * h), rhs(sums.begin() + static_cast<std::ptrdiff_t>(h), sums.end());
  for (std::size_t r = 0; r < h; ++r)
    for (std::size_t c = 0; c < h; ++c)
      M[r * h + c] = gram_[static_cast<std::size_t>(slots_[r]) * m + static_cast<std::size_t>(slots_[c])];
  const std::vector<double> gam = solve_small_spd(M, rhs);
#pragma omp parallel for schedule(static)
  for (std::size_t e = 0; e < total; ++e) {
    const auto [a, i] = at(e);
    double xx = xprev_[e], ff = fprev_[e];
    for (std::size_t r = 0; r < h; ++r) {
      xx -= gam[r] * hx[r][e];
      ff -= gam[r] * hf[r][e];
    }
    x[a][i] = xx + beta_ * ff;
  }
}

}  // namespace gfmd
